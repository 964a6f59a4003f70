// UE 5.8's ACES 2.0 output transform in float32: the parameter block, UE's per-pixel constants and
// the Hellwig 2022 model. Twin of reference/ue/aces2/aces2.{h,cpp} (same function split, same
// names); sources and decisions: docs/ue58-decisions.md. From unicorn2022/UE5.8.0 5d9a05c1:
// ACES/ACESOutputTransform.ush (constants, XYZ_to_Hellwig2022_JMh, Hellwig2022_JMh_to_XYZ,
// Hellwig_J_to_Y, Y_to_Hellwig_J, aces_to_JMh, JMh_to_aces), ACES/ACESUtilities.ush (spow, sdiv,
// satan2, smin).
#ifndef HDRC_ACES2_COMMON_GLSL
#define HDRC_ACES2_COMMON_GLSL

// reference/ue/aces2/aces2.h: ParamsT<float> — 76 floats, std430 without implicit padding; a
// matrix is three vec4 rows (mul(M, v) = (dot(r0.xyz, v), dot(r1.xyz, v), dot(r2.xyz, v))).
struct Aces2Params {
  float peak_luminance;  // nits
  float n_r, g, t_1, c_t, s_2, u_2, m_2;
  float limit_j_max, mid_j, model_gamma, sat, sat_thr, compr, chroma_compress_scale;
  float focus_dist, lower_hull_gamma, ap1_clamp_upper, pad0, pad1;
  vec4 xyz_w_limit, xyz_w_output;
  vec4 limit_rgb_to_xyz[3];
  vec4 limit_xyz_to_rgb[3];
  vec4 output_rgb_to_xyz[3];
  vec4 output_xyz_to_rgb[3];
};

// The block from its 76 floats in ParamsT order (for probes that carry it as constants).
Aces2Params aces2_unpack(float v[76]) {
  Aces2Params p;
  p.peak_luminance = v[0];
  p.n_r = v[1];
  p.g = v[2];
  p.t_1 = v[3];
  p.c_t = v[4];
  p.s_2 = v[5];
  p.u_2 = v[6];
  p.m_2 = v[7];
  p.limit_j_max = v[8];
  p.mid_j = v[9];
  p.model_gamma = v[10];
  p.sat = v[11];
  p.sat_thr = v[12];
  p.compr = v[13];
  p.chroma_compress_scale = v[14];
  p.focus_dist = v[15];
  p.lower_hull_gamma = v[16];
  p.ap1_clamp_upper = v[17];
  p.pad0 = v[18];
  p.pad1 = v[19];
  p.xyz_w_limit = vec4(v[20], v[21], v[22], v[23]);
  p.xyz_w_output = vec4(v[24], v[25], v[26], v[27]);
  for (int r = 0; r < 3; ++r) {
    p.limit_rgb_to_xyz[r] = vec4(v[28 + 4 * r], v[29 + 4 * r], v[30 + 4 * r], 0.0);
    p.limit_xyz_to_rgb[r] = vec4(v[40 + 4 * r], v[41 + 4 * r], v[42 + 4 * r], 0.0);
    p.output_rgb_to_xyz[r] = vec4(v[52 + 4 * r], v[53 + 4 * r], v[54 + 4 * r], 0.0);
    p.output_xyz_to_rgb[r] = vec4(v[64 + 4 * r], v[65 + 4 * r], v[66 + 4 * r], 0.0);
  }
  return p;
}

vec3 aces2_mul_rows(vec4 m[3], vec3 v) {
  return vec3(dot(m[0].xyz, v), dot(m[1].xyz, v), dot(m[2].xyz, v));
}
vec3 aces2_mul(vec3 r0, vec3 r1, vec3 r2, vec3 v) {
  return vec3(dot(r0, v), dot(r1, v), dot(r2, v));
}

// ACESOutputTransform.ush: CAM parameters and the Hellwig inverse matrix (panlrcm).
const float ACES2_REFERENCE_LUMINANCE = 100.0;
const float ACES2_L_A = 100.0;
const float ACES2_Y_B = 20.0;
const float ACES2_RA = 2.0;
const float ACES2_BA = 0.05;
const vec3 ACES2_SURROUND = vec3(0.9, 0.59, 0.9);
const float ACES2_PI = 3.14159265358979323846;

