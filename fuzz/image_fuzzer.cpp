// libFuzzer harness: a candidate image (core/image.cpp read_image), as `verify` reads
// --candidate-dir DIR/ID.exr and a candidate command's output. Seeds: fuzz/corpus/image/ (small
// EXRs: half and float, RGB and RGBA, scanline and tiled, each compression OpenEXR offers).
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/image.h"
#include "fuzz/fuzz_files.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = hdrc::fuzz::write_scratch("candidate.exr", data, size);
  auto img = hdrc::read_image(path);
  if (!img) (void)img.error().to_string();
  return 0;
}
