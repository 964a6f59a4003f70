#include "report/images.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "color/st2084.h"
#include "reference/color/ue_matrices.h"

namespace hdrc::report {

double srgb_oetf(double x) {
  // IEC 61966-2-1:1999 §5.2 (encoding): 12.92·L below 0.0031308, 1.055·L^(1/2.4) − 0.055 above.
  if (!(x > 0)) return 0.0;
  if (x >= 1) return 1.0;
  return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

uint8_t preview_code_exact(double linear) {
  return static_cast<uint8_t>(std::lround(srgb_oetf(linear) * 255.0));
}

namespace {

// kThresholds[k - 1] is the smallest double whose preview_code_exact is at least k (k = 1..255).
// The code is nondecreasing in the value (srgb_oetf is monotonic and lround too), so the code of
// x is the count of thresholds <= x: one binary search instead of a pow per channel, the same
// byte for every value (report_test.cpp, PreviewCodeTableAgreesWithTheFormula). The search starts
// at the formula's inverse of (k - 0.5) / 255 and steps by one ulp to the exact boundary.
struct PreviewThresholds {
  std::array<double, 255> t{};
  PreviewThresholds() {
    for (int k = 1; k <= 255; ++k) {
      const double v = (k - 0.5) / 255.0;
      double x = v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
      // Bounded: the inverse lands within a few ulps of the boundary.
      for (int i = 0; i < 1000 && preview_code_exact(x) >= k; ++i) x = std::nextafter(x, -1.0);
      for (int i = 0; i < 1000 && preview_code_exact(x) < k; ++i) x = std::nextafter(x, 2.0);
      t[static_cast<size_t>(k - 1)] = x;
    }
  }
};

}  // namespace

uint8_t preview_code(double nits, double ev) {
  return preview_code_linear(nits / 100.0 * std::exp2(ev));
}

uint8_t preview_code_linear(double linear) {
  static const PreviewThresholds table;
  if (std::isnan(linear)) return 0;  // srgb_oetf(NaN) = 0
  return static_cast<uint8_t>(std::upper_bound(table.t.begin(), table.t.end(), linear,
                                               [](double a, double b) { return a < b; }) -
                              table.t.begin());
}

std::array<uint8_t, 3> colorize8(double x) {
  // PostProcessVisualizeHDR.usf: Colorize(x). saturate(NaN) = 0 on D3D, so NaN gives blue.
  x = std::isnan(x) ? 0.0 : std::clamp(x, 0.0, 1.0);
  const double t = std::fabs(0.5 - x) * 2.0;  // lerp(green, lerp(blue, red, x), t)
  const double c[3] = {(1 - t) * 0 + t * x, (1 - t) * 1 + t * 0, (1 - t) * 0 + t * (1 - x)};
  return {static_cast<uint8_t>(std::lround(c[0] * 255)),
          static_cast<uint8_t>(std::lround(c[1] * 255)),
          static_cast<uint8_t>(std::lround(c[2] * 255))};
}

std::array<uint8_t, 3> heat_colour(double error, const HeatScale& scale) {
  if (std::isnan(error)) return kMismatchColour;
  if (error <= 0) return {0, 0, 0};
  return colorize8((std::log10(error) - scale.log10_min) / (scale.log10_max - scale.log10_min));
}

namespace {
// runner/diff.cpp's pq_signal: negative and NaN luminance read as 0 nits, capped at 10 000.
double pq_signal(double nits) {
  if (!(nits > 0)) return ref::st2084::pq_from_nits(0.0);
  return ref::st2084::pq_from_nits(std::fmin(nits, ref::st2084::kPeakNits));
}
bool consistent_nonfinite(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return a == b;
}
}  // namespace

double pq10_error(const OutputEncoding& enc, double reference, double candidate) {
  return std::fabs(pq_signal(enc.to_nits(candidate)) - pq_signal(enc.to_nits(reference))) * 1023.0;
}

ref::Mat3 output_to_display(const OutputEncoding& enc) {
  static const ref::Mat3 k2020To709 =
      ref::standard::rgb_to_rgb(ref::standard::kRec2020, ref::standard::kSrgb);
  return k2020To709 * enc.to_rec2020;
}

namespace {
bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// f(x) remembered by the bits of x in a direct-mapped table (4096 slots): exact, since f is a
// pure function of those bits, and cheap where it counts: a test image's values repeat (rows of a
// ramp, flat fields, the same stimulus; 67 % of a 565-case run's reference values and 95 % of its
// input values hit), where f costs two pow (the PQ curves).
template <class F>
class Memo {
 public:
  explicit Memo(F f) : f_(std::move(f)), keys_(kSlots), values_(kSlots) {
    // Every slot starts as a valid entry: f(0).
    std::fill(keys_.begin(), keys_.end(), bits(0.0));
    std::fill(values_.begin(), values_.end(), f_(0.0));
  }
  double operator()(double x) {
    const uint64_t k = bits(x);
    const size_t slot = static_cast<size_t>((k * 0x9E3779B97F4A7C15ull) >> (64 - kBitsOfSlots));
    if (keys_[slot] != k) {
      keys_[slot] = k;
      values_[slot] = f_(x);
    }
    return values_[slot];
  }

 private:
  static constexpr int kBitsOfSlots = 12;
  static constexpr size_t kSlots = size_t{1} << kBitsOfSlots;
  static uint64_t bits(double x) {
    uint64_t u;
    std::memcpy(&u, &x, sizeof u);
    return u;
  }
  F f_;
  std::vector<uint64_t> keys_;
  std::vector<double> values_;
};
}  // namespace

Image nits_image(const Image& img, const OutputEncoding& enc, const Image* like,
                 const Image* like_nits) {
  Image out = img;
  const bool reuse = like && like_nits && like->width == img.width && like->height == img.height &&
                     like_nits->width == img.width && like_nits->height == img.height;
  Memo to_nits([&enc](double v) { return enc.to_nits(v); });
  for (size_t i = 0; i < img.pixel_count(); ++i)
    for (int c = 0; c < 3; ++c) {
      const size_t k = i * Image::kChannels + c;
      double& v = out.data[k];
      if (!std::isfinite(v)) continue;
      v = reuse && same_bits(v, like->data[k]) ? like_nits->data[k] : to_nits(v);
    }
  return out;
}

Rgb8 preview(const Image& img, const OutputEncoding& enc, bool scene_linear_input, double ev,
             const ref::Mat3* to_display) {
  if (!scene_linear_input) return preview_of_nits(img, nits_image(img, enc), ev, to_display);
  Image nits = img;
  for (size_t i = 0; i < img.pixel_count(); ++i)
    for (int c = 0; c < 3; ++c) nits.data[i * Image::kChannels + c] *= 100.0;
  return preview_of_nits(img, nits, ev, to_display);
}

Rgb8 preview_of_nits(const Image& img, const Image& nits_img, double ev,
                     const ref::Mat3* to_display) {
  Rgb8 out(img.width, img.height);
  // preview_code(n, ev) is preview_code_linear(n / 100 · 2^ev): the same product, 2^ev once.
  const double gain = std::exp2(ev);
  Memo code([](double linear) { return static_cast<double>(preview_code_linear(linear)); });
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const double* p = img.px(x, y);
      uint8_t* o = out.px(x, y);
      bool nan = false, inf = false;
      for (int c = 0; c < 3; ++c) {
        nan |= std::isnan(p[c]);
        inf |= std::isinf(p[c]);
      }
      if (nan || inf) {
        std::memcpy(o, nan ? kNanColour.data() : kInfColour.data(), 3);
        continue;
      }
      const double* q = nits_img.px(x, y);
      ref::Vec3 nits{q[0], q[1], q[2]};
      if (to_display) nits = *to_display * nits;
      for (int c = 0; c < 3; ++c) o[c] = static_cast<uint8_t>(code(nits[c] / 100.0 * gain));
    }
  return out;
}

ErrorMaps error_maps(const Image& reference, const Image& candidate, const OutputEncoding& enc,
                     const Tolerance& tol, const Rgb8& ref_preview) {
  if (candidate.width != reference.width || candidate.height != reference.height)
    return error_maps(reference, candidate, reference, candidate, enc, tol, ref_preview);
  const Image rn = nits_image(reference, enc);
  return error_maps(reference, candidate, rn, nits_image(candidate, enc, &reference, &rn), enc, tol,
                    ref_preview);
}

ErrorMaps error_maps(const Image& reference, const Image& candidate, const Image& reference_nits,
                     const Image& candidate_nits, const OutputEncoding& enc, const Tolerance& tol,
                     const Rgb8& ref_preview) {
  ErrorMaps m;
  m.heat = Rgb8(reference.width, reference.height);
  m.heat_itp = Rgb8(reference.width, reference.height);
  m.mask = Rgb8(reference.width, reference.height);
  if (candidate.width != reference.width || candidate.height != reference.height) return m;
  auto over_max = [&](Metric metric, double v) { return !(v <= tol.max(metric)); };
  Memo pq(pq_signal);  // for the colour channels and, in ΔE_ITP, the LMS components
  for (int y = 0; y < reference.height; ++y)
    for (int x = 0; x < reference.width; ++x) {
      const double* r = reference.px(x, y);
      const double* c = candidate.px(x, y);
      const double* rnp = reference_nits.px(x, y);
      const double* cnp = candidate_nits.px(x, y);
      double worst = 0, itp = 0;
      bool mismatch = false, over = false, rgb_finite = true, rgb_same = true;
      ref::Vec3 rn{0, 0, 0}, cn{0, 0, 0};
      for (int ch = 0; ch < 4; ++ch) {
        const bool rf = std::isfinite(r[ch]), cf = std::isfinite(c[ch]);
        if (!rf || !cf) {
          mismatch |= !(!rf && !cf && consistent_nonfinite(r[ch], c[ch]));
          rgb_finite &= ch == 3;
          continue;
        }
        if (ch == 3) continue;  // alpha: judged for non-finite consistency only (diff.cpp)
        rn[ch] = rnp[ch];       // enc.to_nits(r[ch]), decoded once (nits_image)
        cn[ch] = cnp[ch];
        const bool same = same_bits(r[ch], c[ch]);
        rgb_same &= same;
        const double abs = std::fabs(c[ch] - r[ch]);
        const double rel = abs == 0 ? 0.0 : abs / std::fmax(std::fabs(r[ch]), tol.rel_floor);
        // Equal values: |pq_signal(n) - pq_signal(n)| = 0 exactly.
        const double d = same ? 0.0 : std::fabs(pq(cn[ch]) - pq(rn[ch]));
        worst = std::fmax(worst, d * 1023.0);
        over |= over_max(Metric::kLinearAbs, abs) || over_max(Metric::kLinearRel, rel) ||
                over_max(Metric::kPqCode10, d * 1023.0) || over_max(Metric::kPqCode12, d * 4095.0);
      }
      if (rgb_finite) {
        // Equal colours: ΔE_ITP of a colour with itself, 0 exactly (ictcp_from_rec2020_nits is
        // finite for any input: pq_signal maps NaN and negatives to black, caps at 10 000 nits).
        itp = rgb_same ? 0.0
                       : delta_e_itp(ictcp_from_rec2020_nits_with(enc.to_rec2020 * cn, pq),
                                     ictcp_from_rec2020_nits_with(enc.to_rec2020 * rn, pq));
        over |= over_max(Metric::kDeltaEItp, itp);
      }
      const double nan = std::nan("");
      std::memcpy(m.heat.px(x, y), heat_colour(mismatch ? nan : worst, kHeatPq10).data(), 3);
      std::memcpy(m.heat_itp.px(x, y), heat_colour(mismatch ? nan : itp, kHeatItp).data(), 3);
      uint8_t* o = m.mask.px(x, y);
      if (mismatch) {
        std::memcpy(o, kNanColour.data(), 3);
        ++m.mismatch;
      } else if (over) {
        std::memcpy(o, kOverColour.data(), 3);
        ++m.over;
      } else {
        // Within tolerance: the reference's preview as dim grey, for orientation.
        const uint8_t* p = &ref_preview.data[(static_cast<size_t>(y) * reference.width + x) * 3];
        const uint8_t g = static_cast<uint8_t>((p[0] * 3 + p[1] * 6 + p[2]) / 40);
        o[0] = o[1] = o[2] = g;
      }
    }
  return m;
}

std::array<int, 2> thumbnail_size(int width, int height, int max_w, int min_h, int max_h) {
  const int w = std::max(1, std::min(width, max_w));
  const double scale = static_cast<double>(w) / std::max(1, width);
  return {w, std::clamp(static_cast<int>(std::lround(height * scale)), min_h, max_h)};
}

namespace {

// The source column (row) of thumbnail column (row) `x` of `w`, from a source of `n`.
int nearest_source(int x, int w, int n) {
  return std::min(n - 1, static_cast<int>((x + 0.5) * n / w));
}

}  // namespace

Rgb8 thumbnail(const Rgb8& src, int max_w, int min_h, int max_h) {
  const auto [w, h] = thumbnail_size(src.width, src.height, max_w, min_h, max_h);
  if (w == src.width && h == src.height) return src;
  Rgb8 out(w, h);
  // Nearest neighbour: thumbnails of ramps and LUTs keep their hard edges.
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int sx = nearest_source(x, w, src.width), sy = nearest_source(y, h, src.height);
      std::memcpy(out.px(x, y), &src.data[(static_cast<size_t>(sy) * src.width + sx) * 3], 3);
    }
  return out;
}

