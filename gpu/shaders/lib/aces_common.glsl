// ACES constants, matrices and the RRT helper functions shared by the HDR output transform
// (aces_output.glsl) and UE's SDR FilmToneMap, in float32 as UE's shaders evaluate them.
//
// Source: Engine/Shaders/Private/ACES.ush (UE 5.0-era copy, chenyong2github/UnrealEngine, commit
// 09c29cbee980f5c5fbff6c93cf6132e5f4bcf97a; its matrices and functions as in the UE 5.3.2 and 5.5.1
// copies, Mephisto1024/Toon_Engine and lakeone/UE5.51MagicM, whose ACES.ush files are identical;
// docs/ue55-decisions.md D2 and "Colour matrix literals"), which follows aces-dev v1.3
// ACESlib.RRT_Common.ctl / ACESlib.Utilities_Color.ctl.
// Reference (double): reference/ue/aces/aces_common.h, reference/color/ue_matrices.h (ue_literal).
// gpu/aces_shader_test.cpp reads every constant here back from the GPU and compares it with
// float(reference constant) exactly.
//
// Matrices: ACES.ush writes float3x3 literals row by row and applies them as mul(M, v). GLSL's
// mat3(...) constructor fills columns, so each `const mat3` below is written with the same
// row-major literal list and therefore holds M transposed: HLSL mul(M, v) is GLSL `v * M`
// (aces_mul) and HLSL mul(v, M) is GLSL `M * v`.
//
// Non-finite values follow D3D HLSL (d3d_math.glsl): min/max are maxNum/minNum, clamp maps NaN to
// its lower bound, sign(NaN) = 0, sqrt of a negative is NaN, and comparisons with NaN are false.
#ifndef HDRC_ACES_COMMON_GLSL
#define HDRC_ACES_COMMON_GLSL

#include "d3d_math.glsl"

// HLSL mul(M, v) for the row-major literal matrices of this file.
vec3 aces_mul(mat3 m, vec3 v) { return v * m; }

// ACES.ush: HALF_POS_INF (sic: 65535, not the half-float maximum) and HALF_MAX.
const float HALF_POS_INF = 65535.0;
const float HALF_MAX = 65504.0;

// ACES.ush: AP1_2_XYZ_MAT, XYZ_2_AP1_MAT, AP0_2_AP1_MAT, AP1_2_AP0_MAT (UE's 10-digit literals):
// generated into hdrc/interface.glsl from the reference (gpu/shader_constants.cpp:
// shared_matrices), declared as `const mat3` holding the HLSL row-major literal list (see above).
// ACES.ush: AP1_RGB2Y, the Y row of AP1_2_XYZ_MAT.
const vec3 AP1_RGB2Y = vec3(0.2722287168, 0.6740817658, 0.0536895174);

// ACES.ush: RRT "glow" module and red modifier constants.
const float RRT_GLOW_GAIN = 0.05;
const float RRT_GLOW_MID = 0.08;
const float RRT_RED_SCALE = 0.82;
const float RRT_RED_PIVOT = 0.03;
const float RRT_RED_HUE = 0.0;     // degrees
const float RRT_RED_WIDTH = 135.0;  // degrees

// ACES.ush: RRT_SAT_FACTOR, the global desaturation of rrt_sweeteners.
const float RRT_SAT_FACTOR = 0.96;

// ACES.ush: rgb_2_hue's (180. / PI) and sqrt(3.0), folded to float constants. The reference takes
// 180 / pi in double (reference/ue/aces/aces_common.h: rgb_2_hue), so the float of that is used here.
const float ACES_RAD_TO_DEG = 57.295779513082321;  // 180 / pi
const float ACES_SQRT3 = 1.7320508075688772;      // sqrt(3)

// ACES.ush: cubic_basis_shaper's M, the uniform cubic B-spline basis, row-major [k][col] with the
// row of the monomial t^(3-k): (1/6)[[-1, 3, -3, 1], [3, -6, 3, 0], [-3, 0, 3, 0], [1, 4, 1, 0]].
const float CUBIC_BASIS_M[16] = float[16](-1.0 / 6.0, 3.0 / 6.0, -3.0 / 6.0, 1.0 / 6.0,  //
                                           3.0 / 6.0, -6.0 / 6.0, 3.0 / 6.0, 0.0 / 6.0,  //
                                           -3.0 / 6.0, 0.0 / 6.0, 3.0 / 6.0, 0.0 / 6.0,  //
                                           1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0, 0.0 / 6.0);

