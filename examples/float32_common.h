// What the second float32 evaluation's pipelines share (examples/float32_candidate.cpp: operators
// and pq_grading; examples/float32_unity_urp.cpp: unity_urp): the HLSL intrinsics with D3D's
// meaning (docs/spec/semantics.md), params.json numbers and matrices, the ACES helpers that UE's
// and Unity's ACES.ush/ACES.hlsl state alike, the Neutral rational, and the EXR glue. Like the
// candidate itself it links nothing of hdrconform: nlohmann-json and OpenImageIO only.
#ifndef HDRC_EXAMPLES_FLOAT32_COMMON_H
#define HDRC_EXAMPLES_FLOAT32_COMMON_H

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace f32 {

using json = nlohmann::json;
constexpr int kDeclineCase = 77;   // docs/candidate-protocol.md §2: skip this case
constexpr int kDeclineStage = 78;  // the whole stage
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// --- HLSL intrinsics with D3D's meaning (docs/spec/semantics.md) ---
inline float max_num(float a, float b) {
  return std::fmax(a, b);
}  // maxNum: max(0, NaN) = 0
inline float saturate(float x) {
  return std::isnan(x) ? 0.0f : std::fmin(std::fmax(x, 0.0f), 1.0f);
}
inline float clamp_num(float x, float lo, float hi) {
  return std::fmin(std::fmax(x, lo), hi);
}  // clamp(NaN, lo, hi) = lo
// pow(x, y) = exp2(y · log2 x) (semantics.md: DXC's lowering), for x >= 0.
inline float pow_e2(float x, float y) {
  return std::exp2(y * std::log2(x));
}
inline float log10_e2(float x) {
  return std::log2(x) * 0.301029996f;
}  // log10(2)
inline float exp_e2(float x) {
  return std::exp2(x * 1.44269504f);
}  // log2(e)

// A params.json number: a JSON number, or "NaN" / "Infinity" / "-Infinity".
inline float number(const json& v) {
  if (v.is_number()) return static_cast<float>(v.get<double>());
  const std::string s = v.get<std::string>();
  if (s == "NaN") return kNaN;
  return s == "-Infinity" ? -std::numeric_limits<float>::infinity()
                          : std::numeric_limits<float>::infinity();
}

struct M3 {
  float m[3][3];
};
inline M3 matrix(const json& rows) {
  M3 out{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out.m[r][c] = number(rows.at(r).at(c));
  return out;
}
// M · v, each row summed from the last column, fused.
inline void mul(const M3& a, const float v[3], float out[3]) {
  for (int r = 0; r < 3; ++r)
    out[r] = std::fmaf(a.m[r][0], v[0], std::fmaf(a.m[r][1], v[1], a.m[r][2] * v[2]));
}
// A · B in float32, each entry summed from the last term.
inline M3 mul(const M3& a, const M3& b) {
  M3 out{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      out.m[r][c] = a.m[r][2] * b.m[2][c] + a.m[r][1] * b.m[1][c] + a.m[r][0] * b.m[0][c];
  return out;
}

// f(y) = (A y² + C B y + D E) / (A y² + B y + D F) − E / F (Hable's and Unity's Neutral rational,
// docs/spec/operators.md), expanded and fused; above |y| = 1 both divided by y² (in r = 1/y,
// expanded the other way round).
struct Rational {
  float a, b, c, d, e, f;
};
inline float rational(float y, const Rational& k) {
  const float cb = k.c * k.b, de = k.d * k.e, df = k.d * k.f;
  float num, den;
  if (std::fabs(y) <= 1.0f) {
    const float y2 = y * y;
    num = std::fmaf(k.a, y2, std::fmaf(cb, y, de));
    den = std::fmaf(k.a, y2, std::fmaf(k.b, y, df));
  } else {
    const float r = 1.0f / y, r2 = r * r;
    num = std::fmaf(de, r2, std::fmaf(cb, r, k.a));
    den = std::fmaf(df, r2, std::fmaf(k.b, r, k.a));
  }
  // num / den as num · (1 / den); a zero denominator (a pole) is IEEE's ±Inf or NaN.
  return num * (1.0f / den) - k.e * (1.0f / k.f);
}

// Unity's NeutralTonemap of scale · v (Color.hlsl; docs/spec/operators.md, docs/spec/unity_urp.md
// §2.6): v = max(v, 0); ws = 1 / N(5.3); N(v · scale · ws) · ws / 1. +Inf: the written rational is
// ∞/∞ = NaN (the 1/y form would give a number).
inline float unity_neutral(float v, float scale) {
  constexpr Rational kN{0.2f, 0.29f, 0.24f, 0.272f, 0.02f, 0.3f};
  v = max_num(v, 0.0f);
  if (std::isinf(v)) return kNaN;
  const float ws = 1.0f / rational(5.3f, kN);
  return rational(v * (scale * ws), kN) * ws;
}

// The ACES matrices UE's ACES.ush and Unity's ACES.hlsl carry alike (AP0_2_AP1_MAT,
// AP1_2_AP0_MAT, AP1_2_XYZ_MAT, XYZ_2_AP1_MAT; docs/spec/ue55.md §4.5, docs/spec/unity_urp.md
// §2.6), as float32 literals.
const M3 kAp0ToAp1{{{1.4514393161f, -0.2365107469f, -0.2149285693f},
                    {-0.0765537734f, 1.1762296998f, -0.0996759264f},
                    {0.0083161484f, -0.0060324498f, 0.9977163014f}}};
const M3 kAp1ToAp0{{{0.6954522414f, 0.1406786965f, 0.1638690622f},
                    {0.0447945634f, 0.8596711185f, 0.0955343182f},
                    {-0.0055258826f, 0.0040252103f, 1.0015006723f}}};
const M3 kAp1ToXyz{{{0.6624541811f, 0.1340042065f, 0.1561876870f},
                    {0.2722287168f, 0.6740817658f, 0.0536895174f},
                    {-0.0055746495f, 0.0040607335f, 1.0103391003f}}};
const M3 kXyzToAp1{{{1.6410233797f, -0.3248032942f, -0.2364246952f},
                    {-0.6636628587f, 1.6153315917f, 0.0167563477f},
                    {0.0117218943f, -0.0082844420f, 0.9883948585f}}};

// The ACES helpers UE's ACES.ush and Unity's ACES.hlsl state alike (docs/spec/film_tonemap.md
// "The ACES helpers", docs/spec/unity_urp.md §2.6 step 1-2).
inline float rgb_2_yc(const float c[3]) {
  const float r = c[0], g = c[1], b = c[2];
  const float chroma = std::fmaf(r, r - b, std::fmaf(g, g - r, b * (b - g)));
  return (r + g + b + 1.75f * pow_e2(chroma, 0.5f)) * (1.0f / 3.0f);
}
inline float glow_fwd(float yc, float gain, float mid) {
  if (yc <= mid * (2.0f / 3.0f)) return gain;
  if (yc >= 2.0f * mid) return 0.0f;
  return gain * (mid * (1.0f / yc) - 0.5f);
}
inline float center_hue(float h, float center) {
  float c = h - center;
  if (c < -180.0f) c += 360.0f;
  if (c > 180.0f) c -= 360.0f;
  return c;
}

// UE's ACES.ush only (docs/spec/film_tonemap.md "The ACES helpers"; Unity's differ: 1e-4 and
// 1e-2 in the saturation, FastSign, no clamp of the hue).
inline float rgb_2_saturation(const float c[3]) {
  const float mx = max_num(max_num(c[0], c[1]), c[2]);
  const float mn = std::fmin(std::fmin(c[0], c[1]), c[2]);
  return (max_num(mx, 1e-10f) - max_num(mn, 1e-10f)) * (1.0f / max_num(mx, 0.01f));
}
inline float sigmoid_shaper(float x) {
  const float t = max_num(1.0f - std::fabs(0.5f * x), 0.0f);
  const float sign = float(x > 0) - float(x < 0);
  return 0.5f * std::fmaf(sign, 1.0f - t * t, 1.0f);
}
inline float rgb_2_hue(const float c[3]) {
  if (c[0] == c[1] && c[1] == c[2]) return 0.0f;
  float h = 57.2957795f * std::atan2(1.73205081f * (c[1] - c[2]), 2.0f * c[0] - c[1] - c[2]);
  if (h < 0.0f) h += 360.0f;
  return std::fmin(std::fmax(h, 0.0f), 360.0f);
}

inline int fail(const std::string& what) {
  std::fprintf(stderr, "float32_candidate: %s\n", what.c_str());
  return 1;
}

// Reads an EXR as float RGBA (alpha 1 where the file has none).
inline bool read_rgba(const std::string& path, int* w, int* h, std::vector<float>* rgba,
                      std::string* err) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    *err = path + ": " + OIIO::geterror();
    return false;
  }
  const OIIO::ImageSpec spec = in->spec();
  *w = spec.width;
  *h = spec.height;
  const int nc = spec.nchannels;
  if (nc < 3) {
    *err = path + ": fewer than 3 channels";
    return false;
  }
  std::vector<float> px(static_cast<size_t>(*w) * *h * nc);
  if (!in->read_image(0, 0, 0, nc, OIIO::TypeDesc::FLOAT, px.data())) {
    *err = path + ": " + in->geterror();
    return false;
  }
  in->close();
  rgba->assign(static_cast<size_t>(*w) * *h * 4, 1.0f);
  for (size_t i = 0; i < static_cast<size_t>(*w) * *h; ++i)
    for (int c = 0; c < std::min(nc, 4); ++c) (*rgba)[i * 4 + c] = px[i * nc + c];
  return true;
}

// Writes w × h float RGBA pixels as an EXR; the candidate's exit status (0, or 1 with the error).
inline int write_rgba(const std::string& path, int w, int h, const std::vector<float>& rgba) {
  auto o = OIIO::ImageOutput::create(path);
  if (!o) return fail(path + ": " + OIIO::geterror());
  OIIO::ImageSpec spec(w, h, 4, OIIO::TypeDesc::FLOAT);
  if (!o->open(path, spec) || !o->write_image(OIIO::TypeDesc::FLOAT, rgba.data()))
    return fail(path + ": " + o->geterror());
  o->close();
  return 0;
}

// The pipelines beside operators and pq_grading, each in its own file: run the stage of params
// document `doc` (read from folder `dir`, ending in '/') and write `output`; the candidate's exit
// status.
int unity_urp_stage(const json& doc, const std::string& dir, const std::string& output);
int ue55_stage(const json& doc, const std::string& dir, const std::string& output);

}  // namespace f32

#endif