// ACESCommon.ush literals, rows (docs/ue58-decisions.md A6).
const vec3 ACES2_AP0_2_AP1_0 = vec3(1.4514393161, -0.2365107469, -0.2149285693);
const vec3 ACES2_AP0_2_AP1_1 = vec3(-0.0765537734, 1.1762296998, -0.0996759264);
const vec3 ACES2_AP0_2_AP1_2 = vec3(0.0083161484, -0.0060324498, 0.9977163014);
const vec3 ACES2_AP1_2_XYZ_0 = vec3(0.6624541811, 0.1340042065, 0.1561876870);
const vec3 ACES2_AP1_2_XYZ_1 = vec3(0.2722287168, 0.6740817658, 0.0536895174);
const vec3 ACES2_AP1_2_XYZ_2 = vec3(-0.0055746495, 0.0040607335, 1.0103391003);
const vec3 ACES2_AP0_2_XYZ_0 = vec3(0.9525523959, 0.0000000000, 0.0000936786);
const vec3 ACES2_AP0_2_XYZ_1 = vec3(0.3439664498, 0.7281660966, -0.0721325464);
const vec3 ACES2_AP0_2_XYZ_2 = vec3(0.0000000000, 0.0000000000, 1.0088251844);
const vec3 ACES2_XYZ_2_AP0_0 = vec3(1.0498110175, 0.0000000000, -0.0000974845);
const vec3 ACES2_XYZ_2_AP0_1 = vec3(-0.4959030231, 1.3733130458, 0.0982400361);
const vec3 ACES2_XYZ_2_AP0_2 = vec3(0.0000000000, 0.0000000000, 0.9912520182);
const vec3 ACES2_XYZ_2_CAM16_0 = vec3(0.3640744835, 0.5947008156, 0.04110127349);
const vec3 ACES2_XYZ_2_CAM16_1 = vec3(-0.2222450987, 1.0738554823, 0.14794533610);
const vec3 ACES2_XYZ_2_CAM16_2 = vec3(-0.0020676190, 0.0488260453, 0.95038755696);
const vec3 ACES2_CAM16_2_XYZ_0 = vec3(2.0512756811, -1.1400313439, 0.0887556628);
const vec3 ACES2_CAM16_2_XYZ_1 = vec3(0.4269389763, 0.7005835277, -0.1275225040);
const vec3 ACES2_CAM16_2_XYZ_2 = vec3(-0.0174712779, -0.0384725929, 1.0589468739);
const vec3 ACES2_PANLRCM_0 = vec3(460.0, 451.0, 288.0);
const vec3 ACES2_PANLRCM_1 = vec3(460.0, -891.0, -261.0);
const vec3 ACES2_PANLRCM_2 = vec3(460.0, -220.0, -6300.0);

// ACESUtilities.ush: spow, sdiv, satan2, smin.
float aces2_spow(float base, float e) {
  return (base < 0.0 && e != floor(e)) ? 0.0 : pow(base, e);
}
float aces2_sdiv(float a, float b) {
  return b == 0.0 ? 0.0 : a / b;
}
float aces2_satan2(float y, float x) {
  return (x == 0.0 && y == 0.0) ? 0.0 : atan(y, x);
}
float aces2_smin(float a, float b, float s) {
  float h = max(s - abs(a - b), 0.0) / s;
  return min(a, b) - h * h * h * s * (1.0 / 6.0);
}
// wrap_to_360 (HLSL fmod keeps the sign of x).
float aces2_wrap_to_360(float hue) {
  float y = hue - 360.0 * trunc(hue / 360.0);
  return y < 0.0 ? y + 360.0 : y;
}

// The viewing-condition constants every Hellwig function recomputes (k, k4, F_L).
float aces2_f_l() {
  float k = 1.0 / (5.0 * ACES2_L_A + 1.0);
  float k4 = pow(k, 4.0);
  return 0.2 * k4 * (5.0 * ACES2_L_A) +
         0.1 * pow(1.0 - k4, 2.0) * aces2_spow(5.0 * ACES2_L_A, 1.0 / 3.0);
}
float aces2_a_w_j() {
  float f = pow(aces2_f_l(), 0.42);
  return 400.0 * f / (27.13 + f);
}

// post_adaptation_non_linear_response_compression_forward / _inverse.
vec3 aces2_panlrc_fwd(vec3 v, float fl) {
  vec3 f = vec3(aces2_spow(fl * abs(v.x) / 100.0, 0.42), aces2_spow(fl * abs(v.y) / 100.0, 0.42),
                aces2_spow(fl * abs(v.z) / 100.0, 0.42));
  return 400.0 * sign(v) * f / (27.13 + f);
}
vec3 aces2_panlrc_inv(vec3 v, float fl) {
  vec3 av = abs(v);
  vec3 b = 27.13 * av / (400.0 - av);
  return sign(v) * 100.0 / fl *
         vec3(aces2_spow(b.x, 1.0 / 0.42), aces2_spow(b.y, 1.0 / 0.42), aces2_spow(b.z, 1.0 / 0.42));
}

// Hellwig_J_to_Y / Y_to_Hellwig_J (Y in nits).
float aces2_hellwig_j_to_y(float j) {
  float fl = aces2_f_l();
  float z = 1.48 + sqrt(ACES2_Y_B / 100.0);
  float a = aces2_a_w_j() * pow(abs(j) / 100.0, 1.0 / (ACES2_SURROUND.y * z));
  return sign(j) * 100.0 / fl * pow((27.13 * a) / (400.0 - a), 1.0 / 0.42);
}
float aces2_y_to_hellwig_j(float y) {
  float fl = aces2_f_l();
  float z = 1.48 + sqrt(ACES2_Y_B / 100.0);
  float f = pow(fl * abs(y) / 100.0, 0.42);
  return sign(y) * 100.0 * pow((400.0 * f / (27.13 + f)) / aces2_a_w_j(), ACES2_SURROUND.y * z);
}