ErrorMaps error_counts(const Image& reference, const Image& candidate, const OutputEncoding& enc,
                       const Tolerance& tol) {
  ErrorMaps total;
  if (candidate.width != reference.width || candidate.height != reference.height) return total;
  // 64 rows: a 4096-wide strip pair and its nits are 34 MB.
  constexpr int kStripRows = 64;
  for (int y0 = 0; y0 < reference.height; y0 += kStripRows) {
    const int rows = std::min(kStripRows, reference.height - y0);
    Image r(reference.width, rows), c(reference.width, rows);
    const size_t from = static_cast<size_t>(y0) * reference.width * Image::kChannels;
    const size_t n = r.data.size();
    std::copy_n(reference.data.begin() + static_cast<std::ptrdiff_t>(from), n, r.data.begin());
    std::copy_n(candidate.data.begin() + static_cast<std::ptrdiff_t>(from), n, c.data.begin());
    const ErrorMaps m = error_maps(r, c, enc, tol, Rgb8(reference.width, rows));
    total.over += m.over;
    total.mismatch += m.mismatch;
  }
  return total;
}

std::array<int, 2> picture_size(int width, int height) {
  const double pixels = static_cast<double>(width) * height;
  if (pixels <= static_cast<double>(kMaxPicturePixels)) return {width, height};
  const double scale = std::sqrt(static_cast<double>(kMaxPicturePixels) / pixels);
  return {std::max(1, static_cast<int>(width * scale)),
          std::max(1, static_cast<int>(height * scale))};
}

