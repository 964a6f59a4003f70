#include "reference/ue/grading/color_polynomial.h"

#include <algorithm>

#include "color/d3d_math.h"
#include "reference/color/fast_paths.h"
#include "reference/ue/grading/hlsl_ops.h"

namespace hdrc::ref::grading {
namespace {

// FMath::Clamp: X < Min ? Min : (X < Max ? X : Max) — a NaN cvar becomes Max.
float ue_clamp(float x, float lo, float hi) {
  return x < lo ? lo : (x < hi ? x : hi);
}

}  // namespace

MappingPolynomial get_mapping_polynomial(const ColorRemapCvars& cvars) {
  const float min_value = ue_clamp(static_cast<float>(cvars.min), -10.0f, 10.0f);
  const float mid_value = ue_clamp(static_cast<float>(cvars.mid), -10.0f, 10.0f);
  const float max_value = ue_clamp(static_cast<float>(cvars.max), -10.0f, 10.0f);
  const float c = min_value;
  const float b = 4 * mid_value - 3 * min_value - max_value;
  const float a = max_value - min_value - b;
  return {a, b, c};
}

Vec3 apply_mapping_polynomial(const Vec3& film_color, const MappingPolynomial& p) {
  Vec3 out;
  for (int i = 0; i < 3; ++i) {
    out[i] = p.a * (film_color[i] * film_color[i]) + p.b * film_color[i] + p.c;
  }
  return out;
}

Vec3 apply_fade(const Vec3& color, const Fade& f) {
  const Vec3 scaled{color[0] * f.color_scale[0], color[1] * f.color_scale[1],
                    color[2] * f.color_scale[2]};
  const Vec3 overlay{f.overlay_color[0], f.overlay_color[1], f.overlay_color[2]};
  return hlsl::lerp(scaled, overlay, f.overlay_color[3]);
}

InverseGamma get_inverse_gamma(double display_gamma, double tonemapper_gamma) {
  const float display = static_cast<float>(display_gamma);
  const float gamma = static_cast<float>(tonemapper_gamma);
  return {1.0f / display, 2.2f / display, 1.0f / std::max(gamma, 1.0f)};
}

Vec3 apply_film_gamma(const Vec3& film_color_no_gamma, const InverseGamma& g) {
  const Vec3 c = hlsl::max0(film_color_no_gamma);
  return {pow_exp1_shortcut(c[0], g.y), pow_exp1_shortcut(c[1], g.y), pow_exp1_shortcut(c[2], g.y)};
}

}  // namespace hdrc::ref::grading
