// The second float32 evaluation's `unity_urp` pipeline (issue 28 item 6): URP's LUT bake
// (`lut_bake`: LutBuilderHdr / LutBuilderLdr) and the uber pass's ApplyColorGrading
// (`color_grading`), written from docs/spec/unity_urp.md (§1-§5), docs/candidates/lut_bake.md,
// docs/candidates/color_grading.md and docs/spec/semantics.md alone, in float32, in an operation
// order that differs from the project's GLSL (gpu/shaders/unity_urp/lib/unity_color.glsl,
// unity_grade.glsl, unity_tonemap.glsl, unity_lut.glsl) on purpose:
//
//  * LogC and ACEScc with their affine parts folded into one fused step: LogC⁻¹ as
//    exp2(code · (log2 10 / c) − d · log2 10 / c) · (1/a) − b/a, LogC as
//    log2(a·x + b) · (c · log10 2) + d, ACEScc as log2(x) · (1/17.52) + 9.72/17.52 (the GLSL
//    divides (·)/c, (·)/a, (·)/17.52 and multiplies log2 by log10 2 first);
//  * white balance as one matrix LMS2LIN · diag(balance) · LIN2LMS formed in float32 (the GLSL
//    applies the three in turn); the ACES fit's output matrices XYZ_2_REC709 · D60_2_D65 ·
//    AP1_2_XYZ likewise; every matrix and luminance dot product summed last column first, fused;
//  * contrast as ℓ·k + pivot·(1 − k), saturation as σ·c + λ·(1 − σ), shadows/midtones/highlights
//    as c · (Sh·wS + Mid·wM + Hi·wH) (the GLSL: (ℓ − pivot)·k + pivot, λ + σ(c − λ), three
//    products summed); every lerp as a·(1 − t) + b·t (the GLSL: a + t(b − a));
//  * pow as the C library's powf (the GLSL: exp2(y·log2 x)); SoftLight, HsvToRgb and the ACES fit's
//    rational rearranged and fused, the rational in 1/p above p = 1; divisions as reciprocal
//    multiplies where the GLSL divides, and the other way round;
//  * ApplyLut2D as trilinear interpolation of the stored lattice with its eight weights summed (the
//    GLSL: two hardware-bilinear taps lerped; the hardware rounds its weights to 8 bits, this does
//    not); storage rounding through Imath's half and nearbyint (the GLSL scales by powers of two).
//
// The colour curves are at their defaults, as the pipeline's (docs/unity_urp.md, "Decisions";
// spec §4): the secondary curves are neutral and the YRGB curves clamp(·, 0, 127/128).
#include <Imath/half.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "float32_common.h"

