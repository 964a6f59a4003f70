// UE 5.8's ACES 2.0 output transform: parameters and shader stages in double (aces2.h). Each
// function names the UE function it reproduces; ACESOutputTransform.ush unless another file is
// named.
#include "reference/ue/aces2/aces2.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hdrc::ref::aces2 {

namespace {

// ACESOutputTransform.ush: CAM parameters (dim surround; ACESUtils.cpp has the same constants).
constexpr double kLA = 100.0;  // L_A, adapting luminance
constexpr double kYb = 20.0;   // Y_b, background
constexpr double kRa = 2.0;    // ra = 2 · ac_resp
constexpr double kBa = 0.05;   // ba = 0.05 + (2 − ra)
constexpr Vec3 kSurround{0.9, 0.59, 0.9};
// Gamut compression constants (smoothCusps … compressionThreshold).
constexpr double kSmoothCusps = 0.12;
constexpr double kSmoothM = 0.27;
constexpr double kCuspMidBlend = 1.3;
constexpr double kFocusGainBlend = 0.3;
constexpr double kFocusAdjustGain = 0.55;
constexpr double kFocusDistance = 1.35;
constexpr double kFocusDistanceScaling = 1.75;
constexpr double kCompressionThreshold = 0.75;
// init_ODTParams: chroma compress presets.
constexpr double kChromaCompress = 2.4;
constexpr double kChromaCompressFact = 3.3;
constexpr double kChromaExpand = 1.3;
constexpr double kChromaExpandFact = 0.69;
constexpr double kChromaExpandThr = 0.5;
// chromaCompressionNorm: the hue-dependent normalisation's Fourier coefficients.
constexpr std::array<double, 7> kNormCoefs{11.34072, 16.46899, 7.88380, 14.66441,
                                           -6.37224, 9.19364,  77.12896};
// panlrcm, the Hellwig inverse matrix (Lib.Academy.OutputTransform.ctl: generate_panlrcm,
// normalised so that the first row is 460), applied as (1/1403) · panlrcm · (A, a, b).
const Mat3 kPanlrcm{{460.0, 451.0, 288.0,    //
                     460.0, -891.0, -261.0,  //
                     460.0, -220.0, -6300.0}};

// HLSL semantics used by the shader: sign(0) = 0; max/min/clamp return the other operand for a
// NaN one (D3D10+ IEEE maxNum); lerp(a, b, t) = a + t·(b − a).
double hlsl_sign(double v) {
  return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0);
}
double lerp(double a, double b, double t) {
  return a + t * (b - a);
}
// ACESUtilities.ush: spow (0 for a negative base with a non-integer exponent), sdiv, satan2, smin.
double spow(double base, double e) {
  return (base < 0.0 && e != std::floor(e)) ? 0.0 : std::pow(base, e);
}
double sdiv(double a, double b) {
  return b == 0.0 ? 0.0 : a / b;
}
double satan2(double y, double x) {
  return (x == 0.0 && y == 0.0) ? 0.0 : std::atan2(y, x);
}
double smin(double a, double b, double s) {
  const double h = std::fmax(s - std::fabs(a - b), 0.0) / s;
  return std::fmin(a, b) - h * h * h * s * (1.0 / 6.0);
}
// wrap_to_360, hue_position_in_uniform_table (int() truncates a non-negative value),
// next_position_in_table, base_hue_for_position.
double wrap_to_360(double hue) {
  double y = std::fmod(hue, 360.0);
  if (y < 0.0) y += 360.0;
  return y;
}
int hue_position(double hue, int table_size) {
  return static_cast<int>(wrap_to_360(hue) / 360.0 * table_size);
}
int next_position(int entry, int table_size) {
  return (entry + 1) % table_size;
}

// Viewing-condition constants that every Hellwig function recomputes (k, k4, F_L, z for
// Y_w = 100).
double f_l() {
  const double k = 1.0 / (5.0 * kLA + 1.0);
  const double k4 = std::pow(k, 4.0);
  return 0.2 * k4 * (5.0 * kLA) + 0.1 * std::pow(1.0 - k4, 2.0) * spow(5.0 * kLA, 1.0 / 3.0);
}
double a_w_j() {
  const double f = std::pow(f_l(), 0.42);
  return 400.0 * f / (27.13 + f);
}
double z_of(double y_w) {
  return 1.48 + std::sqrt(sdiv(kYb, y_w));
}

// post_adaptation_non_linear_response_compression_forward / _inverse, per channel.
double panlrc_fwd(double v, double fl) {
  const double f = spow(fl * std::fabs(v) / 100.0, 0.42);
  return 400.0 * hlsl_sign(v) * f / (27.13 + f);
}
double panlrc_inv(double v, double fl) {
  const double av = std::fabs(v);
  return hlsl_sign(v) * 100.0 / fl * spow(27.13 * av / (400.0 - av), 1.0 / 0.42);
}

