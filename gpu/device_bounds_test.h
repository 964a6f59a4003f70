// The device gpu_tests run on and the bounds a test may hold it to (header-only, tests only).
//
// gpu_tests run on lavapipe in CI and on any Vulkan device named by HDRC_VK_DEVICE. Their tight
// bounds were set on lavapipe, a float32-exact device (runner/dither.h float32_exact_device: the
// Vulkan engine on llvmpipe without a device model). On such a device every test keeps its bound
// exactly. On another device a test uses a bound derived from the Vulkan specification instead,
// never a measured one:
//  * "Precision and Operation of SPIR-V Instructions": the interval arithmetic of
//    reference/color/spirv_precision.h (OpFDiv 2.5 ULP, exp2 3 + 2|x| ULP, log2, pow inherited,
//    a·b + c fused or not);
//  * "Fixed-Point Data Conversions" and the float16 rounding mode: store_either_way's neighbours
//    (reference/color/device_allowance.h unorm_floor/ceil, half_round_down/up);
//  * "Texel Filtering" / subTexelPrecisionBits: the weight box (device_allowance.h
//    linear_tap_box), 2^-bits per weight;
//  * a whole stage: the reference's own device ranges (ResolvedCase::device_allowances,
//    Image::device_admissible), as `hdrconform run` judges a case after its tight miss.
// HDRC_DEVICE_MODEL=worst runs the tests that build their engines with test_options() under the
// worst-case device model (a device that is not float32-exact, on lavapipe): their derived
// branch is then exercised against the model's output.
// Tests about lavapipe itself (its name, its serial execution, its timing) and the worst-case
// model's probes (which assume an exact base device) skip with the reason on other devices; tests
// that need the Khronos validation layer skip where it is not installed, except on lavapipe (CI
// installs it: a missing layer there stays a failure).
#pragma once

#include <gtest/gtest.h>
#include <vulkan/vulkan.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "core/engine.h"
#include "core/image.h"
#include "gpu/vulkan_engine.h"
#include "reference/color/device_allowance.h"
#include "reference/color/noise_range.h"
#include "reference/color/spirv_precision.h"
#include "reference/reference_engine.h"
#include "reference/ue/combine_luts.h"

