// An RGBA image of doubles, row-major, (0,0) top-left. Every engine hands its output over as this
// type: the reference computes in double, the GPU engine's float32 results are widened exactly.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "core/result.h"

namespace hdrc {

struct Image {
  int width = 0;
  int height = 0;
  static constexpr int kChannels = 4;  // RGBA
  std::vector<double> data;            // width * height * 4
  // Named numbers a stage outputs besides pixels (e.g. the values VisualizeHDR prints as text),
  // recorded in results.json so a port can be checked without pixel-exact text.
  std::map<std::string, double> values;

  Image() = default;
  Image(int w, int h) : width(w), height(h), data(static_cast<size_t>(w) * h * kChannels, 0.0) {}
  size_t pixel_count() const { return static_cast<size_t>(width) * height; }
  double* px(int x, int y) { return &data[(static_cast<size_t>(y) * width + x) * kChannels]; }
  const double* px(int x, int y) const {
    return &data[(static_cast<size_t>(y) * width + x) * kChannels];
  }
};

// Reads an image file (EXR or anything OpenImageIO reads). Fewer than 4 channels: missing colour
// channels are an error, missing alpha is filled with 1.
Result<Image> read_image(const std::string& path);

// Writes a 32-bit float EXR (ZIP compression) atomically: a temporary file beside the target is
// written first and renamed over it, so a failed write never leaves a half-written file.
Status write_exr(const std::string& path, const Image& image);

}  // namespace hdrc
