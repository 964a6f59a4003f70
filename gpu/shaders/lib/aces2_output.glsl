// UE 5.8's ACES 2.0 output transform in float32: tonescale, table lookups, chroma compression,
// gamut compression and the whole transform, forward and inverse. Twin of
// reference/ue/aces2/aces2.{h,cpp}; from ACES/ACESOutputTransform.ush, ACES/ACESDisplayEncoding.ush
// and TonemapCommon.ush (unicorn2022/UE5.8.0 5d9a05c1); the tonescale from
// ampas/aces-core lib/Lib.Academy.Tonescale.ctl (docs/ue58-decisions.md A5).
//
// The three tables are UE's textures (docs/ue58-decisions.md A7); the including shader defines
// how a texel is read (UE: Texture2D<float>.Load, 0 outside the texture):
//   float aces2_reach_load(int i);          // ACES_ReachMTable, 360 × 1
//   float aces2_cusp_load(int c, int row);  // ACES_GamutCuspTable, 3 × 362
//   float aces2_gamma_load(int i);          // ACES_UpperHullGammaTable, 362 × 1
#ifndef HDRC_ACES2_OUTPUT_GLSL
#define HDRC_ACES2_OUTPUT_GLSL

#include "aces2_common.glsl"

float aces2_reach_load(int i);
float aces2_cusp_load(int c, int row);
float aces2_gamma_load(int i);

const int ACES2_TABLE_SIZE = 360;
const int ACES2_TOTAL_TABLE_SIZE = 362;
const int ACES2_BASE_INDEX = 1;

// Gamut compression constants.
const float ACES2_SMOOTH_CUSPS = 0.12;
const float ACES2_SMOOTH_M = 0.27;
const float ACES2_CUSP_MID_BLEND = 1.3;
const float ACES2_FOCUS_GAIN_BLEND = 0.3;
const float ACES2_FOCUS_ADJUST_GAIN = 0.55;
const float ACES2_COMPRESSION_THRESHOLD = 0.75;

// hue_position_in_uniform_table.
int aces2_hue_position(float hue, int table_size) {
  return int(aces2_wrap_to_360(hue) / 360.0 * float(table_size));
}

// Lib.Academy.Tonescale.ctl: tonescale_fwd (nits out) / tonescale_inv (nits/100 in).
float aces2_tonescale_fwd(float x, Aces2Params p) {
  float f = p.m_2 * pow(max(0.0, x) / (x + p.s_2), p.g);
  float h = max(0.0, f * f / (f + p.t_1));
  return h * p.n_r;
}
float aces2_tonescale_inv(float y, Aces2Params p) {
  float z = max(0.0, min(p.peak_luminance / (p.u_2 * p.n_r), y));
  float h = (z + sqrt(z * (4.0 * p.t_1 + z))) / 2.0;
  return p.s_2 / (pow(p.m_2 / h, 1.0 / p.g) - 1.0);
}

// reachMFromTable (i_hi wraps to 0 after 359: t = (h − 359)/(0 − 359) there).
float aces2_reach_m_from_table(float h) {
  int i_lo = aces2_hue_position(h, ACES2_TABLE_SIZE);
  int i_hi = (i_lo + 1) % ACES2_TABLE_SIZE;
  float t = (h - float(i_lo)) / float(i_hi - i_lo);
  return mix(aces2_reach_load(i_lo), aces2_reach_load(i_hi), t);
}

// cuspFromTable: (J, M) of the cusp at hue h.
vec2 aces2_cusp_from_table(float h) {
  int low = 0;
  int high = ACES2_BASE_INDEX + ACES2_TABLE_SIZE;
  int i = aces2_hue_position(h, ACES2_TABLE_SIZE) + ACES2_BASE_INDEX;
  while (low + 1 < high) {
    if (h > aces2_cusp_load(2, i)) {
      low = i;
    } else {
      high = i;
    }
    i = (low + high) / 2;
  }
  vec3 lo = vec3(aces2_cusp_load(0, high - 1), aces2_cusp_load(1, high - 1),
                 aces2_cusp_load(2, high - 1));
  vec3 hi = vec3(aces2_cusp_load(0, high), aces2_cusp_load(1, high), aces2_cusp_load(2, high));
  float t = (h - lo.z) / (hi.z - lo.z);
  return vec2(mix(lo.x, hi.x, t), mix(lo.y, hi.y, t));
}

