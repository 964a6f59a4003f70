#include "reference/ue/tonemap.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "color/d3d_math.h"
#include "color/st2084.h"
#include "reference/color/device_allowance.h"
#include "reference/color/ue_matrices.h"
#include "reference/ue/lut_shaper.h"
#include "reference/ue/ue_pixel_device.h"

namespace hdrc::ref {

namespace {

constexpr double kAcesHdrYMin = 0.0001;  // UE_ACES_HDR_Y_MIN (TonemapCommon.ush)

// range: where the LUT value float32 cannot decide (a texel's TexelRange), its admissible range
// is written there and *ambiguous set; left alone otherwise.
// lazy: the LUT's texels baked as this lookup reads them (lut is then ignored).
Vec3 lookup(const ParamBlock& p, const Vec3& final_linear, const BakedLut* lut, Vec3* encoded,
            const TexelEvaluator* texel, Range3* range = nullptr, bool* ambiguous = nullptr,
            LazyBakedLut* lazy = nullptr) {
  Vec3 e;
  for (int c = 0; c < 3; ++c) e[c] = lut_encode(p.output_device, final_linear[c]);
  if (encoded) *encoded = e;
  if (lazy) lut = &lazy->prepare(e);
  if (lut) {
    if (range && sample_lut_range(*lut, e, range)) *ambiguous = true;
    return sample_lut(*lut, e);
  }
  Vec3 clamped;
  for (int c = 0; c < 3; ++c) {
    clamped[c] = d3d::clamp_address(e[c]);
    if (std::isnan(clamped[c])) return {d3d::kNaN, d3d::kNaN, d3d::kNaN};
  }
  TexelRange texel_range;
  const Vec3 stored =
      texel ? (*texel)(clamped, range ? &texel_range : nullptr) : combine_luts_texel(p, clamped);
  if (range && texel_range.ambiguous) {
    *range = scale(texel_range.range, 1.05);
    *ambiguous = true;
  }
  return {stored[0] * 1.05, stored[1] * 1.05, stored[2] * 1.05};
}

}  // namespace

Vec3 post_convert(const ParamBlock& p, const Vec3& out_device, bool scrgb_in_pass) {
  switch (p.output_device) {
    case 5:
    case 6:
      if (!scrgb_in_pass) return out_device;
      return st2084_to_scrgb(out_device, p.output_max_luminance);
    case 7:
      return {st2084::nits_from_pq(out_device[0]), st2084::nits_from_pq(out_device[1]),
              st2084::nits_from_pq(out_device[2])};
    default:
      return out_device;
  }
}

namespace {

// post_convert over an admissible range: per-channel nondecreasing decodes, then (devices 5/6) a
// matrix.
Range3 post_convert_range(const ParamBlock& p, const Range3& r) {
  switch (p.output_device) {
    case 5:
    case 6: {
      const double max_nits = p.output_max_luminance;
      const Range3 lin = map_nondecreasing(r, [max_nits](double pq) {
        if (std::isnan(pq)) return pq;
        const double nits = std::clamp(st2084::nits_from_pq(pq), kAcesHdrYMin, max_nits);
        return (nits - kAcesHdrYMin) / (max_nits - kAcesHdrYMin);
      });
      return scale(apply_matrix(ap1_to_output_gamut(0), lin), max_nits / 80.0);
    }
    case 7:
      return map_nondecreasing(r, [](double pq) { return st2084::nits_from_pq(pq); });
    default:
      return r;
  }
}

// post_convert_range with the decode's own error on a conformant device (pq_decode_on_device) and
// the scRGB matrix's rounding (kFloat32Noise of the largest channel); `scrgb_in_pass` as
// post_convert's (UE 5.8 writes devices 5/6 unchanged).
Range3 post_convert_device_range(const ParamBlock& p, const Range3& r, bool scrgb_in_pass) {
  if (p.output_device < 5 || p.output_device > 7) return r;
  if (p.output_device != 7 && !scrgb_in_pass) return r;
  Range3 nits = r;
  for (int c = 0; c < 3; ++c) {
    if (std::isnan(r.lo[c]) || std::isnan(r.hi[c])) continue;
    nits.lo[c] = pq_decode_on_device(r.lo[c]).lo;
    nits.hi[c] = pq_decode_on_device(r.hi[c]).hi;
  }
  if (p.output_device == 7) return nits;
  const double max_nits = p.output_max_luminance;
  const Range3 lin = map_nondecreasing(nits, [max_nits](double v) {
    if (std::isnan(v)) return v;
    return (std::clamp(v, kAcesHdrYMin, max_nits) - kAcesHdrYMin) / (max_nits - kAcesHdrYMin);
  });
  Range3 out = scale(apply_matrix(ap1_to_output_gamut(0), lin), max_nits / 80.0);
  double scale = 0;
  for (int c = 0; c < 3; ++c)
    for (double v : {out.lo[c], out.hi[c]})
      if (std::isfinite(v)) scale = std::fmax(scale, std::fabs(v));
  for (int c = 0; c < 3; ++c) {
    out.lo[c] -= kFloat32Noise * scale;
    out.hi[c] += kFloat32Noise * scale;
  }
  return out;
}

}  // namespace

bool tonemap_device_range(const ParamBlock& p, const BakedLut& device_lut, const Vec3& encoded,
                          int sub_texel_bits, double lut_max, bool scrgb_in_pass, const Vec3& rgb,
                          double alpha, size_t pixel, const AdmissibleRange* tight,
                          AdmissibleRange* out, const spirv::Interval* encoded_range) {
  Range3 device;
  if (!sample_lut_device_range(device_lut, encoded, sub_texel_bits, &device, lut_max,
                               encoded_range))
    return false;
  Range3 post = post_convert_device_range(p, device, scrgb_in_pass);
  post.include(rgb);
  if (tight) {  // the tight range stays admissible
    for (int c = 0; c < 3; ++c) {
      post.lo[c] = std::fmin(post.lo[c], tight->lo[c]);
      post.hi[c] = std::fmax(post.hi[c], tight->hi[c]);
    }
  }
  const auto lum = luminance_range(device);
  *out = to_admissible(pixel, post, std::fmin(lum[0], alpha), std::fmax(lum[1], alpha),
                       device.nan[0] || device.nan[1] || device.nan[2]);
  return true;
}

namespace {

// Bilinear sample of `img` at buffer UV with clamp-to-edge addressing.
Vec3 sample_bilinear(const Image& img, double u, double v, double* alpha = nullptr) {
  const double x = u * img.width - 0.5, y = v * img.height - 0.5;
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  auto at = [&](int xi, int yi) {
    return img.px(std::clamp(xi, 0, img.width - 1), std::clamp(yi, 0, img.height - 1));
  };
  double out[4];
  for (int c = 0; c < 4; ++c) {
    const double top = at(x0, y0)[c] + (at(x0 + 1, y0)[c] - at(x0, y0)[c]) * fx;
    const double bot = at(x0, y0 + 1)[c] + (at(x0 + 1, y0 + 1)[c] - at(x0, y0 + 1)[c]) * fx;
    out[c] = top + (bot - top) * fy;
  }
  if (alpha) *alpha = out[3];
  return {out[0], out[1], out[2]};
}

double luminance_sharpen(const Vec3& c) {
  return c[0] * 0.3 + c[1] * 0.59 + c[2] * 0.11;
}

double sign_d3d(double x) {
  return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0);
}

}  // namespace

