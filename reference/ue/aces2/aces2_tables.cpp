// The host side of UE 5.8's ACES 2.0 transform: the Hellwig parameters of an RGB space and the
// three tables UE builds and uploads as textures (Engine/Source/Runtime/Renderer/Private/
// PostProcess/ACESUtils.cpp at unicorn2022/UE5.8.0 5d9a05c1), in double. UE computes them in float;
// docs/ue58-decisions.md A3 says why the reference stays in double.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "reference/ue/aces2/aces2.h"

namespace hdrc::ref::aces2 {

namespace {

// The host computes in float (ACESUtils.cpp: float members, FMath::Pow/Sqrt/Sin/Cos on floats,
// FMatrix44f matrices built in double and cast); TableScalar selects that or double. All of the
// host code below is written once over the scalar type T.
template <typename T>
using V3 = std::array<T, 3>;
template <typename T>
using M3 = std::array<T, 9>;

template <typename T>
V3<T> mul(const M3<T>& m, const V3<T>& v) {
  return {m[0] * v[0] + m[1] * v[1] + m[2] * v[2], m[3] * v[0] + m[4] * v[1] + m[5] * v[2],
          m[6] * v[0] + m[7] * v[1] + m[8] * v[2]};
}
template <typename T>
M3<T> cast(const Mat3& m) {
  M3<T> r;
  for (int i = 0; i < 9; ++i) r[i] = static_cast<T>(m.m[i]);
  return r;
}

constexpr double kLA = 100.0, kYb = 20.0;

// ACESUtils.cpp: JMhParams.
template <typename T>
struct HostJMh {
  T f_l, z, a_w, a_w_j;
  V3<T> d_rgb;
  M3<T> rgb_to_cam16, cam16_to_rgb;
};

// ACESUtils.cpp: PanlrcForward / PanlrcInverse (FMath::CopySign(1, v): +1 for +0).
template <typename T>
T panlrc_forward(T v, T fl) {
  const T f = std::pow(fl * std::fabs(v) / T(100), T(0.42));
  return (T(400) * std::copysign(T(1), v) * f) / (T(27.13) + f);
}
template <typename T>
T panlrc_inverse(T v, T fl) {
  return std::copysign(T(1), v) * T(100) / fl *
         std::pow((T(27.13) * std::fabs(v) / (T(400) - std::fabs(v))), T(1) / T(0.42));
}

// ACESUtils.cpp: InitJMhParams. XYZ_w and RGB_w are FVector (double) there; the rest float.
template <typename T>
HostJMh<T> init_jmh(const Chromaticities& c) {
  const Mat3 to_xyz = rgb_to_xyz(c);
  const Mat3 xyz_to_cam16 = inverse(rgb_to_xyz(kCam16));
  const Vec3 xyz_w = to_xyz * Vec3{100.0, 100.0, 100.0};
  const T y_w = static_cast<T>(xyz_w[1]);
  const Vec3 rgb_w = xyz_to_cam16 * xyz_w;
  HostJMh<T> p{};
  const T k = T(1) / (T(5) * T(kLA) + T(1));
  const T k4 = std::pow(k, T(4));
  const T n = T(kYb) / y_w;
  p.f_l = T(0.2) * k4 * (T(5) * T(kLA)) +
          T(0.1) * std::pow((T(1) - k4), T(2)) * std::pow(T(5) * T(kLA), T(1) / T(3));
  p.z = T(1.48) + std::sqrt(n);
  V3<T> rgb_aw;
  for (int i = 0; i < 3; ++i) {
    p.d_rgb[i] = y_w / static_cast<T>(rgb_w[i]);
    rgb_aw[i] = panlrc_forward(p.d_rgb[i] * static_cast<T>(rgb_w[i]), p.f_l);
  }
  p.a_w = T(2) * rgb_aw[0] + rgb_aw[1] + T(0.05) * rgb_aw[2];
  const T f_l_w = std::pow(p.f_l, T(0.42));
  p.a_w_j = (T(400) * f_l_w) / (T(27.13) + f_l_w);
  // FColorSpaceTransform(In, CAM16, EChromaticAdaptationMethod::None).ApplyScale(100), in double,
  // then FMatrix44f.
  Mat3 t = xyz_to_cam16 * to_xyz;
  for (double& v : t.m) v *= 100.0;
  p.rgb_to_cam16 = cast<T>(t);
  p.cam16_to_rgb = cast<T>(inverse(t));
  return p;
}

// ACESUtils.cpp: Y_to_J ("optimization used during initialization").
template <typename T>
T host_y_to_j(T y, const HostJMh<T>& p) {
  const T f = std::pow(p.f_l * std::fabs(y) / T(100), T(0.42));
  return std::copysign(T(1), y) * T(100) *
         std::pow(((T(400) * f) / (T(27.13) + f)) / p.a_w_j, T(0.59) * p.z);
}

// ACESUtils.cpp: JMh_to_RGB.
template <typename T>
V3<T> jmh_to_rgb(const V3<T>& jmh, const HostJMh<T>& p) {
  const T hr = jmh[2] * static_cast<T>(std::numbers::pi) / T(180);
  const T sc = jmh[1] / (T(43) * T(0.9));
  const T achromatic = p.a_w * std::pow(jmh[0] / T(100), T(1) / (T(0.59) * p.z));
  const T a = sc * std::cos(hr), b = sc * std::sin(hr);
  const T r_a = (T(460) * achromatic + T(451) * a + T(288) * b) / T(1403);
  const T g_a = (T(460) * achromatic - T(891) * a - T(261) * b) / T(1403);
  const T b_a = (T(460) * achromatic - T(220) * a - T(6300) * b) / T(1403);
  const V3<T> cam{panlrc_inverse(r_a, p.f_l) / p.d_rgb[0], panlrc_inverse(g_a, p.f_l) / p.d_rgb[1],
                  panlrc_inverse(b_a, p.f_l) / p.d_rgb[2]};
  return mul(p.cam16_to_rgb, cam);
}

// ACESUtils.cpp: RGB_to_JMh.
template <typename T>
V3<T> rgb_to_jmh(const V3<T>& rgb, const HostJMh<T>& p) {
  const V3<T> m = mul(p.rgb_to_cam16, rgb);
  const T r = panlrc_forward(m[0] * p.d_rgb[0], p.f_l);
  const T g = panlrc_forward(m[1] * p.d_rgb[1], p.f_l);
  const T b = panlrc_forward(m[2] * p.d_rgb[2], p.f_l);
  const T achromatic = T(2) * r + g + T(0.05) * b;
  const T a = r - T(12) * g / T(11) + b / T(11);
  const T bb = (r + g - T(2) * b) / T(9);
  const T j = T(100) * std::pow(achromatic / p.a_w, T(0.59) * p.z);
  const T mm = j == T(0) ? T(0) : T(43) * T(0.9) * std::sqrt(a * a + bb * bb);
  T h = std::fmod(std::atan2(bb, a) * T(180) / static_cast<T>(std::numbers::pi), T(360));
  if (h < T(0)) h += T(360);
  return {j, mm, h};
}

template <typename T>
bool any_below_zero(const V3<T>& rgb) {
  return rgb[0] < T(0) || rgb[1] < T(0) || rgb[2] < T(0);
}

// ACESUtils.cpp: HSV_to_RGB (hue in [0, 1), six sectors).
template <typename T>
V3<T> hsv_to_rgb(const V3<T>& hsv) {
  const T c = hsv[2] * hsv[1];
  const T x = c * (T(1) - std::fabs(std::fmod(hsv[0] * T(6), T(2)) - T(1)));
  const T m = hsv[2] - c;
  V3<T> rgb;
  if (hsv[0] < T(1) / T(6)) {
    rgb = {c, x, T(0)};
  } else if (hsv[0] < 2.0 / 6.0) {
    rgb = {x, c, T(0)};
  } else if (hsv[0] < 3.0 / 6.0) {
    rgb = {T(0), c, x};
  } else if (hsv[0] < 4.0 / 6.0) {
    rgb = {T(0), x, c};
  } else if (hsv[0] < 5.0 / 6.0) {
    rgb = {x, T(0), c};
  } else {
    rgb = {c, T(0), x};
  }
  return {rgb[0] + m, rgb[1] + m, rgb[2] + m};
}

template <typename T>
T lerp(T a, T b, T t) {
  return a + t * (b - a);
}

// ACESUtils.cpp: CuspToTable (indices clamped to the table, i_hi >= 1).
template <typename T>
std::array<T, 2> cusp_to_table(T h, const std::array<V3<T>, kTotalTableSize>& gt) {
  const auto clamp_index = [](int i) { return std::min(kTotalTableSize - 1, std::max(0, i)); };
  T wrapped = std::fmod(h, T(360));
  if (wrapped < T(0)) wrapped += T(360);
  int lo = 0, hi = kBaseIndex + kTableSize;
  int i = clamp_index(static_cast<int>(wrapped / T(360) * static_cast<T>(kTableSize)) + kBaseIndex);
  while (lo + 1 < hi) {
    if (h > gt[i][2]) {
      lo = i;
    } else {
      hi = i;
    }
    i = clamp_index((lo + hi) / 2);
  }
  hi = std::max(1, hi);
  const T t = (h - gt[hi - 1][2]) / (gt[hi][2] - gt[hi - 1][2]);
  return {lerp(gt[hi - 1][0], gt[hi][0], t), lerp(gt[hi - 1][1], gt[hi][1], t)};
}

// The ODT scalars the host recomputes for MakeUpperHullGamma (FUpperHullGammaTable::Update:
// LimitJMax, Mid_J, FocusDist, LowerHullGamma from InitToneScaleParams and Y_to_J).
template <typename T>
struct HullParams {
  T peak, limit_j_max, mid_j, focus_dist, lower_hull_gamma;
};

// ACESUtils.cpp: GetFocusGain, SolveJIntersect, Smin, FindGamutBoundaryIntersection.
template <typename T>
T focus_gain(T j, T cusp_j, T limit_j_max) {
  const T thr = lerp(cusp_j, limit_j_max, T(0.3));
  if (j > thr) {
    const T gain =
        (limit_j_max - thr) / std::max(T(0.0001), limit_j_max - std::min(limit_j_max, j));
    return std::pow(std::log10(gain), T(1) / T(0.55)) + T(1);
  }
  return T(1);
}
template <typename T>
T solve_j_intersect(T j, T m, T focus_j, T max_j, T slope_gain) {
  const T a = m / (focus_j * slope_gain);
  const bool below = j < focus_j;
  const T b =
      below ? T(1) - m / slope_gain : -(T(1) + m / slope_gain + max_j * m / (focus_j * slope_gain));
  const T c = below ? -j : max_j * m / slope_gain + j;
  const T root = std::sqrt(b * b - T(4) * a * c);
  return below ? T(2) * c / (-b - root) : T(2) * c / (-b + root);
}
template <typename T>
T smin(T a, T b, T s) {
  const T h = std::max(s - std::fabs(a - b), T(0)) / s;
  return std::min(a, b) - h * h * h * s * (T(1) / T(6));
}
template <typename T>
V3<T> boundary_intersection(const V3<T>& jmh_s, const std::array<T, 2>& cusp_in, T j_focus, T j_max,
                            T slope_gain, T gamma_top, T gamma_bottom) {
  const T s = std::max(T(0.000001), T(0.12));
  const T cusp_j = cusp_in[0], cusp_m = cusp_in[1] * (T(1) + T(0.27) * s);
  const T j_src = solve_j_intersect(jmh_s[0], jmh_s[1], j_focus, j_max, slope_gain);
  const T j_cusp = solve_j_intersect(cusp_j, cusp_m, j_focus, j_max, slope_gain);
  const T slope = j_src < j_focus ? j_src * (j_src - j_focus) / (j_focus * slope_gain)
                                  : (j_max - j_src) * (j_src - j_focus) / (j_focus * slope_gain);
  const T m_lower =
      j_cusp * std::pow(j_src / j_cusp, T(1) / gamma_bottom) / (cusp_j / cusp_m - slope);
  const T m_upper = cusp_m * (j_max - j_cusp) *
                    std::pow((j_max - j_src) / (j_max - j_cusp), T(1) / gamma_top) /
                    (slope * cusp_m + j_max - cusp_j);
  const T m_boundary = cusp_m * smin(m_lower / cusp_m, m_upper / cusp_m, s);
  return {j_src + slope * m_boundary, m_boundary, j_src};
}

// ACESUtils.cpp: EvaluateGammaFit — true when all three test points' boundary estimates lie
// outside the limiting RGB cube (OutsideHull: RGB · 100 / peak above 1 in some channel).
template <typename T>
bool evaluate_gamma_fit(const std::array<T, 2>& cusp, const std::array<V3<T>, 3>& test, T top_gamma,
                        const HullParams<T>& hp, const HostJMh<T>& limit) {
  const T focus_j = lerp(cusp[0], hp.mid_j, std::min(T(1), T(1.3) - (cusp[0] / hp.limit_j_max)));
  for (const V3<T>& tj : test) {
    const T slope_gain =
        hp.limit_j_max * hp.focus_dist * focus_gain(tj[0], cusp[0], hp.limit_j_max);
    const V3<T> approx = boundary_intersection(tj, cusp, focus_j, hp.limit_j_max, slope_gain,
                                               top_gamma, hp.lower_hull_gamma);
    const V3<T> rgb = jmh_to_rgb(V3<T>{approx[0], approx[1], tj[2]}, limit);
    const T s = T(100) / hp.peak;
    if (!(rgb[0] * s > T(1) || rgb[1] * s > T(1) || rgb[2] * s > T(1))) return false;
  }
  return true;
}

// ACESUtils.cpp: MakeReachMTable (AP1 is the reach gamut).
template <typename T>
std::array<double, kTableSize> reach_table(double peak_luminance) {
  const HostJMh<T> p = init_jmh<T>(kAp1);
  const T limit_j_max = host_y_to_j(static_cast<T>(peak_luminance), p);
  std::array<double, kTableSize> table{};
  for (int i = 0; i < kTableSize; ++i) {
    const T hue = static_cast<T>(i);
    const T search_range = T(50);
    T low = T(0), high = low + search_range;
    bool outside = false;
    while (!outside && high < T(1300)) {
      outside = any_below_zero(jmh_to_rgb(V3<T>{limit_j_max, high, hue}, p));
      if (!outside) {
        low = high;
        high = high + search_range;
      }
    }
    while (static_cast<double>(high - low) > 1e-2) {  // float − float compared with the double 1e-2
      const T mid = (high + low) / T(2);
      if (any_below_zero(jmh_to_rgb(V3<T>{limit_j_max, mid, hue}, p))) {
        high = mid;
      } else {
        low = mid;
      }
    }
    table[i] = high;
  }
  return table;
}

// ACESUtils.cpp: MakeGamutTable.
template <typename T>
std::array<V3<T>, kTotalTableSize> cusp_table(const Chromaticities& limit, double peak_luminance) {
  const HostJMh<T> p = init_jmh<T>(limit);
  std::array<V3<T>, kTableSize> unsorted;
  for (int i = 0; i < kTableSize; ++i) {
    const T h_norm = static_cast<T>(i) / static_cast<T>(kTableSize);
    const V3<T> rgb = hsv_to_rgb(V3<T>{h_norm, T(1), T(1)});
    const T s = static_cast<T>(peak_luminance) / T(100);
    unsorted[i] = rgb_to_jmh(V3<T>{s * rgb[0], s * rgb[1], s * rgb[2]}, p);
  }
  int min_h = 0;
  for (int i = 0; i < kTableSize; ++i) {
    if (unsorted[i][2] < unsorted[min_h][2]) min_h = i;
  }
  std::array<V3<T>, kTotalTableSize> table{};
  for (int i = 0; i < kTableSize; ++i) table[i + kBaseIndex] = unsorted[(min_h + i) % kTableSize];
  table[0] = table[kBaseIndex + kTableSize - 1];
  table[kBaseIndex + kTableSize] = table[kBaseIndex];
  table[0][2] = table[0][2] - T(360);
  table[kTableSize + 1][2] = table[kTableSize + 1][2] + T(360);
  return table;
}

// ACESUtils.cpp: FUpperHullGammaTable::Update → MakeUpperHullGamma.
template <typename T>
std::array<double, kTotalTableSize> gamma_table(const std::array<V3<T>, kTotalTableSize>& cusps,
                                                double peak_luminance,
                                                const Chromaticities& limit) {
  // The scalars as the host derives them (InitToneScaleParams, Y_to_J with AP0's JMhParams).
  const Params dp = make_params(peak_luminance, limit, limit);
  const HostJMh<T> ap0 = init_jmh<T>(kAp0);
  HullParams<T> hp;
  hp.peak = static_cast<T>(peak_luminance);
  hp.limit_j_max = host_y_to_j(hp.peak, ap0);
  hp.mid_j = host_y_to_j(static_cast<T>(dp.c_t) * T(100), ap0);
  const T log_peak = std::log10(hp.peak / T(100));
  hp.focus_dist = T(1.35) + T(1.35) * T(1.75) * log_peak;
  hp.lower_hull_gamma = T(1.14) + T(0.07) * log_peak;
  const HostJMh<T> limit_params = init_jmh<T>(limit);

  const std::array<T, 3> positions{T(0.01), T(0.5), T(0.99)};
  std::array<T, kTableSize> gamma{};
  for (int i = 0; i < kTableSize; ++i) {
    gamma[i] = T(-1);
    const T hue = static_cast<T>(i);
    const std::array<T, 2> cusp = cusp_to_table(hue, cusps);
    std::array<V3<T>, 3> test;
    for (int k = 0; k < 3; ++k) {
      test[k] = {cusp[0] + ((hp.limit_j_max - cusp[0]) * positions[k]), cusp[1], hue};
    }
    const T step = T(0.4), accuracy = T(1e-5);  // GammaSearchStep, GammaAccuracy
    T low = T(0), high = low + step;            // GammaMinimum
    bool outside = false;
    while (!outside && high < T(5)) {
      if (evaluate_gamma_fit(cusp, test, high, hp, limit_params)) {
        outside = true;
      } else {
        low = high;
        high = high + step;
      }
    }
    while ((high - low) > accuracy) {
      const T g = (high + low) / T(2);
      if (evaluate_gamma_fit(cusp, test, g, hp, limit_params)) {
        high = g;
        gamma[i] = high;
      } else {
        low = g;
      }
    }
  }
  std::array<double, kTotalTableSize> table{};
  for (int i = 0; i < kTableSize; ++i) table[i + kBaseIndex] = gamma[i];
  table[0] = gamma[kTableSize - 1];
  table[kTotalTableSize - 1] = gamma[0];
  return table;
}

template <typename T>
Tables tables(const Params& p, const Chromaticities& limit) {
  Tables t{};
  t.reach_m = reach_table<T>(p.peak_luminance);
  const auto cusps = cusp_table<T>(limit, p.peak_luminance);
  for (int i = 0; i < kTotalTableSize; ++i) {
    for (int c = 0; c < 3; ++c) t.gamut_cusp[i][c] = cusps[i][c];
  }
  t.upper_hull_gamma = gamma_table<T>(cusps, p.peak_luminance, limit);
  return t;
}

}  // namespace

JMhParams make_jmh_params(const Chromaticities& c) {
  const HostJMh<double> h = init_jmh<double>(c);
  JMhParams p{};
  p.f_l = h.f_l;
  p.z = h.z;
  p.a_w = h.a_w;
  p.a_w_j = h.a_w_j;
  p.xyz_w = rgb_to_xyz(c) * Vec3{100.0, 100.0, 100.0};
  p.d_rgb = h.d_rgb;
  std::copy(h.rgb_to_cam16.begin(), h.rgb_to_cam16.end(), p.rgb_to_cam16.m.begin());
  std::copy(h.cam16_to_rgb.begin(), h.cam16_to_rgb.end(), p.cam16_to_rgb.m.begin());
  return p;
}

Vec3 host_rgb_to_jmh(const Vec3& rgb, const JMhParams& p) {
  HostJMh<double> h{p.f_l, p.z, p.a_w, p.a_w_j, p.d_rgb, p.rgb_to_cam16.m, p.cam16_to_rgb.m};
  return rgb_to_jmh<double>(rgb, h);
}

Vec3 host_jmh_to_rgb(const Vec3& jmh, const JMhParams& p) {
  HostJMh<double> h{p.f_l, p.z, p.a_w, p.a_w_j, p.d_rgb, p.rgb_to_cam16.m, p.cam16_to_rgb.m};
  return jmh_to_rgb<double>(jmh, h);
}

std::array<double, kTableSize> make_reach_m_table(double peak_luminance, TableScalar s) {
  return s == TableScalar::kFloat32 ? reach_table<float>(peak_luminance)
                                    : reach_table<double>(peak_luminance);
}

std::array<std::array<double, 3>, kTotalTableSize> make_gamut_cusp_table(
    const Chromaticities& limit, double peak_luminance, TableScalar s) {
  std::array<std::array<double, 3>, kTotalTableSize> out{};
  if (s == TableScalar::kFloat32) {
    const auto t = cusp_table<float>(limit, peak_luminance);
    for (int i = 0; i < kTotalTableSize; ++i) {
      for (int c = 0; c < 3; ++c) out[i][c] = t[i][c];
    }
    return out;
  }
  return cusp_table<double>(limit, peak_luminance);
}

std::array<double, kTotalTableSize> make_upper_hull_gamma_table(
    const std::array<std::array<double, 3>, kTotalTableSize>& gamut_cusp, double peak_luminance,
    const Chromaticities& limit, TableScalar s) {
  if (s == TableScalar::kFloat32) {
    std::array<V3<float>, kTotalTableSize> cusps;
    for (int i = 0; i < kTotalTableSize; ++i) {
      for (int c = 0; c < 3; ++c) cusps[i][c] = static_cast<float>(gamut_cusp[i][c]);
    }
    return gamma_table<float>(cusps, peak_luminance, limit);
  }
  return gamma_table<double>(gamut_cusp, peak_luminance, limit);
}

Tables make_tables(const Params& p, const Chromaticities& limit, TableScalar s) {
  return s == TableScalar::kFloat32 ? tables<float>(p, limit) : tables<double>(p, limit);
}

}  // namespace hdrc::ref::aces2
