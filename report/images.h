// The report's pictures: SDR previews of HDR images, the error heatmap, the over-tolerance mask,
// thumbnail sizes, and the float data the case page's script reads. Mappings are documented in
// report/html_report.h and mirrored in report/assets/report.js (exposure control, pixel probe).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/case.h"
#include "core/image.h"
#include "core/result.h"
#include "runner/diff.h"

namespace hdrc::report {

// An 8-bit sRGB image, RGB, row-major.
struct Rgb8 {
  int width = 0, height = 0;
  std::vector<uint8_t> data;  // width * height * 3
  Rgb8() = default;
  Rgb8(int w, int h) : width(w), height(h), data(static_cast<size_t>(w) * h * 3, 0) {}
  uint8_t* px(int x, int y) { return &data[(static_cast<size_t>(y) * width + x) * 3]; }
};

inline constexpr std::array<uint8_t, 3> kNanColour{255, 0, 255};         // magenta
inline constexpr std::array<uint8_t, 3> kInfColour{0, 255, 255};         // cyan
inline constexpr std::array<uint8_t, 3> kMismatchColour{255, 255, 255};  // heatmap: white
inline constexpr std::array<uint8_t, 3> kOverColour{255, 0, 0};          // mask: red

// The heatmaps' scales: log10 of the error from min to max. PQ error in 10-bit code values
// (tolerances are 0.01–1 code); ΔE_ITP (≈ 1 is a just-noticeable difference, BT.2124).
struct HeatScale {
  double log10_min, log10_max;
};
inline constexpr HeatScale kHeatPq10{-4.0, 1.0};
inline constexpr HeatScale kHeatItp{-3.0, 2.0};

// sRGB OETF (IEC 61966-2-1, the piecewise curve) of a display-linear value in [0, 1].
double srgb_oetf(double linear);

// One channel value → 8-bit display code: sRGB_OETF(clamp(nits / 100 · 2^ev, 0, 1)).
uint8_t preview_code(double nits, double ev);
// The code of linear = nits / 100 · 2^ev, from a table of the 255 code boundaries; and the same
// byte computed by the formula, lround(srgb_oetf(linear) · 255), which the table reproduces for
// every double (tests).
uint8_t preview_code_linear(double linear);
uint8_t preview_code_exact(double linear);

// UE's Colorize(x) (PostProcessVisualizeHDR.usf): x = saturate(x);
// lerp(green, lerp(blue, red, x), |0.5 − x|·2): 0 blue, 0.5 green, 1 red. As 8-bit RGB.
std::array<uint8_t, 3> colorize8(double x);

// The heatmap colour of one error (0 → black, NaN → kMismatchColour) on `scale`.
std::array<uint8_t, 3> heat_colour(double error, const HeatScale& scale);

// The PQ signal difference · 1023 of two values under `enc` (runner/diff.cpp's metric).
double pq10_error(const OutputEncoding& enc, double reference, double candidate);

// SDR preview of `img` whose values are decoded to nits by `to_nits`; with `to_display`, each
// pixel's nits are first converted from the image's gamut to the display's (Rec.709/sRGB
// primaries, D65): a Rec.2020 or P3 output is shown in its true colours, not its raw triplets.
Rgb8 preview(const Image& img, const OutputEncoding& enc, bool scene_linear_input, double ev = 0,
             const ref::Mat3* to_display = nullptr);
// The same from `nits`, `img`'s values already decoded (nits_image): the report decodes each
// image once for its preview, error maps and float data.
Rgb8 preview_of_nits(const Image& img, const Image& nits, double ev = 0,
                     const ref::Mat3* to_display = nullptr);

// `img` with its finite colour values decoded to nits by `enc` (alpha and non-finite values as
// they are). With `like` and `like_nits` (the nits_image of `like` under the same encoding), a
// value bit for bit equal to `like`'s at the same place takes its nits from there: the same
// number, without decoding it again (a candidate is often bit-identical to its reference).
Image nits_image(const Image& img, const OutputEncoding& enc, const Image* like = nullptr,
                 const Image* like_nits = nullptr);

// The matrix from `enc`'s output gamut to the display (sRGB primaries): the standard BT.2020 →
// BT.709 matrix from the primaries (reference/color/ue_matrices.h: standard::rgb_to_rgb, both
// D65) · enc.to_rec2020.
ref::Mat3 output_to_display(const OutputEncoding& enc);

struct ErrorMaps {
  Rgb8 heat, heat_itp, mask;      // PQ 10-bit heatmap, ΔE_ITP heatmap, over-tolerance mask
  size_t over = 0, mismatch = 0;  // pixels over the tolerance; pixels with a non-finite mismatch
};
// Heatmaps and over-tolerance mask, per pixel with runner/diff.cpp's metrics: a pixel is over
// when any value of it exceeds the max of a judged metric (linear_abs, linear_rel, pq_code10/12
// per colour channel; ΔE_ITP per pixel), a mismatch when any channel (alpha too) pairs a
// non-finite value inconsistently. `ref_preview` is dimmed under the mask.
ErrorMaps error_maps(const Image& reference, const Image& candidate, const OutputEncoding& enc,
                     const Tolerance& tol, const Rgb8& ref_preview);
// The same with both images' nits_image under `enc` given (decoded once by the caller). Values
// bit for bit equal in both images have no error by construction: their PQ and ΔE_ITP terms are
// 0 without evaluating the curves (identical inputs give identical outputs), so the maps and the
// counts are those of the full evaluation.
ErrorMaps error_maps(const Image& reference, const Image& candidate, const Image& reference_nits,
                     const Image& candidate_nits, const OutputEncoding& enc, const Tolerance& tol,
                     const Rgb8& ref_preview);

// The over-tolerance and mismatch counts of error_maps over whole images, without their maps:
// computed in strips of rows, so that the memory is a strip's and not the images' (a 4096x4096
// pair's nits images and maps were 1.9 GB). Used where the pictures are made from sampled
// pixels (picture_size) and the counts must still be of every pixel.
ErrorMaps error_counts(const Image& reference, const Image& candidate, const OutputEncoding& enc,
                       const Tolerance& tol);

// The size of a case's pictures made here (the pages of images over 4 Mpixel, which get no float
// data): the image's own size up to kMaxPicturePixels, else scaled down, aspect kept, to at most
// that many pixels; the pictures are nearest-neighbour samples of the images (sample_nearest),
// shown stretched to the image's size. 1 Mpixel: more than the page's view shows unzoomed (at most
// 1100 CSS pixels wide), and a sixteenth of a 4096x4096 image's picture memory and PNG encoding.
inline constexpr size_t kMaxPicturePixels = size_t{1} << 20;
std::array<int, 2> picture_size(int width, int height);

// A small copy for list pages: at most `max_w` wide, height stretched into [min_h, max_h].
Rgb8 thumbnail(const Rgb8& src, int max_w, int min_h, int max_h);
// The pixels of `src` a `width` x `height` nearest-neighbour thumbnail shows (the sampling of
// thumbnail()), as an image: per-pixel pictures of it equal thumbnail() of the full pictures.
Image sample_nearest(const Image& src, int width, int height);
// The thumbnail's size, {width, height}, for an image of `width` x `height`. The list pages show
// thumbnails at this size (CSS image-rendering: pixelated, nearest neighbour as here).
std::array<int, 2> thumbnail_size(int width, int height, int max_w, int min_h, int max_h);

// Writes an 8-bit RGB PNG through OpenImageIO.
Status write_png(const std::string& path, const Rgb8& img);
// The same PNG's bytes, made in memory (for a data: URL); "" if encoding fails.
std::string png_bytes(const Rgb8& img);

// Base64 of the float32 (little-endian) values of the given channels of `img`.
std::string float32_base64(const Image& img, int channels);

// The float32 values of the given channels of `img`, packed for the case pages: byte planes (byte
// 0 of every value, then byte 1, ...; little-endian), zlib-deflated (RFC 1950, what the page's
// DecompressionStream('deflate') reads), then base64. Lossless: the probe shows the EXR's float32
// values exactly. "" if deflate fails.
std::string float32_packed_base64(const Image& img, int channels);

// Whether `bytes`, an OpenEXR file, is one the case page's script decodes itself (report.js
// decodeExr), so that the page carries the file as it is, with no decoding and repacking here:
// OpenEXR 2 single-part scan lines (no tiles, deep data or parts), compression NONE, ZIPS or ZIP,
// channels R, G, B and optionally A and nothing else, each HALF or FLOAT sampled 1 x 1, a data
// window of `width` x `height`, and an offset table whose every chunk header lies in the file, at
// the y it must have, with a size that fits. A walk of the bytes with every read bounded (OpenEXR
// file layout, openexr.com "OpenEXR File Layout"); the file was already read by OpenImageIO.
bool exr_embeddable(std::string_view bytes, int width, int height);

// Base64 (RFC 4648, with padding) of `n` bytes.
std::string base64_of(const uint8_t* bytes, size_t n);

// Whether every alpha value of `img` equals `*value` (set from the first pixel).
bool constant_alpha(const Image& img, double* value);

}  // namespace hdrc::report