// hueDependentUpperHullGamma (i_hi modulo the texture width 362).
float aces2_upper_hull_gamma_from_table(float h) {
  int i_lo = aces2_hue_position(h, ACES2_TABLE_SIZE) + ACES2_BASE_INDEX;
  int i_hi = (i_lo + 1) % ACES2_TOTAL_TABLE_SIZE;
  float base_hue = float(i_lo - ACES2_BASE_INDEX) * 360.0 / float(ACES2_TABLE_SIZE);
  return mix(aces2_gamma_load(i_lo), aces2_gamma_load(i_hi), aces2_wrap_to_360(h) - base_hue);
}

// chromaCompressionNorm.
float aces2_chroma_compression_norm(float h, Aces2Params p) {
  float hr = h / 180.0 * ACES2_PI;
  float a = cos(hr);
  float b = sin(hr);
  float cos_hr2 = a * a - b * b;
  float sin_hr2 = 2.0 * a * b;
  float cos_hr3 = 4.0 * a * a * a - 3.0 * a;
  float sin_hr3 = 3.0 * b - 4.0 * b * b * b;
  float m = 11.34072 * a + 16.46899 * cos_hr2 + 7.88380 * cos_hr3 + 14.66441 * b +
            -6.37224 * sin_hr2 + 9.19364 * sin_hr3 + 77.12896;
  return m * p.chroma_compress_scale;
}

// toe_fwd / toe_inv.
float aces2_toe_fwd(float x, float limit, float k1_in, float k2_in) {
  if (x > limit) return x;
  float k2 = max(k2_in, 0.001);
  float k1 = sqrt(k1_in * k1_in + k2 * k2);
  float k3 = (limit + k1) / (limit + k2);
  float minus_b = k3 * x - k1;
  float minus_c = k2 * k3 * x;
  return 0.5 * (minus_b + sqrt(minus_b * minus_b + 4.0 * minus_c));
}
float aces2_toe_inv(float x, float limit, float k1_in, float k2_in) {
  if (x > limit) return x;
  float k2 = max(k2_in, 0.001);
  float k1 = sqrt(k1_in * k1_in + k2 * k2);
  float k3 = (limit + k1) / (limit + k2);
  return (x * x + k1 * x) / (k3 * (x + k2));
}

// chromaCompression: M of jmh (J already tonemapped) given the J before the tonescale.
float aces2_chroma_compression(vec3 jmh, float orig_j, Aces2Params p, bool invert) {
  float j = jmh.x;
  float m = jmh.y;
  float h = jmh.z;
  if (m == 0.0) return m;
  float nj = j / p.limit_j_max;
  float snj = max(0.0, 1.0 - nj);
  float mnorm = aces2_chroma_compression_norm(h, p);
  float limit = pow(nj, p.model_gamma) * aces2_reach_m_from_table(h) / mnorm;
  float toe_limit = limit - 0.001;
  float toe_snj_sat = snj * p.sat;
  float toe_sqrt_nj_sat_thr = sqrt(nj * nj + p.sat_thr);
  float toe_nj_compr = nj * p.compr;
  if (!invert) {
    m = m * pow(j / orig_j, p.model_gamma);
    m = m / mnorm;
    m = limit - aces2_toe_fwd(limit - m, toe_limit, toe_snj_sat, toe_sqrt_nj_sat_thr);
    m = aces2_toe_fwd(m, limit, toe_nj_compr, snj);
    return m * mnorm;
  }
  m = m / mnorm;
  m = aces2_toe_inv(m, limit, toe_nj_compr, snj);
  m = limit - aces2_toe_inv(limit - m, toe_limit, toe_snj_sat, toe_sqrt_nj_sat_thr);
  m = m * mnorm;
  return m * pow(j / orig_j, -p.model_gamma);
}

// tonemapAndCompress_fwd / _inv.
vec3 aces2_tonemap_and_compress_fwd(vec3 jmh, Aces2Params p) {
  float linear = aces2_hellwig_j_to_y(jmh.x) / ACES2_REFERENCE_LUMINANCE;
  float j_ts = aces2_y_to_hellwig_j(aces2_tonescale_fwd(linear, p));
  return vec3(j_ts, aces2_chroma_compression(vec3(j_ts, jmh.yz), jmh.x, p, false), jmh.z);
}
vec3 aces2_tonemap_and_compress_inv(vec3 jmh, Aces2Params p) {
  float luminance = aces2_hellwig_j_to_y(jmh.x);
  float linear = aces2_tonescale_inv(luminance / ACES2_REFERENCE_LUMINANCE, p);
  float j = aces2_y_to_hellwig_j(linear * ACES2_REFERENCE_LUMINANCE);
  return vec3(j, aces2_chroma_compression(jmh, j, p, true), jmh.z);
}