Vec3 st2084_to_scrgb(const Vec3& pq, double max_odt_nits) {
  // nits = clamp(ST2084ToLinear(pq), 1e-4, Max); linCV = (nits − 1e-4)/(Max − 1e-4);
  // scRGB = (XYZ→sRGB · D60→D65 · AP1→XYZ) · linCV · Max/80.
  Vec3 lin;
  for (int c = 0; c < 3; ++c) {
    const double nits = std::clamp(st2084::nits_from_pq(pq[c]), kAcesHdrYMin, max_odt_nits);
    lin[c] = (nits - kAcesHdrYMin) / (max_odt_nits - kAcesHdrYMin);
    if (std::isnan(pq[c])) lin[c] = d3d::kNaN;
  }
  const Vec3 s = ap1_to_output_gamut(0) * lin;
  const double k = max_odt_nits / 80.0;
  return {s[0] * k, s[1] * k, s[2] * k};
}

Vignette ue55_vignette(const ParamBlock& p) {
  Vignette v;
  v.intensity = p.vignette_intensity;
  return v;
}

Vec3 vignette_mask(const Vignette& v, double pos_x, double pos_y, double aspect,
                   VignetteTrace* trace) {
  // PostProcessCommon.ush (5.8) ComputeVignetteMask: Weight 1 for Intensity <= 0; cosine-fourth
  // law Square(rcp(|(V − (Centre − 0.5)) · Intensity|² + 1)); without USE_ADVANCED_VIGNETTE
  // every type is the cosine-fourth law. Advanced, not Texture (or Texture without
  // USE_VIGNETTE_TEXTURE, which RemapPermutation turns off at feature level SM5 and below):
  // Position = InvSize · V, Distance = length2(Position − (Centre − 0.5)) for Oval, else 0;
  // Weight = lerp(1, pow(saturate(1 − Distance), Softness), Intensity). Result lerp(Colour, 1,
  // Weight). V is VignetteSpace's: Pos · (1, AspectRatio) · sqrt(2)/sqrt(1 + AspectRatio²), for
  // the Texture type Pos · (saturate(1/AspectRatio), saturate(AspectRatio)) (TonemapCommonVS
  // passes VignetteType whatever the permutation; at SM5 the Texture type's weight is 1 anyway).
  // With USE_VIGNETTE_TEXTURE the Texture type samples the texture's red channel at
  // (InvSize · V − (Centre − 0.5)) · 0.5 + 0.5: Weight = lerp(1, sample, Intensity).
  const double k = std::sqrt(2.0) / std::sqrt(1.0 + aspect * aspect);
  double vx = pos_x * 1.0 * k, vy = pos_y * aspect * k;
  const double cx = v.center[0] - 0.5, cy = v.center[1] - 0.5;
  const int type = v.advanced ? v.type : 0;
  double weight = 1.0;
  if (v.intensity <= 0.0) {
  } else if (type == 1 && v.use_texture) {
    double u = 0, w = 0;
    vignette_texture_uv(v, pos_x, pos_y, aspect, &u, &w, trace);
    weight = 1.0 + v.intensity * (vignette_texture_sample(v, u, w, trace) - 1.0);
  } else if (type == 0) {
    vx = (vx - cx) * v.intensity;
    vy = (vy - cy) * v.intensity;
    const double m = 1.0 / (vx * vx + vy * vy + 1.0);
    weight = m * m;
  } else {
    double distance = 0.0;
    if (type == 2) {
      const double dx = v.inv_size[0] * vx - cx, dy = v.inv_size[1] * vy - cy;
      distance = dx * dx + dy * dy;
    }
    const double w = d3d::pow(d3d::saturate(1.0 - distance), v.softness);
    weight = 1.0 + v.intensity * (w - 1.0);  // HLSL lerp(1, w, I) = 1 + I·(w − 1)
  }
  if (trace) trace->weight = weight;
  Vec3 out;
  for (int c = 0; c < 3; ++c) out[c] = v.color[c] + weight * (1.0 - v.color[c]);
  return out;
}