namespace f32 {
namespace {

// --- Constants (docs/spec/unity_urp.md §2.2, §2.3, §2.5) ---
// §2.2: Unity's LogC (ALEXA EI 1000, fast form).
constexpr float kLogcA = 5.555556f, kLogcB = 0.047996f, kLogcC = 0.244161f, kLogcD = 0.386036f;
constexpr float kLog2Of10 = 3.32192809f, kLog10Of2 = 0.301029996f;
constexpr float kAcesccMidgray = 0.4135884f;  // §2.3 step 3's pivot
constexpr float kHalfMax = 65504.0f;
constexpr float kCurveCap = 127.0f / 128.0f;  // §4: the default YRGB curves' last texel
const float kLum709[3] = {0.2126729f, 0.7151522f, 0.0721750f};
const float kLumAp1[3] = {0.272229f, 0.674082f, 0.0536895f};  // AP1_RGB2Y
const M3 kLin2Lms{{{0.390405f, 0.549941f, 0.00892632f},
                   {0.0708416f, 0.963172f, 0.00135775f},
                   {0.0231082f, 0.128021f, 0.936245f}}};
const M3 kLms2Lin{{{2.85847f, -1.62879f, -0.0248910f},
                   {-0.210182f, 1.15820f, 0.000324281f},
                   {-0.0418120f, -0.118169f, 1.06867f}}};
const M3 kSrgbToAp0{{{0.4397010f, 0.3829780f, 0.1773350f},
                     {0.0897923f, 0.8134230f, 0.0967616f},
                     {0.0175440f, 0.1115440f, 0.8707040f}}};
const M3 kXyzToRec709{{{3.2409699419f, -1.5373831776f, -0.4986107603f},
                       {-0.9692436363f, 1.8759675015f, 0.0415550574f},
                       {0.0556300797f, -0.2039769589f, 1.0569715142f}}};
const M3 kD60ToD65{{{0.98722400f, -0.00611327f, 0.0159533f},
                    {-0.00759836f, 1.00186000f, 0.0053302f},
                    {0.00307257f, -0.00509595f, 1.0816800f}}};

float dot(const float w[3], const float c[3]) {
  return std::fmaf(w[0], c[0], std::fmaf(w[1], c[1], w[2] * c[2]));
}
// HLSL lerp written a·(1 − t) + b·t.
float mix(float a, float b, float t) {
  return std::fmaf(b, t, a * (1.0f - t));
}
float hlsl_sign(float x) {
  return float(x > 0.0f) - float(x < 0.0f);
}
// HLSL smoothstep; equal edges as HLSL's division by 0 then saturate (§7 item 6): 1 above, else 0.
float smoothstep(float e0, float e1, float x) {
  if (e0 == e1) return x > e0 ? 1.0f : 0.0f;
  const float t = saturate((x - e0) * (1.0f / (e1 - e0)));
  return t * t * std::fmaf(-2.0f, t, 3.0f);
}
// PositivePow and HLSL pow of a non-negative base, through the C library.
float powf_abs(float x, float y) {
  return std::pow(std::fabs(x), y);
}

// --- LogC and ACEScc (§2.2, §2.5) ---
float linear_from_logc(float code) {
  constexpr float k1 = kLog2Of10 / kLogcC, k0 = -kLogcD * (kLog2Of10 / kLogcC);
  return std::fmaf(std::exp2(std::fmaf(code, k1, k0)), 1.0f / kLogcA, -kLogcB / kLogcA);
}
float logc_from_linear(float x) {
  // max(a·x + b, 0) with maxNum: NaN → 0 → −Inf, which saturate turns to 0 (semantics.md).
  return std::fmaf(std::log2(max_num(std::fmaf(kLogcA, x, kLogcB), 0.0f)), kLogcC * kLog10Of2,
                   kLogcD);
}
float acescc_from_linear(float x) {
  x = clamp_num(x, 0.0f, kHalfMax);
  const float l = x < 0.00003051757f ? std::log2(std::fmaf(x, 0.5f, 0.00001525878f)) : std::log2(x);
  return std::fmaf(l, 1.0f / 17.52f, 9.72f / 17.52f);
}
float linear_from_acescc(float y) {
  static const float kTop = (std::log2(kHalfMax) + 9.72f) / 17.52f;
  if (y < -0.3013698630f)
    return std::fmaf(std::exp2(std::fmaf(y, 17.52f, -9.72f)), 2.0f, -0x1p-15f);
  if (y < kTop) return std::exp2(std::fmaf(y, 17.52f, -9.72f));
  return kHalfMax;
}

// --- HSV (§2.4) ---
void hsv_from_rgb(const float c[3], float hsv[3]) {
  const float r = c[0], g = c[1], b = c[2];
  float p[4], q[4];
  if (g >= b) {  // HLSL step(b, g)
    p[0] = g, p[1] = b, p[2] = 0.0f, p[3] = -1.0f / 3.0f;
  } else {
    p[0] = b, p[1] = g, p[2] = -1.0f, p[3] = 2.0f / 3.0f;
  }
  if (r >= p[0]) {
    q[0] = r, q[1] = p[1], q[2] = p[2], q[3] = p[0];
  } else {
    q[0] = p[0], q[1] = p[1], q[2] = p[3], q[3] = r;
  }
  const float d = q[0] - std::fmin(q[3], q[1]);
  hsv[0] = std::fabs(std::fmaf(q[3] - q[1], 1.0f / std::fmaf(6.0f, d, 1e-4f), q[2]));
  hsv[1] = d * (1.0f / (q[0] + 1e-4f));
  hsv[2] = q[0];
}
void rgb_from_hsv(const float hsv[3], float c[3]) {
  const float k[3] = {1.0f, 2.0f / 3.0f, 1.0f / 3.0f};
  for (int i = 0; i < 3; ++i) {
    const float x = hsv[0] + k[i];
    const float p = std::fabs(std::fmaf(x - std::floor(x), 6.0f, -3.0f));
    c[i] = hsv[2] * mix(1.0f, saturate(p - 1.0f), hsv[1]);
  }
}

// SoftLight (§2.3 step 6): b ≥ 0.5: √a(2b − 1) + 2a(1 − b); else 2ab + a²(1 − 2b) = a(2b + a(1 −
// 2b)).
float soft_light(float a, float b) {
  if (b >= 0.5f) return std::fmaf(std::sqrt(a), 2.0f * b - 1.0f, (a + a) * (1.0f - b));
  return a * std::fmaf(a, 1.0f - 2.0f * b, b + b);
}

// --- Tone maps (§2.6) ---
float fast_sign(float x) {
  return x >= 0.0f ? 1.0f : -1.0f;
}  // §7 item 5: +1 at ±0; NaN → −1 (saturate(NaN · FLT_MAX + 0.5) = 0)

// The fitted tone scale (§2.6 ACES step 4), expanded and fused; above p = 1 in r = 1/p. ±Inf:
// ∞/∞ = NaN, as IEEE evaluates the written form.
float aces_fit_curve(float p) {
  constexpr float kA = 0.0245786f, kB = 0.000090537f, kC = 0.983729f, kD = 0.4329510f,
                  kE = 0.238081f;
  if (std::isinf(p)) return kNaN;
  if (std::fabs(p) <= 1.0f)
    return std::fmaf(p, p, std::fmaf(kA, p, -kB)) / std::fmaf(kC * p, p, std::fmaf(kD, p, kE));
  const float r = 1.0f / p;
  return std::fmaf(-kB * r, r, std::fmaf(kA, r, 1.0f)) / std::fmaf(kE * r, r, std::fmaf(kD, r, kC));
}

void desaturate_ap1(float c[3], float s) {
  const float y = dot(kLumAp1, c);
  for (int i = 0; i < 3; ++i) c[i] = mix(y, c[i], s);
}

// AcesTonemap (fitted, §2.6 ACES steps 1-7): ACES2065-1 in, linear Rec.709 out, not clamped.
void aces_tonemap(const float in[3], float out[3]) {
  static const M3 kOut = mul(kXyzToRec709, mul(kD60ToD65, kAp1ToXyz));
  float a[3] = {in[0], in[1], in[2]};
  // 1. Glow.
  const float mx = std::fmax(std::fmax(a[0], a[1]), a[2]);
  const float mn = std::fmin(std::fmin(a[0], a[1]), a[2]);
  const float sat = (max_num(mx, 1e-4f) - max_num(mn, 1e-4f)) * (1.0f / max_num(mx, 1e-2f));
  const float chroma =
      std::fmaf(a[0], a[0] - a[2], std::fmaf(a[1], a[1] - a[0], a[2] * (a[2] - a[1])));
  const float yc = (a[0] + a[1] + a[2] + 1.75f * std::sqrt(max_num(chroma, 0.0f))) * (1.0f / 3.0f);
  const float x = (sat - 0.4f) * 5.0f;
  const float t = max_num(1.0f - std::fabs(0.5f * x), 0.0f);
  const float sigma = 0.5f * std::fmaf(fast_sign(x), 1.0f - t * t, 1.0f);
  const float glow = 1.0f + glow_fwd(yc, 0.05f * sigma, 0.08f);
  for (float& c : a) c *= glow;
  // 2. Red modifier (hue in degrees, 0 for grey, wrapped to [0, 360), centred on 0).
  float hue = 0.0f;
  if (!(a[0] == a[1] && a[1] == a[2])) {
    hue = 57.2957795f * std::atan2(1.73205081f * (a[1] - a[2]), 2.0f * a[0] - a[1] - a[2]);
    if (hue < 0.0f) hue += 360.0f;
  }
  const float w = smoothstep(0.0f, 1.0f, 1.0f - std::fabs(center_hue(hue, 0.0f) * (2.0f / 135.0f)));
  a[0] = std::fmaf(w * w * sat * (1.0f - 0.82f), 0.03f - a[0], a[0]);
  // 3. To AP1, clamp, desaturate 0.96.
  float p[3];
  mul(kAp0ToAp1, a, p);
  for (float& c : p) c = max_num(c, 0.0f);
  desaturate_ap1(p, 0.96f);
  // 4. The fitted tone scale.
  float q[3];
  for (int i = 0; i < 3; ++i) q[i] = aces_fit_curve(p[i]);
  // 5. Dark to dim surround.
  float xyz[3];
  mul(kAp1ToXyz, q, xyz);
  const float inv_sum = 1.0f / max_num(xyz[0] + xyz[1] + xyz[2], 1e-4f);
  const float cx = xyz[0] * inv_sum, cy = xyz[1] * inv_sum;
  const float big_y = std::pow(clamp_num(xyz[1], 0.0f, kHalfMax), 0.9811f);
  const float m = big_y / max_num(cy, 1e-4f);
  const float dim[3] = {cx * m, big_y, ((1.0f - cy) - cx) * m};
  mul(kXyzToAp1, dim, q);
  // 6. ODT desaturation 0.93; 7. to linear Rec.709.
  desaturate_ap1(q, 0.93f);
  mul(kOut, q, out);
}

// --- The grade (§1's shader constants, §2.3, §3) ---
struct Grade {
  bool hdr = false, aces = false;  // HDR grading; mode A (HDR grading with ACES, §2.3)
  int tonemap = 0;                 // 0 None, 1 Neutral, 2 ACES
  M3 white_balance{};              // LMS2LIN · diag(_ColorBalance) · LIN2LMS
  const float* lum = kLum709;
  float filter[3], hue_shift, saturation, contrast, mixer[3][3], lift[3], gamma[3], gain[3];
  float shadows[3], midtones[3], highlights[3], limits[4], split_s[3], split_h[3], balance;
};

void vec3(const json& v, float out[3]) {
  for (int i = 0; i < 3; ++i) out[i] = number(v.at(i));
}

Grade grade_from(const json& p) {
  Grade g;
  g.hdr = p.at("urp_grading_mode").get<int>() == 1;
  g.tonemap = p.at("urp_tonemap_mode").get<int>();
  g.aces = g.hdr && g.tonemap == 2;
  if (g.aces) g.lum = kLumAp1;
  float cb[3];
  vec3(p.at("urp_color_balance"), cb);
  M3 scaled = kLin2Lms;
  for (int r = 0; r < 3; ++r)
    for (float& v : scaled.m[r]) v *= cb[r];
  g.white_balance = mul(kLms2Lin, scaled);
  vec3(p.at("urp_color_filter"), g.filter);
  const json& hsc = p.at("urp_hue_sat_con");
  g.hue_shift = number(hsc.at(0));
  g.saturation = number(hsc.at(1));
  g.contrast = number(hsc.at(2));
  vec3(p.at("urp_channel_mixer_red"), g.mixer[0]);
  vec3(p.at("urp_channel_mixer_green"), g.mixer[1]);
  vec3(p.at("urp_channel_mixer_blue"), g.mixer[2]);
  vec3(p.at("urp_lift"), g.lift);
  vec3(p.at("urp_gamma"), g.gamma);
  vec3(p.at("urp_gain"), g.gain);
  vec3(p.at("urp_shadows"), g.shadows);
  vec3(p.at("urp_midtones"), g.midtones);
  vec3(p.at("urp_highlights"), g.highlights);
  for (int i = 0; i < 4; ++i) g.limits[i] = number(p.at("urp_sha_hi_limits").at(i));
  vec3(p.at("urp_split_shadows"), g.split_s);
  g.balance = number(p.at("urp_split_shadows").at(3));
  vec3(p.at("urp_split_highlights"), g.split_h);
  return g;
}

// ColorGrade (§2.3, HDR: a LogC code) or FragLutBuilderLdr's grade (§3: a linear code), before the
// tone map.
void color_grade(const Grade& g, const float code[3], float c[3]) {
  float t[3];
  // 1. Decode (HDR only).
  for (int i = 0; i < 3; ++i) t[i] = g.hdr ? linear_from_logc(code[i]) : code[i];
  // 2. White balance.
  mul(g.white_balance, t, c);
  // 3. Contrast about ACEScc_MIDGRAY: ℓ·k + pivot·(1 − k).
  const float k = g.contrast, offset = kAcesccMidgray * (1.0f - k);
  if (g.aces) {
    float ap0[3];
    mul(kSrgbToAp0, c, ap0);
    for (int i = 0; i < 3; ++i)
      t[i] = linear_from_acescc(std::fmaf(acescc_from_linear(ap0[i]), k, offset));
    mul(kAp0ToAp1, t, c);  // ACEScg from here on
  } else {
    for (int i = 0; i < 3; ++i)
      c[i] = linear_from_logc(std::fmaf(logc_from_linear(c[i]), k, offset));
  }
  // 4-5. Colour filter, clamp.
  for (int i = 0; i < 3; ++i) c[i] = max_num(c[i] * g.filter[i], 0.0f);
  // 6. Split toning in gamma space.
  float gm[3], clamped[3];
  for (int i = 0; i < 3; ++i) {
    gm[i] = powf_abs(c[i], 1.0f / 2.2f);
    clamped[i] = saturate(gm[i]);
  }
  const float lam = saturate(dot(g.lum, clamped) + g.balance);
  for (int i = 0; i < 3; ++i) {
    const float sh = mix(0.5f, g.split_s[i], 1.0f - lam), hi = mix(0.5f, g.split_h[i], lam);
    c[i] = powf_abs(soft_light(soft_light(gm[i], sh), hi), 2.2f);
  }
  // 7. Channel mixer.
  for (int i = 0; i < 3; ++i) t[i] = dot(g.mixer[i], c);
  // 8. Shadows, midtones, highlights: c · (Sh·wS + Mid·wM + Hi·wH).
  const float luma = dot(g.lum, t);
  const float ws = 1.0f - smoothstep(g.limits[0], g.limits[1], luma);
  const float wh = smoothstep(g.limits[2], g.limits[3], luma);
  const float wm = (1.0f - wh) - ws;
  for (int i = 0; i < 3; ++i)
    t[i] *= std::fmaf(g.highlights[i], wh, std::fmaf(g.midtones[i], wm, g.shadows[i] * ws));
  // 9. Lift, gain, gamma: sign(c)·|c|^gamma of c·gain + lift.
  for (int i = 0; i < 3; ++i) {
    const float v = std::fmaf(t[i], g.gain[i], g.lift[i]);
    t[i] = hlsl_sign(v) * powf_abs(v, g.gamma[i]);
  }
  // 10. Hue shift through HSV, one RotateHue wrap (default secondary curves: satMult 1, no
  // hue-vs-hue offset).
  float hsv[3];
  hsv_from_rgb(t, hsv);
  float hue = hsv[0] + g.hue_shift;
  hsv[0] = hue < 0.0f ? hue + 1.0f : (hue > 1.0f ? hue - 1.0f : hue);
  rgb_from_hsv(hsv, c);
  // 11. Global saturation: σ·c + λ·(1 − σ).
  const float l2 = dot(g.lum, c), rest = l2 * (1.0f - g.saturation);
  for (int i = 0; i < 3; ++i) c[i] = std::fmaf(g.saturation, c[i], rest);
  // 12. The default YRGB curves, inside FastTonemap / FastTonemapInvert in HDR only.
  if (g.hdr) {
    const float m = std::fmax(std::fmax(c[0], c[1]), c[2]) + 1.0f;
    for (int i = 0; i < 3; ++i) t[i] = clamp_num(c[i] / m, 0.0f, kCurveCap);
    const float tm = std::fmax(std::fmax(t[0], t[1]), t[2]);
    for (int i = 0; i < 3; ++i) c[i] = t[i] / (1.0f - tm);
  } else {
    for (int i = 0; i < 3; ++i) c[i] = clamp_num(c[i], 0.0f, kCurveCap);
  }
  // 13. Clamp.
  for (int i = 0; i < 3; ++i) c[i] = max_num(c[i], 0.0f);
}

// The bake's value for a lattice code (§2.6: HDR tone map, not clamped; §3: LDR saturate).
void bake_texel(const Grade& g, const float code[3], float out[3]) {
  float c[3];
  color_grade(g, code, c);
  if (!g.hdr) {
    for (int i = 0; i < 3; ++i) out[i] = saturate(c[i]);
  } else if (g.tonemap == 1) {
    for (int i = 0; i < 3; ++i) out[i] = unity_neutral(c[i], 1.0f);
  } else if (g.tonemap == 2) {
    float ap0[3];
    mul(kAp1ToAp0, c, ap0);
    aces_tonemap(ap0, out);
  } else {
    for (int i = 0; i < 3; ++i) out[i] = c[i];
  }
}

// docs/candidates/lut_bake.md: 1 RGBA16F (nearest half, ties to even, overflow ±Inf), 3 RGBA8
// UNORM (saturate, nearest k/255), otherwise float32.
float quantize(float v, int format) {
  if (format == 1) return static_cast<float>(Imath::half(v));
  if (format == 3) return std::nearbyint(saturate(v) * 255.0f) / 255.0f;
  return v;
}

// The strip, H² × H RGBA: lattice (r, g, b) at pixel (r + H·b, g) (§2.1, §5.5).
struct Lut {
  int n = 0;
  std::vector<float> rgba;
  size_t index(int r, int g, int b) const {
    return (static_cast<size_t>(g) * n * n + r + static_cast<size_t>(n) * b) * 4;
  }
  const float* at(int r, int g, int b) const { return &rgba[index(r, g, b)]; }
  float* at(int r, int g, int b) { return &rgba[index(r, g, b)]; }
};

Lut bake(const Grade& g, int n, int format) {
  Lut lut;
  lut.n = n;
  lut.rgba.assign(static_cast<size_t>(n) * n * n * 4, 1.0f);
  const float step = 1.0f / static_cast<float>(n - 1);
  for (int b = 0; b < n; ++b)
    for (int gg = 0; gg < n; ++gg)
      for (int r = 0; r < n; ++r) {
        const float code[3] = {r * step, gg * step, b * step};
        float out[3];
        bake_texel(g, code, out);
        float* px = lut.at(r, gg, b);
        for (int i = 0; i < 3; ++i) px[i] = quantize(out[i], format);
      }
  return lut;
}

// ApplyLut2D (§5.3) as trilinear interpolation of the stored lattice: the eight corner weights
// formed first and summed from the last corner. uvw is in [0, 1] (saturated by both callers).
void apply_lut(const Lut& lut, const float uvw[3], float out[3]) {
  const int top = lut.n - 1;
  int i0[3], i1[3];
  float f[3];
  for (int k = 0; k < 3; ++k) {
    const float x = uvw[k] * static_cast<float>(top), fl = std::floor(x);
    i0[k] = static_cast<int>(fl);
    f[k] = x - fl;
    i1[k] = std::min(i0[k] + 1, top);
  }
  float acc[3] = {0.0f, 0.0f, 0.0f};
  for (int corner = 7; corner >= 0; --corner) {
    const int br = corner & 1, bg = (corner >> 1) & 1, bb = (corner >> 2) & 1;
    const float w =
        (br ? f[0] : 1.0f - f[0]) * (bg ? f[1] : 1.0f - f[1]) * (bb ? f[2] : 1.0f - f[2]);
    if (w == 0.0f) continue;  // a clamped neighbour of weight 0 (and 0 · Inf) takes no part
    const float* t = lut.at(br ? i1[0] : i0[0], bg ? i1[1] : i0[1], bb ? i1[2] : i0[2]);
    for (int c = 0; c < 3; ++c) acc[c] = std::fmaf(w, t[c], acc[c]);
  }
  for (int c = 0; c < 3; ++c) out[c] = acc[c];
}

// ApplyColorGrading (§5.2) of one pixel: post exposure; HDR: the lookup at saturate(LogC(x)); LDR:
// the lookup at saturate(Tonemap(x)).
void color_grading(const Grade& g, const Lut& lut, float exposure, float px[3]) {
  float x[3], uvw[3];
  for (int i = 0; i < 3; ++i) x[i] = px[i] * exposure;
  if (g.hdr) {
    for (int i = 0; i < 3; ++i) uvw[i] = saturate(logc_from_linear(x[i]));
  } else {
    if (g.tonemap == 2) {
      float ap0[3];
      mul(kSrgbToAp0, x, ap0);
      aces_tonemap(ap0, x);
    } else if (g.tonemap == 1) {
      for (float& v : x) v = unity_neutral(v, 1.0f);
    }
    for (int i = 0; i < 3; ++i) uvw[i] = saturate(x[i]);
  }
  apply_lut(lut, uvw, px);
}

}  // namespace

int unity_urp_stage(const json& doc, const std::string& dir, const std::string& output) {
  const std::string stage = doc.at("stage");
  if (stage != "lut_bake" && stage != "color_grading") {
    std::printf("unity_urp stage %s is not implemented by this port\n", stage.c_str());
    return kDeclineStage;
  }
  if (!doc.value("degenerate", json()).is_null()) {
    std::printf("degenerate case: not judged\n");
    return kDeclineCase;
  }
  const json& p = doc.at("params");
  const int n = p.at("lut_size").get<int>(), format = p.at("lut_format").get<int>();
  if (n < 2) return fail("params.lut_size " + std::to_string(n) + " is under 2");
  const Grade g = grade_from(p);
  const Lut lut = bake(g, n, format);
  if (stage == "lut_bake") {
    const int w = doc.at("output").at("width"), h = doc.at("output").at("height");
    if (w != n * n || h != n)
      return fail("output " + std::to_string(w) + " x " + std::to_string(h) + " is not the " +
                  std::to_string(n * n) + " x " + std::to_string(n) + " strip");
    return write_rgba(output, w, h, lut.rgba);
  }
  int w = 0, h = 0;
  std::vector<float> image;
  std::string err;
  if (!read_rgba(dir + doc.at("images").at("input").at("file").get<std::string>(), &w, &h, &image,
                 &err))
    return fail(err);
  const float exposure = number(p.at("urp_post_exposure"));
  for (size_t i = 0; i < image.size() / 4; ++i) color_grading(g, lut, exposure, &image[i * 4]);
  return write_rgba(output, w, h, image);
}

}  // namespace f32
