// libFuzzer harness: a candidate image (core/image.cpp read_image), as `verify` reads
// --candidate-dir DIR/ID.exr and a candidate command's output. Seeds: fuzz/corpus/image/ (small
// EXRs: half and float, RGB and RGBA, scanline and tiled, each compression OpenEXR offers).
//
// Images declaring more than 256x256 pixels are not decoded here: a few hundred bytes can
// declare the largest size read_image accepts (4096x4096, 0.5 GB of pixels), whose allocation alone
// takes seconds under the fuzzer's instrumentation and would stop the fuzzer at its timeout
// instead of letting it explore. Those sizes and the limits themselves are unit tests'
// (runner/fuzz_found_test.cpp); their headers are still checked here.
#include <OpenImageIO/imageio.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "core/exr_header.h"
#include "core/image.h"
#include "fuzz/fuzz_files.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = hdrc::fuzz::write_scratch("candidate.exr", data, size);
  if (hdrc::Status st = hdrc::check_exr_header(path); !st) {
    (void)st.error().to_string();
    return 0;
  }
  if (auto in = OIIO::ImageInput::open(path)) {
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.image_pixels() > 256 * 256 || spec.nchannels > 64) return 0;
  }
  auto img = hdrc::read_image(path);
  if (!img) (void)img.error().to_string();
  return 0;
}