void vignette_texture_uv(const Vignette& v, double pos_x, double pos_y, double aspect, double* u,
                         double* w, VignetteTrace* trace) {
  // PostProcessCommon.ush VignetteSpace (VIGNETTE_TYPE_TEXTURE) and ComputeVignetteMask's
  // SampleLevel coordinate.
  const double vx = pos_x * d3d::saturate(1.0 / aspect), vy = pos_y * d3d::saturate(aspect);
  *u = (v.inv_size[0] * vx - (v.center[0] - 0.5)) * 0.5 + 0.5;
  *w = (v.inv_size[1] * vy - (v.center[1] - 0.5)) * 0.5 + 0.5;
  if (trace) {
    trace->space[0] = vx;
    trace->space[1] = vy;
    trace->uv[0] = *u;
    trace->uv[1] = *w;
  }
}

double vignette_texture_sample(const Vignette& v, double u, double w, VignetteTrace* trace) {
  const double cx = u * v.tex_width - 0.5, cy = w * v.tex_height - 0.5;
  const LinearTap tx = linear_tap(cx, v.tex_width);
  const LinearTap ty = linear_tap(cy, v.tex_height);
  auto at = [&](int x, int y) { return v.tex[static_cast<size_t>(y) * v.tex_width + x]; };
  const double top = at(tx.i0, ty.i0) + (at(tx.i1, ty.i0) - at(tx.i0, ty.i0)) * tx.f;
  const double bottom = at(tx.i0, ty.i1) + (at(tx.i1, ty.i1) - at(tx.i0, ty.i1)) * tx.f;
  const double sample = top + (bottom - top) * ty.f;
  if (trace) {
    trace->textured = true;
    trace->texel[0] = cx;
    trace->texel[1] = cy;
    const double taps[4] = {at(tx.i0, ty.i0), at(tx.i1, ty.i0), at(tx.i0, ty.i1), at(tx.i1, ty.i1)};
    std::copy(taps, taps + 4, trace->taps);
    trace->sample = sample;
  }
  return sample;
}

