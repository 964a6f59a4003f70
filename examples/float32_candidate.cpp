// A second, independent float32 evaluation of the `operators` and `pq_grading` pipelines (issue
// 28 item 6; `unity_urp` is examples/float32_unity_urp.cpp, the glue they share
// examples/float32_common.h): written from docs/spec/operators.md, docs/spec/film_tonemap.md and
// docs/spec/pq_grading.md alone, in float32, in an operation order that differs from the
// project's GLSL (gpu/shaders/operators/lib/operators.glsl, gpu/shaders/lib/film_tonemap.glsl,
// gpu/shaders/pq_grading/lib/pq_grading.glsl) on purpose:
//
//  * rationals expanded (a·y² + b·y + c) and fused (fmaf) where the GLSL nests them unfused
//    (y·(a·y + b) + c); divisions as a multiply by the reciprocal, or the other way round;
//  * log10 as log2(x)·log10(2), exp as exp2(x·log2(e)), pow and sqrt as exp2(y·log2(x));
//  * matrix products summed last column first and fused; FilmToneMap's AP1 → AP0 product formed
//    in float32 from the two literals (as UE's shader forms it), summed in the other order;
//  * desaturation's lerp as a·(1 − t) + b·t; the strip's bilinear filter as four weights summed
//    (the GLSL nests two lerps; the hardware filter rounds its weights to 8 bits, this does not);
//    PQ decode, / 10000, / ExposureFract, · Amplify folded into one factor.
//
// It links nothing of hdrconform (nlohmann-json for params.json, OpenImageIO and Imath for EXR
// and half), like examples/standalone_candidate.cpp, and follows the candidate protocol
// (docs/candidate-protocol.md): exit 0 written, 78 any stage but tone_curve, pq_grade and
// unity_urp's lut_bake and color_grading, 1 an error.
//
//   float32_candidate --params params.json --output out.exr
//   hdrconform verify --filter 'operators/*'
//       --candidate-cmd 'float32_candidate --params {params} --output {output}'
//
// Its CTests (examples/CMakeLists.txt, examples.float32_candidate.*) require every operators,
// pq_grading and unity_urp case to pass: the limits must admit any float32 evaluation order
// (docs/tolerances.md, "A second float32 evaluation").
#include <Imath/half.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "float32_common.h"