namespace hdrc::gpu::testing {

// The criterion of runner/dither.h float32_exact_device, restated (gpu_tests do not link the
// runner): the device says so, or it is llvmpipe without a device model.
inline bool float32_exact(const DeviceInfo& d) {
  if (d.precision.float32_exact) return true;
  return d.engine == "vulkan" && d.device.rfind("llvmpipe", 0) == 0 && d.precision.model.empty();
}

// The device model the tests that build their engines with test_options() run under: the
// environment's HDRC_DEVICE_MODEL, "none" (the default) or "worst" (core/device_precision.h, as
// `hdrconform run --device-model worst`). Under "worst" the device is not float32-exact, so those
// tests take their derived bounds on lavapipe, against the model's output. Another value is an
// error naming the variable, the value and the choices (the test that asks fails with it).
inline Result<DeviceModel> test_device_model() {
  const char* e = std::getenv("HDRC_DEVICE_MODEL");
  const std::string v = e == nullptr ? "" : e;
  if (v.empty() || v == "none") return DeviceModel::kNone;
  if (v == "worst") return DeviceModel::kWorst;
  return Error{"", "HDRC_DEVICE_MODEL", "unknown device model '" + v + "'", "none, worst"};
}

// The options of an engine on the tests' device: the default device (HDRC_VK_DEVICE where set,
// else lavapipe) under test_device_model().
inline VulkanOptions test_options() {
  VulkanOptions o;
  const Result<DeviceModel> model = test_device_model();
  if (model.ok())
    o.device_model = *model;
  else
    ADD_FAILURE() << model.error().to_string();
  return o;
}

// The device an engine with test_options() opens, asked once per process.
inline const DeviceInfo& test_device() {
  static const DeviceInfo info = [] {
    VulkanEngine engine(test_options());
    const Status st = engine.init();
    return st.ok() ? engine.device() : DeviceInfo{};
  }();
  return info;
}

// Whether the tests' device is float32-exact (lavapipe): the tight bounds hold there.
// HDRC_TEST_DERIVED_BOUNDS=1 takes the other branch on any device, so that the derived bounds
// are exercised on lavapipe too (they must hold there: its values are a conformant device's).
inline bool exact_device() {
  static const bool forced = [] {
    const char* e = std::getenv("HDRC_TEST_DERIVED_BOUNDS");
    return e != nullptr && std::string(e) == "1";
  }();
  return !forced && float32_exact(test_device());
}

// Whether the tests' device is lavapipe (llvmpipe), whatever its precision.
inline bool lavapipe_device() {
  return test_device().device.rfind("llvmpipe", 0) == 0;
}

// Whether the Khronos validation layer is installed (vkEnumerateInstanceLayerProperties).
inline bool validation_layer_installed() {
  uint32_t n = 0;
  if (vkEnumerateInstanceLayerProperties(&n, nullptr) != VK_SUCCESS) return false;
  std::vector<VkLayerProperties> layers(n);
  if (vkEnumerateInstanceLayerProperties(&n, layers.data()) != VK_SUCCESS) return false;
  for (const auto& l : layers)
    if (std::strcmp(l.layerName, "VK_LAYER_KHRONOS_validation") == 0) return true;
  return false;
}

// The reason a test about lavapipe itself skips elsewhere ("" on lavapipe).
inline std::string not_lavapipe_reason(const char* why) {
  if (lavapipe_device()) return "";
  return std::string("about lavapipe, the device is ") + test_device().device + ": " + why;
}

// The reason a test that assumes a float32-exact device skips elsewhere ("" on such a device).
inline std::string not_exact_reason(const char* why) {
  if (exact_device()) return "";
  const std::string model = test_device().precision.model;
  return std::string("assumes a float32-exact device, ") + test_device().device +
         (model.empty() ? "" : " under the " + model + "-case device model (HDRC_DEVICE_MODEL)") +
         " is not (runner/dither.h float32_exact_device): " + why;
}

// The reason a test that needs the validation layer skips ("" where it runs): where the layer is
// missing, except on lavapipe (CI installs vulkan-validationlayers; there it stays a failure).
inline std::string no_validation_layer_reason() {
  if (lavapipe_device() || validation_layer_installed()) return "";
  return "the Khronos validation layer (VK_LAYER_KHRONOS_validation) is not installed on " +
         test_device().device;
}

// Skips the test with `reason` where it is not empty (never a silent pass).
#define HDRC_SKIP_IF(reason_expr)                                    \
  do {                                                               \
    const std::string hdrc_skip_reason = (reason_expr);              \
    if (!hdrc_skip_reason.empty()) GTEST_SKIP() << hdrc_skip_reason; \
  } while (0)

// The interval a device may give for float32 `num / den` with exact float32 operands ("Precision
// and Operation of SPIR-V Instructions": OpFDiv 2.5 ULP); a float32-exact device gives the
// correctly rounded quotient only.
inline ref::spirv::Interval quotient_on_device(float num, float den, bool exact) {
  if (exact) return ref::spirv::Interval::point(static_cast<float>(num / den));
  return ref::spirv::div(ref::spirv::Interval::point(num), ref::spirv::Interval::point(den));
}

// The values a LUT texel store of a value in `v` may leave ("Fixed-Point Data Conversions": a
// float → UNORM conversion gives either of the two nearest codes; float → float16 rounds with
// the implementation's mode unless shaderRoundingModeRTEFloat16, then to nearest; float32 keeps
// the float): format 0 UNORM with `levels` (1023, or 3 for the 2-bit alpha), 1 float16, 2
// float32. Either neighbour of each end (store_either_way's rule, reference/ue/combine_luts.cpp),
// RTE or not: the interval's ends are not floats themselves, so both roundings stay possible.
inline ref::spirv::Interval stored_on_device(ref::spirv::Interval v, int format, double levels) {
  if (format == 0) return {ref::unorm_floor(v.lo, levels), ref::unorm_ceil(v.hi, levels)};
  if (format == 1) return {ref::half_round_down(v.lo), ref::half_round_up(v.hi)};
  return {ref::float_round_down(v.lo), ref::float_round_up(v.hi)};
}

// |error| bound of one linear filter axis from the weight's sub-texel precision ("Texel
// Filtering", subTexelPrecisionBits): the weight may be either grid value of 2^-bits around the
// exact one, so the filtered value moves by at most 2^-bits · |difference of the two taps|.
inline double weight_precision(int sub_texel_bits) {
  return std::ldexp(1.0, -sub_texel_bits);
}

// The reference moved, in every pixel with a device range (Image::device_admissible), to the
// value of the range nearest the candidate, as the diff judges against the nearest admissible
// value (docs/diff-metrics.md, "Admissible ranges"): a test's own metric on (this, candidate) is
// then the candidate's distance outside what a conformant device may produce, held to the test's
// own tight bound. NaN stays where the range admits it and the candidate has it.
inline Image nearest_admissible(const Image& reference, const Image& candidate) {
  Image out = reference;
  for (const AdmissibleRange& r : reference.device_admissible)
    for (int c = 0; c < Image::kChannels; ++c) {
      const size_t k = r.pixel * Image::kChannels + c;
      const double g = candidate.data[k];
      if (std::isnan(g)) {
        if (r.nan_ok & (1u << c)) out.data[k] = g;
      } else if (r.lo[c] <= r.hi[c]) {
        out.data[k] = std::fmin(std::fmax(g, r.lo[c]), r.hi[c]);
      }
    }
  return out;
}

// A whole stage's reference as a test compares it with the GPU's output `got`: ReferenceEngine's
// output on a float32-exact device (the tight bounds, unchanged); elsewhere (`derived`) the
// stage's device ranges for `device`'s precision (ResolvedCase::device_allowances, as
// `hdrconform run` judges a case after its tight miss: runner/run.cpp
// judge_with_device_allowances), nearest `got`.
inline Result<Image> stage_reference(ref::ReferenceEngine& reference, ResolvedCase rc,
                                     const Image& got, bool derived = !exact_device(),
                                     const DevicePrecision& device = test_device().precision) {
  if (derived) {
    rc.device = device;
    rc.device_allowances = true;
  }
  auto want = reference.run(rc);
  if (!want || !derived) return want;
  return nearest_admissible(*want, got);
}

// How far `g` lies outside channel `c` of `r` (0 inside; NaN admitted where the range says so;
// else a NaN on either side is infinitely far).
inline double outside(const ref::Range3& r, int c, double g) {
  if (std::isnan(g)) return r.nan[c] ? 0.0 : HUGE_VAL;
  if (!(r.lo[c] <= r.hi[c])) return HUGE_VAL;
  return g < r.lo[c] ? r.lo[c] - g : g > r.hi[c] ? g - r.hi[c] : 0.0;
}

// The GPU's own baked LUT (read back from the combine_luts stage) as a device LUT whose texel
// ranges are its texels themselves: the Tonemap pass's device ranges over it
// (reference/ue/tonemap.h, tonemap_image with a device LUT) then hold the sampler's weight box and
// the pass's own arithmetic, not CombineLUTs' storage (the texels are what the GPU stored).
inline ref::BakedLut as_device_lut(ref::BakedLut lut) {
  lut.lo = lut.texels;
  lut.hi = lut.texels;
  lut.flags.assign(lut.texels.size(), ref::BakedLut::kAmbiguous);
  for (size_t i = 0; i < lut.texels.size(); ++i)
    for (int c = 0; c < 3; ++c)
      if (std::isnan(lut.texels[i][c])) lut.flags[i] |= static_cast<uint8_t>(1u << c);
  return lut;
}

}  // namespace hdrc::gpu::testing
