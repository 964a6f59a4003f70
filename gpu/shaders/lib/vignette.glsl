// Vignette (cosine-fourth law): TonemapCommon.ush VignetteSpace and ComputeVignetteMask, called
// from PostProcessTonemap.usf TonemapCommonVS / TonemapCommonPS (docs/spec/ue55.md §6.1 step 3). Reference:
// reference/ue/tonemap.cpp, step 3.
#ifndef HDRC_VIGNETTE_GLSL
#define HDRC_VIGNETTE_GLSL

#include "d3d_math.glsl"

// Pos · (1, AspectRatio) · sqrt(2)/sqrt(1 + AspectRatio²); AspectRatio = ViewportHeight/Width.
vec2 vignette_space(vec2 lens_pos, float aspect_ratio) {
  float scale = sqrt(2.0) / sqrt(1.0 + aspect_ratio * aspect_ratio);
  return lens_pos * vec2(1.0, aspect_ratio) * scale;
}

// Square(rcp(|V · Intensity|² + 1)).
float vignette_mask(vec2 v, float intensity) {
  v *= intensity;
  float tan2_angle = dot(v, v);
  float r = 1.0 / (tan2_angle + 1.0);
  return r * r;
}

// UE 5.8's VignetteSpace with the type (PostProcessCommon.ush): the Texture type (1) scales Pos by
// (saturate(1/AspectRatio), saturate(AspectRatio)), the others as vignette_space. TonemapCommonVS
// passes VignetteType whatever the permutation.
vec2 vignette_space58(vec2 lens_pos, int type, float aspect_ratio) {
  if (type == 1) {
    float inv_aspect_ratio = 1.0 / aspect_ratio;
    return lens_pos * vec2(saturate_d3d(inv_aspect_ratio), saturate_d3d(aspect_ratio));
  }
  return vignette_space(lens_pos, aspect_ratio);
}

// UE 5.8's ComputeVignetteMask (PostProcessCommon.ush), a colour: Weight 1 for Intensity <= 0;
// the cosine-fourth law on V − (Centre − 0.5); with USE_ADVANCED_VIGNETTE (`advanced`, the type is
// not CosineFourthLaw) and a type other than it, Weight = lerp(1, pow(saturate(1 − Distance),
// Softness), Intensity) with Distance = length2(InvSize · V − (Centre − 0.5)) for Oval, 0 otherwise
// (Texture without USE_VIGNETTE_TEXTURE, off at feature level SM5: RemapPermutation); result
// lerp(Colour, 1, Weight). params0 = (Intensity, Colour), params1 = (Centre, InvSize), params2 =
// Softness. UE 5.5's vignette is this at type 0, centre (0.5, 0.5), colour 0, to the bit
// (tonemap_effects.glsl tonemap_vignette). Reference: reference/ue/tonemap.cpp vignette_mask.
// USE_VIGNETTE_TEXTURE: a shader that defines HDRC_VIGNETTE_TEXTURE (a bool expression, the
// permutation) and vignette_texture_sample(uv) before including this file has the Texture branch:
// Weight = lerp(1, sample.r at (InvSize · V − (Centre − 0.5)) · 0.5 + 0.5, Intensity).
vec3 vignette_mask58(vec2 lens_pos, float aspect_ratio, int type, bool advanced, vec4 params0,
                     vec4 params1, float params2) {
  vec2 v = vignette_space58(lens_pos, type, aspect_ratio);
  float intensity = params0.x;
  vec2 center = params1.xy - 0.5;
  int t = advanced ? type : 0;
  float weight = 1.0;
  if (intensity <= 0.0) {
#ifdef HDRC_VIGNETTE_TEXTURE
  } else if (t == 1 && HDRC_VIGNETTE_TEXTURE) {
    float s = vignette_texture_sample((params1.zw * v - center) * 0.5 + 0.5);
    weight = lerp_d3d(1.0, s, intensity);
#endif
  } else if (t == 0) {
    weight = vignette_mask(v - center, intensity);
  } else {
    float distance = 0.0;
    if (t == 2) {
      vec2 d = params1.zw * v - center;
      distance = dot(d, d);
    }
    weight = lerp_d3d(1.0, pow_d3d(saturate_d3d(1.0 - distance), params2), intensity);
  }
  return lerp_d3d(params0.yzw, vec3(1.0), weight);
}

#endif