Vec3 scale(double s, const Vec3& v) {
  return {s * v[0], s * v[1], s * v[2]};
}
Vec3 mul(const Params::Rows& m, const Vec3& v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
          m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}
Params::Rows rows_of(const Mat3& m) {
  Params::Rows r{};
  for (int i = 0; i < 3; ++i) r[i] = {m(i, 0), m(i, 1), m(i, 2), 0.0};
  return r;
}
Vec3 xyz_of(const Params::Row& r) {
  return {r[0], r[1], r[2]};
}

// ACESCommon.ush literals (10 decimals). The AP0/AP1 ones are the same literals UE 5.5's ACES.ush
// writes (reference/color/ue_matrices.cpp cites the files); UE 5.8 moved them to
// ACES/ACESCommon.ush, which is not in the public copy [R]. XYZ_2_CAM16_MAT / CAM16_2_XYZ_MAT:
// ACESCommon.ush's CAM16 pair as a public HLSL port of it writes them [R]; aces2_test measures both
// sets against the matrices derived from chromaticities (largest entry difference < 1e-9), so the
// choice moves no output by more than ~1e-9 relative.
PixelMatrices ue_literal_matrices() {
  PixelMatrices m;
  m.ap0_to_ap1 = Mat3{{1.4514393161, -0.2365107469, -0.2149285693,  //
                       -0.0765537734, 1.1762296998, -0.0996759264,  //
                       0.0083161484, -0.0060324498, 0.9977163014}};
  m.ap1_to_xyz = Mat3{{0.6624541811, 0.1340042065, 0.1561876870,  //
                       0.2722287168, 0.6740817658, 0.0536895174,  //
                       -0.0055746495, 0.0040607335, 1.0103391003}};
  m.ap0_to_xyz = Mat3{{0.9525523959, 0.0000000000, 0.0000936786,   //
                       0.3439664498, 0.7281660966, -0.0721325464,  //
                       0.0000000000, 0.0000000000, 1.0088251844}};
  m.xyz_to_ap0 = Mat3{{1.0498110175, 0.0000000000, -0.0000974845,  //
                       -0.4959030231, 1.3733130458, 0.0982400361,  //
                       0.0000000000, 0.0000000000, 0.9912520182}};
  m.xyz_to_cam16 = Mat3{{0.3640744835, 0.5947008156, 0.04110127349,   //
                         -0.2222450987, 1.0738554823, 0.14794533610,  //
                         -0.0020676190, 0.0488260453, 0.95038755696}};
  m.cam16_to_xyz = Mat3{{2.0512756811, -1.1400313439, 0.0887556628,  //
                         0.4269389763, 0.7005835277, -0.1275225040,  //
                         -0.0174712779, -0.0384725929, 1.0589468739}};
  return m;
}

PixelMatrices derived_matrices() {
  PixelMatrices m;
  m.ap0_to_xyz = rgb_to_xyz(kAp0);
  m.xyz_to_ap0 = inverse(m.ap0_to_xyz);
  m.ap1_to_xyz = rgb_to_xyz(kAp1);
  m.ap0_to_ap1 = inverse(m.ap1_to_xyz) * m.ap0_to_xyz;
  m.cam16_to_xyz = rgb_to_xyz(kCam16);
  m.xyz_to_cam16 = inverse(m.cam16_to_xyz);
  return m;
}

// getFocusGain (the host's GetFocusGain clamps J to limitJmax first, which gives the same value).
double focus_gain(double j, double cusp_j, double limit_j_max) {
  const double thr = lerp(cusp_j, limit_j_max, kFocusGainBlend);
  if (j > thr) {
    const double gain = (limit_j_max - thr) / std::fmax(0.0001, limit_j_max - j);
    return std::pow(std::log10(gain), 1.0 / kFocusAdjustGain) + 1.0;
  }
  return 1.0;
}

// solve_J_intersect.
double solve_j_intersect(double j, double m, double focus_j, double max_j, double slope_gain) {
  const double a = m / (focus_j * slope_gain);
  const bool below = j < focus_j;
  const double b =
      below ? 1.0 - m / slope_gain : -(1.0 + m / slope_gain + max_j * m / (focus_j * slope_gain));
  const double c = below ? -j : max_j * m / slope_gain + j;
  const double root = std::sqrt(b * b - 4.0 * a * c);
  return below ? 2.0 * c / (-b - root) : 2.0 * c / (-b + root);
}