// getFocusGain.
float aces2_focus_gain(float j, float cusp_j, float limit_j_max) {
  float thr = mix(cusp_j, limit_j_max, ACES2_FOCUS_GAIN_BLEND);
  if (j > thr) {
    float gain = (limit_j_max - thr) / max(0.0001, limit_j_max - j);
    return pow(log(gain) / log(10.0), 1.0 / ACES2_FOCUS_ADJUST_GAIN) + 1.0;
  }
  return 1.0;
}

// solve_J_intersect.
float aces2_solve_j_intersect(float j, float m, float focus_j, float max_j, float slope_gain) {
  float a = m / (focus_j * slope_gain);
  bool below = j < focus_j;
  float b = below ? 1.0 - m / slope_gain
                  : -(1.0 + m / slope_gain + max_j * m / (focus_j * slope_gain));
  float c = below ? -j : max_j * m / slope_gain + j;
  float root = sqrt(b * b - 4.0 * a * c);
  return below ? 2.0 * c / (-b - root) : 2.0 * c / (-b + root);
}

float aces2_projection_slope(float intersect_j, float focus_j, float max_j, float slope_gain) {
  return intersect_j < focus_j
             ? intersect_j * (intersect_j - focus_j) / (focus_j * slope_gain)
             : (max_j - intersect_j) * (intersect_j - focus_j) / (focus_j * slope_gain);
}

// findGamutBoundaryIntersection: (boundary J, boundary M, projection J at M = 0).
vec3 aces2_find_gamut_boundary_intersection(vec3 jmh_s, vec2 cusp_in, float j_focus, float j_max,
                                            float slope_gain, float gamma_top,
                                            float gamma_bottom) {
  float s = max(0.000001, ACES2_SMOOTH_CUSPS);
  float cusp_j = cusp_in.x;
  float cusp_m = cusp_in.y * (1.0 + ACES2_SMOOTH_M * s);
  float j_src = aces2_solve_j_intersect(jmh_s.x, jmh_s.y, j_focus, j_max, slope_gain);
  float j_cusp = aces2_solve_j_intersect(cusp_j, cusp_m, j_focus, j_max, slope_gain);
  float slope = aces2_projection_slope(j_src, j_focus, j_max, slope_gain);
  float m_lower = j_cusp * pow(j_src / j_cusp, 1.0 / gamma_bottom) / (cusp_j / cusp_m - slope);
  float m_upper = cusp_m * (j_max - j_cusp) * pow((j_max - j_src) / (j_max - j_cusp), 1.0 / gamma_top) /
                  (slope * cusp_m + j_max - cusp_j);
  float m_boundary = cusp_m * aces2_smin(m_lower / cusp_m, m_upper / cusp_m, s);
  return vec3(j_src + slope * m_boundary, m_boundary, j_src);
}

// compressionFunction.
float aces2_compression_function(float v, float thr, float lim, bool invert) {
  float s = (lim - thr) * (1.0 - thr) / (lim - 1.0);
  float nd = (v - thr) / s;
  if (invert) {
    if (v < thr || lim <= 1.0001 || v > thr + s) return v;
    return thr + s * (-nd / (nd - 1.0));
  }
  if (v < thr || lim <= 1.0001) return v;
  return thr + s * nd / (1.0 + nd);
}

// compressGamut (with getReachBoundary at the gamut boundary point).
vec3 aces2_compress_gamut(vec3 jmh, Aces2Params p, float jx, bool invert) {
  float j = jmh.x;
  float m = jmh.y;
  float h = jmh.z;
  vec2 cusp = aces2_cusp_from_table(h);
  if (m < 0.0001 || j > p.limit_j_max) return vec3(j, 0.0, h);
  float focus_j = mix(cusp.x, p.mid_j, min(1.0, ACES2_CUSP_MID_BLEND - cusp.x / p.limit_j_max));
  float slope_gain = p.limit_j_max * p.focus_dist * aces2_focus_gain(jx, cusp.x, p.limit_j_max);
  float gamma_top = aces2_upper_hull_gamma_from_table(h);
  vec3 boundary = aces2_find_gamut_boundary_intersection(jmh, cusp, focus_j, p.limit_j_max,
                                                         slope_gain, gamma_top, p.lower_hull_gamma);
  float reach_max_m = aces2_reach_m_from_table(h);
  float reach_gain =
      p.limit_j_max * p.focus_dist * aces2_focus_gain(boundary.x, cusp.x, p.limit_j_max);
  float intersect_j =
      aces2_solve_j_intersect(boundary.x, boundary.y, focus_j, p.limit_j_max, reach_gain);
  float reach_slope = aces2_projection_slope(intersect_j, focus_j, p.limit_j_max, reach_gain);
  float reach_m = p.limit_j_max * pow(intersect_j / p.limit_j_max, p.model_gamma) * reach_max_m /
                  (p.limit_j_max - reach_slope * reach_max_m);
  float difference = max(1.0001, reach_m / boundary.y);
  float threshold = max(ACES2_COMPRESSION_THRESHOLD, 1.0 / difference);
  float v = aces2_compression_function(m / boundary.y, threshold, difference, invert);
  return vec3(boundary.z + v * (boundary.x - boundary.z), v * boundary.y, h);
}

