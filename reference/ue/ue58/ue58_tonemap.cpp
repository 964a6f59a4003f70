// UE 5.8's Tonemap pass (ue58_tonemap.h). Every step UE 5.5 shares is reference/ue/tonemap.cpp's;
// this file holds what 5.8 changed (docs/ue58-differences.md T1-T3).
#include "reference/ue/ue58/ue58_tonemap.h"

#include <vector>

#include "color/vec.h"

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
  return v;
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

Image tonemap_image(const ParamBlock& p, const Image& scene, const Image* bloom, const Image* dirt,
                    const BakedLut& lut) {
  Image out(scene.width, scene.height);
  const Vignette vignette = tonemap_vignette(p);
  const LutShaper shaper = tonemap_lut_shaper(p);
  for (int y = 0; y < scene.height; ++y) {
    for (int x = 0; x < scene.width; ++x) {
      const Vec3 final_linear = tonemap_final_linear(p, scene, bloom, dirt, x, y, vignette);
      Vec3 encoded;
      for (int c = 0; c < 3; ++c) encoded[c] = lut_encode(shaper, final_linear[c]);
      // A NaN coordinate (the log shaper of a NaN) reads NaN, as UE 5.5's port decision
      // (docs/ue55-decisions.md D-NF); sample_lut returns NaN in every channel.
      const Vec3 device = sample_lut(lut, encoded, p.ue58_lut_max);
      const Vec3 o = post_convert(p, device, false);
      double* dst = out.px(x, y);
      dst[0] = o[0];
      dst[1] = o[1];
      dst[2] = o[2];
      dst[3] = device[0] * 0.299 + device[1] * 0.587 + device[2] * 0.114;
    }
  }
  return out;
}

}  // namespace hdrc::ref::ue58