// The projection line's slope through (intersect J, 0) (findGamutBoundaryIntersection,
// getReachBoundary).
double projection_slope(double intersect_j, double focus_j, double max_j, double slope_gain) {
  return intersect_j < focus_j
             ? intersect_j * (intersect_j - focus_j) / (focus_j * slope_gain)
             : (max_j - intersect_j) * (intersect_j - focus_j) / (focus_j * slope_gain);
}

// compressionFunction.
double compression_function(double v, double thr, double lim, bool invert) {
  const double s = (lim - thr) * (1.0 - thr) / (lim - 1.0);
  const double nd = (v - thr) / s;
  if (invert) {
    if (v < thr || lim <= 1.0001 || v > thr + s) return v;
    return thr + s * (-nd / (nd - 1.0));
  }
  if (v < thr || lim <= 1.0001) return v;
  return thr + s * nd / (1.0 + nd);
}

// toe_fwd / toe_inv.
double toe_fwd(double x, double limit, double k1_in, double k2_in) {
  if (x > limit) return x;
  const double k2 = std::fmax(k2_in, 0.001);
  const double k1 = std::sqrt(k1_in * k1_in + k2 * k2);
  const double k3 = (limit + k1) / (limit + k2);
  const double minus_b = k3 * x - k1;
  const double minus_c = k2 * k3 * x;
  return 0.5 * (minus_b + std::sqrt(minus_b * minus_b + 4.0 * minus_c));
}
double toe_inv(double x, double limit, double k1_in, double k2_in) {
  if (x > limit) return x;
  const double k2 = std::fmax(k2_in, 0.001);
  const double k1 = std::sqrt(k1_in * k1_in + k2 * k2);
  const double k3 = (limit + k1) / (limit + k2);
  return (x * x + k1 * x) / (k3 * (x + k2));
}

// compressGamut.
Vec3 compress_gamut(const Vec3& jmh, const Params& p, const Tables& t, double jx, bool invert,
                    const Behaviour& b) {
  const double j = jmh[0], m = jmh[1], h = jmh[2];
  const std::array<double, 2> cusp = cusp_from_table(h, t);
  if (m < 0.0001 || j > p.limit_j_max) return {j, 0.0, h};

  const double focus_j =
      lerp(cusp[0], p.mid_j, std::fmin(1.0, kCuspMidBlend - cusp[0] / p.limit_j_max));
  const double slope_gain = p.limit_j_max * p.focus_dist * focus_gain(jx, cusp[0], p.limit_j_max);
  const double gamma_top = upper_hull_gamma_from_table(h, t);
  const Vec3 boundary = find_gamut_boundary_intersection(jmh, cusp, focus_j, p.limit_j_max,
                                                         slope_gain, gamma_top, p.lower_hull_gamma);
  const double boundary_j = boundary[0], boundary_m = boundary[1], project_j = boundary[2];
  if (b.boundary_guard == Flavour::kOcio && boundary_m <= 0.0) return {j, 0.0, h};

  // getReachBoundary, evaluated at the gamut boundary point.
  const double reach_max_m = reach_m_from_table(h, t);
  const double reach_gain =
      p.limit_j_max * p.focus_dist * focus_gain(boundary_j, cusp[0], p.limit_j_max);
  const double intersect_j =
      solve_j_intersect(boundary_j, boundary_m, focus_j, p.limit_j_max, reach_gain);
  const double reach_slope = projection_slope(intersect_j, focus_j, p.limit_j_max, reach_gain);
  const double reach_m = p.limit_j_max * std::pow(intersect_j / p.limit_j_max, p.model_gamma) *
                         reach_max_m / (p.limit_j_max - reach_slope * reach_max_m);

  const double difference = std::fmax(1.0001, reach_m / boundary_m);
  const double threshold = std::fmax(kCompressionThreshold, 1.0 / difference);
  const double v = compression_function(m / boundary_m, threshold, difference, invert);
  return {project_j + v * (boundary_j - project_j), v * boundary_m, h};
}

}  // namespace

// SMPTE ST 2065-1 (AP0), Academy S-2014-004 (AP1), ITU-R BT.709, SMPTE EG 432-1, ITU-R BT.2020.
const Chromaticities kAp0{{0.7347, 0.2653}, {0.0, 1.0}, {0.0001, -0.0770}, {0.32168, 0.33767}};
const Chromaticities kAp1{{0.713, 0.293}, {0.165, 0.830}, {0.128, 0.044}, {0.32168, 0.33767}};
const Chromaticities kRec709{{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}, {0.3127, 0.3290}};
const Chromaticities kP3D65{{0.680, 0.320}, {0.265, 0.690}, {0.150, 0.060}, {0.3127, 0.3290}};
const Chromaticities kRec2020{{0.708, 0.292}, {0.170, 0.797}, {0.131, 0.046}, {0.3127, 0.3290}};
// Lib.Academy.OutputTransform.ctl: CAM16_PRI.
const Chromaticities kCam16{{0.8336, 0.1735}, {2.3854, -1.4659}, {0.087, -0.125}, {0.333, 0.333}};

