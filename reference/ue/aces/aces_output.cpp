#include "reference/ue/aces/aces_output.h"

#include <cmath>

#include "color/d3d_math.h"
#include "reference/color/noise_range.h"
#include "reference/color/ue_matrices.h"
#include "reference/ue/aces/aces_common.h"

namespace hdrc::ref::aces {
namespace {

namespace lit = ue_literal;

// ACES.ush constants.
constexpr double kHalfPosInf = 65535.0;  // HALF_POS_INF (sic, not 65504)
constexpr double kHalfMax = 65504.0;     // HALF_MAX
constexpr double kRrtSatFactor = 0.96;   // RRT_SAT_FACTOR
// compressColor: LIM_CYAN/MAGENTA/YELLOW, THR_CYAN/MAGENTA/YELLOW, PWR.
constexpr Vec3 kCompressLimit{1.147, 1.264, 1.312};
constexpr Vec3 kCompressThreshold{0.815, 0.803, 0.880};
constexpr double kCompressPower = 1.2;

// HLSL clamp(x, lo, hi) = min(max(x, lo), hi) with maxNum/minNum: NaN → lo.
inline double hlsl_clamp(double x, double lo, double hi) {
  return d3d::min_num(d3d::max_num(x, lo), hi);
}

inline Vec3 hlsl_clamp(const Vec3& v, double lo, double hi) {
  return {hlsl_clamp(v[0], lo, hi), hlsl_clamp(v[1], lo, hi), hlsl_clamp(v[2], lo, hi)};
}

// HLSL lerp(a, b, t) = a + t·(b − a).
double lerp(double a, double b, double t) {
  return a + t * (b - a);
}

// ACES.ush: ssts's (a, b, c) = mul(cf, M1) with M1 = [[0.5, −1, 0.5], [−1, 1, 0.5], [0.5, 0, 0]]
// applied to the row vector cf = coefs[j..j+2], for every interval j = 0 … 3 (j = 3 when
// knot_coord rounds to 3, hence the 6th coefficient). A function of the parameters only:
// computed once per TsParams (SstsPrecomputed::low/high) with the shader's operations.
std::array<SplineSegment, 4> spline_segments(const std::array<double, 6>& coefs) {
  std::array<SplineSegment, 4> seg;
  for (int j = 0; j < 4; ++j) {
    const double c0 = coefs[j], c1 = coefs[j + 1], c2 = coefs[j + 2];
    seg[j] = {0.5 * c0 - c1 + 0.5 * c2, -c0 + c1, 0.5 * c0 + 0.5 * c1};
  }
  return seg;
}

// ACES.ush: ssts, one spline half. knot_coord = (N_KNOTS − 1)·(lx − lo)/(hi − lo), j = int() (the
// HLSL float→int conversion truncates toward zero; knot_coord > 0 here), t = knot_coord − j;
// logy = (t², t, 1) · (a, b, c)_j.
inline double spline_half(double lx, double log_lo, double log_hi,
                          const std::array<SplineSegment, 4>& seg) {
  const double knot_coord = 3.0 * (lx - log_lo) / (log_hi - log_lo);
  const int j = static_cast<int>(knot_coord);
  const double t = knot_coord - j;
  return t * t * seg[j].a + t * seg[j].b + seg[j].c;
}

// ACES.ush: compress's scale, scl = (lim − thr) / pow(pow((1 − thr)/(lim − thr), −pwr) − 1, 1/pwr):
// a function of the constants only, which ACES.ush evaluates on every call; here once per channel.
const Vec3& compress_scale() {
  static const Vec3 scale = [] {
    Vec3 scl;
    for (int i = 0; i < 3; ++i) {
      const double lim = kCompressLimit[i], thr = kCompressThreshold[i], pwr = kCompressPower;
      scl[i] = (lim - thr) / d3d::pow(d3d::pow((1.0 - thr) / (lim - thr), -pwr) - 1.0, 1.0 / pwr);
    }
    return scl;
  }();
  return scale;
}

// ACES.ush: compress — distance compression above the threshold (forward only); `scl` is
// compress_scale()'s.
double compress(double dist, double thr, double pwr, double scl) {
  if (dist < thr) return dist;
  const double nd = (dist - thr) / scl;
  const double p = d3d::pow(nd, pwr);
  return thr + scl * nd / d3d::pow(1.0 + p, 1.0 / pwr);
}

// ACES.ush: cubic_basis_shaper(center_hue(rgb_2_hue(rgb), RRT_RED_HUE), RRT_RED_WIDTH), without
// rgb_2_hue's atan2(y, x) where the result is known to be exactly 0: for a non-grey rgb with
// x = 2r − g − b < 0 and y = √3(g − b) not NaN, atan2 lies in [π/2, π] or [−π, −π/2] (glibc's
// atan2 is within an ulp), so the hue is in [90°, 270°] and, centred on RRT_RED_HUE = 0°, at least
// 90° > RRT_RED_WIDTH/2 = 67.5° away, where cubic_basis_shaper returns 0.0·1.5 = +0. x and y are
// rgb_2_hue's own expressions. Greys keep rgb_2_hue's special case (hue 0).
double red_hue_weight(const Vec3& rgb) {
  static_assert(kRrtRedHue == 0.0 && kRrtRedWidth / 2.0 < 90.0);
  const double x = 2.0 * rgb[0] - rgb[1] - rgb[2];
  const double y = std::sqrt(3.0) * (rgb[1] - rgb[2]);
  const bool grey = rgb[0] == rgb[1] && rgb[1] == rgb[2];
  if (x < 0.0 && !std::isnan(y) && !grey) return 0.0;
  return cubic_basis_shaper(center_hue(rgb_2_hue(rgb), kRrtRedHue), kRrtRedWidth);
}

// ACES.ush: limit_to_primaries with LIMITING_PRI = ACEScg (XYZ_2_AP1_MAT / AP1_2_XYZ_MAT).
Vec3 limit_to_ap1(const Vec3& xyz) {
  return lit::kAp1ToXyz * hlsl_clamp(lit::kXyzToAp1 * xyz, 0.0, 1.0);
}

// Whether lerp(aces, compress_color(aces), 0) is `aces` itself, bit for bit, without computing
// compress_color. lerp(a, c, ±0) = a + ±0·(c − a) = a when c − a is finite and a ≠ 0 (only
// −0 + +0 = +0 changes a bit). c − a is finite when every |a| ≤ 1e290: AP0_2_AP1's rows have
// absolute sums ≤ 1.91, so |AP1| ≤ 1.91e290; bypassed, compr = AP1; otherwise ach ≥ 1e-10, so
// every dist = (ach − AP1)/ach is finite and ≥ 0, compress(dist) is dist < thr < 1 or finite in
// [thr, lim + rounding] (nd^pwr may overflow to +Inf, which yields thr), so
// |ach − compr_dist·ach| ≤ ach; AP1_2_AP0's rows have absolute sums ≤ 1.012, so |c| < 2e290. NaN,
// ±Inf, huge and zero channels take the full path, where compressColor's NaN (see header) or the
// sign of zero must come out.
bool gamut_compression_is_identity(const Vec3& aces, double gamut_compression) {
  if (gamut_compression != 0.0) return false;
  for (const double v : aces) {
    if (!(std::fabs(v) <= 1e290) || v == 0.0) return false;
  }
  return true;
}

Vec3 output_transform_precomputed(const Vec3& aces, const TsParams& params,
                                  const SstsPrecomputed& pre);

// TonemapCommon.ush: ACESOutputTransforms1000/2000 body up to outputTransform's input (AP0).
Vec3 aces_output_input(const Vec3& scene_linear, const Mat3& wcs_to_ap0,
                       const AcesShaderParams& params) {
  const double scm = params.scene_color_multiplier;
  Vec3 aces =
      wcs_to_ap0 * Vec3{scene_linear[0] * scm, scene_linear[1] * scm, scene_linear[2] * scm};
  // GamutCompression = 0 is UE's default; there the lerp keeps `aces` except for the inputs
  // gamut_compression_is_identity() sends through it.
  if (!gamut_compression_is_identity(aces, params.gamut_compression)) {
    const Vec3 compressed = compress_color(aces);
    for (int i = 0; i < 3; ++i) aces[i] = lerp(aces[i], compressed[i], params.gamut_compression);
  }
  return aces;
}

// TonemapCommon.ush: ACESOutputTransforms1000/2000 body.
Vec3 aces_output_transforms(const Vec3& scene_linear, const Mat3& wcs_to_ap0,
                            const AcesShaderParams& params) {
  return output_transform_precomputed(aces_output_input(scene_linear, wcs_to_ap0, params),
                                      params.aces_params, params.ssts_pre);
}

}  // namespace

AcesShaderParams compute_aces_tonemap_params(const AcesTonemapParams& packed) {
  AcesShaderParams out;
  TsParams& p = out.aces_params;
  p.min = {packed.min_max_data[0], packed.min_max_data[1], 0.0};
  p.mid = {packed.mid_data[0], packed.mid_data[1], packed.mid_data[2]};
  p.max = {packed.min_max_data[2], packed.min_max_data[3], 0.0};
  p.coefs_low = {packed.coefs_low_0[0], packed.coefs_low_0[1], packed.coefs_low_0[2],
                 packed.coefs_low_0[3], packed.coefs_low_4,    packed.coefs_low_4};
  p.coefs_high = {packed.coefs_high_0[0], packed.coefs_high_0[1], packed.coefs_high_0[2],
                  packed.coefs_high_0[3], packed.coefs_high_4,    packed.coefs_high_4};
  out.scene_color_multiplier = packed.scene_color_multiplier;
  out.gamut_compression = packed.gamut_compression;
  out.ssts_pre = ssts_precompute(p);
  return out;
}

SstsPrecomputed ssts_precompute(const TsParams& c) {
  SstsPrecomputed l;
  l.min_x = std::log10(c.min.x);
  l.mid_x = std::log10(c.mid.x);
  l.max_x = std::log10(c.max.x);
  l.min_icpt = std::log10(c.min.y) - c.min.slope * l.min_x;
  l.max_icpt = std::log10(c.max.y) - c.max.slope * l.max_x;
  l.low = spline_segments(c.coefs_low);
  l.high = spline_segments(c.coefs_high);
  return l;
}

namespace {

// ACES.ush: ssts, with l = ssts_precompute(c).
inline double ssts_precomputed(double x, const TsParams& c, const SstsPrecomputed& l) {
  // max(x, 1e-10) is maxNum: NaN → 1e-10, i.e. NaN maps to Min.y like any x ≤ Min.x.
  const double lx = std::log10(d3d::max_num(x, 1e-10));
  double ly;
  if (lx <= l.min_x) {
    ly = lx * c.min.slope + l.min_icpt;
  } else if (lx > l.min_x && lx < l.mid_x) {
    ly = spline_half(lx, l.min_x, l.mid_x, l.low);
  } else if (lx >= l.mid_x && lx < l.max_x) {
    ly = spline_half(lx, l.mid_x, l.max_x, l.high);
  } else {
    ly = lx * c.max.slope + l.max_icpt;
  }
  return d3d::pow(10.0, ly);  // ACES.ush: pow10(x) = pow(10, x)
}

}  // namespace

double ssts(double x, const TsParams& c) {
  return ssts_precomputed(x, c, ssts_precompute(c));
}

Vec3 rrt_sweeteners(const Vec3& in_value) {
  Vec3 aces = in_value;

  // Glow module.
  const double saturation = rgb_2_saturation(aces);
  const double yc_in = rgb_2_yc(aces);
  const double s = sigmoid_shaper((saturation - 0.4) / 0.2);
  const double added_glow = 1.0 + glow_fwd(yc_in, kRrtGlowGain * s, kRrtGlowMid);
  for (double& v : aces) v *= added_glow;

  // Red modifier: hue after glow, saturation from before it (as ACES.ush).
  const double hue_weight = red_hue_weight(aces);
  aces[0] += hue_weight * saturation * (kRrtRedPivot - aces[0]) * (1.0 - kRrtRedScale);

  // ACES to the AP1 rendering space; clamp() maps NaN to 0 (see header).
  aces = hlsl_clamp(aces, 0.0, kHalfPosInf);
  Vec3 rgb_pre = hlsl_clamp(lit::kAp0ToAp1 * aces, 0.0, kHalfMax);

  // Global desaturation: lerp(dot(rgbPre, AP1_RGB2Y), rgbPre, RRT_SAT_FACTOR).
  const double y = dot(rgb_pre, lit::kAp1RgbToY);
  for (double& v : rgb_pre) v = lerp(y, v, kRrtSatFactor);
  return rgb_pre;
}

Vec3 compress_color(const Vec3& aces) {
  const Vec3 lin_ap1 = lit::kAp0ToAp1 * aces;
  // max_f3 is maxNum-based; comparisons with NaN are false, so a NaN `ach` does not bypass.
  const double ach = d3d::max_num(lin_ap1[0], d3d::max_num(lin_ap1[1], lin_ap1[2]));
  Vec3 compr_lin_ap1 = lin_ap1;
  if (!(ach < 1e-10 || aces[0] < 0.0 || aces[1] < 0.0 || aces[2] < 0.0)) {
    const Vec3& scl = compress_scale();
    for (int i = 0; i < 3; ++i) {
      const double dist = (ach - lin_ap1[i]) / std::fabs(ach);
      const double compr_dist = compress(dist, kCompressThreshold[i], kCompressPower, scl[i]);
      compr_lin_ap1[i] = ach - compr_dist * std::fabs(ach);
    }
  }
  return lit::kAp1ToAp0 * compr_lin_ap1;
}

namespace {

// output_transform with ssts_precompute(params) given.
Vec3 output_transform_precomputed(const Vec3& aces, const TsParams& params,
                                  const SstsPrecomputed& pre) {
  const double y_min = params.min.y;  // Y_MIN, nits
  const double y_max = params.max.y;  // Y_MAX, nits

  const Vec3 rgb_pre = rrt_sweeteners(aces);
  Vec3 linear_cv;
  for (int i = 0; i < 3; ++i) {
    const double rgb_post = ssts_precomputed(rgb_pre[i], params, pre);  // nits, AP1
    linear_cv[i] = (rgb_post - y_min) / (y_max - y_min);                // Y_2_linCV
  }
  // AP1 → XYZ; dark surround: no adjustment; limit to the AP1 primaries; the display white is D60
  // so no CAT; XYZ → display primaries (AP1).
  const Vec3 xyz = limit_to_ap1(lit::kAp1ToXyz * linear_cv);
  linear_cv = hlsl_clamp(lit::kXyzToAp1 * xyz, 0.0, kHalfPosInf);
  // EOTF 4 (linear) with STRETCH_BLACK: clamp(linCV_2_Y(linearCV, Y_MAX, 0), 0, HALF_POS_INF).
  Vec3 out;
  for (int i = 0; i < 3; ++i)
    out[i] = hlsl_clamp(linear_cv[i] * (y_max - 0.0) + 0.0, 0.0, kHalfPosInf);
  return out;
}

}  // namespace

Vec3 output_transform(const Vec3& aces, const TsParams& params) {
  return output_transform_precomputed(aces, params, ssts_precompute(params));
}

Vec3 aces_output_transforms_1000(const Vec3& scene_linear, const Mat3& wcs_to_ap0,
                                 const AcesShaderParams& params) {
  return aces_output_transforms(scene_linear, wcs_to_ap0, params);
}

Vec3 aces_output_transforms_2000(const Vec3& scene_linear, const Mat3& wcs_to_ap0,
                                 const AcesShaderParams& params) {
  return aces_output_transforms(scene_linear, wcs_to_ap0, params);
}

Vec3 aces_rgb_pre(const Vec3& scene_linear, const Mat3& wcs_to_ap0,
                  const AcesShaderParams& params) {
  return rrt_sweeteners(aces_output_input(scene_linear, wcs_to_ap0, params));
}

// outputTransform after rrt_sweeteners, on a range: ssts per channel is nondecreasing (ACES.ush:
// the two B-spline halves have nondecreasing coefficients and meet the linear segments at their
// knots, TsParams' slopes ≥ 0), so the range's end points map to the result's; Y_2_linCV and
// linCV_2_Y are increasing affine maps (Y_MAX > Y_MIN); the clamps are nondecreasing; the matrix
// pairs around limit_to_primaries are linear, each applied as its composed matrix (XYZ_2_AP1 ·
// AP1_2_XYZ, one exact interval product: the real values the chain takes for every point of the
// range, without the dependency widening of two separate interval products).
Range3 output_transform_tail_range(const Range3& rgb_pre, const AcesShaderParams& params) {
  const TsParams& c = params.aces_params;
  const double y_min = c.min.y, y_max = c.max.y;
  const Range3 lin_cv = map_nondecreasing(rgb_pre, [&](double v) {
    return (ssts_precomputed(v, c, params.ssts_pre) - y_min) / (y_max - y_min);
  });
  const Mat3 round_trip = lit::kXyzToAp1 * lit::kAp1ToXyz;
  const Range3 limited = map_nondecreasing(apply_matrix(round_trip, lin_cv),
                                           [](double v) { return hlsl_clamp(v, 0.0, 1.0); });
  return map_nondecreasing(apply_matrix(round_trip, limited), [y_max](double v) {
    return hlsl_clamp(hlsl_clamp(v, 0.0, kHalfPosInf) * (y_max - 0.0) + 0.0, 0.0, kHalfPosInf);
  });
}

}  // namespace hdrc::ref::aces
