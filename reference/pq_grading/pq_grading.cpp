#include "reference/pq_grading/pq_grading.h"

#include <Imath/half.h>

#include <algorithm>
#include <cmath>

#include "color/d3d_math.h"
#include "color/st2084.h"
#include "core/cube/cube.h"
#include "reference/color/device_allowance.h"
#include "reference/color/linear_tap.h"
#include "reference/color/strip_device_range.h"
#include "reference/operators/operators.h"
#include "reference/ue/grading/film_tonemap.h"

namespace hdrc::ref::pq_grading {

const char* display_name(int d) {
  static const char* const kNames[] = {"SDR", "HDR"};
  return (d >= 0 && d < 2) ? kNames[d] : nullptr;
}

const char* back_buffer_name(int b) {
  static const char* const kNames[kBackBufferCount] = {"R10G10B10A2", "RGBA16F", "SRGB8", "RGB8"};
  return (b >= 0 && b < kBackBufferCount) ? kNames[b] : nullptr;
}

double store_rgba16f(double v) {
  if (std::isnan(v)) return v;
  const double c = std::clamp(v, -kHalfMax, kHalfMax);
  // Imath's float -> half conversion rounds to nearest, ties to even (Imath half.h, imath_float_to_
  // half); the input is float32 already (resolve_case rounds every input value).
  return static_cast<double>(static_cast<float>(Imath::half(static_cast<float>(c))));
}

double srgb_encode(double v) {
  // IEC 61966-2-1:1999 §5.3 (equations of the encoding): the 0.0031308 break point and the 1.055 /
  // 0.055 / 2.4 constants of the standard.
  if (!(v > 0.0031308)) return 12.92 * v;
  return 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

StripLut strip_lut(const Image& strip, const ParamBlock& p) {
  StripLut l;
  l.strip = &strip;
  l.size = p.user_lut_size;
  const int n = l.size;
  auto c = std::make_shared<cube::CubeLut>();
  c->size_3d = n;
  for (int i = 0; i < 3; ++i) {
    l.domain_min[i] = p.user_lut_domain_min[i];
    l.domain_max[i] = p.user_lut_domain_max[i];
    c->domain_min_3d[i] = static_cast<float>(l.domain_min[i]);
    c->domain_max_3d[i] = static_cast<float>(l.domain_max[i]);
  }
  if (n >= 2 && strip.width == n * n && strip.height == n) {
    c->table_3d.resize(static_cast<size_t>(n) * n * n);
    for (int b = 0; b < n; ++b)
      for (int g = 0; g < n; ++g)
        for (int r = 0; r < n; ++r) {
          const double* px = strip.px(r + n * b, g);
          c->table_3d[static_cast<size_t>(r) + static_cast<size_t>(n) * (g + n * b)] = {
              static_cast<float>(px[0]), static_cast<float>(px[1]), static_cast<float>(px[2])};
        }
  }
  l.cube = std::move(c);
  return l;
}

Vec3 domain_normalise(const StripLut& lut, const Vec3& v) {
  Vec3 t;
  for (int c = 0; c < 3; ++c)
    t[c] = d3d::saturate((v[c] - lut.domain_min[c]) / (lut.domain_max[c] - lut.domain_min[c]));
  return t;
}

namespace {

using Tap = LinearTap;  // reference/color/linear_tap.h

Vec3 texel(const Image& img, int x, int y) {
  const double* px = img.px(x, y);
  return {px[0], px[1], px[2]};
}

Vec3 mix(const Vec3& a, const Vec3& b, double f) {
  return {a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f, a[2] + (b[2] - a[2]) * f};
}

Vec3 bilinear(const Image& img, double u, double v) {
  const Tap tx = linear_tap(u * img.width - 0.5, img.width),
            ty = linear_tap(v * img.height - 0.5, img.height);
  return mix(mix(texel(img, tx.i0, ty.i0), texel(img, tx.i1, ty.i0), tx.f),
             mix(texel(img, tx.i0, ty.i1), texel(img, tx.i1, ty.i1), tx.f), ty.f);
}

}  // namespace

Vec3 sample_strip(const StripLut& lut, const Vec3& t) {
  StripTrace unused;
  return sample_strip(lut, t, &unused);
}

Vec3 sample_strip(const StripLut& lut, const Vec3& t, StripTrace* trace) {
  const double n = lut.size;
  Vec3 uvw;
  for (int c = 0; c < 3; ++c) uvw[c] = t[c] * ((n - 1.0) / n) + 0.5 / n;
  const double w = uvw[2] * n - 0.5;
  const double int_w = std::floor(w);
  const double frac_w = w - int_w;
  const double u = (uvw[0] + int_w) / n;
  const Vec3 tap0 = bilinear(*lut.strip, u, uvw[1]);
  const Vec3 tap1 = bilinear(*lut.strip, u + 1.0 / n, uvw[1]);
  *trace = {uvw, w, int_w, frac_w, u, tap0, tap1};
  return mix(tap0, tap1, frac_w);
}

Vec3 lookup(const StripLut& lut, const Vec3& pq, LutEval eval) {
  if (eval == LutEval::kStrip) return sample_strip(lut, domain_normalise(lut, pq));
  const auto out = cube::apply(
      *lut.cube, {pq[0], pq[1], pq[2]},
      eval == LutEval::kTrilinear ? cube::Interp::trilinear : cube::Interp::tetrahedral);
  return {out[0], out[1], out[2]};
}

Vec3 display_map(const ParamBlock& p, const Vec3& graded) {
  return display_map(p, graded, nullptr);
}

Vec3 display_map(const ParamBlock& p, const Vec3& graded, operators::UeFilmicTrace* filmic) {
  if (p.pq_display == static_cast<int>(Display::kHdr)) {
    const grading::FilmParams film{p.film_slope, p.film_toe, p.film_shoulder, p.film_black_clip,
                                   p.film_white_clip};
    const operators::UeFilmicSpace space{p.pq_rec709_to_ap1, p.pq_ap1_to_rec709};
    return filmic ? operators::ue_filmic(graded, film, space, filmic)
                  : operators::ue_filmic(graded, film, space);
  }
  if (p.pq_display == static_cast<int>(Display::kSdr))
    return {operators::aces_narkowicz(graded[0]), operators::aces_narkowicz(graded[1]),
            operators::aces_narkowicz(graded[2])};
  return {d3d::kNaN, d3d::kNaN, d3d::kNaN};
}

double encode_output(const ParamBlock& p, double d) {
  switch (static_cast<BackBuffer>(p.pq_back_buffer)) {
    case BackBuffer::kR10G10B10A2:
      return d3d::saturate(st2084::pq_from_nits(d * p.pq_white_nits));
    case BackBuffer::kRgba16f:
      return d * p.pq_white_nits / kScRgbWhiteNits;
    case BackBuffer::kSrgb8:
      return srgb_encode(d3d::saturate(d));
    case BackBuffer::kRgb8:
      return std::pow(d3d::saturate(d), 1.0 / kRgb8Gamma);
  }
  return d3d::kNaN;
}

Trace grade(const ParamBlock& p, const StripLut& lut, const Vec3& scene, LutEval eval) {
  Trace t;
  for (int c = 0; c < 3; ++c) {
    t.stored[c] = store_rgba16f(scene[c]);
    t.exposed[c] = d3d::saturate(t.stored[c] * p.pq_exposure_fract);
    t.pq[c] = st2084::pq_from_nits(t.exposed[c] * st2084::kPeakNits);
  }
  if (eval == LutEval::kStrip) {
    t.lut_coord = domain_normalise(lut, t.pq);
    t.graded_pq = sample_strip(lut, t.lut_coord, &t.strip);
  } else {
    t.graded_pq = lookup(lut, t.pq, eval);
  }
  for (int c = 0; c < 3; ++c)
    t.graded[c] = st2084::nits_from_pq(t.graded_pq[c]) / st2084::kPeakNits / p.pq_exposure_fract *
                  p.pq_amplify;
  t.display = display_map(p, t.graded, &t.filmic);
  for (int c = 0; c < 3; ++c) t.out[c] = encode_output(p, t.display[c]);
  return t;
}

std::vector<NamedValue> named_values(const ParamBlock& p, const StripLut& lut, const Vec3& scene) {
  const Trace t = grade(p, lut, scene, LutEval::kStrip);
  std::vector<NamedValue> out;
  add_named(&out, "input", scene);
  add_named(&out, "exposure_fract", p.pq_exposure_fract);
  add_named(&out, "white_nits", p.pq_white_nits);
  add_named(&out, "stored", t.stored);
  add_named(&out, "exposed", t.exposed);
  add_named(&out, "pq", t.pq);
  add_named(&out, "lut_coord", t.lut_coord);
  add_named(&out, "uvw", t.strip.uvw);
  add_named(&out, "slice_w", t.strip.w);
  add_named(&out, "slice_i", t.strip.i);
  add_named(&out, "slice_f", t.strip.f);
  add_named(&out, "u", t.strip.u);
  add_named(&out, "tap0", t.strip.tap0);
  add_named(&out, "tap1", t.strip.tap1);
  add_named(&out, "graded_pq", t.graded_pq);
  add_named(&out, "graded", t.graded);
  if (p.pq_display == static_cast<int>(Display::kHdr)) {
    add_named(&out, "ap1", t.filmic.ap1);
    grading::film_named_values(t.filmic.film, true, &out);
    add_named(&out, "tone_ap1", t.filmic.tone_ap1);
    add_named(&out, "rec709", t.filmic.rec709);
  }
  add_named(&out, "display", t.display);
  add_named(&out, "out", t.out);
  return out;
}

// --- Device allowances ---

spirv::Interval pq_from_nits_on_device(spirv::Interval nits) {
  using namespace spirv;
  Interval lm = Interval::point(0.0);  // pow_d3d(0, m1) = 0
  if (nits.hi > 0) {
    const Interval y =
        div(Interval{std::max(nits.lo, 0.0), nits.hi}, Interval::point(st2084::kPeakNits));
    lm = pow(Interval{std::max(y.lo, 0x1p-149), y.hi}, st2084::kM1);
    if (!(nits.lo > 0)) lm.lo = 0.0;
  }
  const Interval num = mul_add(Interval::point(st2084::kC2), lm, Interval::point(st2084::kC1));
  const Interval den = mul_add(Interval::point(st2084::kC3), lm, Interval::point(1.0));
  return pow(mul(num, div(Interval::point(1.0), den)), st2084::kM2);
}

namespace {

// pqg_encode_output of one display value as a device may evaluate it (pq_grading.glsl).
spirv::Interval encode_output_on_device(const ParamBlock& p, double d) {
  using namespace spirv;
  const Interval dv = Interval::point(d);
  switch (static_cast<BackBuffer>(p.pq_back_buffer)) {
    case BackBuffer::kR10G10B10A2: {
      const Interval q = pq_from_nits_on_device(mul(dv, Interval::point(p.pq_white_nits)));
      return {d3d::saturate(q.lo), d3d::saturate(q.hi)};
    }
    case BackBuffer::kRgba16f:
      return div(mul(dv, Interval::point(p.pq_white_nits)), Interval::point(kScRgbWhiteNits));
    case BackBuffer::kSrgb8: {
      const double v = d3d::saturate(d);
      if (!(v > 0.0031308)) return mul(Interval::point(12.92), Interval::point(v));
      return mul_add(Interval::point(1.055), pow(Interval::point(v), 1.0 / 2.4),
                     Interval::point(-0.055));
    }
    case BackBuffer::kRgb8: {
      const double v = d3d::saturate(d);
      if (!(v > 0)) return Interval::point(0.0);
      return pow(Interval::point(v), 1.0 / kRgb8Gamma);
    }
  }
  return Interval::point(d3d::kNaN);
}

}  // namespace

Range3 grade_device_range(const ParamBlock& p, const StripLut& lut, const Vec3& scene,
                          const DevicePrecision& d) {
  using namespace spirv;
  const Trace t = grade(p, lut, scene, LutEval::kStrip);
  Range3 ref = Range3::point(t.out);
  if (std::isnan(scene[0]) || std::isnan(scene[1]) || std::isnan(scene[2])) return ref;
  // 1-3. The lighting target's half (packHalf2x16 rounds by the device's float16 rounding mode
  // unless it guarantees RTE), the exposure multiply, saturate, PQ.
  Range3 pq_t;
  for (int c = 0; c < 3; ++c) {
    const double v = std::clamp(scene[c], -kHalfMax, kHalfMax);
    // Vulkan's float16 rounding modes are RTE and RTZ: the nearest half or the one toward zero.
    const double rtz = v >= 0 ? half_round_down(v) : half_round_up(v);
    const Interval stored =
        d.fp16_rte ? Interval::point(t.stored[c])
                   : Interval{std::fmin(rtz, t.stored[c]), std::fmax(rtz, t.stored[c])};
    const Interval e = mul(stored, Interval::point(p.pq_exposure_fract));
    const Interval exposed{d3d::saturate(e.lo), d3d::saturate(e.hi)};
    const Interval pq = pq_from_nits_on_device(mul(exposed, Interval::point(st2084::kPeakNits)));
    // pqg_domain_normalise: (v − min) / (max − min), saturate.
    const Interval span =
        sub(Interval::point(lut.domain_max[c]), Interval::point(lut.domain_min[c]));
    const Interval n = div(sub(pq, Interval::point(lut.domain_min[c])), span);
    pq_t.lo[c] = d3d::saturate(n.lo);
    pq_t.hi[c] = d3d::saturate(n.hi);
  }
  // 4. The strip lookup: RGBA32F holds the .cube's floats, so the texels are exact; the weights
  // take their boxes. The shader's coordinate arithmetic after the normalisation (uvw = t·(N −
  // 1)/N + 0.5/N, w = uvw.b·N − 0.5, u = (uvw.r + floor(w))/N: correctly rounded steps and one
  // division, 2.5 ULP) errs by under 3·10^-7 in u and uvw, within kFloat32Noise (2^-20, 16 ULP of
  // 1), which is the coordinate noise used (in texels: N² · 2^-20 along the strip's x).
  // The filter's own arithmetic in float32, the RGBA32F strip's precision (VK-GL-CTS's filtering
  // precision; device_allowance.h FilterArithmetic).
  const Range3 g =
      strip_lookup_device_range({lut.strip, lut.strip, lut.size}, pq_t, d.sub_texel_bits,
                                kFloat32Noise, FilterArithmetic::float32());
  // 5. PQ decode (nits_from_pq, increasing), / 10000 / ExposureFract · Amplify. A negative graded
  // signal is NaN on the device (pow_d3d): no allowance is derived for such a pixel.
  Range3 graded;
  for (int c = 0; c < 3; ++c) {
    if (g.nan[c] || !(g.lo[c] >= 0) || !(g.hi[c] <= 1e30)) return ref;
    const Interval nits{pq_decode_on_device(g.lo[c]).lo, pq_decode_on_device(g.hi[c]).hi};
    const Interval lin = div(nits, Interval::point(st2084::kPeakNits));
    const Interval v =
        mul(div(lin, Interval::point(p.pq_exposure_fract)), Interval::point(p.pq_amplify));
    // The sign of a product or quotient is exact: non-negative nits stay non-negative (the
    // bounds' ULP around an exact 0 would otherwise admit a negative denormal).
    graded.lo[c] = std::max(v.lo, 0.0);
    graded.hi[c] = v.hi;
  }
  // 6. The display mapping over the box of its input: its extremes at the box's corners to first
  // order (the box is a few float32 ulps to a filter weight step wide, the mapping smooth), then
  // kShaderNoise of the largest channel for its float32 arithmetic (matrices, log10/pow of
  // FilmToneMap, the rational fit).
  Range3 disp = Range3::point(t.display);
  for (int corner = 0; corner < 8; ++corner) {
    Vec3 v;
    for (int c = 0; c < 3; ++c) v[c] = (corner >> c) & 1 ? graded.hi[c] : graded.lo[c];
    disp.include(display_map(p, v));
  }
  double big = 0;
  for (int c = 0; c < 3; ++c)
    big = std::fmax(big, std::fmax(std::fabs(disp.lo[c]), std::fabs(disp.hi[c])));
  const double noise = kShaderNoise * big;
  // 7. The back buffer's encoding, nondecreasing: the device's low end of the low end, high end of
  // the high end.
  Range3 out;
  for (int c = 0; c < 3; ++c) {
    if (disp.nan[c]) return ref;
    out.lo[c] = encode_output_on_device(p, disp.lo[c] - noise).lo;
    out.hi[c] = encode_output_on_device(p, disp.hi[c] + noise).hi;
    if (std::isnan(out.lo[c]) || std::isnan(out.hi[c])) return ref;
  }
  out.include(t.out);
  return out;
}

// --- Settings ---

namespace {
constexpr std::array<double, 4> s1(double v) {
  return {v, 0, 0, 0};
}
}  // namespace

const std::vector<SettingInfo>& pq_grading_setting_table() {
  static const std::vector<SettingInfo> table = {
      {"Amplify", 1, s1(kDefaultAmplify), 1e-3, 1e3,
       "pq_amplify, and pq_exposure_fract = 1e-4 x Amplify (the issue's ExposureFract)"},
      {"Display", 1, s1(static_cast<double>(Display::kHdr)), 0, 1,
       "pq_display: 0 SDR (Narkowicz's ACES fit), 1 HDR (UE's FilmToneMap) (a name or its number)"},
      {"BackBuffer", 1, s1(static_cast<double>(BackBuffer::kR10G10B10A2)), 0, kBackBufferCount - 1,
       "pq_back_buffer: 0 R10G10B10A2 (PQ), 1 RGBA16F (scRGB), 2 SRGB8, 3 RGB8 (gamma 2.2) (a name "
       "or its number)"},
      {"PeakNits", 1, s1(kDefaultPeakNits), 80, 10000,
       "pq_white_nits of the HDR display: the nits of display value 1.0 in the PQ and RGBA16F "
       "encodings (SDR: 100)"},
  };
  return table;
}

const std::vector<SettingChoice>* pq_grading_setting_choices(std::string_view setting) {
  static const std::vector<SettingChoice> displays = {{"SDR", 0}, {"HDR", 1}};
  static const std::vector<SettingChoice> buffers = [] {
    std::vector<SettingChoice> c;
    for (int i = 0; i < kBackBufferCount; ++i) c.push_back({back_buffer_name(i), double(i)});
    return c;
  }();
  if (setting == "Display") return &displays;
  if (setting == "BackBuffer") return &buffers;
  return nullptr;
}

void derive_pq_grading(const SettingValues& s, ParamBlock* p) {
  auto get = [&s](std::string_view name) {
    if (find_setting(s.table(), name)) return s.get(name);
    return find_setting(pq_grading_setting_table(), name)->default_value[0];
  };
  p->pq_amplify = get("Amplify");
  p->pq_exposure_fract = kExposureFractPerAmplify * p->pq_amplify;
  p->pq_display = static_cast<int>(get("Display"));
  p->pq_back_buffer = static_cast<int>(get("BackBuffer"));
  p->pq_white_nits =
      p->pq_display == static_cast<int>(Display::kHdr) ? get("PeakNits") : kSdrWhiteNits;
  const grading::FilmParams film{};  // UE's Default (Scene.cpp FPostProcessSettings)
  p->film_slope = film.slope;
  p->film_toe = film.toe;
  p->film_shoulder = film.shoulder;
  p->film_black_clip = film.black_clip;
  p->film_white_clip = film.white_clip;
  const operators::UeFilmicSpace space = operators::ue_filmic_space();
  p->pq_rec709_to_ap1 = space.rec709_to_ap1;
  p->pq_ap1_to_rec709 = space.ap1_to_rec709;
}

}  // namespace hdrc::ref::pq_grading