Mat3 rgb_to_xyz(const Chromaticities& c) {
  const auto xyz = [](const std::array<double, 2>& xy) {
    return Vec3{xy[0] / xy[1], 1.0, (1.0 - xy[0] - xy[1]) / xy[1]};
  };
  const Vec3 r = xyz(c.red), g = xyz(c.green), b = xyz(c.blue), w = xyz(c.white);
  const Mat3 prim{{r[0], g[0], b[0], r[1], g[1], b[1], r[2], g[2], b[2]}};
  const Vec3 s = inverse(prim) * w;
  return prim * Mat3::diag(s);
}

const PixelMatrices& pixel_matrices(Flavour f) {
  static const PixelMatrices ue = ue_literal_matrices();
  static const PixelMatrices derived = derived_matrices();
  return f == Flavour::kUe ? ue : derived;
}

Params make_params(double peak_luminance, const Chromaticities& limit,
                   const Chromaticities& output) {
  Params p{};
  // Lib.Academy.Tonescale.ctl: init_TSParams.
  const double n = peak_luminance;
  const double n_r = 100.0, g = 1.15, c = 0.18, c_d = 10.013, w_g = 0.14, t_1 = 0.04;
  const double r_hit_min = 128.0, r_hit_max = 896.0;
  const double r_hit = r_hit_min + (r_hit_max - r_hit_min) * (std::log(n / n_r) / std::log(100.0));
  const double m_0 = n / n_r;
  const double m_1 = 0.5 * (m_0 + std::sqrt(m_0 * (m_0 + 4.0 * t_1)));
  const double u = std::pow((r_hit / m_1) / ((r_hit / m_1) + 1.0), g);
  const double m = m_1 / u;
  const double w_i = std::log(n / 100.0) / std::log(2.0);
  const double c_t = c_d / n_r * (1.0 + w_i * w_g);
  const double g_ip = 0.5 * (c_t + std::sqrt(c_t * (c_t + 4.0 * t_1)));
  const double g_ipp2 = -(m_1 * std::pow(g_ip / m, 1.0 / g)) / (std::pow(g_ip / m, 1.0 / g) - 1.0);
  const double w_2 = c / g_ipp2;
  p.peak_luminance = n;
  p.n_r = n_r;
  p.g = g;
  p.t_1 = t_1;
  p.c_t = c_t;
  p.s_2 = w_2 * m_1;
  p.u_2 = std::pow((r_hit / m_1) / ((r_hit / m_1) + w_2), g);
  p.m_2 = m_1 / p.u_2;

  // init_ODTParams.
  p.limit_j_max = y_to_hellwig_j(n);
  p.mid_j = y_to_hellwig_j(c_t * 100.0);
  const double log_peak = std::log10(n / n_r);
  p.compr = kChromaCompress + (kChromaCompress * kChromaCompressFact) * log_peak;
  p.sat = std::fmax(0.2, kChromaExpand - (kChromaExpand * kChromaExpandFact) * log_peak);
  p.sat_thr = kChromaExpandThr / n;
  p.chroma_compress_scale = std::pow(0.03379 * n, 0.30596) - 0.45135;
  p.model_gamma = 1.0 / (kSurround[1] * (1.48 + std::sqrt(kYb / kLA)));
  p.focus_dist = kFocusDistance + kFocusDistance * kFocusDistanceScaling * log_peak;
  p.lower_hull_gamma = 1.14 + 0.07 * log_peak;
  // clamp_AP1: upper_clamp_limit (8 · r_hit).
  p.ap1_clamp_upper = 8.0 * (128.0 + 768.0 * (std::log(n / 100.0) / std::log(10000.0 / 100.0)));

  const Mat3 limit_to_xyz = rgb_to_xyz(limit), output_to_xyz = rgb_to_xyz(output);
  p.limit_rgb_to_xyz = rows_of(limit_to_xyz);
  p.limit_xyz_to_rgb = rows_of(inverse(limit_to_xyz));
  p.output_rgb_to_xyz = rows_of(output_to_xyz);
  p.output_xyz_to_rgb = rows_of(inverse(output_to_xyz));
  const Vec3 w_limit = limit_to_xyz * Vec3{100.0, 100.0, 100.0};
  const Vec3 w_output = output_to_xyz * Vec3{100.0, 100.0, 100.0};
  p.xyz_w_limit = {w_limit[0], w_limit[1], w_limit[2], 0.0};
  p.xyz_w_output = {w_output[0], w_output[1], w_output[2], 0.0};
  return p;
}

