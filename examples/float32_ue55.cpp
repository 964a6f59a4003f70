// The second float32 evaluation's `ue55` pipeline, output devices 3 and 4 (ACES 1000 and 2000
// nits, ST 2084; issue 28 item 6): the stages `shaper`, `combine_luts` (CombineLUTs' grading and
// the ACES 1.3 output transform) and `tonemap` (colour fringe, sharpen, vignette, exposure, tint,
// bloom and its dirt mask, the PQ shaper, the baked LUT's lookup), written from docs/spec/ue55.md
// (§3.1, §4, §5.1-§5.2, §6.1), docs/spec/film_tonemap.md (the ACES helpers), docs/spec/semantics.md
// and docs/candidates/{shaper,combine_luts,tonemap}.md, in float32, in an operation order that
// differs from the project's GLSL (gpu/shaders/lib/st2084.glsl, combine_luts.glsl,
// color_correct.glsl, expand_gamut.glsl, aces_rrt.glsl, aces_tonescale.glsl, aces_output.glsl,
// tonemap_effects.glsl, lut_sample.glsl) on purpose:
//
//  * pow, log10 and 10^x through the C library (powf, log10f; the GLSL: exp2/log2 with D3D's
//    constants); the PQ rational fused, its / 10000 and · 100 folded;
//  * ColorCorrect's and the gamut expansion's lerps as a·(1 − t) + b·t; matrices summed last
//    column first, fused; the output transform's XYZ round trips (AP1 → XYZ → AP1, twice) as one
//    product matrix formed in float32; the SSTS spline and the red modifier's cubic B-spline in
//    Horner form, fused; divisions as reciprocal multiplies;
//  * the LUT lookup as eight trilinear weights summed from the last corner, the fringe's bilinear
//    taps as four (the GLSL: the hardware's filter, its weights rounded to 8 bits).
//
// Declined: every other stage (exit 78), every other output device and degenerate cases (exit 77),
// as the porter's port (examples/porters/ue55_dev3/, device 3 alone) declines them. Device 4
// differs from 3 only in the parameters (the ACES tone scale's, ap1_to_output) params.json carries.
#include <Imath/half.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "float32_common.h"