Vec3 tonemap_final_linear(const ParamBlock& p, const Image& scene, const Image* bloom,
                          const Image* dirt, int x, int y, const Vignette& vignette_params,
                          FinalLinearParts* parts) {
  const double w = scene.width, h = scene.height;
  const double aspect = h / w;  // ViewportHeight / ViewportWidth
  const double u = (x + 0.5) / w, v = (y + 0.5) / h;
  const double pos_x = u * 2.0 - 1.0, pos_y = 1.0 - v * 2.0;  // screen position, y up
  const double* px = scene.px(x, y);
  Vec3 s{px[0], px[1], px[2]};
  // 1. Colour fringe: R (and alpha) and G from shifted lens positions, B in place.
  if (p.fringe[3] != 0.0) {
    auto shifted = [&](double scale) {
      const double lx =
          pos_x - sign_d3d(pos_x) * d3d::saturate(std::fabs(pos_x) - p.fringe[2]) * scale;
      const double ly =
          pos_y - sign_d3d(pos_y) * d3d::saturate(std::fabs(pos_y) - p.fringe[2]) * scale;
      return sample_bilinear(scene, lx * 0.5 + 0.5, 0.5 - ly * 0.5);
    };
    s[0] = shifted(p.fringe[0])[0];
    s[1] = shifted(p.fringe[1])[1];
  }
  // 2. Sharpen against the four neighbours.
  if (p.sharpen_div6 > 0.0) {
    auto at = [&](int dx, int dy) {
      const double* q =
          scene.px(std::clamp(x + dx, 0, scene.width - 1), std::clamp(y + dy, 0, scene.height - 1));
      return Vec3{q[0], q[1], q[2]};
    };
    const Vec3 n[4] = {at(-1, 0), at(1, 0), at(0, -1), at(0, 1)};
    const double a0 = luminance_sharpen(s);
    double edge = 0.0;
    for (const Vec3& c : n) edge = std::fmax(edge, std::fabs(a0 - luminance_sharpen(c)));
    const double mask = d3d::saturate(1.0 - p.exposure * edge);
    for (int c = 0; c < 3; ++c) {
      const double sum = n[0][c] + n[1][c] + n[2][c] + n[3][c];
      s[c] += (sum - 4.0 * s[c]) * (-mask * p.sharpen_div6);
    }
  }
  // 3. Vignette (in the viewport's aspect).
  const Vec3 vignette = vignette_mask(vignette_params, pos_x, pos_y, aspect);
  // 4–5. Tint, exposure, vignette; bloom.
  Vec3 final_linear;
  for (int c = 0; c < 3; ++c)
    final_linear[c] = s[c] * p.scene_color_tint[c] * (p.exposure * vignette[c]);
  Vec3 b{};
  if (bloom) {
    b = sample_bilinear(*bloom, u, v);
    if (dirt) {
      const Vec3 d = sample_bilinear(*dirt, u, v);
      for (int c = 0; c < 3; ++c) b[c] *= 1.0 + d[c] * p.bloom_dirt_tint[c];
    }
    for (int c = 0; c < 3; ++c) final_linear[c] += b[c] * (p.exposure * vignette[c]);
  }
  if (parts) *parts = FinalLinearParts{s, b, vignette, bloom != nullptr};
  return final_linear;
}