Aces2ParamsGpu to_gpu(const Params& p) {
  static_assert(sizeof(Params) == 76 * sizeof(double));
  Aces2ParamsGpu g{};
  const auto* src = reinterpret_cast<const double*>(&p);
  auto* dst = reinterpret_cast<float*>(&g);
  for (int i = 0; i < 76; ++i) dst[i] = static_cast<float>(src[i]);
  return g;
}

// ---- Hellwig 2022 -------------------------------------------------------------------------------

double hellwig_j_to_y(double j) {
  // Hellwig_J_to_Y (surround 0.59, L_A 100, Y_b 20; n = Y_b / 100).
  const double fl = f_l();
  const double z = 1.48 + std::sqrt(kYb / 100.0);
  const double a = a_w_j() * std::pow(std::fabs(j) / 100.0, 1.0 / (kSurround[1] * z));
  return hlsl_sign(j) * 100.0 / fl * std::pow((27.13 * a) / (400.0 - a), 1.0 / 0.42);
}

double y_to_hellwig_j(double y) {
  // Y_to_Hellwig_J.
  const double fl = f_l();
  const double z = 1.48 + std::sqrt(kYb / 100.0);
  const double f = std::pow(fl * std::fabs(y) / 100.0, 0.42);
  return hlsl_sign(y) * 100.0 * std::pow((400.0 * f / (27.13 + f)) / a_w_j(), kSurround[1] * z);
}

Vec3 xyz_to_jmh(const Vec3& xyz_nits, const Vec3& xyz_w, Flavour matrices) {
  // XYZ_to_Hellwig2022_JMh (D = 1: no degree of adaptation).
  const Mat3& to_cam16 = pixel_matrices(matrices).xyz_to_cam16;
  const double y_w = xyz_w[1];
  const Vec3 rgb_w = to_cam16 * xyz_w;
  const double fl = f_l();
  const double z = 1.48 + std::sqrt(kYb / y_w);
  const Vec3 d_rgb{y_w / rgb_w[0], y_w / rgb_w[1], y_w / rgb_w[2]};
  Vec3 rgb_aw, rgb_a;
  const Vec3 rgb = to_cam16 * xyz_nits;
  for (int i = 0; i < 3; ++i) {
    rgb_aw[i] = panlrc_fwd(d_rgb[i] * rgb_w[i], fl);
    rgb_a[i] = panlrc_fwd(d_rgb[i] * rgb[i], fl);
  }
  const double a_w = kRa * rgb_aw[0] + rgb_aw[1] + kBa * rgb_aw[2];
  const double a = rgb_a[0] - 12.0 * rgb_a[1] / 11.0 + rgb_a[2] / 11.0;
  const double b = (rgb_a[0] + rgb_a[1] - 2.0 * rgb_a[2]) / 9.0;
  const double h = wrap_to_360(satan2(b, a) * 180.0 / std::numbers::pi);
  const double achromatic = kRa * rgb_a[0] + rgb_a[1] + kBa * rgb_a[2];
  const double j = 100.0 * std::pow(achromatic / a_w, kSurround[1] * z);
  const double m = (j == 0.0) ? 0.0 : 43.0 * kSurround[2] * std::sqrt(a * a + b * b);
  return {j, m, h};
}

Vec3 jmh_to_xyz(const Vec3& jmh, const Vec3& xyz_w, Flavour matrices) {
  // Hellwig2022_JMh_to_XYZ.
  const PixelMatrices& mats = pixel_matrices(matrices);
  const double y_w = xyz_w[1];
  const Vec3 rgb_w = mats.xyz_to_cam16 * xyz_w;
  const double fl = f_l();
  const double z = z_of(y_w);
  const Vec3 d_rgb{y_w / rgb_w[0], y_w / rgb_w[1], y_w / rgb_w[2]};
  Vec3 rgb_aw;
  for (int i = 0; i < 3; ++i) rgb_aw[i] = panlrc_fwd(d_rgb[i] * rgb_w[i], fl);
  const double a_w = kRa * rgb_aw[0] + rgb_aw[1] + kBa * rgb_aw[2];
  const double hr = jmh[2] / 180.0 * std::numbers::pi;
  const double achromatic = a_w * spow(jmh[0] / 100.0, 1.0 / (kSurround[1] * z));
  const double gamma = jmh[1] / (43.0 * kSurround[2]);
  const Vec3 rgb_a =
      scale(1.0 / 1403.0, kPanlrcm * Vec3{achromatic, gamma * std::cos(hr), gamma * std::sin(hr)});
  Vec3 rgb;
  for (int i = 0; i < 3; ++i) rgb[i] = panlrc_inv(rgb_a[i], fl) / d_rgb[i];
  return mats.cam16_to_xyz * rgb;
}

