#include "reference/ue/ue58/ue58_combine_luts.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "color/d3d_math.h"
#include "color/gamma_correction.h"
#include "color/st2084.h"
#include "reference/color/device_allowance.h"
#include "reference/color/spirv_precision.h"
#include "reference/color/ue_log_shaper.h"
#include "reference/ue/aces/aces_output.h"
#include "reference/ue/combine_luts.h"
#include "reference/ue/grading/color_correct.h"
#include "reference/ue/grading/color_polynomial.h"
#include "reference/ue/grading/expand_gamut.h"
#include "reference/ue/grading/film_tonemap.h"
#include "reference/ue/grading/hlsl_ops.h"
#include "reference/ue/lut_store_range.h"

namespace hdrc::ref::ue58 {

namespace {

constexpr double kLinearToNits = 100.0;   // LinearToNitsScale
constexpr double kPqWhiteNits = 10000.0;  // UE_PQ_WHITE_NITS
constexpr double kScRgbWhiteNits = 80.0;  // UE_SCRGB_WHITE_NITS (GammaCorrectionCommon.ush)
constexpr double kBt1886Gamma = 2.4;      // PostProcessCombineLUTs.usf: Bt1886Gamma
// PostProcessCombineLUTs.usf: ApplyToneCurve (Filmic): "reciprocal of ST2084 at 100 nits", and
// PostProcessCombineLUTsInner.usf: MethodLUTsCommon, which undoes it.
constexpr double kFilmPqScale = 1.9682001;
constexpr double kFilmPqUnscale = .5080784215;

// LinearToST2084 per channel (a negative or NaN input is NaN, as pow of a negative base on D3D).
Vec3 pq(const Vec3& nits) {
  Vec3 out;
  for (int c = 0; c < 3; ++c)
    out[c] = (std::isnan(nits[c]) || nits[c] < 0.0) ? d3d::kNaN : st2084::pq_from_nits(nits[c]);
  return out;
}
Vec3 pq_inv(const Vec3& e) {
  return {st2084::nits_from_pq(e[0]), st2084::nits_from_pq(e[1]), st2084::nits_from_pq(e[2])};
}
Vec3 clamp3(const Vec3& v, double lo, double hi) {
  // HLSL clamp = min(max(v, lo), hi): max/min ignore a NaN operand, so NaN becomes lo.
  return {std::fmin(std::fmax(v[0], lo), hi), std::fmin(std::fmax(v[1], lo), hi),
          std::fmin(std::fmax(v[2], lo), hi)};
}
Vec3 scale(const Vec3& v, double k) {
  return {v[0] * k, v[1] * k, v[2] * k};
}
Vec3 pow3(const Vec3& v, double g) {
  return {d3d::pow(v[0], g), d3d::pow(v[1], g), d3d::pow(v[2], g)};
}

// The set's members in the block: ParamsT<double> is 76 doubles in std430 order (aces2.h A9).
static_assert(sizeof(aces2::Params) == 76 * sizeof(double));

template <size_t N>
void put_scalars(const double* v, size_t count, Vec4Array<N>* out) {
  for (size_t i = 0; i < N * 4; ++i) (*out)[i / 4][i % 4] = i < count ? v[i] : 0.0;
}
template <size_t N>
void get_scalars(const Vec4Array<N>& in, size_t count, double* v) {
  for (size_t i = 0; i < count; ++i) v[i] = in[i / 4][i % 4];
}

}  // namespace

Aces2Set unpack_aces2_set(const ParamBlock& p, bool sdr) {
  Aces2Set s;
  double scalars[76];
  get_scalars(sdr ? p.ue58_aces2_params_sdr : p.ue58_aces2_params, 76, scalars);
  std::memcpy(&s.params, scalars, sizeof scalars);
  get_scalars(sdr ? p.ue58_reach_table_sdr : p.ue58_reach_table, aces2::kTableSize,
              s.tables.reach_m.data());
  get_scalars(sdr ? p.ue58_gamma_table_sdr : p.ue58_gamma_table, aces2::kTotalTableSize,
              s.tables.upper_hull_gamma.data());
  const auto& cusp = sdr ? p.ue58_cusp_table_sdr : p.ue58_cusp_table;
  for (int r = 0; r < aces2::kTotalTableSize; ++r)
    for (int c = 0; c < 3; ++c) s.tables.gamut_cusp[r][c] = cusp[r][c];
  return s;
}

void pack_aces2_set(const aces2::Params& params, const aces2::Tables& tables, bool sdr,
                    ParamBlock* p) {
  double scalars[76];
  std::memcpy(scalars, &params, sizeof scalars);
  put_scalars(scalars, 76, sdr ? &p->ue58_aces2_params_sdr : &p->ue58_aces2_params);
  put_scalars(tables.reach_m.data(), aces2::kTableSize,
              sdr ? &p->ue58_reach_table_sdr : &p->ue58_reach_table);
  put_scalars(tables.upper_hull_gamma.data(), aces2::kTotalTableSize,
              sdr ? &p->ue58_gamma_table_sdr : &p->ue58_gamma_table);
  auto& cusp = sdr ? p->ue58_cusp_table_sdr : p->ue58_cusp_table;
  for (int r = 0; r < aces2::kTotalTableSize; ++r)
    cusp[r] = {tables.gamut_cusp[r][0], tables.gamut_cusp[r][1], tables.gamut_cusp[r][2], 0.0};
}

CombineLuts58::CombineLuts58(const ParamBlock& p)
    : p_(p), fwd_(unpack_aces2_set(p, false)), sdr_(unpack_aces2_set(p, true)) {
  if (!p_.ue58_inner_needed) return;
  const size_t m = static_cast<size_t>(p_.ue58_inner_lut_size);
  inner_.resize(m * m * m);
  inner_out_.resize(m * m * m);
  inner_done_.assign(m * m * m, 0);
  inner_range_.resize(m * m * m);
  inner_range_done_.assign(m * m * m, 0);
}

// AddCombineLUTPass: the inner LUT, M^3 texels at (i, j, k) / (M - 1) (MainCS: DispatchThreadId
// * InvLUTSizeMinusOne), stored in the LUT format (CreateLUTRenderTarget: A2B10G10R10, or
// PF_FloatRGBA when bUseFloatOutput).
const Vec3& CombineLuts58::inner_stored(int r, int g, int b) const {
  const int m = p_.ue58_inner_lut_size;
  const size_t i = (static_cast<size_t>(b) * m + g) * m + r;
  if (!inner_done_[i]) {
    const double step = 1.0 / (m - 1);
    // The output before its encode is kept for the device range (inner_stored_range).
    inner_out_[i] = inner_output({r * step, g * step, b * step});
    const Vec3 v = inner_encode(inner_out_[i]);
    for (int c = 0; c < 3; ++c) inner_[i][c] = quantize_lut_value(p_.ue58_inner_format, v[c]);
    inner_done_[i] = 1;
  }
  return inner_[i];
}

std::vector<Vec3> CombineLuts58::inner_lut() const {
  std::vector<Vec3> out;
  if (!p_.ue58_inner_needed) return out;
  const int m = p_.ue58_inner_lut_size;
  for (int b = 0; b < m; ++b)
    for (int g = 0; g < m; ++g)
      for (int r = 0; r < m; ++r) out.push_back(inner_stored(r, g, b));
  return out;
}

// PostProcessCombineLUTsInner.usf: ComputeOutputACES — the output transform on the graded colour
// (working colour space): ACES 2.0 (TonemapCommon.ush: ACESOutputTransform with
// TotalSceneColorMultiplier, WorkingColorSpace.ToAP0, the forward tables, bScaleWhite, the
// limiting and encoding primaries) or ACES 1.3 (the 5.5 body, then AP1_2_Output). Nits.
Vec3 CombineLuts58::output_aces(const Vec3& graded) const {
  if (p_.ue58_aces_version > 1) {
    const Vec3 ap0 = p_.wcs_to_ap0 * scale(graded, p_.ue58_total_scene_color_multiplier);
    return aces2::aces_output_transform_nits(ap0, fwd_.params, fwd_.tables,
                                             p_.ue58_scale_white != 0);
  }
  return p_.ap1_to_output *
         aces::aces_output_transforms_1000(graded, p_.wcs_to_ap0, aces_params(p_));
}

// PostProcessCombineLUTsInner.usf: ComputeInvOutputACES — ACES 2.0's inverse at 100 nits with the
// SDR tables and the working colour space as limit, back to the working colour space, divided by
// ACESSceneColorMultiplier; ACES 1.3 has no inverse and returns the constant (1, 0, 1).
Vec3 CombineLuts58::inv_output_aces(const Vec3& film_nits) const {
  if (p_.ue58_aces_version <= 1) return {1.0, 0.0, 1.0};
  const Vec3 ap0 = aces2::aces_inv_output_transform_nits(film_nits, sdr_.params, sdr_.tables,
                                                         p_.ue58_scale_white_sdr != 0);
  return scale(p_.ue58_wcs_from_ap0 * ap0, 1.0 / p_.aces_scene_color_multiplier);
}

// PostProcessCombineLUTsInner.usf: MethodLUTsCommon up to its encode: the output transform's nits.
Vec3 CombineLuts58::inner_output(const Vec3& e) const {
  return inner_output_from_nits(inner_input_nits(e));
}

// MethodLUTsCommon's decode of its lattice coordinate: ST2084ToLinear of it (StandardACES), or of
// it x 0.5080784215 (Filmic's "automatic HDR": undoes the outer LUT's x 1.9682001). Nits.
Vec3 CombineLuts58::inner_input_nits(const Vec3& e) const {
  if (p_.ue58_tonemapping_method == static_cast<int>(Method::kStandardAces)) return pq_inv(e);
  return pq_inv(scale(e, kFilmPqUnscale));
}

// MethodLUTsCommon from that decode on: StandardACES reads it as AP1 (nits / 100), Filmic through
// the SDR inverse; then the output transform.
Vec3 CombineLuts58::inner_output_from_nits(const Vec3& nits) const {
  if (p_.ue58_tonemapping_method == static_cast<int>(Method::kStandardAces))
    return output_aces(p_.wcs_from_ap1 * scale(nits, 1.0 / kLinearToNits));
  return output_aces(inv_output_aces(nits));
}

// PostProcessCombineLUTsInner.usf: MethodLUTsCommon.
Vec3 CombineLuts58::inner_texel(const Vec3& e) const {
  return inner_encode(inner_output(e));
}

// MethodLUTsCommon's encode of the output transform's nits: PQ above 100 nits, else sRGB.
Vec3 CombineLuts58::inner_encode(Vec3 out) const {
  if (p_.output_max_luminance > kLinearToNits) return pq(clamp3(out, 0.0, kPqWhiteNits));
  out = clamp3(scale(out, 1.0 / kLinearToNits), 0.0, 1.0);  // saturate
  return {linear_to_srgb(out[0]), linear_to_srgb(out[1]), linear_to_srgb(out[2])};
}

// PostProcessCombineLUTs.usf: InnerLookupTable. The sampler is bilinear with clamp addressing on a
// volume (AddCombineLUTPass: TStaticSamplerState<SF_Bilinear, AM_Clamp, ...>), i.e. trilinear
// filtering; here with exact weights (docs/ue58-decisions.md E2).
Vec3 CombineLuts58::inner_lookup(const Vec3& encoded, bool inv_eotf_pq) const {
  const int m = p_.ue58_inner_lut_size;
  const double inv = 1.0 / m;
  Vec3 color{0, 0, 0};
  if (inner_.empty()) {
    // GBlackVolumeTexture: never sampled on a path that needs the inner LUT (bNeedsInnerTonemapping
    // LUT covers every caller), kept for completeness.
  } else if (std::isnan(encoded[0]) || std::isnan(encoded[1]) || std::isnan(encoded[2])) {
    color = {d3d::kNaN, d3d::kNaN, d3d::kNaN};
  } else if (exact_inner_) {
    color = inner_texel(clamp3(encoded, 0.0, 1.0));
  } else {
    int i0[3], i1[3];
    double f[3];
    for (int c = 0; c < 3; ++c) {
      const double uvw = encoded[c] * (1.0 - inv) + 0.5 * inv;
      const double x = uvw * m - 0.5;
      const double fl = std::floor(x);
      f[c] = x - fl;
      const int i = static_cast<int>(std::clamp(fl, -1.0, static_cast<double>(m)));
      i0[c] = std::clamp(i, 0, m - 1);
      i1[c] = std::clamp(i + 1, 0, m - 1);
    }
    for (int corner = 0; corner < 8; ++corner) {
      const int r = corner & 1 ? i1[0] : i0[0];
      const int g = corner & 2 ? i1[1] : i0[1];
      const int b = corner & 4 ? i1[2] : i0[2];
      const double w = (corner & 1 ? f[0] : 1 - f[0]) * (corner & 2 ? f[1] : 1 - f[1]) *
                       (corner & 4 ? f[2] : 1 - f[2]);
      if (w == 0.0) continue;  // weight 0 adds nothing (not evaluated, as the GPU skips it)
      const Vec3& t = inner_stored(r, g, b);
      for (int c = 0; c < 3; ++c) color[c] += w * t[c];
    }
  }
  if (p_.output_max_luminance > kLinearToNits) {
    if (!inv_eotf_pq) color = scale(pq_inv(color), 1.0 / kLinearToNits);
  } else {
    // sRGBToLinear without 5.5's min-normal clamp (docs/ue58-differences.md L16).
    for (int c = 0; c < 3; ++c) color[c] = srgb_to_linear(color[c], MinNormalClamp::kOff);
    if (inv_eotf_pq) color = pq(scale(color, kLinearToNits));
  }
  return color;
}

// PostProcessCombineLUTs.usf: ComputeGradedColor — FromAP1 · ColorAP1 with the fade (float32's
// range on the product, as reference/ue/combine_luts.cpp does for 5.5).
Vec3 CombineLuts58::graded_color(const Vec3& color_ap1) const {
  const Vec3 g = p_.wcs_from_ap1 * color_ap1;
  const grading::Fade fade{
      {p_.color_scale[0], p_.color_scale[1], p_.color_scale[2]},
      {p_.overlay_color[0], p_.overlay_color[1], p_.overlay_color[2], p_.overlay_color[3]}};
  return grading::apply_fade({grading::hlsl::f32_range(g[0]), grading::hlsl::f32_range(g[1]),
                              grading::hlsl::f32_range(g[2])},
                             fade);
}

// PostProcessCombineLUTs.usf: ComputeFilmColorNoGamma — 5.5's film path unchanged (blue
// correction, FilmToneMap, max(0, FromAP1 ·), r.Color.* polynomial, fade). No user-LUT blend: the
// ue58 stage takes no user LUT (docs/ue58-decisions.md E5).
Vec3 CombineLuts58::film_color_no_gamma(const Vec3& color_ap1) const {
  grading::FilmPathParams film;
  film.blue_correction = p_.blue_correction;
  film.tone_curve_amount = p_.tone_curve_amount;
  film.film = {p_.film_slope, p_.film_toe, p_.film_shoulder, p_.film_black_clip,
               p_.film_white_clip};
  const Vec3 f = grading::film_color(color_ap1, film, working_color_space(p_));
  const Vec3 mapped = grading::apply_mapping_polynomial(
      f, {p_.mapping_polynomial[0], p_.mapping_polynomial[1], p_.mapping_polynomial[2]});
  const grading::Fade fade{
      {p_.color_scale[0], p_.color_scale[1], p_.color_scale[2]},
      {p_.overlay_color[0], p_.overlay_color[1], p_.overlay_color[2], p_.overlay_color[3]}};
  return grading::apply_fade(mapped, fade);
}

// PostProcessCombineLUTs.usf: ApplyToneCurve(ColorAP1, PeakLuminance, AP1_2_Output, InvEOTF).
Vec3 CombineLuts58::apply_tone_curve(const Vec3& color_ap1, double peak, bool inv_eotf_pq) const {
  if (p_.ue58_tonemapping_method == static_cast<int>(Method::kStandardAces)) {
    const Vec3 graded_ap1 = p_.wcs_to_ap1 * graded_color(color_ap1);
    const Vec3 enc = pq(clamp3(scale(graded_ap1, kLinearToNits), 0.0, kPqWhiteNits));
    return inner_lookup(enc, inv_eotf_pq);
  }
  const Vec3 film_no_gamma = film_color_no_gamma(color_ap1);
  const Vec3 film = grading::apply_film_gamma(
      film_no_gamma, {p_.inverse_gamma[0], p_.inverse_gamma[1], p_.inverse_gamma[2]});
  // UE-29935 workaround, 5.8: only for an sRGB working colour space AND the sRGB output gamut.
  Vec3 out =
      (p_.wcs_is_srgb && p_.output_gamut == 0) ? film : p_.ap1_to_output * (p_.wcs_to_ap1 * film);
  if (peak > kLinearToNits) {
    // "Automatic HDR": sRGB-encoded values re-linearised with BT.1886 (TonemappingSDRInvEOTF sRGB),
    // then PQ at 100 nits normalised to 1, through the inner LUT.
    if (p_.ue58_sdr_inv_eotf == 0) {
      out = {linear_to_srgb(out[0]), linear_to_srgb(out[1]), linear_to_srgb(out[2])};
      out = pow3(out, kBt1886Gamma);
    }
    const Vec3 enc = scale(pq(clamp3(scale(out, kLinearToNits), 0.0, kPqWhiteNits)), kFilmPqScale);
    return inner_lookup(enc, inv_eotf_pq);
  }
  return inv_eotf_pq ? pq(scale(out, kLinearToNits)) : out;  // ApplyInvEOTF
}

// PostProcessCombineLUTs.usf: CombineLUTsCommon up to ColorCorrectAll (AP1).
Vec3 CombineLuts58::color_corrected(const Vec3& e) const {
  Vec3 linear;
  if (p_.ue58_lut_shaper) {
    linear = scale(pq_inv(e), 1.0 / kLinearToNits);
  } else {
    for (int c = 0; c < 3; ++c) linear[c] = ue_log::lin_from_log(e[c]) - ue_log::lin_from_log(0.0);
  }
  // White balance: a runtime branch on |WhiteTemp - 6500| > 1e-8 || |WhiteTint| > 1e-8 in 5.8
  // (5.5's SKIP_TEMPERATURE permutation), the same condition the host's white_balance_enabled is.
  const Vec3 balanced = p_.white_balance_enabled ? p_.white_balance * linear : linear;
  const Vec3 ap1 = grading::expand_gamut(p_.wcs_to_ap1 * balanced, p_.expand_gamut);
  return grading::color_correct_all(ap1, color_correct_params(p_));
}

// PostProcessCombineLUTs.usf: CombineLUTsCommon.
Vec3 CombineLuts58::outer_texel(const Vec3& e) const {
  const Vec3 cc = color_corrected(e);
  Vec3 device;
  switch (p_.output_device) {
    case 0: {
      const Vec3 x = apply_tone_curve(cc, kLinearToNits, false);
      device = p_.ue58_sdr_inv_eotf == 0
                   ? Vec3{linear_to_srgb(x[0]), linear_to_srgb(x[1]), linear_to_srgb(x[2])}
                   : pow3(x, 1.0 / kBt1886Gamma);
      break;
    }
    case 1:
      device = linear_to_rec709_branchless(apply_tone_curve(cc, kLinearToNits, false));
      break;
    case 3:
    case 4:
      device = apply_tone_curve(cc, p_.output_max_luminance, true);
      break;
    case 5:
    case 6:
      device = scale(apply_tone_curve(cc, p_.output_max_luminance, false),
                     kLinearToNits / kScRgbWhiteNits);
      break;
    case 7:
      device = pq(p_.ap1_to_output * (p_.wcs_to_ap1 * graded_color(cc)));
      break;
    case 8:
      device = graded_color(cc);
      break;
    case 9:
      device = apply_tone_curve(cc, kLinearToNits, false);
      break;
    default:  // 2, the shader's final else: explicit gamma
      device = pow3(apply_tone_curve(cc, kLinearToNits, false), p_.inverse_gamma[2]);
  }
  return scale(device, p_.ue58_lut_inv_max);
}

// ---- Device allowances (docs/precision.md "Device allowances", docs/ue58-decisions.md E8) ----

namespace {

// pq(clamp3(nits, 0, 10000)) over a range on a device: HLSL clamp makes NaN 0, then LinearToST2084
// with the precision table's bounds (device_allowance.h pq_encode_on_device; PQ is increasing).
Range3 pq_clamped_on_device(const Range3& nits) {
  Range3 r;
  for (int c = 0; c < 3; ++c) {
    auto clamp = [](double v) { return std::isnan(v) ? 0.0 : std::clamp(v, 0.0, kPqWhiteNits); };
    double lo = clamp(nits.lo[c]), hi = clamp(nits.hi[c]);
    if (nits.nan[c]) lo = 0.0;
    if (hi < lo) hi = lo;
    const spirv::Interval e = pq_encode_on_device(lo, hi);
    r.lo[c] = e.lo;
    r.hi[c] = e.hi;
  }
  return r;
}

// pq(nits) without the clamp (device 7, ApplyInvEOTF): a negative value is NaN (pow of a negative
// base), as the point path's pq().
Range3 pq_on_device(const Range3& nits) {
  Range3 r;
  for (int c = 0; c < 3; ++c) {
    double lo = nits.lo[c], hi = nits.hi[c];
    r.nan[c] = nits.nan[c] || std::isnan(lo) || std::isnan(hi) || lo < 0.0;
    if (!(hi >= 0.0)) {
      r.lo[c] = r.hi[c] = d3d::kNaN;
      continue;
    }
    lo = std::isnan(lo) ? 0.0 : std::fmax(lo, 0.0);
    const spirv::Interval e = pq_encode_on_device(lo, hi);
    r.lo[c] = e.lo;
    r.hi[c] = e.hi;
  }
  return r;
}

// A product by a positive constant in float32 (OpFMul, correctly rounded: half an ULP each way).
Range3 mul_on_device(const Range3& r, double k) {
  Range3 out = r;
  for (int c = 0; c < 3; ++c) {
    const spirv::Interval m = spirv::mul({r.lo[c], r.hi[c]}, spirv::Interval::point(k));
    out.lo[c] = m.lo;
    out.hi[c] = m.hi;
  }
  return out;
}

// The range of `at` with the upstream shader arithmetic's noise: kShaderNoise of its largest
// channel (noise_range.h).
Range3 with_shader_noise(const Vec3& at) {
  Range3 r = Range3::point(at);
  widen_noise(at, kShaderNoise, &r);
  return r;
}

// pow(x, 2.4) (BT.1886's re-linearisation of Filmic's automatic HDR) on a device: inherited from
// exp2(2.4·log2 x); log2's 3 ulp(24) = 5.7e-6 absolute times 2.4·ln 2: 9.5e-6 relative; exp2 of
// |2.4·log2 x| ≤ 58: 3 + 2·58 = 119 ulp = 1.4e-5 relative. Together 2.4e-5, under 2^-15
// (kShaderNoise), the figure applied.
constexpr double kBt1886PowNoise = kShaderNoise;

// Each lookup of the trilinear filter's three lerp levels rounds (a + t·(b − a): 2.5 ULP of the
// larger operand, spirv_precision.h; as strip_device_range.h): 7.5 ULP of the largest texel bound.
constexpr double kTrilinearUlps = 7.5;

// linear_tap_boxes (the consecutive boxes of one texel pair already merged there), with a pair
// of equal (clamped) taps weighing nothing: one corner.
std::vector<TapBox> merged_tap_boxes(double t, int size, int bits, double noise) {
  std::vector<TapBox> out = linear_tap_boxes(t, size, bits, noise);
  for (TapBox& b : out)
    if (b.i0 == b.i1) b.f_lo = b.f_hi = 0;
  return out;
}

}  // namespace

const Range3& CombineLuts58::inner_stored_range(int r, int g, int b,
                                                const DevicePrecision& device) const {
  const int m = p_.ue58_inner_lut_size;
  const size_t i = (static_cast<size_t>(b) * m + g) * m + r;
  if (inner_range_done_[i]) return inner_range_[i];
  const Vec3& stored = inner_stored(r, g, b);  // and inner_out_[i], the output before its encode
  // The lattice coordinate's decode on a device (MainCS: DispatchThreadId * InvLUTSizeMinusOne, a
  // multiply by the float32 reciprocal, or the GLSL twin's division by M - 1: the hull of both;
  // Filmic's x 0.5080784215; ST2084ToLinear, pq_decode_on_device): near the SDR peak the
  // decode's bounds leave the nits about 2e-4 relative wide (pow(., 1/m1 = 6.28) of the
  // difference Np - c1). The output transform is evaluated at the 8 corners of that box, each
  // with kShaderNoise on top (docs/ue58-decisions.md E9: Filmic's SDR inverse amplifies the box
  // where the inverse gamut compressor is near its asymptote and a channel of a saturated colour
  // lands near black).
  spirv::Interval box[3];
  const int idx[3] = {r, g, b};
  const bool filmic = p_.ue58_tonemapping_method != static_cast<int>(Method::kStandardAces);
  for (int c = 0; c < 3; ++c) {
    const spirv::Interval n = spirv::Interval::point(idx[c]);
    const spirv::Interval by_mul =
        spirv::mul(n, spirv::Interval::point(static_cast<float>(1.0 / (m - 1))));
    const spirv::Interval by_div = spirv::div(n, spirv::Interval::point(m - 1));
    spirv::Interval e{std::fmin(by_mul.lo, by_div.lo), std::fmax(by_mul.hi, by_div.hi)};
    if (filmic) e = spirv::mul(e, spirv::Interval::point(static_cast<float>(kFilmPqUnscale)));
    box[c] = {pq_decode_on_device(std::fmax(e.lo, 0.0)).lo, pq_decode_on_device(e.hi).hi};
  }
  Range3 out = with_shader_noise(inner_out_[i]);
  for (int k = 0; k < 8; ++k) {
    const Vec3 nits{k & 1 ? box[0].hi : box[0].lo, k & 2 ? box[1].hi : box[1].lo,
                    k & 4 ? box[2].hi : box[2].lo};
    const Range3 corner = with_shader_noise(inner_output_from_nits(nits));
    out.include(corner.lo);
    out.include(corner.hi);
  }
  Range3 enc;
  if (p_.output_max_luminance > kLinearToNits) {
    enc = pq_clamped_on_device(out);
  } else {
    // saturate(out / 100) (NaN → 0), then the sRGB encode's pow (kEncodePowNoise).
    Range3 x = scale(out, 1.0 / kLinearToNits);
    for (int c = 0; c < 3; ++c) {
      x.lo[c] = std::isnan(x.lo[c]) || x.nan[c] ? 0.0 : std::clamp(x.lo[c], 0.0, 1.0);
      x.hi[c] = std::isnan(x.hi[c]) ? 0.0 : std::clamp(x.hi[c], 0.0, 1.0);
      x.nan[c] = false;
    }
    enc = widen_relative(map_nondecreasing(x, [](double v) { return linear_to_srgb(v); }),
                         kEncodePowNoise);
  }
  enc.include(
      inner_encode(inner_out_[i]));  // the float32-exact value, whatever path rounded the ends
  Vec3 lo, hi;
  uint8_t nan = 0;
  store_either_way(p_.ue58_inner_format, device.fp16_rte, enc, &lo, &hi, &nan);
  Range3& range = inner_range_[i];
  for (int c = 0; c < 3; ++c) {
    range.lo[c] = std::fmin(lo[c], stored[c]);
    range.hi[c] = std::fmax(hi[c], stored[c]);
    range.nan[c] = (nan & (1u << c)) != 0 || std::isnan(stored[c]);
  }
  inner_range_done_[i] = 1;
  return range;
}

Range3 CombineLuts58::inner_lookup_range(const Range3& encoded, bool inv_eotf_pq,
                                         const DevicePrecision& device) const {
  const int m = p_.ue58_inner_lut_size;
  Range3 color;
  if (inner_.empty()) return Range3::point({0, 0, 0});  // as inner_lookup: never on such a path
  // Per axis: UVW = encoded·(1 − 1/M) + 0.5/M and the filter's UVW·M − 0.5 = encoded·(M − 1),
  // over the coordinate's range, plus the float32 rounding of those steps (a few ULP of UVW ≤ 1,
  // times M in texel units: 4 ULP of max(1, |encoded|)).
  std::vector<TapBox> taps[3];
  bool nan_in = false;
  for (int a = 0; a < 3; ++a) {
    nan_in = nan_in || encoded.nan[a];
    const double lo = encoded.lo[a] * (m - 1), hi = encoded.hi[a] * (m - 1);
    const double noise =
        0.5 * (hi - lo) + 4.0 * spirv::ulp32(std::fmax(1.0, std::fabs(encoded.hi[a]))) * m;
    taps[a] = merged_tap_boxes(0.5 * (lo + hi), m, device.sub_texel_bits, noise);
  }
  for (int c = 0; c < 3; ++c) {
    color.lo[c] = HUGE_VAL;
    color.hi[c] = -HUGE_VAL;
  }
  bool all_nonnegative = true;
  double big = 0;
  uint8_t nan = 0;
  // Every combination of the axes' boxes, every corner of each box: the filtered value is linear
  // in each weight (and nondecreasing in each texel), so the per-channel extremes lie there
  // (as reference/ue/combine_luts.cpp sample_lut_device_range).
  const size_t combos = taps[0].size() * taps[1].size() * taps[2].size();
  for (size_t combo = 0; combo < combos; ++combo) {
    const TapBox* box[3] = {&taps[0][combo % taps[0].size()],
                            &taps[1][(combo / taps[0].size()) % taps[1].size()],
                            &taps[2][combo / (taps[0].size() * taps[1].size())]};
    // The 8 texels of this combination, once; then the corners (one per axis where the box is
    // a single weight).
    const Range3* texel[8];
    for (int k = 0; k < 8; ++k) {
      // A texel whose weight is 0 at every corner is not read (as inner_lookup skips it).
      bool read = true;
      for (int a = 0; a < 3; ++a)
        read = read && ((k >> a) & 1 ? box[a]->f_hi > 0 : box[a]->f_lo < 1);
      texel[k] = nullptr;
      if (!read) continue;
      texel[k] =
          &inner_stored_range(k & 1 ? box[0]->i1 : box[0]->i0, k & 2 ? box[1]->i1 : box[1]->i0,
                              k & 4 ? box[2]->i1 : box[2]->i0, device);
      for (int c = 0; c < 3; ++c) {
        if (texel[k]->nan[c]) nan |= uint8_t(1u << c);
        all_nonnegative = all_nonnegative && texel[k]->lo[c] >= 0;
        big = std::fmax(big, std::fmax(std::fabs(texel[k]->lo[c]), std::fabs(texel[k]->hi[c])));
      }
    }
    for (int corner = 0; corner < 8; ++corner) {
      bool repeated = false;
      for (int a = 0; a < 3; ++a)
        repeated = repeated || (((corner >> a) & 1) && box[a]->f_lo == box[a]->f_hi);
      if (repeated) continue;
      Vec3 slo{}, shi{};
      for (int k = 0; k < 8; ++k) {
        double w = 1;
        for (int a = 0; a < 3; ++a) {
          const double f = (corner >> a) & 1 ? box[a]->f_hi : box[a]->f_lo;
          w *= (k >> a) & 1 ? f : 1 - f;
        }
        if (w == 0 || !texel[k]) continue;
        for (int c = 0; c < 3; ++c) {
          slo[c] += w * texel[k]->lo[c];
          shi[c] += w * texel[k]->hi[c];
        }
      }
      for (int c = 0; c < 3; ++c) {
        color.lo[c] = std::fmin(color.lo[c], slo[c]);
        color.hi[c] = std::fmax(color.hi[c], shi[c]);
      }
    }
  }
  const double e = kTrilinearUlps * spirv::ulp32(big);
  for (int c = 0; c < 3; ++c) {
    color.lo[c] -= e;
    if (all_nonnegative) color.lo[c] = std::fmax(color.lo[c], 0.0);
    color.hi[c] += e;
    color.nan[c] = nan_in || (nan & (1u << c)) != 0;
  }
  if (p_.output_max_luminance > kLinearToNits) {
    if (inv_eotf_pq) return color;
    // ST2084ToLinear on a device (pq_decode_on_device, increasing), then / 100.
    Range3 nits = color;
    for (int c = 0; c < 3; ++c) {
      nits.lo[c] = pq_decode_on_device(color.lo[c]).lo;
      nits.hi[c] = pq_decode_on_device(color.hi[c]).hi;
    }
    return mul_on_device(nits, 1.0 / kLinearToNits);
  }
  // sRGBToLinear (without the min-normal clamp), its pow's kEncodePowNoise.
  Range3 linear = widen_relative(
      map_nondecreasing(color, [](double v) { return srgb_to_linear(v, MinNormalClamp::kOff); }),
      kEncodePowNoise);
  return inv_eotf_pq ? pq_on_device(mul_on_device(linear, kLinearToNits)) : linear;
}

Range3 CombineLuts58::tone_curve_range(const Vec3& color_ap1, double peak, bool inv_eotf_pq,
                                       const DevicePrecision& device) const {
  if (p_.ue58_tonemapping_method == static_cast<int>(Method::kStandardAces)) {
    const Vec3 graded_ap1 = p_.wcs_to_ap1 * graded_color(color_ap1);
    const Range3 nits = with_shader_noise(scale(graded_ap1, kLinearToNits));
    return inner_lookup_range(pq_clamped_on_device(nits), inv_eotf_pq, device);
  }
  const grading::InverseGamma gamma{p_.inverse_gamma[0], p_.inverse_gamma[1], p_.inverse_gamma[2]};
  Range3 out = map_nondecreasing(with_shader_noise(film_color_no_gamma(color_ap1)), [&](double v) {
    return grading::apply_film_gamma({v, v, v}, gamma)[0];
  });
  if (gamma.y != 1.0) out = widen_relative(out, kEncodePowNoise);
  if (!(p_.wcs_is_srgb && p_.output_gamut == 0))
    out = apply_matrix(p_.ap1_to_output, apply_matrix(p_.wcs_to_ap1, out));
  if (peak > kLinearToNits) {
    if (p_.ue58_sdr_inv_eotf == 0) {
      out = widen_relative(map_nondecreasing(out, [](double v) { return linear_to_srgb(v); }),
                           kEncodePowNoise);
      out = widen_relative(map_nonnegative(out, [](double v) { return d3d::pow(v, kBt1886Gamma); }),
                           kBt1886PowNoise);
    }
    const Range3 enc =
        mul_on_device(pq_clamped_on_device(mul_on_device(out, kLinearToNits)), kFilmPqScale);
    return inner_lookup_range(enc, inv_eotf_pq, device);
  }
  return inv_eotf_pq ? pq_on_device(mul_on_device(out, kLinearToNits)) : out;
}

Range3 CombineLuts58::outer_texel_range(const Vec3& e, const DevicePrecision& device) const {
  const Vec3 cc = color_corrected(e);
  const double peak = p_.output_max_luminance;
  Range3 d;
  switch (p_.output_device) {
    case 0: {
      const Range3 x = tone_curve_range(cc, kLinearToNits, false, device);
      d = p_.ue58_sdr_inv_eotf == 0
              ? map_nondecreasing(x, [](double v) { return linear_to_srgb(v); })
              : map_nonnegative(x, [](double v) { return d3d::pow(v, 1.0 / kBt1886Gamma); });
      d = widen_relative(d, kEncodePowNoise);
      break;
    }
    case 1:
      d = widen_relative(map_nondecreasing(tone_curve_range(cc, kLinearToNits, false, device),
                                           [](double v) { return linear_to_rec709_branchless(v); }),
                         kEncodePowNoise);
      break;
    case 3:
    case 4:
      d = tone_curve_range(cc, peak, true, device);
      break;
    case 5:
    case 6:
      d = mul_on_device(tone_curve_range(cc, peak, false, device), kLinearToNits / kScRgbWhiteNits);
      break;
    case 7: {
      const Range3 out = apply_matrix(
          p_.ap1_to_output, apply_matrix(p_.wcs_to_ap1, with_shader_noise(graded_color(cc))));
      d = pq_on_device(mul_on_device(out, kLinearToNits));
      break;
    }
    case 8:
      d = with_shader_noise(graded_color(cc));
      break;
    case 9:
      d = tone_curve_range(cc, kLinearToNits, false, device);
      break;
    default: {  // 2: explicit gamma
      const double g = p_.inverse_gamma[2];
      d = widen_relative(map_nonnegative(tone_curve_range(cc, kLinearToNits, false, device),
                                         [g](double v) { return d3d::pow(v, g); }),
                         kEncodePowNoise);
    }
  }
  if (p_.ue58_lut_inv_max != 1.0) d = mul_on_device(d, p_.ue58_lut_inv_max);
  d.include(outer_texel(e));  // the float32-exact value, whatever path rounded the ends
  return d;
}

DeviceLutRanges bake_outer_lut_device(const ParamBlock& p, const DevicePrecision& device) {
  return bake_outer_lut_device(CombineLuts58(p), p, device);
}

DeviceLutRanges bake_outer_lut_device(const CombineLuts58& luts, const ParamBlock& p,
                                      const DevicePrecision& device) {
  const int n = p.lut_size;
  const size_t count = static_cast<size_t>(n) * n * n;
  DeviceLutRanges out;
  out.lo.resize(count);
  out.hi.resize(count);
  out.nan.assign(count, 0);
  const double step = 1.0 / (n - 1);
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r) {
        const size_t i = (static_cast<size_t>(b) * n + g) * n + r;
        const Vec3 e{r * step, g * step, b * step};
        // The range holds outer_texel's value (outer_texel_range includes it), so the store's
        // either-way ends hold the tight bake's nearest value too.
        store_either_way(p.lut_format, device.fp16_rte, luts.outer_texel_range(e, device),
                         &out.lo[i], &out.hi[i], &out.nan[i]);
      }
  return out;
}

std::vector<Vec3> bake_outer_lut(const ParamBlock& p) {
  return bake_outer_lut(CombineLuts58(p), p);
}

std::vector<Vec3> bake_outer_lut(const CombineLuts58& luts, const ParamBlock& p) {
  const int n = p.lut_size;
  std::vector<Vec3> out(static_cast<size_t>(n) * n * n);
  const double step = 1.0 / (n - 1);  // MainCS: DispatchThreadId * InvLUTSizeMinusOne
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r) {
        const Vec3 v = luts.outer_texel({r * step, g * step, b * step});
        Vec3& t = out[(static_cast<size_t>(b) * n + g) * n + r];
        for (int c = 0; c < 3; ++c) t[c] = quantize_lut_value(p.lut_format, v[c]);
      }
  return out;
}

}  // namespace hdrc::ref::ue58