Image sample_nearest(const Image& src, int width, int height) {
  Image out(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double* p =
          src.px(nearest_source(x, width, src.width), nearest_source(y, height, src.height));
      std::copy(p, p + Image::kChannels, out.px(x, y));
    }
  return out;
}

namespace {

// The report's PNG settings, for files and in-memory PNGs alike.
OIIO::ImageSpec png_spec(const Rgb8& img) {
  OIIO::ImageSpec spec(img.width, img.height, 3, OIIO::TypeDesc::UINT8);
  // zlib level 3 and libpng's SUB filter alone (PNG_FILTER_SUB, 0x10) instead of level 6 with
  // the adaptive choice among all five filters per row: on the report's PNGs (4316 of a 565-case
  // run) 2.3x less encoding CPU for 15 % more bytes (7.0 vs 6.1 MB; the report is ~76 MB, mostly
  // float data). Level 1 alone measured 0.47 vs 0.79 s for 7.0 MB, SUB at level 3 0.36 s.
  spec.attribute("png:compressionLevel", 3);
  spec.attribute("png:filter", 0x10);
  return spec;
}

}  // namespace

Status write_png(const std::string& path, const Rgb8& img) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out) return Error{path, "", "cannot create a PNG writer: " + OIIO::geterror(), ""};
  const OIIO::ImageSpec spec = png_spec(img);
  if (!out->open(path, spec)) return Error{path, "", "cannot open: " + out->geterror(), ""};
  const bool ok = out->write_image(OIIO::TypeDesc::UINT8, img.data.data());
  const bool closed = out->close();
  if (!ok || !closed) return Error{path, "", "cannot write: " + out->geterror(), ""};
  return {};
}