Vec3 aces_to_jmh(const Vec3& aces, const Params& p, const Behaviour& b) {
  const PixelMatrices& m = pixel_matrices(b.matrices);
  Vec3 ap1 = m.ap0_to_ap1 * aces;
  if (b.ap1_clamp == Flavour::kUe) {
    // clamp_AP1: HLSL clamp(x, 0, hi) = min(max(x, 0), hi), NaN → 0.
    for (double& v : ap1) v = std::fmin(std::fmax(v, 0.0), p.ap1_clamp_upper);
  }
  const Vec3 xyz = m.ap1_to_xyz * ap1;
  const Vec3 xyz_w =
      m.ap0_to_xyz * Vec3{kReferenceLuminance, kReferenceLuminance, kReferenceLuminance};
  return xyz_to_jmh(scale(kReferenceLuminance, xyz), xyz_w, b.matrices);
}

Vec3 jmh_to_aces(const Vec3& jmh, const Behaviour& b) {
  const PixelMatrices& m = pixel_matrices(b.matrices);
  const Vec3 xyz_w =
      m.ap0_to_xyz * Vec3{kReferenceLuminance, kReferenceLuminance, kReferenceLuminance};
  const Vec3 xyz = scale(1.0 / kReferenceLuminance, jmh_to_xyz(jmh, xyz_w, b.matrices));
  return m.xyz_to_ap0 * xyz;
}

// ---- Tonescale and chroma compression
// ------------------------------------------------------------

double tonescale_fwd(double x, const Params& p) {
  // Lib.Academy.Tonescale.ctl: tonescale_fwd (modified Michaelis-Menten plus flare), nits out.
  const double f = p.m_2 * std::pow(std::fmax(0.0, x) / (x + p.s_2), p.g);
  const double h = std::fmax(0.0, f * f / (f + p.t_1));
  return h * p.n_r;
}

double tonescale_inv(double y, const Params& p) {
  // Lib.Academy.Tonescale.ctl: tonescale_inv (y = nits / 100), scene-linear out.
  const double z = std::fmax(0.0, std::fmin(p.peak_luminance / (p.u_2 * p.n_r), y));
  const double h = (z + std::sqrt(z * (4.0 * p.t_1 + z))) / 2.0;
  return p.s_2 / (std::pow(p.m_2 / h, 1.0 / p.g) - 1.0);
}

double reach_m_from_table(double h, const Tables& t) {
  // reachMFromTable: i_hi wraps to 0 after 359, so t = (h − 359)/(0 − 359) there (the CTL and
  // OCIO 2.4.1 do the same). Load outside the 360 texels reads 0 (D3D out-of-bounds Load).
  const int i_lo = hue_position(h, kTableSize);
  const int i_hi = next_position(i_lo, kTableSize);
  const auto load = [&](int i) { return (i >= 0 && i < kTableSize) ? t.reach_m[i] : 0.0; };
  const double tt = (h - i_lo) / static_cast<double>(i_hi - i_lo);
  return lerp(load(i_lo), load(i_hi), tt);
}

std::array<double, 2> cusp_from_table(double h, const Tables& t) {
  // cuspFromTable (the host's CuspToTable also clamps the indices to [0, 361] and i_hi to >= 1;
  // neither can change a result: i starts in [1, 361] and the search keeps low < high).
  int low = 0;
  int high = kBaseIndex + kTableSize;
  int i = std::min(hue_position(h, kTableSize) + kBaseIndex, kTotalTableSize - 1);
  while (low + 1 < high) {
    if (h > t.gamut_cusp[i][2]) {
      low = i;
    } else {
      high = i;
    }
    i = (low + high) / 2;
  }
  const auto& lo = t.gamut_cusp[high - 1];
  const auto& hi = t.gamut_cusp[high];
  const double tt = (h - lo[2]) / (hi[2] - lo[2]);
  return {lerp(lo[0], hi[0], tt), lerp(lo[1], hi[1], tt)};
}

double upper_hull_gamma_from_table(double h, const Tables& t) {
  // hueDependentUpperHullGamma: i_hi = (i_lo + 1) mod 362 (the texture's width, GetDimensions).
  const int i_lo = hue_position(h, kTableSize) + kBaseIndex;
  const int i_hi = next_position(i_lo, kTotalTableSize);
  const double base_hue = (i_lo - kBaseIndex) * 360.0 / kTableSize;
  const auto load = [&](int i) {
    return (i >= 0 && i < kTotalTableSize) ? t.upper_hull_gamma[i] : 0.0;
  };
  return lerp(load(i_lo), load(i_hi), wrap_to_360(h) - base_hue);
}