void tonemap_encoded_device_range(const ParamBlock& p, const FinalLinearParts& parts,
                                  spirv::Interval out[3]) {
  // tonemap_effects.glsl tonemap_final_linear_masked's products, scene · tint · (exposure ·
  // vignette) (+ bloom · (exposure · vignette)), each correctly rounded, the operands as their
  // float32 neighbours, then the shaper's encode op by op (ue_pixel_device.h lut_encode_clamped:
  // PQ's divide, two pows, the multiply-adds and the reciprocal with the precision table's
  // bounds). PQ's m2 = 78.84 amplifies the quotient's few roundings: from 100 nits up the
  // encode's range is wider than kShaderNoise (±4.55e-5 at 1000 nits, ±4.80e-5 at 3143 nits:
  // 1.49× and 1.57×); docs/precision.md, "The worst-case device with the allowances". The
  // effects' own arithmetic before the products (the fringe's and bloom's filters, the sharpen,
  // the vignette mask) stays under kShaderNoise (sample_lut_device_range).
  using ue_device::constant;
  for (int c = 0; c < 3; ++c) {
    const spirv::Interval k =
        spirv::mul(constant(p.exposure), parts.vignette[c] == 1.0 ? spirv::Interval::point(1.0)
                                                                  : constant(parts.vignette[c]));
    spirv::Interval x =
        spirv::mul(spirv::mul(constant(parts.scene[c]), constant(p.scene_color_tint[c])), k);
    if (parts.bloom) x = spirv::add(x, spirv::mul(constant(parts.bloom_rgb[c]), k));
    out[c] = ue_device::lut_encode_clamped(p.output_device, x);
  }
}

Vec3 tonemap_centre_pixel(const ParamBlock& p, const Vec3& scene, const BakedLut* lut,
                          TonemapTrace* trace) {
  return tonemap_centre_pixel(p, scene, lut, trace, nullptr);
}

Vec3 tonemap_centre_pixel(const ParamBlock& p, const Vec3& scene, const BakedLut* lut,
                          TonemapTrace* trace, const TexelEvaluator* texel) {
  TonemapTrace t;
  t.scene = scene;
  for (int c = 0; c < 3; ++c) t.exposed[c] = scene[c] * p.scene_color_tint[c] * p.exposure;
  t.lut = lookup(p, t.exposed, lut, &t.encoded, texel);
  t.luminance = t.lut[0] * 0.299 + t.lut[1] * 0.587 + t.lut[2] * 0.114;
  t.output = post_convert(p, t.lut, true);
  if (trace) *trace = t;
  return t.output;
}

Image tonemap_image(const ParamBlock& p, const Image& scene, const Image* bloom, const Image* dirt,
                    const BakedLut* lut) {
  return tonemap_image(p, scene, bloom, dirt, lut, nullptr);
}

Image tonemap_image(const ParamBlock& p, const Image& scene, const Image* bloom, const Image* dirt,
                    const BakedLut* lut, LazyBakedLut* lazy) {
  return tonemap_image(p, scene, bloom, dirt, lut, lazy, nullptr, 0);
}

