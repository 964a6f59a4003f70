// UE 5.8's Tonemap pass (ue58_tonemap.h). Every step UE 5.5 shares is reference/ue/tonemap.cpp's;
// this file holds what 5.8 changed (docs/ue58-differences.md T1-T3).
#include "reference/ue/ue58/ue58_tonemap.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "color/vec.h"
#include "reference/color/device_allowance.h"

namespace hdrc::ref::ue58 {

LutShaper tonemap_lut_shaper(const ParamBlock& p) {
  // PostProcessTonemap.usf ColorLookupTable: BRANCH on LUTShaper (r.LUT.Shaper,
  // GetTonemapperOutputDeviceParameters), PQ of clamp(LinearColor · LinearToNitsScale, 0, 10000).
  return {p.ue58_lut_shaper == 1, true};
}

Vignette tonemap_vignette(const ParamBlock& p) {
  // PostProcessTonemap.cpp AddTonemapPass: VignetteType, VignetteParams0 = (Intensity, Color.rgb),
  // VignetteParams1 = (Center, 1 / max(0.001, Size)), VignetteParams2 = Softness; the permutation
  // USE_ADVANCED_VIGNETTE = VignetteType != CosineFourthLaw (BuildCommonPermutationDomain).
  Vignette v;
  v.type = p.ue58_vignette_type;
  v.advanced = p.ue58_vignette_type != 0;
  v.intensity = p.ue58_vignette_params0[0];
  v.color = {p.ue58_vignette_params0[1], p.ue58_vignette_params0[2], p.ue58_vignette_params0[3]};
  v.center[0] = p.ue58_vignette_params1[0];
  v.center[1] = p.ue58_vignette_params1[1];
  v.inv_size[0] = p.ue58_vignette_params1[2];
  v.inv_size[1] = p.ue58_vignette_params1[3];
  v.softness = p.ue58_vignette_params2;
  // USE_VIGNETTE_TEXTURE (BuildCommonPermutationDomain, RemapPermutation) and the bound texture.
  v.use_texture = p.ue58_vignette_texture != 0;
  const int w = p.ue58_vignette_tex_width, h = p.ue58_vignette_tex_height;
  if (w >= 1 && h >= 1 && w * h <= static_cast<int>(p.ue58_vignette_tex.size() * 4)) {
    v.tex_width = w;
    v.tex_height = h;
    v.tex.resize(static_cast<size_t>(w) * h);
    for (size_t i = 0; i < v.tex.size(); ++i) v.tex[i] = p.ue58_vignette_tex[i / 4][i % 4];
  }
  return v;
}

VignetteTextureImage vignette_texture_stimulus(int which) {
  // A UNORM8 texture holds k/255 (the texel values both engines read).
  auto unorm8 = [](double x) { return std::round(std::clamp(x, 0.0, 1.0) * 255.0) / 255.0; };
  VignetteTextureImage t;
  if (which == 1) {
    t.width = t.height = 16;
  } else if (which == 2) {
    t.width = 16;
    t.height = 8;
  } else {
    return t;  // GSystemTextures.GetWhiteDummy: one texel of 1
  }
  t.texels.resize(static_cast<size_t>(t.width) * t.height);
  for (int y = 0; y < t.height; ++y)
    for (int x = 0; x < t.width; ++x) {
      const double cx = (x + 0.5) / t.width, cy = (y + 0.5) / t.height;
      double value;
      if (which == 1) {
        const double dx = cx * 2 - 1, dy = cy * 2 - 1;
        value = 1.0 - (dx * dx + dy * dy);
      } else {
        value = 0.1 + 0.9 * cx * (0.25 + 0.75 * cy);
      }
      t.texels[static_cast<size_t>(y) * t.width + x] = unorm8(value);
    }
  return t;
}

bool vignette_texture_device_range(const Vignette& v, double pos_x, double pos_y, double aspect,
                                   int sub_texel_bits, Vec3* lo, Vec3* hi) {
  if (!(v.intensity > 0.0) || !v.advanced || v.type != 1 || !v.use_texture) return false;
  double u = 0, w = 0;
  vignette_texture_uv(v, pos_x, pos_y, aspect, &u, &w);
  // The shader's coordinate carries its own float32 error: kShaderNoise of it (noise_range.h's
  // convention for the steps before a lookup), in texels; then the hardware filter's weight boxes
  // (subTexelPrecisionBits) and its arithmetic in the UNORM8 texture's precision.
  const auto bx = linear_tap_boxes(u * v.tex_width - 0.5, v.tex_width, sub_texel_bits,
                                   kShaderNoise * v.tex_width);
  const auto by = linear_tap_boxes(w * v.tex_height - 0.5, v.tex_height, sub_texel_bits,
                                   kShaderNoise * v.tex_height);
  auto at = [&](int x, int y) { return v.tex[static_cast<size_t>(y) * v.tex_width + x]; };
  double s_lo = HUGE_VAL, s_hi = -HUGE_VAL;
  for (const TapBox& x : bx)
    for (const TapBox& y : by) {
      // Tap k: bit 0 set for x's upper texel, bit 1 for y's (filter_taps' index order).
      const double t[4] = {at(x.i0, y.i0), at(x.i1, y.i0), at(x.i0, y.i1), at(x.i1, y.i1)};
      for (const double fx : {x.f_lo, x.f_hi})
        for (const double fy : {y.f_lo, y.f_hi}) {
          const double alpha[2] = {fx, fy};
          const FilteredRange r =
              filter_taps(2, alpha, t, t, FilterArithmetic::unorm(8), sub_texel_bits);
          s_lo = std::fmin(s_lo, r.lo);
          s_hi = std::fmax(s_hi, r.hi);
        }
    }
  // Weight = lerp(1, sample, Intensity), increasing in the sample (Intensity > 0); the mask
  // lerp(Colour, 1, Weight) is monotonic in Weight, rising or falling with 1 − Colour.
  const double w_lo = 1.0 + v.intensity * (s_lo - 1.0), w_hi = 1.0 + v.intensity * (s_hi - 1.0);
  for (int c = 0; c < 3; ++c) {
    const double a = v.color[c] + w_lo * (1.0 - v.color[c]);
    const double b = v.color[c] + w_hi * (1.0 - v.color[c]);
    (*lo)[c] = std::fmin(a, b);
    (*hi)[c] = std::fmax(a, b);
  }
  return true;
}

BakedLut baked_outer_lut(const ParamBlock& p) {
  return baked_outer_lut(CombineLuts58(p), p);
}

BakedLut baked_outer_lut(const CombineLuts58& luts, const ParamBlock& p) {
  BakedLut lut;
  lut.size = p.lut_size;
  lut.layout = 0;  // 5.8 bakes a volume only (docs/ue58-differences.md L14)
  lut.lut_format = p.lut_format;
  lut.texels = bake_outer_lut(luts, p);
  return lut;
}

BakedLut baked_outer_lut_device(const CombineLuts58& luts, const ParamBlock& p,
                                const DevicePrecision& device) {
  BakedLut lut = baked_outer_lut(luts, p);
  DeviceLutRanges d = bake_outer_lut_device(luts, p, device);
  lut.lo = std::move(d.lo);
  lut.hi = std::move(d.hi);
  lut.flags.resize(lut.texels.size());
  for (size_t i = 0; i < lut.flags.size(); ++i)
    lut.flags[i] = static_cast<uint8_t>(BakedLut::kAmbiguous | (d.nan[i] & 0x7));
  return lut;
}

Image tonemap_image(const ParamBlock& p, const Image& scene, const Image* bloom, const Image* dirt,
                    const BakedLut& lut) {
  return tonemap_image(p, scene, bloom, dirt, lut, nullptr, 0);
}

Image tonemap_image(const ParamBlock& p, const Image& scene, const Image* bloom, const Image* dirt,
                    const BakedLut& lut, const BakedLut* device_lut, int sub_texel_bits) {
  Image out(scene.width, scene.height);
  const Vignette vignette = tonemap_vignette(p);
  const LutShaper shaper = tonemap_lut_shaper(p);
  const double aspect = static_cast<double>(scene.height) / scene.width;
  for (int y = 0; y < scene.height; ++y) {
    for (int x = 0; x < scene.width; ++x) {
      FinalLinearParts parts;
      const Vec3 final_linear = tonemap_final_linear(p, scene, bloom, dirt, x, y, vignette, &parts);
      Vec3 encoded;
      for (int c = 0; c < 3; ++c) encoded[c] = lut_encode(shaper, final_linear[c]);
      // The Texture vignette's mask on a conformant device (vignette_texture_device_range): the
      // lookup's coordinate over the mask's range, FinalLinear = (S · tint + Bloom) · (exposure ·
      // mask) being monotonic in the mask and the shaper monotonic; sample_lut_device_range adds
      // kShaderNoise of the coordinate around it.
      spirv::Interval encoded_range[3];
      bool has_encoded_range = false;
      Vec3 mask_lo, mask_hi;
      if (device_lut && vignette_texture_device_range(vignette, (x + 0.5) / scene.width * 2 - 1,
                                                      1 - (y + 0.5) / scene.height * 2, aspect,
                                                      sub_texel_bits, &mask_lo, &mask_hi)) {
        has_encoded_range = true;
        for (int c = 0; c < 3; ++c) {
          auto at = [&](double m) {
            double f = parts.scene[c] * p.scene_color_tint[c] * (p.exposure * m);
            if (parts.bloom) f += parts.bloom_rgb[c] * (p.exposure * m);
            return lut_encode(shaper, f);
          };
          const double a = at(mask_lo[c]), b = at(mask_hi[c]);
          encoded_range[c] = {std::fmin(std::fmin(a, b), encoded[c]),
                              std::fmax(std::fmax(a, b), encoded[c])};
          if (std::isnan(a) || std::isnan(b)) has_encoded_range = false;
        }
      }
      // A NaN coordinate (the log shaper of a NaN) reads NaN, as UE 5.5's port decision
      // (docs/ue55-decisions.md D-NF); sample_lut returns NaN in every channel.
      const Vec3 device = sample_lut(lut, encoded, p.ue58_lut_max);
      const Vec3 o = post_convert(p, device, false);
      double* dst = out.px(x, y);
      dst[0] = o[0];
      dst[1] = o[1];
      dst[2] = o[2];
      dst[3] = device[0] * 0.299 + device[1] * 0.587 + device[2] * 0.114;
      AdmissibleRange range;
      if (device_lut &&
          tonemap_device_range(p, *device_lut, encoded, sub_texel_bits, p.ue58_lut_max, false, o,
                               dst[3], static_cast<size_t>(y) * scene.width + x, nullptr, &range,
                               has_encoded_range ? encoded_range : nullptr))
        out.device_admissible.push_back(range);
    }
  }
  if (device_lut) {
    out.device_allowances = {
        "filter weights (" + std::to_string(sub_texel_bits) + " sub-texel bits)",
        "LUT storage rounding (either neighbour; inner and outer LUT)",
        "shader arithmetic (the Vulkan precision table's bounds)"};
    if (vignette.use_texture && vignette.type == 1 && vignette.intensity > 0.0)
      out.device_allowances.push_back("vignette texture filter (" + std::to_string(sub_texel_bits) +
                                      " sub-texel bits, UNORM8 filtering precision)");
  }
  return out;
}

}  // namespace hdrc::ref::ue58