// gamutMap_fwd / gamutMap_inv.
vec3 aces2_gamut_map_fwd(vec3 jmh, Aces2Params p) {
  return aces2_compress_gamut(jmh, p, jmh.x, false);
}
vec3 aces2_gamut_map_inv(vec3 jmh, Aces2Params p) {
  vec2 cusp = aces2_cusp_from_table(jmh.z);
  float jx = jmh.x;
  if (jx <= mix(cusp.x, p.limit_j_max, ACES2_FOCUS_GAIN_BLEND)) {
    return aces2_compress_gamut(jmh, p, jx, true);
  }
  jx = aces2_compress_gamut(jmh, p, jx, true).x;
  return aces2_compress_gamut(jmh, p, jx, true);
}

// JMh_to_output_XYZ / XYZ_output_to_JMh.
vec3 aces2_jmh_to_output_xyz(vec3 jmh, Aces2Params p) {
  return (1.0 / ACES2_REFERENCE_LUMINANCE) * aces2_jmh_to_xyz(jmh, p.xyz_w_limit.xyz);
}
vec3 aces2_xyz_output_to_jmh(vec3 xyz, Aces2Params p) {
  return aces2_xyz_to_jmh(ACES2_REFERENCE_LUMINANCE * xyz, p.xyz_w_limit.xyz);
}

// outputTransform_fwd / outputTransform_inv: AP0 ↔ display XYZ (1.0 = 100 nits).
vec3 aces2_output_transform_fwd(vec3 aces, Aces2Params p) {
  vec3 jmh = aces2_aces_to_jmh(aces, p);
  vec3 tonemapped = aces2_tonemap_and_compress_fwd(jmh, p);
  vec3 compressed = aces2_gamut_map_fwd(tonemapped, p);
  return aces2_jmh_to_output_xyz(compressed, p);
}
vec3 aces2_output_transform_inv(vec3 xyz, Aces2Params p) {
  vec3 compressed = aces2_xyz_output_to_jmh(xyz, p);
  vec3 tonemapped = aces2_gamut_map_inv(compressed, p);
  vec3 jmh = aces2_tonemap_and_compress_inv(tonemapped, p);
  return aces2_jmh_to_aces(jmh);
}

// The limiting-primaries RGB of a display XYZ and back.
vec3 aces2_limit_rgb_from_xyz(vec3 xyz, Aces2Params p) {
  return aces2_mul_rows(p.limit_xyz_to_rgb, xyz);
}
vec3 aces2_xyz_from_limit_rgb(vec3 rgb, Aces2Params p) {
  return aces2_mul_rows(p.limit_rgb_to_xyz, rgb);
}

// ACESDisplayEncoding.ush: clamp_zero_to_peakLuminance, apply_white_scale's factor.
vec3 aces2_clamp_zero_to_peak(vec3 xyz, Aces2Params p) {
  vec3 rgb = clamp(aces2_mul_rows(p.limit_xyz_to_rgb, xyz), 0.0,
                   p.peak_luminance / ACES2_REFERENCE_LUMINANCE);
  return aces2_mul_rows(p.limit_rgb_to_xyz, rgb);
}
float aces2_white_scale(Aces2Params p) {
  vec3 rgb_w = (1.0 / ACES2_REFERENCE_LUMINANCE) * aces2_mul_rows(p.output_xyz_to_rgb, p.xyz_w_limit.xyz);
  return 1.0 / max(max(rgb_w.x, rgb_w.y), rgb_w.z);
}

// TonemapCommon.ush: ACESOutputTransform from AP0 on — encoding RGB in nits.
vec3 aces2_aces_output_transform_nits(vec3 aces, Aces2Params p, bool scale_white) {
  vec3 xyz = aces2_clamp_zero_to_peak(aces2_output_transform_fwd(aces, p), p);
  if (scale_white) xyz = aces2_white_scale(p) * xyz;
  return ACES2_REFERENCE_LUMINANCE * aces2_mul_rows(p.output_xyz_to_rgb, xyz);
}

#endif  // HDRC_ACES2_OUTPUT_GLSL
