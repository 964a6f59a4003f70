// libFuzzer harness: one case file (cases/**/*.json) through the case loader, with the suite's
// own defaults (named tolerance sets and presets), then the resolution of every small case it
// expands to (cvars to parameters, stimuli). Seeds: fuzz/corpus/case_file/ (the suite's case
// files).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "runner/case_loader.h"

namespace {

const hdrc::SuiteDefaults& defaults() {
  static const hdrc::SuiteDefaults d = [] {
    std::vector<hdrc::Error> errors;
    return hdrc::load_suite_defaults(HDRC_SOURCE_CASES_DIR, &errors);
  }();
  return d;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<hdrc::Error> errors;
  auto cases = hdrc::parse_case_file(std::string(HDRC_SOURCE_CASES_DIR) + "/fuzz/case.json", text,
                                     HDRC_SOURCE_CASES_DIR, "fuzz/case", defaults(), &errors);
  for (const hdrc::Error& e : errors) (void)e.to_string();
  // Resolving builds the stimulus: only small ones, so that an iteration stays fast (the size
  // limits themselves are the loader's job, checked by its tests).
  size_t resolved = 0;
  for (const hdrc::Case& c : cases) {
    long long px = 0;
    for (const hdrc::InputSpec* in : {&c.input, &c.bloom, &c.bloom_dirt})
      px = std::max(px, static_cast<long long>(in->width) * in->height);
    if (px > 64 * 64 || ++resolved > 8) continue;
    auto r = hdrc::resolve_case(c);
    if (!r) (void)r.error().to_string();
  }
  return 0;
}