std::string png_bytes(const Rgb8& img) {
  std::vector<unsigned char> buf;
  OIIO::Filesystem::IOVecOutput vec(buf);
  auto out = OIIO::ImageOutput::create("png");
  if (!out || !out->set_ioproxy(&vec)) return {};
  if (!out->open("memory.png", png_spec(img))) return {};
  const bool ok = out->write_image(OIIO::TypeDesc::UINT8, img.data.data());
  if (!out->close() || !ok) return {};
  return std::string(buf.begin(), buf.end());
}

std::string base64_of(const uint8_t* bytes, size_t n) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((n + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < n; i += 3) {
    const uint32_t v = (bytes[i] << 16) | (bytes[i + 1] << 8) | bytes[i + 2];
    for (int s : {18, 12, 6, 0}) out += kAlphabet[(v >> s) & 63];
  }
  if (i < n) {
    const uint32_t v = (bytes[i] << 16) | (i + 1 < n ? bytes[i + 1] << 8 : 0);
    out += kAlphabet[v >> 18];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < n ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string float32_base64(const Image& img, int channels) {
  std::vector<uint8_t> bytes;
  bytes.reserve(img.pixel_count() * channels * 4);
  for (size_t i = 0; i < img.pixel_count(); ++i)
    for (int c = 0; c < channels; ++c) {
      const float f = static_cast<float>(img.data[i * Image::kChannels + c]);
      uint32_t u;
      std::memcpy(&u, &f, 4);
      for (int b = 0; b < 4; ++b) bytes.push_back(static_cast<uint8_t>(u >> (8 * b)));  // LE
    }
  return base64_of(bytes.data(), bytes.size());
}

bool constant_alpha(const Image& img, double* value) {
  if (img.pixel_count() == 0) return false;
  const double a = img.data[3];
  for (size_t i = 0; i < img.pixel_count(); ++i) {
    const double v = img.data[i * Image::kChannels + 3];
    if (!(v == a)) return false;  // NaN alpha is never constant
  }
  *value = a;
  return true;
}

std::string float32_packed_base64(const Image& img, int channels) {
  const size_t count = img.pixel_count() * static_cast<size_t>(channels);
  // Byte planes: byte b of every value together (exponents and high mantissa bytes of smooth
  // images repeat, which deflate finds).
  std::vector<uint8_t> planes(count * 4);
  size_t j = 0;
  for (size_t i = 0; i < img.pixel_count(); ++i)
    for (int c = 0; c < channels; ++c, ++j) {
      const float f = static_cast<float>(img.data[i * Image::kChannels + c]);
      uint32_t u;
      std::memcpy(&u, &f, 4);
      for (int b = 0; b < 4; ++b) planes[b * count + j] = static_cast<uint8_t>(u >> (8 * b));
    }
  uLongf size = compressBound(static_cast<uLong>(planes.size()));
  std::vector<uint8_t> z(size);
  // Level 1: within a few % of level 6's size on these planes, several times faster (the report
  // is built at the end of every run).
  if (compress2(z.data(), &size, planes.data(), static_cast<uLong>(planes.size()), 1) != Z_OK)
    return "";
  return base64_of(z.data(), size);
}

namespace {

// A bounded little-endian reader over a byte string: every read checks the end first.
struct ByteReader {
  std::string_view b;
  size_t at = 0;
  bool ok = true;
  bool need(size_t n) {
    if (!ok || n > b.size() - at) ok = false;
    return ok;
  }
  uint64_t le(size_t n) {
    if (!need(n)) return 0;
    uint64_t v = 0;
    for (size_t i = 0; i < n; ++i)
      v |= static_cast<uint64_t>(static_cast<uint8_t>(b[at + i])) << (8 * i);
    at += n;
    return v;
  }
  int32_t i32() { return static_cast<int32_t>(static_cast<uint32_t>(le(4))); }
  // A NUL-terminated string of at most 255 bytes (OpenEXR's long-name limit).
  std::string_view cstr() {
    if (!ok) return {};
    const size_t end = b.find('\0', at);
    if (end == std::string_view::npos || end - at > 255) {
      ok = false;
      return {};
    }
    std::string_view s = b.substr(at, end - at);
    at = end + 1;
    return s;
  }
};

}  // namespace

bool exr_embeddable(std::string_view bytes, int width, int height) {
  if (width <= 0 || height <= 0) return false;
  ByteReader r{bytes};
  if (r.le(4) != 20000630) return false;  // the magic number 76 2f 31 01
  const uint64_t version = r.le(4);
  // Version 2; flags: 0x200 tiled, 0x800 deep ("non-image"), 0x1000 multi-part. 0x400 (long
  // names) changes nothing a scan-line reader does.
  if ((version & 0xFF) != 2 || (version & (0x200 | 0x800 | 0x1000)) != 0) return false;
  int compression = -1, line_order = 0;
  bool have_window = false;
  int32_t y_min = 0, x_min = 0, x_max = -1, y_max = -1;
  size_t bytes_per_pixel = 0;
  bool rgb[3] = {false, false, false};
  for (int attrs = 0; attrs < 1000; ++attrs) {  // bounded: a real header has a few dozen
    const std::string_view name = r.cstr();
    if (!r.ok) return false;
    if (name.empty()) break;
    const std::string_view type = r.cstr();
    const int32_t size = r.i32();
    if (!r.ok || size < 0 || !r.need(static_cast<size_t>(size))) return false;
    ByteReader v{bytes.substr(r.at, static_cast<size_t>(size))};
    r.at += static_cast<size_t>(size);
    if (name == "channels") {
      if (type != "chlist") return false;
      for (int ch = 0; ch < 16; ++ch) {
        const std::string_view cn = v.cstr();
        if (!v.ok) return false;
        if (cn.empty()) break;
        const int32_t pixel_type = v.i32();
        v.le(4);  // pLinear and 3 reserved bytes
        const int32_t xs = v.i32(), ys = v.i32();
        if (!v.ok || xs != 1 || ys != 1 || (pixel_type != 1 && pixel_type != 2)) return false;
        if (cn == "R")
          rgb[0] = true;
        else if (cn == "G")
          rgb[1] = true;
        else if (cn == "B")
          rgb[2] = true;
        else if (cn != "A")
          return false;
        bytes_per_pixel += pixel_type == 1 ? 2 : 4;
      }
      if (v.at != v.b.size()) return false;  // more than R, G, B, A (or a repeated name)
    } else if (name == "compression") {
      if (type != "compression" || size != 1) return false;
      compression = static_cast<int>(v.le(1));
    } else if (name == "dataWindow") {
      if (type != "box2i" || size != 16) return false;
      x_min = v.i32(), y_min = v.i32(), x_max = v.i32(), y_max = v.i32();
      have_window = true;
    } else if (name == "lineOrder") {
      if (type != "lineOrder" || size != 1) return false;
      line_order = static_cast<int>(v.le(1));
    } else if (name == "tiles" || name == "type" || name == "chunkCount") {
      return false;  // tiles, or a typed part: not what a single-part scan-line file has
    }
  }
  // Channel names are unique in a valid file; R, G, B present and at most 16 bytes a pixel.
  if (!rgb[0] || !rgb[1] || !rgb[2] || bytes_per_pixel > 16) return false;
  if (!have_window || static_cast<int64_t>(x_max) - x_min + 1 != width ||
      static_cast<int64_t>(y_max) - y_min + 1 != height)
    return false;
  if (line_order > 1) return false;  // RANDOM_Y: chunks in any order; not written by us
  int lines;                         // scan lines per chunk
  switch (compression) {
    case 0:
    case 2:
      lines = 1;
      break;  // NONE, ZIPS
    case 3:
      lines = 16;
      break;  // ZIP
    default:
      return false;
  }
  const int64_t chunks = (static_cast<int64_t>(height) + lines - 1) / lines;
  const size_t line_bytes = static_cast<size_t>(width) * bytes_per_pixel;
  const size_t table = r.at;
  if (!r.need(static_cast<size_t>(chunks) * 8)) return false;
  for (int64_t k = 0; k < chunks; ++k) {
    ByteReader t{bytes, table + static_cast<size_t>(k) * 8};
    const uint64_t offset = t.le(8);
    if (offset > bytes.size()) return false;
    ByteReader c{bytes, static_cast<size_t>(offset)};
    const int32_t y = c.i32(), size = c.i32();
    if (!c.ok || size <= 0 || !c.need(static_cast<size_t>(size))) return false;
    // Chunk k holds rows y_min + k·lines onwards; in bytes at most lines · line_bytes (stored
    // data is exactly that; compressed data is smaller, or OpenEXR stores it raw).
    if (static_cast<int64_t>(y) != y_min + k * lines) return false;
    const int64_t rows = std::min<int64_t>(lines, static_cast<int64_t>(y_max) - y + 1);
    const uint64_t raw = static_cast<uint64_t>(rows) * line_bytes;
    if (static_cast<uint64_t>(size) > raw ||
        (compression == 0 && static_cast<uint64_t>(size) != raw))
      return false;
  }
  return true;
}

}  // namespace hdrc::report
