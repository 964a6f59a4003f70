// libFuzzer harness: an exported case's params.json as `verify`'s candidates and
// examples/vulkan_candidate read it (load_exported_case: stage, params, the images it names).
// The scratch folder holds a small valid input.exr, so that image references can resolve.
// Seeds: fuzz/corpus/params/ (params.json files of `hdrconform export`).
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/image.h"
#include "fuzz/fuzz_files.h"
#include "runner/export.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const bool input_written = [] {
    hdrc::Image img(4, 2);
    for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = 0.125 * static_cast<double>(i % 9);
    return static_cast<bool>(hdrc::write_exr(hdrc::fuzz::scratch_dir() + "/input.exr", img));
  }();
  (void)input_written;
  const std::string path = hdrc::fuzz::write_scratch("params.json", data, size);
  auto rc = hdrc::load_exported_case(path);
  if (!rc) (void)rc.error().to_string();
  return 0;
}
