// libFuzzer harness: `verify --candidate-limits FILE` (load_candidate_limits: the bounded reader,
// then known_limits.json's form with the candidate engines), and the limits it returns matched
// against a case id as verify does. Seeds: fuzz/corpus/candidate_limits/ (the example's file, and
// small valid and invalid forms).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz/fuzz_files.h"
#include "runner/case_loader.h"
#include "runner/verify.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = hdrc::fuzz::write_scratch("candidate_limits.json", data, size);
  std::vector<hdrc::Error> errors;
  const std::vector<hdrc::KnownLimit> limits = hdrc::load_candidate_limits(path, &errors);
  for (const hdrc::KnownLimit& k : limits)
    (void)hdrc::matches_filter("tonemap/shaper_pq/pq_ramp_dev3", k.cases);
  for (const hdrc::Error& e : errors) (void)e.to_string();
  return 0;
}