namespace f32 {
namespace {

// docs/spec/ue55.md §3.1: SMPTE ST 2084.
constexpr float kM1 = 0.1593017578125f, kM2 = 78.84375f;
constexpr float kC1 = 0.8359375f, kC2 = 18.8515625f, kC3 = 18.6875f;
// §4.5, §5.1: AP1_RGB2Y and the fake-wide-gamut matrix (the ACES matrices: float32_common.h).
const float kAp1Rgb2Y[3] = {0.2722287168f, 0.6740817658f, 0.0536895174f};
const M3 kExpand{{{1.3704123718f, -0.3292921877f, -0.0636831194f},
                  {-0.0834334917f, 1.0970927480f, -0.0108613795f},
                  {-0.0257933209f, -0.0986257988f, 1.2036949526f}}};

// HLSL pow (semantics.md): NaN for x < 0 or NaN and for pow(0, 0); 0^y = 0 for y > 0, +Inf for y
// < 0; otherwise the C library's powf.
float hlsl_pow(float x, float y) {
  if (std::isnan(x) || std::isnan(y) || x < 0.0f) return kNaN;
  if (x == 0.0f) return y > 0.0f ? 0.0f : (y < 0.0f ? INFINITY : kNaN);
  return std::pow(x, y);
}
float dot(const float w[3], const float c[3]) {
  return std::fmaf(w[2], c[2], std::fmaf(w[1], c[1], w[0] * c[0]));
}
float mix(float a, float b, float t) {
  return std::fmaf(b, t, a * (1.0f - t));
}  // HLSL lerp as a·(1 − t) + b·t
float smoothstep(float e0, float e1, float x) {
  const float t = saturate((x - e0) * (1.0f / (e1 - e0)));
  return t * t * std::fmaf(-2.0f, t, 3.0f);
}

// §3.1: LinearToST2084 of nits (no clamp: a negative value is NaN) and ST2084ToLinear in nits
// times `scale` (the / 100 of CombineLUTs and the shaper folded in).
float pq_encode(float nits) {
  const float lm = hlsl_pow(nits * 1e-4f, kM1);
  return hlsl_pow(std::fmaf(kC2, lm, kC1) / std::fmaf(kC3, lm, 1.0f), kM2);
}
float pq_decode(float e, float scale) {
  const float p = hlsl_pow(e, 1.0f / kM2);
  return hlsl_pow(max_num(p - kC1, 0.0f) * (1.0f / std::fmaf(-kC3, p, kC2)), 1.0f / kM1) *
         (1e4f * scale);
}

// --- ACES 1.3 (docs/spec/ue55.md §5.1-§5.2) ---

// The red modifier's cubic B-spline of width w (135), in Horner form per knot interval.
float cubic_basis_shaper(float x, float w) {
  // Rows of M (t³, t², t, 1) per knot interval j, column 3 − j of the uniform B-spline basis.
  static const float kB[4][4] = {{-1.0f / 6, 3.0f / 6, -3.0f / 6, 1.0f / 6},
                                 {3.0f / 6, -6.0f / 6, 3.0f / 6, 0.0f},
                                 {-3.0f / 6, 0.0f, 3.0f / 6, 0.0f},
                                 {1.0f / 6, 4.0f / 6, 1.0f / 6, 0.0f}};
  if (!(x > -0.5f * w && x < 0.5f * w)) return 0.0f;
  const float kc = std::fmaf(x, 4.0f / w, 2.0f);
  const int j = std::min(static_cast<int>(std::floor(kc)), 3);
  const float t = kc - static_cast<float>(j);
  const int col = 3 - j;
  const float y =
      std::fmaf(std::fmaf(std::fmaf(kB[0][col], t, kB[1][col]), t, kB[2][col]), t, kB[3][col]);
  return 1.5f * y;
}

// compressColor (§5.1, the parametric gamut compression): AP0 in, AP0 out.
void compress_color(const float aces[3], float out[3]) {
  float lin[3];
  mul(kAp0ToAp1, aces, lin);
  const float ach = std::fmax(std::fmax(lin[0], lin[1]), lin[2]);
  if (ach < 1e-10f || aces[0] < 0.0f || aces[1] < 0.0f || aces[2] < 0.0f) {
    for (int i = 0; i < 3; ++i) out[i] = aces[i];
    return;
  }
  const float lims[3] = {1.147f, 1.264f, 1.312f}, thrs[3] = {0.815f, 0.803f, 0.880f};
  constexpr float kPow = 1.2f;
  const float inv_ach = 1.0f / std::fabs(ach);
  float c[3];
  for (int i = 0; i < 3; ++i) {
    float d = (ach - lin[i]) * inv_ach;
    const float lim = lims[i], thr = thrs[i];
    if (d >= thr) {
      const float scl =
          (lim - thr) / std::pow(std::pow((1.0f - thr) / (lim - thr), -kPow) - 1.0f, 1.0f / kPow);
      const float nd = (d - thr) / scl;
      d = std::fmaf(scl, nd / std::pow(1.0f + std::pow(nd, kPow), 1.0f / kPow), thr);
    }
    c[i] = std::fmaf(-d, std::fabs(ach), ach);
  }
  mul(kAp1ToAp0, c, out);
}

// RRT sweeteners (§5.1): glow, red modifier, clamps, AP1, RRT desaturation 0.96.
void rrt_sweeteners(float a[3], float out[3]) {
  const float sat = rgb_2_saturation(a);
  const float yc = rgb_2_yc(a);
  const float s = sigmoid_shaper((sat - 0.4f) * 5.0f);
  const float glow = 1.0f + glow_fwd(yc, 0.05f * s, 0.08f);
  for (int i = 0; i < 3; ++i) a[i] *= glow;
  const float w = cubic_basis_shaper(center_hue(rgb_2_hue(a), 0.0f), 135.0f);
  a[0] = std::fmaf(w * sat * (1.0f - 0.82f), 0.03f - a[0], a[0]);
  for (int i = 0; i < 3; ++i) a[i] = clamp_num(a[i], 0.0f, 65535.0f);
  float pre[3];
  mul(kAp0ToAp1, a, pre);
  for (float& v : pre) v = clamp_num(v, 0.0f, 65504.0f);
  const float y = dot(kAp1Rgb2Y, pre);
  for (int i = 0; i < 3; ++i) out[i] = mix(y, pre[i], 0.96f);
}

// The single-stage tone scale (§5.2) from the params' spline (the device's, from params.json).
struct Ssts {
  float min_x, min_y, max_x, max_y, mid_x;
  float low[6], high[6];
  float lmin, lmid, lmax, lymin, lymax;
  float operator()(float x) const {
    const float lx = std::log10(max_num(x, 1e-10f));
    float ly;
    if (lx <= lmin) {
      ly = lymin;
    } else if (lx < lmax) {
      const bool lo = lx < lmid;
      const float* c = lo ? low : high;
      const float kc =
          lo ? (lx - lmin) * (3.0f / (lmid - lmin)) : (lx - lmid) * (3.0f / (lmax - lmid));
      const int j = static_cast<int>(kc);
      const float t = kc - static_cast<float>(j);
      const float c0 = c[j], c1 = c[j + 1], c2 = c[j + 2];
      // t²(c0/2 − c1 + c2/2) + t(c1 − c0) + (c0 + c1)/2, Horner, fused.
      ly = std::fmaf(std::fmaf(0.5f * (c0 + c2) - c1, t, c1 - c0), t, 0.5f * (c0 + c1));
    } else {
      ly = lymax;
    }
    return std::pow(10.0f, ly);
  }
};

// --- The grade (§4) ---
struct Ue55 {
  M3 to_ap1, from_ap1, to_ap0, ap1_to_output, wb;
  bool wb_enabled = false;
  Ssts ssts{};
  M3 round_trip{};  // XYZ_2_AP1 · AP1_2_XYZ, formed in float32
  float expand_gamut, color_scale[3], overlay[4], scm, gamut_compression;
  // ColorCorrect's zones: saturation, contrast, gamma, gain (products of the zone's and the
  // global vec4, times their w) and offset (sums), per zone (shadows, midtones, highlights).
  float sat[3][3], contrast[3][3], inv_gamma[3][3], gain[3][3], offset[3][3];
  float shadows_max, highlights_min, highlights_max;
};

float vec4_at(const json& v, int i) {
  return number(v.at(i));
}

Ue55 ue55_from(const json& p) {
  Ue55 u;
  u.to_ap1 = matrix(p.at("wcs_to_ap1"));
  u.from_ap1 = matrix(p.at("wcs_from_ap1"));
  u.to_ap0 = matrix(p.at("wcs_to_ap0"));
  u.ap1_to_output = matrix(p.at("ap1_to_output"));
  u.wb_enabled = p.at("white_balance_enabled").get<int>() != 0;
  u.wb = matrix(p.at("white_balance"));
  const json& mm = p.at("aces_min_max");
  u.ssts.min_x = vec4_at(mm, 0);
  u.ssts.min_y = vec4_at(mm, 1);
  u.ssts.max_x = vec4_at(mm, 2);
  u.ssts.max_y = vec4_at(mm, 3);
  u.ssts.mid_x = vec4_at(p.at("aces_mid"), 0);
  for (int i = 0; i < 4; ++i) {
    u.ssts.low[i] = vec4_at(p.at("aces_coefs_low_0"), i);
    u.ssts.high[i] = vec4_at(p.at("aces_coefs_high_0"), i);
  }
  u.ssts.low[4] = u.ssts.low[5] = number(p.at("aces_coefs_low_4"));
  u.ssts.high[4] = u.ssts.high[5] = number(p.at("aces_coefs_high_4"));
  u.ssts.lmin = std::log10(u.ssts.min_x);
  u.ssts.lmid = std::log10(u.ssts.mid_x);
  u.ssts.lmax = std::log10(u.ssts.max_x);
  u.ssts.lymin = std::log10(u.ssts.min_y);
  u.ssts.lymax = std::log10(u.ssts.max_y);
  u.round_trip = mul(kXyzToAp1, kAp1ToXyz);
  u.expand_gamut = number(p.at("expand_gamut"));
  for (int i = 0; i < 3; ++i) u.color_scale[i] = vec4_at(p.at("color_scale"), i);
  for (int i = 0; i < 4; ++i) u.overlay[i] = vec4_at(p.at("overlay_color"), i);
  u.scm = number(p.at("aces_scene_color_multiplier"));
  u.gamut_compression = number(p.at("aces_gamut_compression"));
  const char* zones[3] = {"_shadows", "_midtones", "_highlights"};
  for (int z = 0; z < 3; ++z) {
    auto prod = [&](const char* k, int i) {
      const json& zv = p.at(std::string("cc_") + k + zones[z]);
      const json& gv = p.at(std::string("cc_") + k);
      return (vec4_at(zv, i) * vec4_at(gv, i)) * (vec4_at(zv, 3) * vec4_at(gv, 3));
    };
    for (int i = 0; i < 3; ++i) {
      u.sat[z][i] = prod("saturation", i);
      u.contrast[z][i] = prod("contrast", i);
      u.inv_gamma[z][i] = 1.0f / prod("gamma", i);
      u.gain[z][i] = prod("gain", i);
      const json& zo = p.at(std::string("cc_offset") + zones[z]);
      const json& go = p.at("cc_offset");
      u.offset[z][i] = (vec4_at(zo, i) + vec4_at(go, i)) + (vec4_at(zo, 3) + vec4_at(go, 3));
    }
  }
  u.shadows_max = number(p.at("cc_shadows_max"));
  u.highlights_min = number(p.at("cc_highlights_min"));
  u.highlights_max = number(p.at("cc_highlights_max"));
  return u;
}

// §4.6 ColorCorrectAll: three zones blended by luma weights.
void color_correct_all(const Ue55& u, const float c[3], float out[3]) {
  const float luma = dot(kAp1Rgb2Y, c);
  const float ws = 1.0f - smoothstep(0.0f, u.shadows_max, luma);
  const float wh = smoothstep(u.highlights_min, u.highlights_max, luma);
  const float wm = (1.0f - wh) - ws;
  const float w[3] = {ws, wm, wh};
  float acc[3] = {0.0f, 0.0f, 0.0f};
  for (int z = 2; z >= 0; --z) {
    for (int i = 0; i < 3; ++i) {
      float v = max_num(0.0f, mix(luma, c[i], u.sat[z][i]));
      v = hlsl_pow(v * (1.0f / 0.18f), u.contrast[z][i]) * 0.18f;
      v = hlsl_pow(v, u.inv_gamma[z][i]);
      acc[i] = std::fmaf(std::fmaf(v, u.gain[z][i], u.offset[z][i]), w[z], acc[i]);
    }
  }
  for (int i = 0; i < 3; ++i) out[i] = acc[i];
}

// §4.3-§5.2 and §4.12 for devices 3 and 4: a lattice coordinate (PQ) to OutDeviceColor (PQ).
void texel(const Ue55& u, const float coord[3], float out[3]) {
  float lin[3], t[3], ap1[3];
  for (int i = 0; i < 3; ++i) lin[i] = pq_decode(coord[i], 0.01f);  // §4.3
  if (u.wb_enabled) {                                               // §4.4
    mul(u.wb, lin, t);
    for (int i = 0; i < 3; ++i) lin[i] = t[i];
  }
  mul(u.to_ap1, lin, ap1);  // §4.5
  const float luma = dot(kAp1Rgb2Y, ap1);
  float amount = 0.0f;  // D-NaN: the black lattice point
  if (luma != 0.0f) {
    const float inv = 1.0f / luma;
    float d2 = 0.0f;
    for (int i = 2; i >= 0; --i) {
      const float d = std::fmaf(ap1[i], inv, -1.0f);
      d2 = std::fmaf(d, d, d2);
    }
    amount = (1.0f - std::exp2(-4.0f * d2)) *
             (1.0f - std::exp2((-4.0f * u.expand_gamut) * (luma * luma)));
  }
  float ex[3];
  mul(kExpand, ap1, ex);
  for (int i = 0; i < 3; ++i) ap1[i] = mix(ap1[i], ex[i], amount);
  float cc[3], graded[3];
  color_correct_all(u, ap1, cc);  // §4.6
  mul(u.from_ap1, cc, graded);    // §4.7
  for (int i = 0; i < 3; ++i)
    graded[i] = mix(graded[i] * u.color_scale[i], u.overlay[i], u.overlay[3]);
  // §5.1 ACES 1.3 (1000 or 2000 nits: the params' tone scale).
  float aces[3], comp[3], pre[3];
  for (float& v : graded) v *= u.scm;
  mul(u.to_ap0, graded, aces);
  compress_color(aces, comp);
  // lerp(aces, comp, gc) as HLSL writes it: a NaN or Inf channel survives gc = 0 (semantics.md).
  for (int i = 0; i < 3; ++i) aces[i] = aces[i] + u.gamut_compression * (comp[i] - aces[i]);
  rrt_sweeteners(aces, pre);
  float cv[3], r1[3], r2[3];
  const float inv_range = 1.0f / (u.ssts.max_y - u.ssts.min_y);
  for (int i = 0; i < 3; ++i) cv[i] = (u.ssts(pre[i]) - u.ssts.min_y) * inv_range;
  mul(u.round_trip, cv, r1);
  for (float& v : r1) v = clamp_num(v, 0.0f, 1.0f);
  mul(u.round_trip, r1, r2);
  float nits[3], odt[3];
  for (int i = 0; i < 3; ++i)
    nits[i] = clamp_num(clamp_num(r2[i], 0.0f, 65535.0f) * u.ssts.max_y, 0.0f, 65535.0f);
  mul(u.ap1_to_output, nits, odt);  // §4.12, devices 3 and 4
  for (int i = 0; i < 3; ++i) out[i] = pq_encode(odt[i]);
}

// §4.12 storage: 0 A2B10G10R10 UNORM (saturate, nearest k/1023; NaN 0), 1 RGBA16F, else float32.
float quantize(float v, int format) {
  if (format == 0) return std::nearbyint(saturate(v) * 1023.0f) / 1023.0f;
  if (format == 1) return static_cast<float>(Imath::half(v));
  return v;
}

// The baked LUT, lattice (r, g, b) at index (b·N + g)·N + r, RGB; each texel OutDeviceColor /
// 1.05, rounded to the format.
std::vector<float> bake(const Ue55& u, int n, int layout, int format) {
  std::vector<float> lut(static_cast<size_t>(n) * n * n * 3);
  const float inv = 1.0f / static_cast<float>(n - 1);
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r) {
        // §4.2: the 2-D layout's texel centres sit 1e-5 past the lattice in r and g.
        const float off = layout == 1 ? 1e-5f : 0.0f;
        const float coord[3] = {(static_cast<float>(r) + off) * inv,
                                (static_cast<float>(g) + off) * inv, static_cast<float>(b) * inv};
        float v[3];
        texel(u, coord, v);
        float* t = &lut[((static_cast<size_t>(b) * n + g) * n + r) * 3];
        for (int i = 0; i < 3; ++i) t[i] = quantize(v[i] * (1.0f / 1.05f), format);
      }
  return lut;
}

// §6.1 step 7: trilinear at enc · (N − 1), clamp-to-edge; a NaN coordinate gives NaN (D-NF).
void sample(const std::vector<float>& lut, int n, const float enc[3], float out[3]) {
  if (std::isnan(enc[0]) || std::isnan(enc[1]) || std::isnan(enc[2])) {
    out[0] = out[1] = out[2] = kNaN;
    return;
  }
  int i0[3], i1[3];
  float f[3];
  for (int k = 0; k < 3; ++k) {
    const float x = clamp_num(enc[k], 0.0f, 1.0f) * static_cast<float>(n - 1);
    i0[k] = std::min(static_cast<int>(std::floor(x)), n - 1);
    f[k] = x - static_cast<float>(i0[k]);
    i1[k] = std::min(i0[k] + 1, n - 1);
  }
  float acc[3] = {0.0f, 0.0f, 0.0f};
  for (int corner = 7; corner >= 0; --corner) {
    const int br = corner & 1, bg = (corner >> 1) & 1, bb = (corner >> 2) & 1;
    const float w =
        (br ? f[0] : 1.0f - f[0]) * (bg ? f[1] : 1.0f - f[1]) * (bb ? f[2] : 1.0f - f[2]);
    if (w == 0.0f) continue;
    const float* t =
        &lut[((static_cast<size_t>(bb ? i1[2] : i0[2]) * n + (bg ? i1[1] : i0[1])) * n +
              (br ? i1[0] : i0[0])) *
             3];
    for (int c = 0; c < 3; ++c) acc[c] = std::fmaf(w, t[c], acc[c]);
  }
  for (int c = 0; c < 3; ++c) out[c] = acc[c];
}

float sharpen_luma(const float* c) {
  return std::fmaf(0.11f, c[2], std::fmaf(0.59f, c[1], 0.3f * c[0]));
}

int decline(int code, const std::string& why) {
  std::printf("%s\n", why.c_str());
  return code;
}

}  // namespace

