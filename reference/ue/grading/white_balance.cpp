#include "reference/ue/grading/white_balance.h"

#include <cmath>

namespace hdrc::ref::grading {
namespace {

struct Uv {
  double u, v;  // CIE 1960 UCS
};

// Krystek 1985 as TonemapCommon.ush: PlanckianLocusChromaticity writes it.
Uv krystek_uv(double t) {
  const double u = (0.860117757 + 1.54118254e-4 * t + 1.28641212e-7 * t * t) /
                   (1.0 + 8.42420235e-4 * t + 7.08145163e-7 * t * t);
  const double v = (0.317398726 + 4.22806245e-5 * t + 4.20481691e-8 * t * t) /
                   (1.0 - 2.89741816e-5 * t + 1.61456053e-7 * t * t);
  return {u, v};
}

Chromaticity xy_from_uv(Uv c) {
  const double d = 2.0 * c.u - 8.0 * c.v + 4.0;
  return {3.0 * c.u / d, 2.0 * c.v / d};
}

}  // namespace

Chromaticity planckian_locus_chromaticity(double temp_k) {
  return xy_from_uv(krystek_uv(temp_k));
}

Chromaticity d_illuminant_chromaticity(double temp_k) {
  // "Correct for revision of Plank's law. This makes 6500 == D65" (UE comment).
  const double t = temp_k * (1.4388 / 1.438);
  const double w = 1.0 / t;
  const double x = t <= 7000.0 ? 0.244063 + (0.09911e3 + (2.9678e6 - 4.6070e9 * w) * w) * w
                               : 0.237040 + (0.24748e3 + (1.9018e6 - 2.0064e9 * w) * w) * w;
  const double y = -3.0 * x * x + 2.87 * x - 0.275;
  return {x, y};
}

Chromaticity planckian_isothermal(double temp_k, double tint) {
  const double t = temp_k;
  Uv c = krystek_uv(t);
  const double ud_den = 1.41213984e6 + 1189.62 * t + t * t;
  const double vd_den = 6.19363586e6 - 179.456 * t + t * t;
  double ud = (-1.13758118e9 - 1.91615621e6 * t - 1.53177 * t * t) / (ud_den * ud_den);
  double vd = (1.97471536e9 - 705674.0 * t - 308.607 * t * t) / (vd_den * vd_den);
  const double len = std::sqrt(ud * ud + vd * vd);  // HLSL normalize()
  ud /= len;
  vd /= len;
  // "Correlated color temperature is meaningful within +/- 0.05" (UE comment).
  c.u += vd * tint * 0.05;
  c.v += -ud * tint * 0.05;
  return xy_from_uv(c);
}

Vec3 xyz_from_xy(Chromaticity xy) {
  const double y = std::fmax(xy.y, 1e-10);
  return {xy.x / y, 1.0, (1.0 - xy.x - xy.y) / y};
}

const Mat3 kBradfordCone{{0.8951, 0.2664, -0.1614,  //
                          -0.7502, 1.7135, 0.0367,  //
                          0.0389, -0.0685, 1.0296}};
const Mat3 kBradfordInvConeLiteral{{0.9869929, -0.1470543, 0.1599627,  //
                                    0.4323053, 0.5183603, 0.0492912,   //
                                    -0.0085287, 0.0400428, 0.9684867}};

Mat3 chromatic_adaptation(Chromaticity src, Chromaticity dst) {
  const Vec3 src_cone = kBradfordCone * xyz_from_xy(src);
  const Vec3 dst_cone = kBradfordCone * xyz_from_xy(dst);
  const Mat3 von_kries =
      Mat3::diag({dst_cone[0] / src_cone[0], dst_cone[1] / src_cone[1], dst_cone[2] / src_cone[2]});
  return kBradfordInvConeLiteral * (von_kries * kBradfordCone);
}

bool white_balance_skipped(const WhiteBalanceParams& p) {
  return std::fabs(p.white_temp - 6500.0) <= kSkipTemperatureTolerance &&
         std::fabs(p.white_tint - 0.0) <= kSkipTemperatureTolerance;
}

WhiteBalanceWhites white_balance_whites(const WhiteBalanceParams& p) {
  const Chromaticity daylight = d_illuminant_chromaticity(p.white_temp);
  const Chromaticity planckian = planckian_locus_chromaticity(p.white_temp);
  Chromaticity src = p.white_temp < 4000.0 ? planckian : daylight;
  const Chromaticity isothermal = planckian_isothermal(p.white_temp, p.white_tint);
  src.x += isothermal.x - planckian.x;
  src.y += isothermal.y - planckian.y;
  if (p.temperature_type == TemperatureType::kColorTemperature) return {kWhiteBalanceD65, src};
  return {src, kWhiteBalanceD65};
}

Mat3 white_balance_matrix(const WhiteBalanceParams& p, const WorkingColorSpace& wcs) {
  const WhiteBalanceWhites w = white_balance_whites(p);
  return wcs.from_xyz * (chromatic_adaptation(w.src, w.dst) * wcs.to_xyz);
}

Vec3 white_balance(const Vec3& linear, const WhiteBalanceParams& p, const WorkingColorSpace& wcs) {
  if (white_balance_skipped(p)) return linear;
  return white_balance_matrix(p, wcs) * linear;
}

}  // namespace hdrc::ref::grading