namespace {

using namespace f32;

// --- The per-channel operators (docs/spec/operators.md, "The operators") ---

// Reinhard 2002 eq. 3, x / (1 + x), as x · (1 / (1 + x)); above |x| = 1 as 1 / (1/x + 1), so a
// finite input whose product overflows still reaches 1. ±Inf: ∞/∞ = NaN.
float reinhard(float x) {
  if (std::fabs(x) <= 1.0f) return x * (1.0f / (1.0f + x));
  return 1.0f / (1.0f / x + 1.0f);
}

// Eq. 4, x (1 + x / Lw²) / (1 + x) with x = scale · v, expanded: (x + x² / Lw²) / (1 + x); above
// |x| = 1 divided by x: (1 + v · (scale / Lw²)) / (1 / x + 1), so a huge v does not overflow.
float reinhard_white(float v, float scale, float white) {
  const float x = scale * v, inv_w2 = 1.0f / (white * white);
  if (std::fabs(x) <= 1.0f) return std::fmaf(x * x, inv_w2, x) * (1.0f / (1.0f + x));
  return std::fmaf(v, scale * inv_w2, 1.0f) / (1.0f / x + 1.0f);
}

// Hable: f(bias · x) / f(W), as f(bias · x) · (1 / f(W)).
float hable(float x, const Rational& k, float w, float bias) {
  return rational(bias * x, k) * (1.0f / rational(w, k));
}

// Narkowicz: saturate((2.51 y² + 0.03 y) / (2.43 y² + 0.59 y + 0.14)), y = pre_scale · x.
float aces_narkowicz(float x, float pre_scale) {
  const float y = pre_scale * x;
  float q;
  if (std::fabs(y) <= 1.0f) {
    const float y2 = y * y;
    q = std::fmaf(2.51f, y2, 0.03f * y) / std::fmaf(2.43f, y2, std::fmaf(0.59f, y, 0.14f));
  } else {
    const float r = 1.0f / y;
    q = std::fmaf(0.03f, r, 2.51f) / std::fmaf(0.14f * r, r, std::fmaf(0.59f, r, 2.43f));
  }
  return saturate(q);
}

// --- UE 5.5's FilmToneMap (docs/spec/film_tonemap.md) ---

struct Film {
  float slope, toe, shoulder, black_clip, white_clip;
  float toe_scale, shoulder_scale, toe_match, straight_match, shoulder_match;
};
// "The match points", in float32.
Film film_params(const json& p) {
  Film f{};
  f.slope = number(p.at("film_slope"));
  f.toe = number(p.at("film_toe"));
  f.shoulder = number(p.at("film_shoulder"));
  f.black_clip = number(p.at("film_black_clip"));
  f.white_clip = number(p.at("film_white_clip"));
  f.toe_scale = 1.0f + f.black_clip - f.toe;
  f.shoulder_scale = 1.0f + f.white_clip - f.shoulder;
  const float log_in = log10_e2(0.18f);
  if (f.toe > 0.8f) {
    f.toe_match = (1.0f - f.toe - 0.18f) / f.slope + log_in;
  } else {
    const float bt = (0.18f + f.black_clip) / f.toe_scale - 1.0f;
    // 0.5 · ln((1 + bt) / (1 − bt)) = 0.5 · log2(...) · ln 2
    f.toe_match =
        log_in - 0.5f * std::log2((1.0f + bt) / (1.0f - bt)) * 0.693147181f * f.toe_scale / f.slope;
  }
  f.straight_match = (1.0f - f.toe) / f.slope - f.toe_match;
  f.shoulder_match = f.shoulder / f.slope - f.straight_match;
  return f;
}

// Step 5, one channel.
float film_curve(float w, const Film& f) {
  const float log_color = log10_e2(w);
  const float straight = f.slope * (log_color + f.straight_match);
  const float toe =
      -f.black_clip +
      2.0f * f.toe_scale /
          (1.0f + exp_e2((-2.0f * f.slope / f.toe_scale) * (log_color - f.toe_match)));
  const float shoulder =
      (1.0f + f.white_clip) -
      2.0f * f.shoulder_scale /
          (1.0f + exp_e2((2.0f * f.slope / f.shoulder_scale) * (log_color - f.shoulder_match)));
  const float toe_color = log_color < f.toe_match ? toe : straight;
  const float shoulder_color = log_color > f.shoulder_match ? shoulder : straight;
  float t = saturate((log_color - f.toe_match) * (1.0f / (f.shoulder_match - f.toe_match)));
  if (f.shoulder_match < f.toe_match) t = 1.0f - t;
  const float blend = t * t * (3.0f - 2.0f * t);
  // lerp as HLSL writes it, a + t (b − a): black's NaN (lerp(0, −∞, 0)) depends on it.
  return toe_color + blend * (shoulder_color - toe_color);
}

// AP1_RGB2Y; lerp(y, c, s) written y·(1 − s) + c·s (both finite here: step 4 clamped, step 5's
// NaN goes through either way).
void desaturate(float c[3], float s) {
  const float y =
      std::fmaf(0.0536895174f, c[2], std::fmaf(0.6740817658f, c[1], 0.2722287168f * c[0]));
  for (int i = 0; i < 3; ++i) c[i] = std::fmaf(c[i], s, y * (1.0f - s));
}

void film_tone_map(const float ap1[3], const Film& f, float out[3]) {
  static const M3 kAp1ToXyz{{{0.6624541811f, 0.1340042065f, 0.1561876870f},
                             {0.2722287168f, 0.6740817658f, 0.0536895174f},
                             {-0.0055746495f, 0.0040607335f, 1.0103391003f}}};
  static const M3 kXyzToAp0{{{1.0498110175f, 0.0f, -0.0000974845f},
                             {-0.4959030231f, 1.3733130458f, 0.0982400361f},
                             {0.0f, 0.0f, 0.9912520182f}}};
  static const M3 kAp0ToAp1{{{1.4514393161f, -0.2365107469f, -0.2149285693f},
                             {-0.0765537734f, 1.1762296998f, -0.0996759264f},
                             {0.0083161484f, -0.0060324498f, 0.9977163014f}}};
  static const M3 kAp1ToAp0 = mul(kXyzToAp0, kAp1ToXyz);
  // 1. To AP0.
  float ap0[3];
  mul(kAp1ToAp0, ap1, ap0);
  // 2. Glow (RRT_GLOW_GAIN 0.05, RRT_GLOW_MID 0.08).
  const float sat = rgb_2_saturation(ap0);
  const float yc = rgb_2_yc(ap0);
  const float s = sigmoid_shaper((sat - 0.4f) * 5.0f);  // / 0.2
  const float glow = 1.0f + glow_fwd(yc, 0.05f * s, 0.08f);
  for (float& c : ap0) c *= glow;
  // 3. Red modifier (RRT_RED_SCALE 0.82, PIVOT 0.03, HUE 0, WIDTH 135), smoothstep².
  const float centered = center_hue(rgb_2_hue(ap0), 0.0f);
  const float st = saturate(1.0f - std::fabs(centered * (2.0f / 135.0f)));
  const float smooth = st * st * (3.0f - 2.0f * st);
  const float hue_weight = smooth * smooth;
  ap0[0] = std::fmaf(hue_weight * sat * (1.0f - 0.82f), 0.03f - ap0[0], ap0[0]);
  // 4. To AP1, clamp, pre-desaturate 0.96.
  float w[3];
  mul(kAp0ToAp1, ap0, w);
  for (float& c : w) c = max_num(0.0f, c);
  desaturate(w, 0.96f);
  // 5. The curve per channel; 6. post-desaturate 0.93, clamp.
  for (int i = 0; i < 3; ++i) out[i] = film_curve(w[i], f);
  desaturate(out, 0.93f);
  for (int i = 0; i < 3; ++i) out[i] = max_num(0.0f, out[i]);
}

// --- pq_grading (docs/spec/pq_grading.md) ---

// SMPTE ST 2084 in float32 (docs/spec/pq_grading.md, "Constants"), pow as exp2(y · log2 x), the
// division written as a division where the spec multiplies by a reciprocal.
constexpr float kM1 = 2610.0f / 16384.0f, kM2 = 2523.0f / 4096.0f * 128.0f;
constexpr float kC1 = 3424.0f / 4096.0f, kC2 = 2413.0f / 4096.0f * 32.0f,
                kC3 = 2392.0f / 4096.0f * 32.0f;
float pq_from_nits(float n) {
  const float ym = pow_e2(n * 1e-4f, kM1);
  return pow_e2(std::fmaf(kC2, ym, kC1) / std::fmaf(kC3, ym, 1.0f), kM2);
}
float nits_from_pq(float e) {
  const float p = pow_e2(e, 1.0f / kM2);
  return pow_e2(max_num(p - kC1, 0.0f) / std::fmaf(-kC3, p, kC2), 1.0f / kM1) * 1e4f;
}

// The strip texture N² × N (RGBA float, row-major), Vulkan's linear filter with exact float32
// weights and clamp-to-edge (step 5's bilinear).
struct Strip {
  int n = 0, w = 0, h = 0;
  std::vector<float> texels;  // RGBA
  const float* at(int i, int j) const {
    i = i < 0 ? 0 : (i > w - 1 ? w - 1 : i);
    j = j < 0 ? 0 : (j > h - 1 ? h - 1 : j);
    return &texels[(static_cast<size_t>(j) * w + i) * 4];
  }
  void bilinear(float u, float v, float out[3]) const {
    const float a = u * w - 0.5f, b = v * h - 0.5f;
    const float fi = std::floor(a), fj = std::floor(b);
    const float al = a - fi, be = b - fj;
    const int i = static_cast<int>(fi), j = static_cast<int>(fj);
    const float *t00 = at(i, j), *t10 = at(i + 1, j), *t01 = at(i, j + 1), *t11 = at(i + 1, j + 1);
    for (int c = 0; c < 3; ++c) {
      // The four weights formed first, summed from the last tap (the GLSL nests two lerps).
      out[c] = (1 - al) * (1 - be) * t00[c] + al * (1 - be) * t10[c] + (1 - al) * be * t01[c] +
               al * be * t11[c];
    }
  }
};

// Steps 4-5: the domain, then two bilinear taps blended by the slice fraction.
void lut_lookup(const Strip& s, const float dmin[3], const float dmax[3], const float pq[3],
                float out[3]) {
  const float n = static_cast<float>(s.n);
  float uvw[3];
  for (int c = 0; c < 3; ++c) {
    const float t = saturate((pq[c] - dmin[c]) / (dmax[c] - dmin[c]));
    uvw[c] = (t * (n - 1.0f) + 0.5f) / n;  // t (N − 1)/N + 0.5/N, one division
  }
  const float slice_w = uvw[2] * n - 0.5f;
  const float slice_i = std::floor(slice_w), slice_f = slice_w - slice_i;
  const float u = (uvw[0] + slice_i) / n;
  float tap0[3], tap1[3];
  s.bilinear(u, uvw[1], tap0);
  s.bilinear(u + 1.0f / n, uvw[1], tap1);
  for (int c = 0; c < 3; ++c) out[c] = tap0[c] * (1.0f - slice_f) + tap1[c] * slice_f;
}

float srgb_encode(float e) {
  return e <= 0.0031308f ? 12.92f * e : 1.055f * pow_e2(e, 1.0f / 2.4f) - 0.055f;
}

// The operators pipeline's one stage, in place on RGBA pixels.
void tone_curve(const json& p, std::vector<float>* image) {
  const int op = p.at("op_operator");
  const float exposure = number(p.at("op_exposure"));
  const float white = number(p.at("op_white_point"));
  const Rational hable_k{number(p.at("op_hable_a")), number(p.at("op_hable_b")),
                         number(p.at("op_hable_c")), number(p.at("op_hable_d")),
                         number(p.at("op_hable_e")), number(p.at("op_hable_f"))};
  const float hable_w = number(p.at("op_hable_w"));
  const float hable_bias = number(p.at("op_hable_exposure_bias"));
  const float pre_scale = number(p.at("op_narkowicz_pre_scale"));
  const M3 to_ap1 = matrix(p.at("op_rec709_to_ap1"));
  const M3 from_ap1 = matrix(p.at("op_ap1_to_rec709"));
  const Film film = film_params(p);
  for (size_t i = 0; i < image->size() / 4; ++i) {
    float* px = &(*image)[i * 4];
    if (op == 5) {
      // UeFilmic: max(0, FromAP1 · FilmToneMap(ToAP1 · exposure · x)).
      float x[3] = {exposure * px[0], exposure * px[1], exposure * px[2]}, ap1[3], tone[3];
      mul(to_ap1, x, ap1);
      film_tone_map(ap1, film, tone);
      mul(from_ap1, tone, px);
      for (int c = 0; c < 3; ++c) px[c] = max_num(0.0f, px[c]);
      continue;
    }
    for (int c = 0; c < 3; ++c) {
      const float v = px[c];
      if (std::isnan(v)) {
        px[c] = (op == 3 || op == 4) ? 0.0f : kNaN;  // saturate / max(x, 0) of NaN
        continue;
      }
      // ±Inf: ∞/∞ = NaN in every rational; saturate(NaN) = 0 (Narkowicz); Unity's max(x, 0)
      // makes −Inf 0 first. A finite v whose scaled value overflows takes the 1/y forms.
      if (std::isinf(v)) {
        px[c] = op == 3 || (op == 4 && v < 0) ? 0.0f : kNaN;
        continue;
      }
      const float x = exposure * v;
      switch (op) {
        case 0:
          px[c] = reinhard(x);
          break;
        case 1:
          px[c] = reinhard_white(v, exposure, white);
          break;
        case 2:
          px[c] = hable(x, hable_k, hable_w, hable_bias);
          break;
        case 3:
          px[c] = aces_narkowicz(x, pre_scale);
          break;
        default:
          px[c] = unity_neutral(v, exposure);
      }
    }
  }
}

// The pq_grading pipeline's one stage, in place on RGBA pixels.
void pq_grade(const json& p, const Strip& strip, std::vector<float>* image) {
  const int display = p.at("pq_display"), back_buffer = p.at("pq_back_buffer");
  const float amplify = number(p.at("pq_amplify"));
  const float fract = number(p.at("pq_exposure_fract"));
  const float white = number(p.at("pq_white_nits"));
  const M3 to_ap1 = matrix(p.at("pq_rec709_to_ap1"));
  const M3 from_ap1 = matrix(p.at("pq_ap1_to_rec709"));
  float dmin[3], dmax[3];
  for (int c = 0; c < 3; ++c) {
    dmin[c] = number(p.at("user_lut_domain_min").at(c));
    dmax[c] = number(p.at("user_lut_domain_max").at(c));
  }
  const Film film = film_params(p);
  // Step 6's PQ⁻¹ / 10000 / ExposureFract · Amplify as one factor.
  const float decode_scale = amplify / (1e4f * fract);
  for (size_t i = 0; i < image->size() / 4; ++i) {
    float* px = &(*image)[i * 4];
    float pq[3], graded_pq[3], graded[3], out[3];
    for (int c = 0; c < 3; ++c) {
      // 1. RGBA16F lighting target (Imath's half rounds to nearest even; ±Inf clamp first).
      const float s = std::isnan(px[c]) ? px[c] : std::fmin(std::fmax(px[c], -65504.0f), 65504.0f);
      const float stored = static_cast<float>(Imath::half(s));
      // 2-3. Exposure, saturate, PQ encode.
      pq[c] = pq_from_nits(saturate(stored * fract) * 1e4f);
    }
    lut_lookup(strip, dmin, dmax, pq, graded_pq);                                       // 4-5
    for (int c = 0; c < 3; ++c) graded[c] = nits_from_pq(graded_pq[c]) * decode_scale;  // 6
    // 7. Display mapping.
    if (display == 1) {
      float ap1[3], tone[3];
      mul(to_ap1, graded, ap1);
      film_tone_map(ap1, film, tone);
      mul(from_ap1, tone, out);
      for (int c = 0; c < 3; ++c) out[c] = max_num(0.0f, out[c]);
    } else {
      for (int c = 0; c < 3; ++c) out[c] = aces_narkowicz(graded[c], 1.0f);
    }
    // The back buffer's encoding.
    for (int c = 0; c < 3; ++c) {
      switch (back_buffer) {
        case 0:
          px[c] = saturate(pq_from_nits(out[c] * white));
          break;
        case 1:
          px[c] = out[c] * (white * 0.0125f);
          break;
        case 2:
          px[c] = srgb_encode(saturate(out[c]));
          break;
        default:
          px[c] = pow_e2(saturate(out[c]), 1.0f / 2.2f);
      }
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string params_path, output_path;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--params")
      params_path = value;
    else if (key == "--output")
      output_path = value;
    else
      return fail("unknown option " + key + " (valid: --params, --output)");
  }
  if (params_path.empty() || output_path.empty() || argc % 2 == 0)
    return fail("usage: float32_candidate --params P --output O");

  json doc;
  try {
    std::ifstream f(params_path);
    doc = json::parse(f);
  } catch (const std::exception& e) {
    return fail(params_path + ": " + e.what());
  }
  if (doc.value("format_version", 0) != 3)
    return fail(params_path + ": format_version " + doc.value("format_version", json()).dump() +
                ", this port reads 2");
  const std::string stage = doc.at("stage");
  const std::string dir = params_path.substr(0, params_path.find_last_of('/') + 1);
  const std::string pipeline = doc.value("pipeline", "");
  if (pipeline == "unity_urp" || pipeline == "ue55") {
    try {
      return pipeline == "ue55" ? ue55_stage(doc, dir, output_path)
                                : unity_urp_stage(doc, dir, output_path);
    } catch (const std::exception& e) {
      return fail(params_path + ": " + e.what());
    }
  }
  if (stage != "tone_curve" && stage != "pq_grade") {
    std::printf("stage %s is not implemented by this port\n", stage.c_str());
    return kDeclineStage;
  }
  const json& images = doc.at("images");
  int w = 0, h = 0;
  std::vector<float> image;
  std::string err;
  if (!read_rgba(dir + images.at("input").at("file").get<std::string>(), &w, &h, &image, &err))
    return fail(err);
  try {
    if (stage == "tone_curve") {
      tone_curve(doc.at("params"), &image);
    } else {
      Strip strip;
      if (!read_rgba(dir + images.at("user_lut").at("file").get<std::string>(), &strip.w, &strip.h,
                     &strip.texels, &err))
        return fail(err);
      strip.n = strip.h;
      if (strip.w != strip.n * strip.n)
        return fail("user_lut: " + std::to_string(strip.w) + " x " + std::to_string(strip.h) +
                    " is not a strip N² × N");
      pq_grade(doc.at("params"), strip, &image);
    }
  } catch (const std::exception& e) {
    return fail(params_path + ": " + e.what());
  }

  return write_rgba(output_path, w, h, image);
}
