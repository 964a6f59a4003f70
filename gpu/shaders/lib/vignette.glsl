// Vignette (cosine-fourth law): TonemapCommon.ush VignetteSpace and ComputeVignetteMask, called
// from PostProcessTonemap.usf TonemapCommonVS / TonemapCommonPS (docs/spec/ue55.md §6.1 step 3). Reference:
// reference/ue/tonemap.cpp, step 3.
#ifndef HDRC_VIGNETTE_GLSL
#define HDRC_VIGNETTE_GLSL

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

#endif
