#include "reference/ue/grading/expand_gamut.h"

#include <cmath>

#include "reference/color/ue_matrices.h"
#include "reference/ue/grading/hlsl_ops.h"

namespace hdrc::ref::grading {

const Mat3 kWideToXyz{{0.5441691, 0.2395926, 0.1666943,  //
                       0.2394656, 0.7021530, 0.0583814,  //
                       -0.0023439, 0.0361834, 1.0552183}};

Mat3 expand_gamut_matrix() {
  using namespace ue_literal;
  const Mat3 ap1_to_srgb = kXyzToSrgb * (kD60ToD65Cat * kAp1ToXyz);
  return (kXyzToAp1 * kWideToXyz) * ap1_to_srgb;
}

double expand_gamut_amount(const Vec3& color_ap1, double expand_gamut) {
  const double luma = dot(color_ap1, ue_literal::kAp1RgbToY);
  if (luma == 0.0) return 0.0;  // docs/ue55-decisions.md D-NaN
  double dist_sqr = 0.0;
  for (double c : color_ap1) {
    const double d = c / luma - 1.0;
    dist_sqr += d * d;
  }
  return (1.0 - std::exp2(-4.0 * dist_sqr)) * (1.0 - std::exp2(-4.0 * expand_gamut * luma * luma));
}

Vec3 expand_gamut(const Vec3& color_ap1, double expand_gamut) {
  static const Mat3 kExpand = expand_gamut_matrix();
  return hlsl::lerp(color_ap1, kExpand * color_ap1, expand_gamut_amount(color_ap1, expand_gamut));
}

}  // namespace hdrc::ref::grading
