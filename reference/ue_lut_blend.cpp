#include "reference/ue_lut_blend.h"

#include <algorithm>
#include <cmath>

#include "core/case.h"
#include "reference/color/gamma_correction.h"
#include "reference/color/linear_tap.h"

namespace hdrc::ref {

// The loader's rounding (core/case.h: unorm8_value), so that the reference's textures are the
// texels both engines bind.
uint8_t unorm8_from_value(double v) {
  return static_cast<uint8_t>(std::nearbyint(unorm8_value(v) * 255.0));
}

UeLutTexture ue_lut_texture(const std::vector<std::array<float, 3>>& table, bool quantize_8bit) {
  UeLutTexture t;
  constexpr int n = kUeUserLutSize;
  if (table.size() != static_cast<size_t>(n) * n * n) return t;
  t.texels.resize(static_cast<size_t>(kUeUserLutWidth) * kUeUserLutHeight);
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r) {
        const auto& row = table[(static_cast<size_t>(b) * n + g) * n + r];
        Vec3& out = t.texels[static_cast<size_t>(g) * kUeUserLutWidth + r + n * b];
        for (int c = 0; c < 3; ++c) out[c] = quantize_8bit ? unorm8_value(row[c]) : double(row[c]);
      }
  return t;
}

namespace {

using Tap = LinearTap;  // reference/color/linear_tap.h

Vec3 lerp(const Vec3& a, const Vec3& b, double f) {
  return {a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f, a[2] + (b[2] - a[2]) * f};
}

Vec3 bilinear(const UeLutTexture& lut, double u, double v) {
  const Tap x = linear_tap(u * kUeUserLutWidth - 0.5, kUeUserLutWidth);
  const Tap y = linear_tap(v * kUeUserLutHeight - 0.5, kUeUserLutHeight);
  return lerp(lerp(lut.at(x.i0, y.i0), lut.at(x.i1, y.i0), x.f),
              lerp(lut.at(x.i0, y.i1), lut.at(x.i1, y.i1), x.f), y.f);
}

}  // namespace

Vec3 unwrapped_texture3d_sample(const UeLutTexture& lut, const Vec3& uvw) {
  constexpr double size = kUeUserLutSize, inv_size = 1.0 / kUeUserLutSize;
  const double w = uvw[2] * size - 0.5;
  const double int_w = std::floor(w);
  const double frac_w = w - int_w;
  const double u = (uvw[0] + int_w) * inv_size;
  return lerp(bilinear(lut, u, uvw[1]), bilinear(lut, u + inv_size, uvw[1]), frac_w);
}

Vec3 blend_user_luts(const Vec3& film_color, int count, const std::array<double, 5>& weights,
                     const std::array<const UeLutTexture*, 4>& luts) {
  if (count <= 1) return film_color;
  count = std::min(count, 5);
  Vec3 g;
  // saturate: D3D maps NaN to 0 (fmax/fmin are IEEE maxNum/minNum).
  for (int c = 0; c < 3; ++c) g[c] = linear_to_srgb(std::fmin(std::fmax(film_color[c], 0.0), 1.0));
  // UVW = GammaColor · (15/16) + 0.5/16 (the shader's float literals 15.0/16.0, 0.5f/16.0).
  Vec3 uvw;
  for (int c = 0; c < 3; ++c) uvw[c] = g[c] * (15.0 / 16.0) + 0.5 / 16.0;
  Vec3 blended = {weights[0] * g[0], weights[0] * g[1], weights[0] * g[2]};
  for (int i = 1; i < count; ++i) {
    const UeLutTexture* lut = luts[static_cast<size_t>(i - 1)];
    if (!lut || lut->texels.empty()) continue;
    const Vec3 s = unwrapped_texture3d_sample(*lut, uvw);
    for (int c = 0; c < 3; ++c) blended[c] += weights[static_cast<size_t>(i)] * s[c];
  }
  return srgb_to_linear(blended);
}

UeLutSet ue_lut_set(const std::array<Image, kUserLutSlots>& strips) {
  UeLutSet set;
  for (size_t s = 0; s < strips.size(); ++s) {
    const Image& img = strips[s];
    if (img.width != kUeUserLutWidth || img.height != kUeUserLutHeight) continue;
    UeLutTexture& t = set.slots[s];
    t.texels.resize(img.pixel_count());
    for (size_t i = 0; i < t.texels.size(); ++i)
      t.texels[i] = {img.data[i * 4], img.data[i * 4 + 1], img.data[i * 4 + 2]};
  }
  return set;
}

Vec3 blend_user_luts(const Vec3& film_color, const ParamBlock& p, const UeLutSet& luts) {
  const std::array<double, 5> w = {p.lut_weights[0], p.lut_weights[1], p.lut_weights[2],
                                   p.lut_weights[3], p.lut_weight_4};
  return blend_user_luts(film_color, p.lut_blend_count, w,
                         {&luts.slots[0], &luts.slots[1], &luts.slots[2], &luts.slots[3]});
}

}  // namespace hdrc::ref
