// libFuzzer harness: the suite configuration loaders, each given the same text as its file:
// tolerance_overlays.json (parse_tolerance_overlays, and the overlays applied to a case),
// known_limits.json (load_known_limits) and defaults.json (load_suite_defaults: tolerance sets
// and presets). Seeds: fuzz/corpus/suite_config/ (the suite's own three files).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz/fuzz_files.h"
#include "runner/case_loader.h"
#include "runner/tolerance.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<hdrc::Error> errors;

  auto overlays = hdrc::parse_tolerance_overlays("tolerance_overlays.json", text, &errors);
  if (!overlays.empty()) {
    hdrc::Case c;
    c.id = "tonemap/display/fuzz";
    c.stage = hdrc::find_stage("tonemap");
    c.tolerance = hdrc::default_tolerance();
    auto t = hdrc::apply_overlays(c, "vulkan", "llvmpipe (LLVM 15.0.6, 256 bits)", overlays);
    if (t) (void)hdrc::tolerance_json(*t).dump();
  }

  const std::string& dir = hdrc::fuzz::scratch_dir();
  hdrc::fuzz::write_scratch("known_limits.json", data, size);
  (void)hdrc::load_known_limits(dir, &errors);
  hdrc::fuzz::write_scratch("defaults.json", data, size);
  (void)hdrc::load_suite_defaults(dir, &errors);

  for (const hdrc::Error& e : errors) (void)e.to_string();
  return 0;
}
