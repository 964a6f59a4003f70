// Pixel ↔ UV ↔ screen position of a full-viewport screen pass, as UE's Tonemap compute shader
// derives them (PostProcessTonemap.usf: MainCS, UVToScreenPos, ScreenPosToUV; ScreenPass.ush
// viewport parameters for a viewport that is the whole buffer: ScreenPosToViewportScale =
// (W/2, −H/2), ScreenPosToViewportBias = (W/2, H/2), ExtentInverse = 1/(W, H)). The lens
// principal-point transform is UE's default (offset 0, scale 1), so lens positions equal screen
// positions. Reference: reference/ue/tonemap.cpp (u = (x + 0.5)/W, pos = (2u − 1, 1 − 2v)).
#ifndef HDRC_SCREEN_PASS_GLSL
#define HDRC_SCREEN_PASS_GLSL

// MainCS: UV = (DispatchThreadId + 0.5) · Color_ExtentInverse.
vec2 pixel_uv(ivec2 px, vec2 extent) { return (vec2(px) + 0.5) * (1.0 / extent); }

// UVToScreenPos: (UV · Extent − Bias) / Scale; screen position in [−1, 1], y up.
vec2 screen_pos_from_uv(vec2 uv, vec2 extent) {
  return (uv * extent - 0.5 * extent) / (vec2(0.5, -0.5) * extent);
}

// ScreenPosToUV: (ScreenPos · Scale + Bias) · ExtentInverse.
vec2 uv_from_screen_pos(vec2 pos, vec2 extent) {
  return (pos * (vec2(0.5, -0.5) * extent) + 0.5 * extent) * (1.0 / extent);
}

#endif