int ue55_stage(const json& doc, const std::string& dir, const std::string& output) {
  const std::string stage = doc.at("stage");
  if (stage != "shaper" && stage != "combine_luts" && stage != "tonemap")
    return decline(kDeclineStage, "ue55 stage " + stage + " is not implemented by this port");
  if (!doc.value("degenerate", json()).is_null())
    return decline(kDeclineCase, "degenerate case: not judged");
  const json& p = doc.at("params");
  const int device = p.at("output_device").get<int>();
  if (device != 3 && device != 4)
    return decline(kDeclineCase, "output device " + std::to_string(device) +
                                     " is not implemented by this port (devices 3 and 4 only)");
  const int w = doc.at("output").at("width"), h = doc.at("output").at("height");
  const Ue55 u = ue55_from(p);
  const int n = p.at("lut_size").get<int>(), format = p.at("lut_format").get<int>();
  const int layout = p.at("lut_layout").get<int>();
  if (stage == "combine_luts") {
    if (w != n * n || h != n) return fail("output is not the N² × N strip");
    const std::vector<float> lut = bake(u, n, layout, format);
    std::vector<float> img(static_cast<size_t>(w) * h * 4, 0.0f);  // alpha 0
    for (int b = 0; b < n; ++b)
      for (int g = 0; g < n; ++g)
        for (int r = 0; r < n; ++r)
          for (int c = 0; c < 3; ++c)
            img[(static_cast<size_t>(g) * w + r + static_cast<size_t>(n) * b) * 4 + c] =
                lut[((static_cast<size_t>(b) * n + g) * n + r) * 3 + c];
    return write_rgba(output, w, h, img);
  }
  int iw = 0, ih = 0;
  std::vector<float> src;
  std::string err;
  const json& images = doc.at("images");
  if (!read_rgba(dir + images.at("input").at("file").get<std::string>(), &iw, &ih, &src, &err))
    return fail(err);
  if (stage == "shaper") {
    // docs/candidates/shaper.md: PQ of x · 100, the sampler's clamp (NaN stays), decoded / 100.
    for (size_t i = 0; i < src.size() / 4; ++i)
      for (int c = 0; c < 3; ++c) {
        const float e = pq_encode(src[i * 4 + c] * 100.0f);
        src[i * 4 + c] = pq_decode(std::isnan(e) ? e : clamp_num(e, 0.0f, 1.0f), 0.01f);
      }
    return write_rgba(output, iw, ih, src);
  }
  // tonemap (§6.1 steps 2-9).
  // Step 1's colour fringe: (CAScaleR, CAScaleG, StartOffset, on).
  const json fringe_v = p.value("fringe", json::array({0, 0, 0, 0}));
  float fringe[4];
  for (int i = 0; i < 4; ++i) fringe[i] = number(fringe_v.at(i));
  const std::vector<float> lut = bake(u, n, layout, format);
  std::vector<float> bloom, dirt;
  if (images.contains("bloom") && !images.at("bloom").is_null()) {
    int bw = 0, bh = 0;
    if (!read_rgba(dir + images.at("bloom").at("file").get<std::string>(), &bw, &bh, &bloom, &err))
      return fail(err);
    if (bw != iw || bh != ih)
      return decline(kDeclineCase, "a bloom image of another size than the input: not implemented");
  }
  if (images.contains("bloom_dirt") && !images.at("bloom_dirt").is_null()) {
    int dw = 0, dh = 0;
    if (!read_rgba(dir + images.at("bloom_dirt").at("file").get<std::string>(), &dw, &dh, &dirt,
                   &err))
      return fail(err);
    if (dw != iw || dh != ih)
      return decline(kDeclineCase, "a bloom dirt image of another size than the input");
  }
  const json dirt_tint_v = p.value("bloom_dirt_tint", json::array({0, 0, 0, 0}));
  float dirt_tint[3], tint[3];
  for (int c = 0; c < 3; ++c) {
    dirt_tint[c] = number(dirt_tint_v.at(c));
    tint[c] = vec4_at(p.at("scene_color_tint"), c);
  }
  const float exposure = number(p.at("exposure")), vig = number(p.at("vignette_intensity"));
  const float sharpen = number(p.value("sharpen_div6", json(0.0)));
  const float ar = static_cast<float>(ih) / static_cast<float>(iw);
  const float vk = std::sqrt(2.0f / std::fmaf(ar, ar, 1.0f));
  std::vector<float> out(src.size());
  for (int y = 0; y < ih; ++y)
    for (int x = 0; x < iw; ++x) {
      const size_t i = static_cast<size_t>(y) * iw + x;
      float s[3] = {src[i * 4], src[i * 4 + 1], src[i * 4 + 2]};
      // The pixel centre in [−1, 1], y up (steps 1 and 3).
      const float px =
          std::fmaf((static_cast<float>(x) + 0.5f) / static_cast<float>(iw), 2.0f, -1.0f);
      const float py =
          std::fmaf((static_cast<float>(y) + 0.5f) / static_cast<float>(ih), -2.0f, 1.0f);
      if (fringe[3] != 0.0f) {
        // R sampled at the lens position pulled in by CAScaleR, G by CAScaleG: l − sign(l) ·
        // saturate(|l| − StartOffset) · scale; bilinear, the taps clamped to the image.
        for (int c = 0; c < 2; ++c) {
          auto pull = [&](float l) {
            const float sg = float(l > 0.0f) - float(l < 0.0f);
            return std::fmaf(-sg * saturate(std::fabs(l) - fringe[2]), fringe[c], l);
          };
          const float u = std::fmaf(pull(px), 0.5f, 0.5f), v = std::fmaf(pull(py), -0.5f, 0.5f);
          const float fx = clamp_num(std::fmaf(u, static_cast<float>(iw), -0.5f), 0.0f,
                                     static_cast<float>(iw - 1));
          const float fy = clamp_num(std::fmaf(v, static_cast<float>(ih), -0.5f), 0.0f,
                                     static_cast<float>(ih - 1));
          const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
          const int x1 = std::min(x0 + 1, iw - 1), y1 = std::min(y0 + 1, ih - 1);
          const float tx = fx - static_cast<float>(x0), ty = fy - static_cast<float>(y0);
          auto at = [&](int xx, int yy) {
            return src[(static_cast<size_t>(yy) * iw + xx) * 4 + c];
          };
          // The four weights formed first, summed from the last tap.
          s[c] = std::fmaf(tx * ty, at(x1, y1),
                           std::fmaf((1.0f - tx) * ty, at(x0, y1),
                                     std::fmaf(tx * (1.0f - ty), at(x1, y0),
                                               (1.0f - tx) * (1.0f - ty) * at(x0, y0))));
        }
      }
      if (sharpen > 0.0f) {  // step 2; neighbours clamped to the image
        const float* nb[4] = {&src[(static_cast<size_t>(y) * iw + std::min(x + 1, iw - 1)) * 4],
                              &src[(static_cast<size_t>(y) * iw + std::max(x - 1, 0)) * 4],
                              &src[(static_cast<size_t>(std::min(y + 1, ih - 1)) * iw + x) * 4],
                              &src[(static_cast<size_t>(std::max(y - 1, 0)) * iw + x) * 4]};
        const float a0 = sharpen_luma(s);
        float edge = 0.0f;
        for (const float* c : nb) edge = std::fmax(edge, std::fabs(a0 - sharpen_luma(c)));
        const float k = -saturate(1.0f - exposure * edge) * sharpen;
        for (int c = 0; c < 3; ++c)
          s[c] = std::fmaf((nb[3][c] + nb[2][c]) + (nb[1][c] + nb[0][c]) - 4.0f * s[c], k, s[c]);
      }
      float mask = 1.0f;
      if (vig > 0.0f) {  // step 3
        const float vx = px * (vk * vig), vy = py * (ar * vk * vig);
        const float m = 1.0f / std::fmaf(vx, vx, std::fmaf(vy, vy, 1.0f));
        mask = m * m;
      }
      const float em = exposure * mask;
      float enc[3], dev[3];
      for (int c = 0; c < 3; ++c) {
        float fl = s[c] * tint[c] * em;
        if (!bloom.empty()) {  // steps 4-5: bloom, its dirt at the pixel's own UV
          float raw = bloom[i * 4 + c];
          if (!dirt.empty()) raw *= std::fmaf(dirt[i * 4 + c], dirt_tint[c], 1.0f);
          fl = std::fmaf(raw, em, fl);
        }
        enc[c] = pq_encode(fl * 100.0f);
      }
      sample(lut, n, enc, dev);
      for (int c = 0; c < 3; ++c) out[i * 4 + c] = dev[c] * 1.05f;
      out[i * 4 + 3] =
          std::fmaf(0.114f, out[i * 4 + 2], std::fmaf(0.587f, out[i * 4 + 1], 0.299f * out[i * 4]));
    }
  return write_rgba(output, iw, ih, out);
}

}  // namespace f32