double chroma_compression_norm(double h, const Params& p) {
  // chromaCompressionNorm.
  const double hr = h / 180.0 * std::numbers::pi;
  const double a = std::cos(hr), b = std::sin(hr);
  const double cos_hr2 = a * a - b * b;
  const double sin_hr2 = 2.0 * a * b;
  const double cos_hr3 = 4.0 * a * a * a - 3.0 * a;
  const double sin_hr3 = 3.0 * b - 4.0 * b * b * b;
  const auto& k = kNormCoefs;
  const double m = k[0] * a + k[1] * cos_hr2 + k[2] * cos_hr3 + k[3] * b + k[4] * sin_hr2 +
                   k[5] * sin_hr3 + k[6];
  return m * p.chroma_compress_scale;
}

double chroma_compression(const Vec3& jmh, double orig_j, const Params& p, const Tables& t,
                          bool invert) {
  // chromaCompression.
  const double j = jmh[0], h = jmh[2];
  double m = jmh[1];
  if (m == 0.0) return m;
  const double nj = j / p.limit_j_max;
  const double snj = std::fmax(0.0, 1.0 - nj);
  const double mnorm = chroma_compression_norm(h, p);
  const double limit = std::pow(nj, p.model_gamma) * reach_m_from_table(h, t) / mnorm;
  const double toe_limit = limit - 0.001;
  const double toe_snj_sat = snj * p.sat;
  const double toe_sqrt_nj_sat_thr = std::sqrt(nj * nj + p.sat_thr);
  const double toe_nj_compr = nj * p.compr;
  if (!invert) {
    m = m * std::pow(j / orig_j, p.model_gamma);
    m = m / mnorm;
    m = limit - toe_fwd(limit - m, toe_limit, toe_snj_sat, toe_sqrt_nj_sat_thr);
    m = toe_fwd(m, limit, toe_nj_compr, snj);
    return m * mnorm;
  }
  m = m / mnorm;
  m = toe_inv(m, limit, toe_nj_compr, snj);
  m = limit - toe_inv(limit - m, toe_limit, toe_snj_sat, toe_sqrt_nj_sat_thr);
  m = m * mnorm;
  return m * std::pow(j / orig_j, -p.model_gamma);
}

Vec3 tonemap_and_compress_fwd(const Vec3& jmh, const Params& p, const Tables& t) {
  // tonemapAndCompress_fwd.
  const double linear = hellwig_j_to_y(jmh[0]) / kReferenceLuminance;
  const double j_ts = y_to_hellwig_j(tonescale_fwd(linear, p));
  const Vec3 out{j_ts, jmh[1], jmh[2]};
  return {j_ts, chroma_compression(out, jmh[0], p, t, false), jmh[2]};
}

Vec3 tonemap_and_compress_inv(const Vec3& jmh, const Params& p, const Tables& t) {
  // tonemapAndCompress_inv.
  const double luminance = hellwig_j_to_y(jmh[0]);
  const double linear = tonescale_inv(luminance / kReferenceLuminance, p);
  const double j = y_to_hellwig_j(linear * kReferenceLuminance);
  return {j, chroma_compression(jmh, j, p, t, true), jmh[2]};
}

// ---- Gamut mapping
// -------------------------------------------------------------------------------

Vec3 find_gamut_boundary_intersection(const Vec3& jmh_s, const std::array<double, 2>& cusp_in,
                                      double j_focus, double j_max, double slope_gain,
                                      double gamma_top, double gamma_bottom) {
  // findGamutBoundaryIntersection: (J, M) of the boundary and the projection's J at M = 0.
  const double s = std::fmax(0.000001, kSmoothCusps);
  const double cusp_j = cusp_in[0];
  const double cusp_m = cusp_in[1] * (1.0 + kSmoothM * s);
  const double j_src = solve_j_intersect(jmh_s[0], jmh_s[1], j_focus, j_max, slope_gain);
  const double j_cusp = solve_j_intersect(cusp_j, cusp_m, j_focus, j_max, slope_gain);
  const double slope = projection_slope(j_src, j_focus, j_max, slope_gain);
  const double m_lower =
      j_cusp * std::pow(j_src / j_cusp, 1.0 / gamma_bottom) / (cusp_j / cusp_m - slope);
  const double m_upper = cusp_m * (j_max - j_cusp) *
                         std::pow((j_max - j_src) / (j_max - j_cusp), 1.0 / gamma_top) /
                         (slope * cusp_m + j_max - cusp_j);
  const double m_boundary = cusp_m * smin(m_lower / cusp_m, m_upper / cusp_m, s);
  return {j_src + slope * m_boundary, m_boundary, j_src};
}