// ACES.ush: rgb_2_saturation, (max(maxc, 1e-10) - max(minc, 1e-10)) / max(maxc, 0.01).
float rgb_2_saturation(vec3 rgb) {
  float minrgb = min_d3d(min_d3d(rgb.r, rgb.g), rgb.b);
  float maxrgb = max_d3d(max_d3d(rgb.r, rgb.g), rgb.b);
  return (max_d3d(maxrgb, 1e-10) - max_d3d(minrgb, 1e-10)) / max_d3d(maxrgb, 1e-2);
}

// ACES.ush: rgb_2_yc with ycRadiusWeight = 1.75. The radicand is 1/2 the sum of squared channel
// differences in exact arithmetic; in float32 it can round below 0 for near-greys, where HLSL's
// sqrt gives NaN (sqrt_d3d) as D3D would.
float rgb_2_yc(vec3 rgb) {
  const float yc_radius_weight = 1.75;
  float r = rgb.r;
  float g = rgb.g;
  float b = rgb.b;
  float chroma = sqrt_d3d(b * (b - g) + g * (g - r) + r * (r - b));
  return (b + g + r + yc_radius_weight * chroma) / 3.0;
}

// ACES.ush: sigmoid_shaper, from 0 to 1 over x in [-2, 2].
float sigmoid_shaper(float x) {
  float t = max_d3d(1.0 - abs(0.5 * x), 0.0);
  float y = 1.0 + sign_d3d(x) * (1.0 - t * t);
  return 0.5 * y;
}

// ACES.ush: glow_fwd. A NaN yc fails both comparisons and takes the last branch (NaN).
float glow_fwd(float yc_in, float glow_gain_in, float glow_mid) {
  if (yc_in <= 2.0 / 3.0 * glow_mid) return glow_gain_in;
  if (yc_in >= 2.0 * glow_mid) return 0.0;
  return glow_gain_in * (glow_mid / yc_in - 0.5);
}

// ACES.ush: rgb_2_hue, degrees in [0, 360]; UE returns 0 for r = g = b (the CTL returns NaN).
// atan(y, x) is GLSL's atan2; a NaN hue becomes 0 through HLSL clamp.
float rgb_2_hue(vec3 rgb) {
  float hue;
  if (rgb.r == rgb.g && rgb.g == rgb.b) {
    hue = 0.0;
  } else {
    hue = ACES_RAD_TO_DEG * atan(ACES_SQRT3 * (rgb.g - rgb.b), 2.0 * rgb.r - rgb.g - rgb.b);
  }
  if (hue < 0.0) hue = hue + 360.0;
  return clamp_d3d(hue, 0.0, 360.0);
}

// ACES.ush: center_hue, hue - centre wrapped into [-180, 180].
float center_hue(float hue, float center_h) {
  float hue_centered = hue - center_h;
  if (hue_centered < -180.0) {
    hue_centered += 360.0;
  } else if (hue_centered > 180.0) {
    hue_centered -= 360.0;
  }
  return hue_centered;
}

// ACES.ush: cubic_basis_shaper, the red modifier's B-spline of full base width w degrees, times
// 1.5 (peak 1 at x = 0), 0 outside (-w/2, w/2). HLSL `int j = knot_coord` truncates, as int().
float cubic_basis_shaper(float x, float w) {
  float knot0 = -0.5 * w;
  float knot4 = 0.5 * w;
  float y = 0.0;
  if (x > knot0 && x < knot4) {
    float knot_coord = (x - knot0) * 4.0 / w;
    int j = int(knot_coord);
    float t = knot_coord - float(j);
    vec4 monomials = vec4(t * t * t, t * t, t, 1.0);
    if (j >= 0 && j <= 3) {
      int col = 3 - j;
      y = monomials.x * CUBIC_BASIS_M[0 * 4 + col] + monomials.y * CUBIC_BASIS_M[1 * 4 + col] +
          monomials.z * CUBIC_BASIS_M[2 * 4 + col] + monomials.w * CUBIC_BASIS_M[3 * 4 + col];
    }
  }
  return y * 1.5;
}

#endif
