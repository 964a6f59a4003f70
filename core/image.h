// An RGBA image of doubles, row-major, (0,0) top-left. Every engine hands its output over as this
// type: the reference computes in double, the GPU engine's float32 results are widened exactly.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"

namespace hdrc {

// A reference pixel whose value float32 cannot decide: a channel within float32 noise of zero
// reached a function that is steep or undefined there (PQ and pow of a negative are NaN; pow(x,
// 1/10) turns 1e-7 into 0.2), so a correct float32 evaluation may give any value in [lo, hi] per
// channel, or NaN where the channel's bit is set in nan_ok. The diff judges the candidate against
// the nearest admissible value (docs/diff-metrics.md, "Admissible ranges").
//
// kFloat32Noise: the float32 noise bound of a value relative to the largest |channel| of its
// pixel: 2^-20, 16 float32 ulps (2^-24). A channel within it of zero has no reliable sign.
inline constexpr double kFloat32Noise = 1.0 / 1048576.0;
struct AdmissibleRange {
  size_t pixel = 0;  // y * width + x
  std::array<double, 4> lo{}, hi{};
  uint8_t nan_ok = 0;  // bit ch: NaN is admissible in channel ch
};

struct Image {
  int width = 0;
  int height = 0;
  static constexpr int kChannels = 4;  // RGBA
  std::vector<double> data;            // width * height * 4
  // Named numbers a stage outputs besides pixels (e.g. the values VisualizeHDR prints as text),
  // recorded in results.json so a port can be checked without pixel-exact text.
  std::map<std::string, double> values;
  // Reference images only: the pixels with an admissible range, in increasing pixel order (empty
  // for almost every image). Not written to image files.
  std::vector<AdmissibleRange> admissible;
  // Reference images only, where the case asked for device allowances (ResolvedCase::device):
  // the ranges a conformant Vulkan device with those precision properties may produce
  // (docs/precision.md, "Device allowances"), each a superset of the pixel's tight range; and the
  // names of the allowance classes they take in. A candidate outside `admissible` but inside
  // these passes with a named device allowance. Empty for almost every stage. Not written to
  // image files.
  std::vector<AdmissibleRange> device_admissible;
  std::vector<std::string> device_allowances;

  Image() = default;
  Image(int w, int h) : width(w), height(h), data(static_cast<size_t>(w) * h * kChannels, 0.0) {}
  size_t pixel_count() const { return static_cast<size_t>(width) * height; }
  double* px(int x, int y) { return &data[(static_cast<size_t>(y) * width + x) * kChannels]; }
  const double* px(int x, int y) const {
    return &data[(static_cast<size_t>(y) * width + x) * kChannels];
  }
};

// The largest image file read (inputs, candidates, goldens) or stimulus made (4096 x 4096): one
// Image of doubles is then 512 MiB. Checked before any pixel is allocated or decoded. A case is
// limited further by its memory and time budget (runner/budget.h: about 2048 x 2048).
inline constexpr size_t kMaxImagePixels = size_t{4096} * 4096;
// The largest image file read (a 4096x4096 RGBA float EXR, uncompressed, plus headers).
inline constexpr size_t kMaxImageFileBytes = kMaxImagePixels * 4 * 4 + (size_t{16} << 20);

// Reads an image file (EXR or anything OpenImageIO reads). Only a regular file of at most
// kMaxImageFileBytes is opened; a file named *.exr must be an OpenEXR file; the header's size is
// checked against kMaxImagePixels before decoding; the channels must be named R, G, B and
// optionally A (in that order; a missing alpha is filled with 1). Errors name the file.
Result<Image> read_image(const std::string& path);

// Writes a 32-bit float EXR (ZIP compression, lossless) atomically: a temporary file beside the
// target is written first and renamed over it, so a failed write never leaves a half-written file.
// `zip_level`: zlib's level 1-9; -1 OpenEXR's default (4). A run's case images use 1: 20 % less
// encoding CPU for 3 % more bytes (1622 images of a 565-case run: 0.75 vs 0.94 s, 30.7 vs 29.7 MB).
Status write_exr(const std::string& path, const Image& image, int zip_level = -1);

// Images a run wrote, kept in memory for the report it builds at its end, so that the report does
// not read and decode again what the run has just encoded (decoding was a quarter of the report's
// CPU). Process-wide and thread-safe; values are kept as float32, exactly what the EXR holds, so
// an image taken from here is the one read_image would return. Bounded: an image that would take
// the total over the capacity is not kept (the report then reads the file). The capacity is 0
// (nothing kept) until a run sets it. Paths are compared lexically normalised.
namespace written_images {
void set_capacity(size_t bytes);
// After `path` was written with `image`'s values.
void keep(const std::string& path, const Image& image);
// The image kept for `path`, removed from memory; nullopt if none.
std::optional<Image> take(const std::string& path);
// Drops what is kept for `path` (its file was deleted), or everything.
void forget(const std::string& path);
void clear();
size_t bytes_kept();
}  // namespace written_images

}  // namespace hdrc