Vec3 gamut_map_fwd(const Vec3& jmh, const Params& p, const Tables& t, const Behaviour& b) {
  return compress_gamut(jmh, p, t, jmh[0], false, b);
}

Vec3 gamut_map_inv(const Vec3& jmh, const Params& p, const Tables& t, const Behaviour& b) {
  // gamutMap_inv: analytic below the focus-gain threshold, one refinement of Jx above it.
  const std::array<double, 2> cusp = cusp_from_table(jmh[2], t);
  double jx = jmh[0];
  if (jx <= lerp(cusp[0], p.limit_j_max, kFocusGainBlend)) {
    return compress_gamut(jmh, p, t, jx, true, b);
  }
  jx = compress_gamut(jmh, p, t, jx, true, b)[0];
  return compress_gamut(jmh, p, t, jx, true, b);
}

// ---- Output ----------------------------------------------------------------------------------

Vec3 jmh_to_output_xyz(const Vec3& jmh, const Params& p, const Behaviour& b) {
  return scale(1.0 / kReferenceLuminance, jmh_to_xyz(jmh, xyz_of(p.xyz_w_limit), b.matrices));
}

Vec3 xyz_output_to_jmh(const Vec3& xyz, const Params& p, const Behaviour& b) {
  return xyz_to_jmh(scale(kReferenceLuminance, xyz), xyz_of(p.xyz_w_limit), b.matrices);
}

Vec3 output_transform_fwd(const Vec3& aces, const Params& p, const Tables& t, const Behaviour& b) {
  const Vec3 jmh = aces_to_jmh(aces, p, b);
  const Vec3 tonemapped = tonemap_and_compress_fwd(jmh, p, t);
  const Vec3 compressed = gamut_map_fwd(tonemapped, p, t, b);
  return jmh_to_output_xyz(compressed, p, b);
}

Vec3 output_transform_inv(const Vec3& xyz, const Params& p, const Tables& t, const Behaviour& b) {
  const Vec3 compressed = xyz_output_to_jmh(xyz, p, b);
  const Vec3 tonemapped = gamut_map_inv(compressed, p, t, b);
  const Vec3 jmh = tonemap_and_compress_inv(tonemapped, p, t);
  return jmh_to_aces(jmh, b);
}

Vec3 limit_rgb_from_xyz(const Vec3& xyz, const Params& p) {
  return mul(p.limit_xyz_to_rgb, xyz);
}

Vec3 xyz_from_limit_rgb(const Vec3& rgb, const Params& p) {
  return mul(p.limit_rgb_to_xyz, rgb);
}

namespace {
// ACESDisplayEncoding.ush: clamp_zero_to_peakLuminance.
Vec3 clamp_zero_to_peak(const Vec3& xyz, const Params& p) {
  Vec3 rgb = mul(p.limit_xyz_to_rgb, xyz);
  for (double& v : rgb) v = std::fmin(std::fmax(v, 0.0), p.peak_luminance / kReferenceLuminance);
  return mul(p.limit_rgb_to_xyz, rgb);
}
// ACESDisplayEncoding.ush: apply_white_scale's factor (1 / the largest encoding channel of the
// limiting white).
double white_scale(const Params& p) {
  const Vec3 rgb_w =
      scale(1.0 / kReferenceLuminance, mul(p.output_xyz_to_rgb, xyz_of(p.xyz_w_limit)));
  return 1.0 / std::fmax(std::fmax(rgb_w[0], rgb_w[1]), rgb_w[2]);
}
}  // namespace

Vec3 aces_output_transform_nits(const Vec3& aces, const Params& p, const Tables& t,
                                bool scale_white, const Behaviour& b) {
  Vec3 xyz = clamp_zero_to_peak(output_transform_fwd(aces, p, t, b), p);
  if (scale_white) xyz = scale(white_scale(p), xyz);
  return scale(kReferenceLuminance, mul(p.output_xyz_to_rgb, xyz));
}

Vec3 aces_inv_output_transform_nits(const Vec3& nits, const Params& p, const Tables& t,
                                    bool scale_white, const Behaviour& b) {
  Vec3 xyz = mul(p.output_rgb_to_xyz, scale(1.0 / kReferenceLuminance, nits));
  if (scale_white) xyz = scale(1.0 / white_scale(p), xyz);
  xyz = clamp_zero_to_peak(xyz, p);
  return output_transform_inv(xyz, p, t, b);
}

}  // namespace hdrc::ref::aces2