vec3 aces2_xyz_to_cam16(vec3 v) {
  return aces2_mul(ACES2_XYZ_2_CAM16_0, ACES2_XYZ_2_CAM16_1, ACES2_XYZ_2_CAM16_2, v);
}

// XYZ_to_Hellwig2022_JMh (XYZ and white in nits; D = 1).
vec3 aces2_xyz_to_jmh(vec3 xyz, vec3 xyz_w) {
  float y_w = xyz_w.y;
  vec3 rgb_w = aces2_xyz_to_cam16(xyz_w);
  float fl = aces2_f_l();
  float z = 1.48 + sqrt(ACES2_Y_B / y_w);
  vec3 d_rgb = y_w / rgb_w;
  vec3 rgb_aw = aces2_panlrc_fwd(d_rgb * rgb_w, fl);
  float a_w = ACES2_RA * rgb_aw.x + rgb_aw.y + ACES2_BA * rgb_aw.z;
  vec3 rgb_a = aces2_panlrc_fwd(d_rgb * aces2_xyz_to_cam16(xyz), fl);
  float a = rgb_a.x - 12.0 * rgb_a.y / 11.0 + rgb_a.z / 11.0;
  float b = (rgb_a.x + rgb_a.y - 2.0 * rgb_a.z) / 9.0;
  float h = aces2_wrap_to_360(aces2_satan2(b, a) * 180.0 / ACES2_PI);
  float achromatic = ACES2_RA * rgb_a.x + rgb_a.y + ACES2_BA * rgb_a.z;
  float j = 100.0 * pow(achromatic / a_w, ACES2_SURROUND.y * z);
  float m = (j == 0.0) ? 0.0 : 43.0 * ACES2_SURROUND.z * sqrt(a * a + b * b);
  return vec3(j, m, h);
}

// Hellwig2022_JMh_to_XYZ.
vec3 aces2_jmh_to_xyz(vec3 jmh, vec3 xyz_w) {
  float y_w = xyz_w.y;
  vec3 rgb_w = aces2_xyz_to_cam16(xyz_w);
  float fl = aces2_f_l();
  float z = 1.48 + sqrt(aces2_sdiv(ACES2_Y_B, y_w));
  vec3 d_rgb = y_w / rgb_w;
  vec3 rgb_aw = aces2_panlrc_fwd(d_rgb * rgb_w, fl);
  float a_w = ACES2_RA * rgb_aw.x + rgb_aw.y + ACES2_BA * rgb_aw.z;
  float hr = jmh.z / 180.0 * ACES2_PI;
  float achromatic = a_w * aces2_spow(jmh.x / 100.0, 1.0 / (ACES2_SURROUND.y * z));
  float gamma = jmh.y / (43.0 * ACES2_SURROUND.z);
  vec3 rgb_a = (1.0 / 1403.0) * aces2_mul(ACES2_PANLRCM_0, ACES2_PANLRCM_1, ACES2_PANLRCM_2,
                                          vec3(achromatic, gamma * cos(hr), gamma * sin(hr)));
  vec3 rgb = aces2_panlrc_inv(rgb_a, fl) / d_rgb;
  return aces2_mul(ACES2_CAM16_2_XYZ_0, ACES2_CAM16_2_XYZ_1, ACES2_CAM16_2_XYZ_2, rgb);
}

// aces_to_JMh: AP0 → AP1 → clamp_AP1 → XYZ → JMh against the ACES white.
vec3 aces2_aces_to_jmh(vec3 aces, Aces2Params p) {
  vec3 ap1 = aces2_mul(ACES2_AP0_2_AP1_0, ACES2_AP0_2_AP1_1, ACES2_AP0_2_AP1_2, aces);
  ap1 = clamp(ap1, 0.0, p.ap1_clamp_upper);
  vec3 xyz = aces2_mul(ACES2_AP1_2_XYZ_0, ACES2_AP1_2_XYZ_1, ACES2_AP1_2_XYZ_2, ap1);
  vec3 xyz_w = aces2_mul(ACES2_AP0_2_XYZ_0, ACES2_AP0_2_XYZ_1, ACES2_AP0_2_XYZ_2,
                         vec3(ACES2_REFERENCE_LUMINANCE));
  return aces2_xyz_to_jmh(ACES2_REFERENCE_LUMINANCE * xyz, xyz_w);
}

// JMh_to_aces.
vec3 aces2_jmh_to_aces(vec3 jmh) {
  vec3 xyz_w = aces2_mul(ACES2_AP0_2_XYZ_0, ACES2_AP0_2_XYZ_1, ACES2_AP0_2_XYZ_2,
                         vec3(ACES2_REFERENCE_LUMINANCE));
  vec3 xyz = (1.0 / ACES2_REFERENCE_LUMINANCE) * aces2_jmh_to_xyz(jmh, xyz_w);
  return aces2_mul(ACES2_XYZ_2_AP0_0, ACES2_XYZ_2_AP0_1, ACES2_XYZ_2_AP0_2, xyz);
}

#endif  // HDRC_ACES2_COMMON_GLSL
