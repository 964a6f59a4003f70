// Test helpers shared by the Vulkan engine's tests (vulkan_reuse_test.cpp,
// vulkan_hygiene_test.cpp): a seeded random input image, a LUT-carrying case of a UE 5.5 stage
// resolved as the loader would, and bit-for-bit image equality.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>

#include "core/case.h"
#include "core/image.h"
#include "core/pipeline.h"
#include "reference/ue/cpp/resolve.h"

namespace hdrc::gpu::testing {

// w × h pixels, each colour channel 10^u with u uniform in [log_lo, 2] (as float32), alpha 1.
inline Image random_image(int w, int h, uint64_t seed, double log_lo) {
  Image img(w, h);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(log_lo, 2.0);
  for (size_t i = 0; i < img.pixel_count(); ++i) {
    for (int c = 0; c < 3; ++c) img.data[i * 4 + c] = static_cast<float>(std::pow(10.0, u(rng)));
    img.data[i * 4 + 3] = 1.0;
  }
  return img;
}

// A case of `stage` with HDR on, output device `device` and a LUT of edge `size` in `format` and
// `layout`; a combine_luts case gets its N² × N output image as input.
inline ResolvedCase lut_stage_case(const char* id, const char* stage, int device, int size,
                                   int format, int layout, Image input) {
  ResolvedCase rc;
  rc.spec.id = id;
  rc.spec.stage = find_stage(stage);
  rc.spec.cvars.set("r.HDR.EnableHDROutput", 1);
  rc.spec.cvars.set("r.HDR.Display.OutputDevice", device);
  rc.spec.cvars.set("r.LUT.Size", size);
  rc.spec.settings.set("LUTFormat", {static_cast<double>(format), 0, 0, 0}, 1);
  rc.spec.settings.set("LUTLayout", {static_cast<double>(layout), 0, 0, 0}, 1);
  if (std::string(stage) == "combine_luts") input = Image(size * size, size);
  rc.params = *ref::resolve_params(rc.spec, input.width, input.height);
  rc.input = std::move(input);
  return rc;
}

// Bit for bit (a NaN equals the same NaN).
inline bool same_bits(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height &&
         std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(double)) == 0;
}

}  // namespace hdrc::gpu::testing