Image tonemap_image(const ParamBlock& p, const Image& scene, const Image* bloom, const Image* dirt,
                    const BakedLut* lut, LazyBakedLut* lazy, const BakedLut* device_lut,
                    int sub_texel_bits) {
  Image out(scene.width, scene.height);
  std::optional<TexelEvaluator> texel;  // the analytic lookup's parameters, unpacked once
  if (!lut && !lazy) texel.emplace(p);
  const Vignette vignette = ue55_vignette(p);
  for (int y = 0; y < scene.height; ++y) {
    for (int x = 0; x < scene.width; ++x) {
      FinalLinearParts parts;
      const Vec3 final_linear = tonemap_final_linear(p, scene, bloom, dirt, x, y, vignette,
                                                     device_lut ? &parts : nullptr);
      // 7–9. LUT, luminance, per-device post conversion.
      Range3 range;
      bool ambiguous = false;
      Vec3 encoded;
      const Vec3 lut_out = lookup(p, final_linear, lut, &encoded, texel ? &*texel : nullptr, &range,
                                  &ambiguous, lazy);
      const Vec3 o = post_convert(p, lut_out, true);
      double* dst = out.px(x, y);
      dst[0] = o[0];
      dst[1] = o[1];
      dst[2] = o[2];
      dst[3] = lut_out[0] * 0.299 + lut_out[1] * 0.587 + lut_out[2] * 0.114;
      if (ambiguous) {
        Range3 post = post_convert_range(p, range);
        post.include(o);  // the reference's own value, whatever path rounded the end points
        range.include(lut_out);
        // Alpha: the luminance of the LUT value, non-negative weights.
        const auto lum = luminance_range(range);
        out.admissible.push_back(to_admissible(static_cast<size_t>(y) * scene.width + x, post,
                                               lum[0], lum[1],
                                               range.nan[0] || range.nan[1] || range.nan[2]));
      }
      // The lookup's coordinate on a conformant device (tonemap_encoded_device_range: the products
      // of steps 4-5 and the shaper's encode op by op; from 100 nits up wider than kShaderNoise).
      spirv::Interval encoded_range[3];
      if (device_lut) tonemap_encoded_device_range(p, parts, encoded_range);
      AdmissibleRange device;
      if (device_lut && tonemap_device_range(p, *device_lut, encoded, sub_texel_bits, 1.05, true, o,
                                             dst[3], static_cast<size_t>(y) * scene.width + x,
                                             ambiguous ? &out.admissible.back() : nullptr, &device,
                                             encoded_range))
        out.device_admissible.push_back(device);
    }
  }
  if (device_lut)
    out.device_allowances = {
        "filter weights (" + std::to_string(sub_texel_bits) + " sub-texel bits)",
        "LUT storage rounding (either neighbour)",
        "shader arithmetic (the Vulkan precision table's bounds)"};
  return out;
}

bool lazy_bake_pays(const ParamBlock& p, size_t pixels) {
  const size_t n = static_cast<size_t>(std::max(p.lut_size, 0));
  return pixels < n * n * n / 8;
}

double dither_grain(double u, double v) {
  // PostProcessTonemap.usf grain: frac(sin(u + v·543.31)·493013.0), float32 arithmetic.
  const float a = static_cast<float>(u) + static_cast<float>(v) * 543.31f;
  const float g = std::sin(a) * 493013.0f;
  return g - std::floor(g);
}

Image dither_image(const ParamBlock& p, const Image& in) {
  Image out = in;
  // GrainUV in float32 as UE computes it: MainCS's UV = (DispatchThreadId + 0.5) multiplied by
  // Color_ExtentInverse (the float reciprocal of the extent, FScreenPassTextureViewportParameters),
  // then + GrainRandomFull.xy (float constants). A division by the extent in double rounds
  // differently, and the hash magnifies that ~5e5 times (docs/precision.md, dither).
  const float inv_w = 1.0f / static_cast<float>(in.width);
  const float inv_h = 1.0f / static_cast<float>(in.height);
  const float grain_u = static_cast<float>(p.grain_random[0]);
  const float grain_v = static_cast<float>(p.grain_random[1]);
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x) {
      const float u = (static_cast<float>(x) + 0.5f) * inv_w + grain_u;
      const float v = (static_cast<float>(y) + 0.5f) * inv_h + grain_v;
      const double n = 2.0 * dither_grain(u, v) - 1.0;
      // clamp(n·∞, −1, 1) − that · sqrt(saturate(1 − |n|)) (docs/ue55-decisions.md D6.1).
      const double sg = sign_d3d(n);
      const double tri = sg - sg * std::sqrt(d3d::saturate(1.0 - std::fabs(n)));
      double* o = out.px(x, y);
      for (int c = 0; c < 3; ++c) o[c] += tri * p.dither_amount;
    }
  return out;
}

}  // namespace hdrc::ref
