// The engine interface: anything that can run a resolved case and hand back its output image.
//
// Lifecycle (every engine, in this order):
//   1. Construction: cheap, cannot fail, touches no device.
//   2. init(): acquires what the engine needs (for Vulkan: instance, the explicitly selected
//      physical device, queue, shader compiler). An error means "unavailable" — the runner then
//      marks the engine's cases SKIPPED with the error's message as the reason, never PASSED.
//   3. device(): after a successful init, names what runs the cases (recorded in every result).
//   4. run(case): any number of times, any order of cases; each call is independent. An error
//      fails that case only (ERROR verdict); the engine stays usable for the next case.
//   5. Destruction releases everything acquired in init().
#pragma once

#include <string>

#include "core/case.h"
#include "core/device_precision.h"
#include "core/image.h"
#include "core/result.h"

namespace hdrc {

struct DeviceInfo {
  std::string engine;       // "reference", "vulkan"
  std::string device;       // "cpu (double)", "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string driver;       // "Mesa 22.3.6 (LLVM 15.0.6)"
  std::string api_version;  // "1.3.230"
  // The device's precision properties (the Vulkan engine; the reference leaves the defaults, and
  // the worst-case model reports its own). docs/precision.md.
  DevicePrecision precision;
};

class Engine {
 public:
  virtual ~Engine() = default;
  virtual std::string name() const = 0;
  virtual Status init() = 0;
  virtual DeviceInfo device() const = 0;
  virtual Result<Image> run(const ResolvedCase& c) = 0;
  // verify's candidate protocol (README, "Verifying a port"): a candidate may decline what it
  // does not implement. Non-empty: the candidate declines `c` (UNSUPPORTED, never a pass), with
  // the reason. Asked before the case runs (a stage declined earlier: run() is never called) and
  // after run() returned an error (the case itself was declined).
  virtual std::string unsupported(const ResolvedCase& /*c*/) const { return ""; }
};

}  // namespace hdrc
