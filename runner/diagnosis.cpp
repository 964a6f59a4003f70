#include "runner/diagnosis.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <set>

#include "color/gamma_correction.h"
#include "color/st2084.h"
#include "report/assets.h"
#include "runner/json_read.h"

namespace hdrc {

namespace {

std::string fmt3(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

std::string percent(double share) {
  return fmt3(100.0 * share) + " %";
}

// Every `stride`-th pixel of an image of `n` pixels, so that at most kDiagnosisMaxPixels are
// visited.
size_t stride_of(size_t n) {
  return n <= kDiagnosisMaxPixels ? 1 : (n + kDiagnosisMaxPixels - 1) / kDiagnosisMaxPixels;
}

bool finite3(const double* p) {
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

// Calls f(r, c) with the reference's and candidate's RGB of each sampled pixel (stride_of) where
// both are finite; returns how many pixels that was.
template <class F>
size_t for_each_finite_sample(const Image& ref, const Image& cand, F&& f) {
  size_t pixels = 0;
  const size_t n = ref.pixel_count(), step = stride_of(n);
  for (size_t i = 0; i < n; i += step) {
    const double* r = &ref.data[i * Image::kChannels];
    const double* c = &cand.data[i * Image::kChannels];
    if (!finite3(r) || !finite3(c)) continue;
    ++pixels;
    f(r, c);
  }
  return pixels;
}

// The squared error of the candidate against the reference (straight) and against a variant of
// the reference, over the RGB values finite in all three, and how far the variant is from the
// reference.
struct Fit {
  double straight = 0, residual = 0, variant_vs_reference = 0;
  size_t pixels = 0;
};

template <class Variant>
Fit fit_variant(const Image& ref, const Image& cand, Variant&& variant) {
  Fit f;
  const size_t n = ref.pixel_count(), step = stride_of(n);
  for (size_t i = 0; i < n; i += step) {
    const double* r = &ref.data[i * Image::kChannels];
    const double* c = &cand.data[i * Image::kChannels];
    if (!finite3(r) || !finite3(c)) continue;
    double v[3];
    variant(i, r, v);
    if (!finite3(v)) continue;
    ++f.pixels;
    for (int ch = 0; ch < 3; ++ch) {
      f.straight += (c[ch] - r[ch]) * (c[ch] - r[ch]);
      f.residual += (c[ch] - v[ch]) * (c[ch] - v[ch]);
      f.variant_vs_reference += (v[ch] - r[ch]) * (v[ch] - r[ch]);
    }
  }
  return f;
}

// A variant explains the error when it differs from the reference, the candidate differs from the
// reference, and what is left of the squared error is at most `share` of it.
bool explains(const Fit& f, double share) {
  return f.pixels > 0 && f.straight > 0 && f.variant_vs_reference > 0 &&
         f.residual <= share * f.straight;
}

std::string residual_evidence(const Fit& f) {
  return "the variant leaves " + percent(f.residual / f.straight) + " of the squared error, over " +
         std::to_string(f.pixels) + " pixels";
}

using Detector = bool (*)(const Signature&, const DiagnosisInput&, std::string* evidence);

// ---- the detectors ------------------------------------------------------------------------------

// Candidate NaN or Inf where the reference is finite and (near) zero: a max/min/clamp or a
// saturate whose NaN handling differs from the engine's (HLSL's max(NaN, 0) is 0; a port's can
// return NaN), or a division by a value the reference guards.
bool nonfinite_where_reference_zero(const Signature& s, const DiagnosisInput& in,
                                    std::string* evidence) {
  const Image& ref = *in.reference;
  const Image& cand = *in.candidate;
  const bool has_input = in.input && in.input->width == ref.width && in.input->height == ref.height;
  const double zero = s.params.at("reference_abs_max");
  size_t only_candidate = 0, at_zero = 0, input_nan = 0;
  const size_t n = ref.pixel_count(), step = stride_of(n);
  const OutputEncoding& enc = *in.encoding;
  for (size_t i = 0; i < n; i += step) {
    // The pixel's largest |nits|: a NaN against a value within float32 noise of zero is the
    // diff's sign boundary (docs/diff-metrics.md), judged consistent, not a mismatch.
    double scale = 0;
    for (int ch = 0; ch < 3; ++ch)
      for (const Image* img : {&ref, &cand})
        if (const double v = img->data[i * Image::kChannels + ch]; std::isfinite(v))
          scale = std::fmax(scale, std::fabs(enc.to_nits(v)));
    for (int ch = 0; ch < 3; ++ch) {
      const double r = ref.data[i * Image::kChannels + ch];
      const double c = cand.data[i * Image::kChannels + ch];
      if (!std::isfinite(r) || std::isfinite(c)) continue;
      if (enc.nan_marks_negative() && std::isnan(c) &&
          std::fabs(enc.to_nits(r)) < kFloat32Noise * scale)
        continue;
      ++only_candidate;
      if (std::fabs(r) <= zero) {
        ++at_zero;
        if (has_input && std::isnan(in.input->data[i * Image::kChannels + ch])) ++input_nan;
      }
    }
  }
  if (only_candidate == 0 || at_zero == 0 ||
      static_cast<double>(at_zero) < s.params.at("min_share") * static_cast<double>(only_candidate))
    return false;
  *evidence = std::to_string(at_zero) + " of " + std::to_string(only_candidate) +
              " candidate-only non-finite values where the reference is 0" +
              (has_input ? ", " + std::to_string(input_nan) + " of them where the input is NaN"
                         : std::string());
  return true;
}

// The candidate matches a variant of the reference image itself: its channels permuted, or its
// values decoded with the stage's transfer function and encoded with another.
bool matches_variant(const Signature& s, const DiagnosisInput& in, std::string* evidence) {
  const OutputEncoding& enc = *in.encoding;
  std::function<void(const double*, double*)> variant;
  if (s.variant == "swap_rb" || s.variant == "swap_rg" || s.variant == "swap_gb") {
    const int a = s.variant == "swap_gb" ? 1 : 0;
    const int b = s.variant == "swap_rg" ? 1 : 2;
    variant = [a, b](const double* r, double* v) {
      for (int ch = 0; ch < 3; ++ch) v[ch] = r[ch];
      std::swap(v[a], v[b]);
    };
  } else if (s.variant == "srgb_as_gamma22") {
    // Expected: IEC 61966-2-1's piecewise sRGB; the candidate: a pure 2.2 power law on the same
    // linear value (color/gamma_correction.h: UE's sRGBToLinear constants).
    if (enc.transfer != OutputEncoding::Transfer::kSrgb || enc.pre_scale != 1.0) return false;
    variant = [](const double* r, double* v) {
      for (int ch = 0; ch < 3; ++ch)
        v[ch] = std::pow(std::fmax(ref::srgb_to_linear(r[ch]), 0.0), 1.0 / 2.2);
    };
  } else if (s.variant == "gamma22_as_srgb") {
    if (enc.transfer != OutputEncoding::Transfer::kGamma || enc.pre_scale != 1.0 ||
        std::fabs(enc.gamma - 2.2) > 1e-9)
      return false;
    variant = [](const double* r, double* v) {
      for (int ch = 0; ch < 3; ++ch)
        v[ch] = ref::linear_to_srgb(std::pow(std::fmax(r[ch], 0.0), 2.2));
    };
  } else {
    return false;
  }
  const Fit f = fit_variant(*in.reference, *in.candidate,
                            [&](size_t, const double* r, double* v) { variant(r, v); });
  if (!explains(f, s.params.at("max_residual_share"))) return false;
  *evidence = residual_evidence(f);
  return true;
}

// The candidate matches the reference of a changed copy of the case: its input clamped to [0, 1]
// or with R and B swapped, or its lookup tables sampled half a texel off (make_case_variant).
bool matches_case_variant(const Signature& s, const DiagnosisInput& in, std::string* evidence) {
  if (!in.resolved || !in.reference_of) return false;
  if (in.reference->pixel_count() > kDiagnosisMaxPixels) return false;
  ResolvedCase c = *in.resolved;
  if (!make_case_variant(s.variant, &c)) return false;
  auto v = in.reference_of(c);
  if (!v || v->width != in.reference->width || v->height != in.reference->height) return false;
  const Image& variant = *v;
  const Fit f =
      fit_variant(*in.reference, *in.candidate, [&](size_t i, const double*, double* out) {
        for (int ch = 0; ch < 3; ++ch) out[ch] = variant.data[i * Image::kChannels + ch];
      });
  if (!explains(f, s.params.at("max_residual_share"))) return false;
  *evidence = residual_evidence(f);
  return true;
}

// candidate ≈ k · reference in absolute luminance (nits), k ≠ 1: a different nits-per-unit scale
// (scRGB's 80 against 100), paper white, or exposure. k by least squares over the values.
bool uniform_scale(const Signature& s, const DiagnosisInput& in, std::string* evidence) {
  const OutputEncoding& enc = *in.encoding;
  const Image& ref = *in.reference;
  const Image& cand = *in.candidate;
  double rr = 0, rc = 0, cc = 0, straight = 0;
  const size_t pixels = for_each_finite_sample(ref, cand, [&](const double* r, const double* c) {
    for (int ch = 0; ch < 3; ++ch) {
      const double a = enc.to_nits(r[ch]), b = enc.to_nits(c[ch]);
      if (!std::isfinite(a) || !std::isfinite(b)) continue;
      rr += a * a;
      rc += a * b;
      cc += b * b;
      straight += (b - a) * (b - a);
    }
  });
  if (pixels == 0 || !(rr > 0) || !(straight > 0)) return false;
  const double k = rc / rr;
  const double residual = std::fmax(cc - 2 * k * rc + k * k * rr, 0.0);  // Σ (b − k a)²
  if (!(std::fabs(k - 1.0) >= s.params.at("min_deviation")) ||
      !(residual <= s.params.at("max_residual_share") * straight))
    return false;
  *evidence = "candidate = " + fmt3(k) + " x reference in nits (1/" + fmt3(1.0 / k) +
              "), leaving " + percent(residual / straight) + " of the squared error";
  return true;
}

// candidate ≈ reference + d per channel, in the output's own units: a black level, a bias, an
// offset added once too often.
bool constant_offset(const Signature& s, const DiagnosisInput& in, std::string* evidence) {
  const Image& ref = *in.reference;
  const Image& cand = *in.candidate;
  double sum[3] = {0, 0, 0}, sum_sq[3] = {0, 0, 0}, sum_abs_ref[3] = {0, 0, 0};
  const size_t pixels = for_each_finite_sample(ref, cand, [&](const double* r, const double* c) {
    for (int ch = 0; ch < 3; ++ch) {
      sum[ch] += c[ch] - r[ch];
      sum_sq[ch] += (c[ch] - r[ch]) * (c[ch] - r[ch]);
      sum_abs_ref[ch] += std::fabs(r[ch]);
    }
  });
  if (pixels == 0) return false;
  double straight = 0, residual = 0, largest = 0, d[3];
  int widest = 0;
  for (int ch = 0; ch < 3; ++ch) {
    d[ch] = sum[ch] / static_cast<double>(pixels);
    straight += sum_sq[ch];
    residual += std::fmax(sum_sq[ch] - static_cast<double>(pixels) * d[ch] * d[ch], 0.0);
    if (std::fabs(d[ch]) > largest) {
      largest = std::fabs(d[ch]);
      widest = ch;
    }
  }
  // In a LUT stored as RGBA16F (lut_format 1, the LUT geometry every pipeline's bake shares), an
  // offset of about one half-float step at the channel's typical value is the store's rounding gone
  // one way (measured: ue58's scRGB LUTs pass with every red texel one step, 2^-10 at values in
  // [1, 2), above the reference's), not a bias a port added: there it must exceed min_half_steps
  // such steps (IEEE 754 binary16: spacing 2^(e - 10) in [2^e, 2^(e+1)), 2^-24 below 2^-14).
  const bool half_store = in.resolved && in.resolved->spec.stage &&
                          !in.resolved->spec.stage->takes_input &&
                          in.resolved->params.lut_format == 1;
  const double typical = sum_abs_ref[widest] / static_cast<double>(pixels);
  const double half_step = !half_store ? 0.0
                           : typical >= std::ldexp(1.0, -14)
                               ? std::ldexp(1.0, std::ilogb(typical) - 10)
                               : std::ldexp(1.0, -24);
  if (!(straight > 0) || !(largest >= s.params.at("min_offset")) ||
      !(largest >= s.params.at("min_half_steps") * half_step) ||
      !(residual <= s.params.at("max_residual_share") * straight))
    return false;
  *evidence = "candidate − reference = (" + fmt3(d[0]) + ", " + fmt3(d[1]) + ", " + fmt3(d[2]) +
              ") in the output's units, leaving " + percent(residual / straight) +
              " of the squared error";
  return true;
}

// Grey pixels (R = G = B in the reference) right, coloured ones wrong: the error grows with
// saturation and not with luminance. A saturation or hue step, a matrix whose rows do not sum to
// the same value, a per-channel constant applied to the wrong channel.
bool saturation_only(const Signature& s, const DiagnosisInput& in, std::string* evidence) {
  const Image& ref = *in.reference;
  const Image& cand = *in.candidate;
  const double grey_max = s.params.at("grey_saturation_max");
  const double coloured_min = s.params.at("coloured_saturation_min");
  double grey_err = 0, coloured_err = 0;
  size_t grey = 0, coloured = 0;
  const size_t n = ref.pixel_count(), step = stride_of(n);
  for (size_t i = 0; i < n; i += step) {
    const double* r = &ref.data[i * Image::kChannels];
    const double* c = &cand.data[i * Image::kChannels];
    if (!finite3(r) || !finite3(c)) continue;
    const double hi = std::max({r[0], r[1], r[2]}), lo = std::min({r[0], r[1], r[2]});
    if (!(hi > 0)) continue;
    const double sat = (hi - lo) / hi;
    double e = 0;
    for (int ch = 0; ch < 3; ++ch) e = std::fmax(e, std::fabs(c[ch] - r[ch]));
    e /= hi;  // relative to the pixel's level: independent of luminance
    if (sat <= grey_max) {
      ++grey;
      grey_err += e;
    } else if (sat >= coloured_min) {
      ++coloured;
      coloured_err += e;
    }
  }
  const double min_pixels = s.params.at("min_pixels");
  if (static_cast<double>(grey) < min_pixels || static_cast<double>(coloured) < min_pixels)
    return false;
  const double g = grey_err / static_cast<double>(grey);
  const double c = coloured_err / static_cast<double>(coloured);
  if (!(c >= s.params.at("min_coloured_error")) || !(g <= s.params.at("max_grey_share") * c))
    return false;
  *evidence = "mean relative error " + fmt3(g) + " on " + std::to_string(grey) + " grey pixels, " +
              fmt3(c) + " on " + std::to_string(coloured) + " coloured ones";
  return true;
}

struct DetectorEntry {
  DetectorInfo info;
  Detector fn;
};

const std::vector<DetectorEntry>& detector_table() {
  static const std::vector<DetectorEntry> table = {
      {{"nonfinite_where_reference_zero",
        {"reference_abs_max", "min_share"},
        {},
        "candidate NaN/Inf where the reference is finite and |value| <= reference_abs_max, in at "
        "least min_share of the candidate-only non-finite values"},
       nonfinite_where_reference_zero},
      {{"matches_variant",
        {"max_residual_share"},
        {"swap_rb", "swap_rg", "swap_gb", "srgb_as_gamma22", "gamma22_as_srgb"},
        "the candidate matches a variant of the reference image (channels permuted, another "
        "transfer function) within max_residual_share of the squared error"},
       matches_variant},
      {{"matches_case_variant",
        {"max_residual_share"},
        {"saturate_input", "swap_input_rb", "lut_half_texel_up", "lut_half_texel_down",
         "pq_decode_m2_rounded", "pq_decode_m1_rounded"},
        "the candidate matches the reference of a changed copy of the case within "
        "max_residual_share of the squared error"},
       matches_case_variant},
      {{"uniform_scale",
        {"max_residual_share", "min_deviation"},
        {},
        "candidate = k x reference in nits with |k - 1| >= min_deviation, within "
        "max_residual_share of the squared error"},
       uniform_scale},
      {{"constant_offset",
        {"max_residual_share", "min_offset", "min_half_steps"},
        {},
        "candidate = reference + d per channel, |d| >= min_offset (and, in an RGBA16F LUT, >= "
        "min_half_steps float16 steps at the channel's mean |reference|), within "
        "max_residual_share of "
        "the squared error"},
       constant_offset},
      {{"saturation_only",
        {"grey_saturation_max", "coloured_saturation_min", "max_grey_share", "min_pixels",
         "min_coloured_error"},
        {},
        "the mean relative error of grey pixels is at most max_grey_share of the coloured ones', "
        "which is at least min_coloured_error"},
       saturation_only},
  };
  return table;
}

const DetectorEntry* find_detector(const std::string& name) {
  for (const auto& d : detector_table())
    if (d.info.name == name) return &d;
  return nullptr;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& e : v) s += (s.empty() ? "" : ", ") + e;
  return s;
}

// A strip (N² × N, lattice point (r, g, b) at texel (r + N b, g)) as a lookup reads it with its
// coordinate shifted by `delta` texels on every axis, at each lattice point: the value a correct
// lookup then reads there. The lookup is UE's UnwrappedTexture3DSample scheme (pq_grading's and
// UE's user LUT's, docs/spec/pq_grading.md step 5): w = b + delta, two hardware bilinear taps of
// the 2D strip (clamp-to-edge) at (r + delta + N floor(w), g + delta) and N texels right, lerped
// by frac(w). So a shifted lookup reads into the neighbouring slice at a slice's edge, as the
// GPU's does; it is exact at lattice points, second order in the table's curvature between them.
Image shifted_strip(const Image& strip, double delta) {
  const int n = strip.height, w = strip.width;
  Image out = strip;
  auto texel = [&](int x, int y) {
    return strip.px(std::clamp(x, 0, w - 1), std::clamp(y, 0, n - 1));
  };
  auto bilinear = [&](double x, double y, int ch) {
    const double x0 = std::floor(x), y0 = std::floor(y), fx = x - x0, fy = y - y0;
    const int i = static_cast<int>(x0), j = static_cast<int>(y0);
    const double top = texel(i, j)[ch] + fx * (texel(i + 1, j)[ch] - texel(i, j)[ch]);
    const double bottom =
        texel(i, j + 1)[ch] + fx * (texel(i + 1, j + 1)[ch] - texel(i, j + 1)[ch]);
    return top + fy * (bottom - top);
  };
  for (int b = 0; b < n; ++b) {
    const double slice = std::floor(b + delta), frac = b + delta - slice;
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r) {
        double* o = out.px(r + n * b, g);
        const double x = r + delta + n * slice, y = g + delta;
        for (int ch = 0; ch < 3; ++ch) {
          const double t0 = bilinear(x, y, ch), t1 = bilinear(x + n, y, ch);
          o[ch] = t0 + frac * (t1 - t0);
        }
      }
  }
  return out;
}

// ST 2084's m1 and m2 as a port commonly types them: four significant digits
// (docs/constant-sweep.md).
constexpr double kPqM1Typed = 0.1593;
constexpr double kPqM2Typed = 78.84;

// ST 2084's decode (color/st2084.h nits_from_pq: PQ signal to nits) with m1 and m2 given.
double pq_decode_typed(double pq, double m1, double m2) {
  namespace st = ref::st2084;
  const double np = std::pow(pq, 1.0 / m2);
  const double l = std::fmax(np - st::kC1, 0.0) / (st::kC2 - st::kC3 * np);
  return std::pow(l, 1.0 / m1) * st::kPeakNits;
}

}  // namespace

std::string Hint::text() const {
  return "possible cause: " + message + " (" + evidence + "; see " + docs + ")";
}

const std::vector<DetectorInfo>& diagnosis_detectors() {
  static const std::vector<DetectorInfo> infos = [] {
    std::vector<DetectorInfo> v;
    for (const auto& d : detector_table()) v.push_back(d.info);
    return v;
  }();
  return infos;
}

bool make_case_variant(const std::string& variant, ResolvedCase* c) {
  if (variant == "saturate_input" || variant == "swap_input_rb") {
    // A stage that takes no input (a LUT bake: its input is the lattice) has nothing to change.
    if (c->input.data.empty() || (c->spec.stage && !c->spec.stage->takes_input)) return false;
    bool changed = false;
    for (size_t i = 0; i < c->input.pixel_count(); ++i) {
      double* p = &c->input.data[i * Image::kChannels];
      if (variant == "swap_input_rb") {
        changed = changed || !(p[0] == p[2]);
        std::swap(p[0], p[2]);
        continue;
      }
      for (int ch = 0; ch < 3; ++ch) {
        // HLSL saturate: NaN → 0.
        const double v = std::isnan(p[ch]) ? 0.0 : std::clamp(p[ch], 0.0, 1.0);
        changed = changed || !(v == p[ch]);
        p[ch] = v;
      }
    }
    return changed;
  }
  if (variant == "pq_decode_m2_rounded" || variant == "pq_decode_m1_rounded") {
    // A lookup table of PQ signals (pq_grading's) decoded by a port with m2 typed 78.84 or m1
    // typed 0.1593: every value v read as PQ(PQ⁻¹_typed(v)), so that the reference's own decode
    // gives what the port's does. Exact where the lookup's coordinate does not matter (a flat
    // table, pq_grading/isolate/); a table of other values gives a variant that explains nothing.
    const bool m2 = variant == "pq_decode_m2_rounded";
    bool any = false;
    for (Image& strip : c->user_luts)
      for (size_t i = 0; i < strip.pixel_count(); ++i)
        for (int ch = 0; ch < 3; ++ch) {
          double& v = strip.data[i * Image::kChannels + ch];
          const double typed = pq_decode_typed(v, m2 ? ref::st2084::kM1 : kPqM1Typed,
                                               m2 ? kPqM2Typed : ref::st2084::kM2);
          const double e = ref::st2084::pq_from_nits(typed);
          if (std::isfinite(e) && !(e == v)) {
            v = e;
            any = true;
          }
        }
    return any;
  }
  if (variant == "lut_half_texel_up" || variant == "lut_half_texel_down") {
    bool any = false;
    for (Image& strip : c->user_luts) {
      if (strip.data.empty() || strip.height < 2 || strip.width != strip.height * strip.height)
        continue;
      strip = shifted_strip(strip, variant == "lut_half_texel_up" ? 0.5 : -0.5);
      any = true;
    }
    return any;
  }
  return false;
}

Result<std::vector<Signature>> parse_signatures(const std::string& file, const std::string& text) {
  auto doc = parse_json_text<nlohmann::ordered_json>(file, text);
  if (!doc) return doc.error();
  const auto& j = *doc;
  if (!j.is_object() || !j.contains("signatures") || !j["signatures"].is_array())
    return Error{file, "/signatures", "missing or not an array", "an array of signatures"};
  std::vector<Signature> out;
  std::set<std::string> ids;
  std::vector<std::string> detector_names;
  for (const auto& d : diagnosis_detectors()) detector_names.push_back(d.name);
  for (size_t i = 0; i < j["signatures"].size(); ++i) {
    const auto& e = j["signatures"][i];
    const std::string at = "/signatures/" + std::to_string(i);
    if (!e.is_object()) return Error{file, at, "not an object", "a signature object"};
    for (const auto& [key, v] : e.items()) {
      static const std::set<std::string> known = {"id",      "detector", "params",   "variant",
                                                  "message", "docs",     "fallback", "$comment"};
      if (!known.count(key))
        return Error{file, at + "/" + key, "unknown field '" + key + "'",
                     "id, detector, params, variant, message, docs, fallback, $comment"};
      (void)v;
    }
    auto str = [&](const char* key, std::string* to) -> Status {
      if (!e.contains(key) || !e[key].is_string() || e[key].get<std::string>().empty())
        return Error{file, at + "/" + key, "missing, empty or not a string", "a string"};
      *to = e[key].get<std::string>();
      return {};
    };
    Signature s;
    for (auto [key, to] : {std::pair{"id", &s.id}, std::pair{"detector", &s.detector},
                           std::pair{"message", &s.message}, std::pair{"docs", &s.docs}})
      if (Status st = str(key, to); !st) return st.error();
    if (!std::all_of(s.id.begin(), s.id.end(), [](char ch) {
          return (ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '_';
        }))
      return Error{file, at + "/id", "'" + s.id + "' has a character outside [a-z0-9_]",
                   "lower-case letters, digits and '_'"};
    if (!ids.insert(s.id).second)
      return Error{file, at + "/id", "duplicate id '" + s.id + "'", "a unique id"};
    const DetectorEntry* d = find_detector(s.detector);
    if (!d)
      return Error{file, at + "/detector", "unknown detector '" + s.detector + "'",
                   joined(detector_names)};
    if (s.docs != "docs/diagnosis.md#" + s.id)
      return Error{file, at + "/docs", "'" + s.docs + "' is not the signature's section",
                   "docs/diagnosis.md#" + s.id};
    if (e.contains("variant")) {
      if (!e["variant"].is_string())
        return Error{file, at + "/variant", "not a string", joined(d->info.variants)};
      s.variant = e["variant"].get<std::string>();
    }
    const auto& variants = d->info.variants;
    if (variants.empty() ? !s.variant.empty()
                         : std::find(variants.begin(), variants.end(), s.variant) == variants.end())
      return Error{file, at + "/variant", "'" + s.variant + "' is not a variant of " + s.detector,
                   variants.empty() ? "none (omit the field)" : joined(variants)};
    if (e.contains("fallback")) {
      if (!e["fallback"].is_boolean())
        return Error{file, at + "/fallback", "not a boolean", "true or false"};
      s.fallback = e["fallback"].get<bool>();
    }
    if (!e.contains("params") || !e["params"].is_object())
      return Error{file, at + "/params", "missing or not an object", joined(d->info.params)};
    for (const auto& [key, v] : e["params"].items()) {
      const auto& names = d->info.params;
      if (std::find(names.begin(), names.end(), key) == names.end())
        return Error{file, at + "/params/" + key,
                     "unknown parameter '" + key + "' of " + s.detector, joined(names)};
      if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0)
        return Error{file, at + "/params/" + key, "'" + v.dump() + "' is not a finite number >= 0",
                     "a finite number >= 0"};
      s.params[key] = v.get<double>();
    }
    for (const auto& p : d->info.params)
      if (!s.params.count(p))
        return Error{file, at + "/params", "parameter '" + p + "' is missing",
                     joined(d->info.params)};
    out.push_back(std::move(s));
  }
  return out;
}

const std::string& builtin_signatures_text() {
  // Embedded by report/CMakeLists.txt (report::runner_data).
  static const std::string text = [] {
    for (const report::Asset& a : report::runner_data())
      if (a.name == "diagnosis_signatures.json") return std::string(a.contents);
    return std::string();
  }();
  return text;
}

const Result<std::vector<Signature>>& builtin_signatures() {
  static const Result<std::vector<Signature>> s =
      parse_signatures("runner/diagnosis_signatures.json", builtin_signatures_text());
  return s;
}

std::vector<Hint> diagnose(const std::vector<Signature>& signatures, const DiagnosisInput& in) {
  std::vector<Hint> hints;
  if (!in.reference || !in.candidate || !in.encoding ||
      in.reference->width != in.candidate->width || in.reference->height != in.candidate->height)
    return hints;
  for (const bool fallback : {false, true}) {
    if (fallback && !hints.empty()) break;
    for (const Signature& s : signatures) {
      if (s.fallback != fallback) continue;
      const DetectorEntry* d = find_detector(s.detector);
      std::string evidence;
      if (d && d->fn(s, in, &evidence)) hints.push_back({s.id, s.message, evidence, s.docs});
    }
  }
  return hints;
}

}  // namespace hdrc
