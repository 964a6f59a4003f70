#include "reference/ue/ue58/ue58_combine_luts.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "color/d3d_math.h"
#include "color/gamma_correction.h"
#include "color/st2084.h"
#include "reference/color/ue_log_shaper.h"
#include "reference/ue/aces/aces_output.h"
#include "reference/ue/combine_luts.h"
#include "reference/ue/grading/color_correct.h"
#include "reference/ue/grading/color_polynomial.h"
#include "reference/ue/grading/expand_gamut.h"
#include "reference/ue/grading/film_tonemap.h"
#include "reference/ue/grading/hlsl_ops.h"

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
  inner_done_.assign(m * m * m, 0);
}

// AddCombineLUTPass: the inner LUT, M^3 texels at (i, j, k) / (M - 1) (MainCS: DispatchThreadId
// * InvLUTSizeMinusOne), stored in the LUT format (CreateLUTRenderTarget: A2B10G10R10, or
// PF_FloatRGBA when bUseFloatOutput).
const Vec3& CombineLuts58::inner_stored(int r, int g, int b) const {
  const int m = p_.ue58_inner_lut_size;
  const size_t i = (static_cast<size_t>(b) * m + g) * m + r;
  if (!inner_done_[i]) {
    const double step = 1.0 / (m - 1);
    const Vec3 v = inner_texel({r * step, g * step, b * step});
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

// PostProcessCombineLUTsInner.usf: MethodLUTsCommon.
Vec3 CombineLuts58::inner_texel(const Vec3& e) const {
  Vec3 graded;
  if (p_.ue58_tonemapping_method == static_cast<int>(Method::kStandardAces)) {
    graded = p_.wcs_from_ap1 * scale(pq_inv(e), 1.0 / kLinearToNits);
  } else {
    // "Automatic HDR": undo the outer LUT's x 1.9682001, then the SDR inverse.
    graded = inv_output_aces(pq_inv(scale(e, kFilmPqUnscale)));
  }
  Vec3 out = output_aces(graded);
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

// PostProcessCombineLUTs.usf: CombineLUTsCommon.
Vec3 CombineLuts58::outer_texel(const Vec3& e) const {
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
  const Vec3 cc = grading::color_correct_all(ap1, color_correct_params(p_));
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

std::vector<Vec3> bake_outer_lut(const ParamBlock& p) {
  const CombineLuts58 luts(p);
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
