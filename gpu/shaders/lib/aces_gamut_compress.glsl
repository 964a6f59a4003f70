// ACES 1.3 reference gamut compression (forward), float32. Source: ACES.ush (5.0-era copy,
// chenyong2github/UnrealEngine, commit 09c29cbee980f5c5fbff6c93cf6132e5f4bcf97a): compress,
// max_f3, compressColor, which follow aces-dev v1.3 LMT.Academy.ReferenceGamutCompress.ctl, with
// UE's any(ACES < 0) bypass (docs/ue55-decisions.md D2). Reference: reference/ue/aces/aces_output.cpp
// (compress, compress_color).
#ifndef HDRC_ACES_GAMUT_COMPRESS_GLSL
#define HDRC_ACES_GAMUT_COMPRESS_GLSL

#include "aces_common.glsl"

// ACES.ush: LIM_CYAN/MAGENTA/YELLOW (distance compressed to the gamut boundary),
// THR_CYAN/MAGENTA/YELLOW (share of the core gamut protected), PWR (aggressiveness).
const vec3 GAMUT_COMPRESS_LIM = vec3(1.147, 1.264, 1.312);
const vec3 GAMUT_COMPRESS_THR = vec3(0.815, 0.803, 0.880);
const float GAMUT_COMPRESS_PWR = 1.2;

// ACES.ush: compress, forward only (invert = false). HLSL pow semantics (pow_d3d); every base
// here is >= 0 for dist >= thr.
float aces_compress(float dist, float lim, float thr, float pwr) {
  if (dist < thr) return dist;  // no compression below the threshold
  // Scale factor for the y = 1 intersect.
  float scl = (lim - thr) / pow_d3d(pow_d3d((1.0 - thr) / (lim - thr), -pwr) - 1.0, 1.0 / pwr);
  float nd = (dist - thr) / scl;
  float p = pow_d3d(nd, pwr);
  return thr + scl * nd / pow_d3d(1.0 + p, 1.0 / pwr);
}

// ACES.ush: max_f3 (maxNum).
float max_f3(vec3 a) { return max_d3d(a.r, max_d3d(a.g, a.b)); }

// ACES.ush: compressColor — AP0 in, AP0 out; distances from the achromatic axis in AP1.
// Bypassed when ach < 1e-10 or any AP0 channel is negative (UE addition). Comparisons with NaN are
// false, so a NaN achromatic value does not bypass and every channel comes out NaN.
vec3 compress_color(vec3 aces) {
  vec3 lin_ap1 = aces_mul(AP0_2_AP1_MAT, aces);
  float ach = max_f3(lin_ap1);
  vec3 compr_lin_ap1;
  if (ach < 1e-10 || any(lessThan(aces, vec3(0.0)))) {
    compr_lin_ap1 = lin_ap1;
  } else {
    vec3 dist = (ach - lin_ap1) / abs(ach);
    vec3 compr_dist =
        vec3(aces_compress(dist.r, GAMUT_COMPRESS_LIM.r, GAMUT_COMPRESS_THR.r, GAMUT_COMPRESS_PWR),
             aces_compress(dist.g, GAMUT_COMPRESS_LIM.g, GAMUT_COMPRESS_THR.g, GAMUT_COMPRESS_PWR),
             aces_compress(dist.b, GAMUT_COMPRESS_LIM.b, GAMUT_COMPRESS_THR.b, GAMUT_COMPRESS_PWR));
    compr_lin_ap1 = ach - compr_dist * abs(ach);
  }
  return aces_mul(AP1_2_AP0_MAT, compr_lin_ap1);
}

#endif
