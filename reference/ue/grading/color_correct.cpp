#include "reference/ue/grading/color_correct.h"

#include <cstring>

#include "color/d3d_math.h"
#include "reference/color/fast_paths.h"
#include "reference/color/ue_matrices.h"
#include "reference/ue/grading/hlsl_ops.h"

namespace hdrc::ref::grading {
namespace {

Vec4 mul4(const Vec4& a, const Vec4& b) {
  return {a[0] * b[0], a[1] * b[1], a[2] * b[2], a[3] * b[3]};
}
Vec4 add4(const Vec4& a, const Vec4& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]};
}

bool same_zone(const ColorCorrectZone& a, const ColorCorrectZone& b) {
  return std::memcmp(&a, &b, sizeof a) == 0;  // bitwise: +0 and -0 differ, NaN equals itself
}

}  // namespace

ColorCorrectZone combine_with_global(const ColorCorrectZone& zone, const ColorCorrectZone& global) {
  return {mul4(zone.saturation, global.saturation), mul4(zone.contrast, global.contrast),
          mul4(zone.gamma, global.gamma), mul4(zone.gain, global.gain),
          add4(zone.offset, global.offset)};
}

Vec3 color_correct(const Vec3& ap1, const ColorCorrectZone& z) {
  const double luma = dot(ap1, ue_literal::kAp1RgbToY);
  Vec3 c;
  for (int i = 0; i < 3; ++i) {
    double v = hlsl::max(0.0, hlsl::lerp(luma, ap1[i], z.saturation[i] * z.saturation[3]));
    // Each power can leave float32's range where the double does not (ColorGamma 0.01 raises to
    // 100): hlsl::f32_range gives the Inf UE's float shader computes.
    v = hlsl::f32_range(pow_exp1_shortcut(v * (1.0 / 0.18), z.contrast[i] * z.contrast[3])) * 0.18;
    v = hlsl::f32_range(pow_exp1_shortcut(v, 1.0 / (z.gamma[i] * z.gamma[3])));
    c[i] = hlsl::f32_range(v * (z.gain[i] * z.gain[3]) + (z.offset[i] + z.offset[3]));
  }
  return c;
}

ZoneWeights color_correct_weights(double luma_ap1, const ColorCorrectParams& p) {
  const double shadows = 1.0 - hlsl::smoothstep(0.0, p.shadows_max, luma_ap1);
  const double highlights = hlsl::smoothstep(p.highlights_min, p.highlights_max, luma_ap1);
  return {shadows, 1.0 - shadows - highlights, highlights};
}

Vec3 color_correct_all(const Vec3& ap1, const ColorCorrectParams& p) {
  const ZoneWeights w = color_correct_weights(dot(ap1, ue_literal::kAp1RgbToY), p);
  const ColorCorrectZone zs = combine_with_global(p.shadows, p.global);
  const ColorCorrectZone zh = combine_with_global(p.highlights, p.global);
  const ColorCorrectZone zm = combine_with_global(p.midtones, p.global);
  // Zones with bit-identical parameters give bit-identical results (at defaults all three do):
  // evaluate each distinct zone once.
  const bool fast = fast_paths();
  const Vec3 s = color_correct(ap1, zs);
  const Vec3 h = fast && same_zone(zh, zs) ? s : color_correct(ap1, zh);
  const Vec3 m = fast && same_zone(zm, zs) ? s : color_correct(ap1, zm);
  Vec3 out;
  // Left to right as the shader adds, each partial result in float32's range: two zones near
  // FLT_MAX overflow in their sum even where each term does not.
  using hlsl::f32_range;
  for (int i = 0; i < 3; ++i)
    out[i] = f32_range(f32_range(f32_range(s[i] * w.shadows) + f32_range(m[i] * w.midtones)) +
                       f32_range(h[i] * w.highlights));
  return out;
}

}  // namespace hdrc::ref::grading
