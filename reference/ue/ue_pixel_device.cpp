#include "reference/ue/ue_pixel_device.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "color/st2084.h"
#include "reference/color/device_allowance.h"
#include "reference/color/noise_range.h"
#include "reference/color/ue_log_shaper.h"
#include "reference/reference_engine.h"
#include "reference/ue/lut_shaper.h"
#include "reference/ue/ui/composite.h"

namespace hdrc::ref::ue_device {

using spirv::Interval;

namespace {

Interval hull(Interval a, Interval b) {
  return {std::min(a.lo, b.lo), std::max(a.hi, b.hi)};
}

Interval clamp01(Interval x) {
  return {std::clamp(x.lo, 0.0, 1.0), std::clamp(x.hi, 0.0, 1.0)};
}

// ue_log_shaper.glsl lin_from_log: exp2((x − LOG_GREY_CODE) · LOG_LINEAR_RANGE) · LOG_LINEAR_GREY.
Interval lin_from_log(Interval x) {
  const Interval t =
      spirv::mul(spirv::sub(x, constant(ue_log::kGreyCode)), constant(ue_log::kLinearRange));
  return spirv::mul(spirv::exp2(t), constant(ue_log::kLinearGrey));
}

// ue_log_shaper.glsl log_from_lin: saturate(log2(lin) / range − log2(grey) / range + grey code).
// log2 of lin ≤ 0 is −inf or NaN, which saturate makes 0. The constant term is taken as a device
// evaluates it (it may equally be folded exactly: a point inside that interval).
Interval log_from_lin(Interval lin) {
  const Interval range = constant(ue_log::kLinearRange);
  const Interval k = spirv::div(spirv::log2(constant(ue_log::kLinearGrey)), range);
  auto at = [&](double v) -> Interval {
    if (!(v > 0)) return Interval::point(0.0);
    const Interval l = spirv::div(spirv::log2(Interval::point(v)), range);
    return clamp01(spirv::add(spirv::sub(l, k), constant(ue_log::kGreyCode)));
  };
  return hull(at(lin.lo), at(lin.hi));  // nondecreasing: the ends' device ranges
}

Interval black() {
  return lin_from_log(Interval::point(0.0));
}

// dot(m[row].xyz, v) of float32 uniforms: three products and two sums, each correctly rounded
// (OpDot's precision is inherited from OpFMul and OpFAdd, spirvenv-inherited-from), fused or not.
Interval dot_row(const Mat3& m, int row, const Interval v[3]) {
  Interval acc = spirv::mul(constant(m(row, 0)), v[0]);
  for (int j = 1; j < 3; ++j) acc = spirv::mul_add(constant(m(row, j)), v[j], acc);
  return acc;
}

}  // namespace

Interval constant(double v) {
  return {float_round_down(v), float_round_up(v)};
}

Interval pow_const(Interval x, double y) {
  if (!(x.hi > 0)) return Interval::point(0.0);
  const Interval y32 = constant(y);
  const Interval pos{std::max(x.lo, 0x1p-149), x.hi};
  Interval out = hull(spirv::pow(pos, y32.lo), spirv::pow(pos, y32.hi));
  if (!(x.lo > 0)) out.lo = 0.0;
  out.lo = std::max(out.lo, 0.0);
  return out;
}

// st2084.glsl: lm = pow(nits / PQ_PEAK_NITS, PQ_M1);
// pow((PQ_C1 + PQ_C2 · lm) · (1 / (1 + PQ_C3 · lm)), PQ_M2).
// lm enters both the numerator and the denominator: an interval evaluation of the quotient over
// lm's range would let the two move independently (the dependency problem) and widen it ~8x.
// The quotient is increasing in lm (c2 > c1·c3), so each end of lm's range is carried on its own
// through the quotient's steps and the hull taken; the same below for np in the decode.
Interval pq_from_nits(Interval nits) {
  using namespace spirv;
  const Interval lm = pow_const(div(nits, constant(st2084::kPeakNits)), st2084::kM1);
  auto quotient = [](double l) {
    const Interval at = Interval::point(l);
    const Interval num = mul_add(constant(st2084::kC2), at, constant(st2084::kC1));
    const Interval den = mul_add(constant(st2084::kC3), at, Interval::point(1.0));
    return mul(num, div(Interval::point(1.0), den));
  };
  return pow_const(hull(quotient(lm.lo), quotient(lm.hi)), st2084::kM2);
}

// st2084.glsl: np = pow(pq, 1 / PQ_M2); l = max(np − PQ_C1, 0) / (PQ_C2 − PQ_C3 · np);
// pow(l, 1 / PQ_M1) · PQ_PEAK_NITS. Every step is non-negative on a device (a correctly rounded
// or bounded result of non-negative operands keeps its sign; pow_d3d of l ≥ 0 is ≥ 0).
Interval nits_from_pq(Interval pq) {
  using namespace spirv;
  const Interval np = pow_const(pq, 1.0 / st2084::kM2);
  auto ratio = [](double n) {
    const Interval at = Interval::point(n);
    Interval num = sub(at, constant(st2084::kC1));
    num.lo = std::max(num.lo, 0.0);
    num.hi = std::max(num.hi, 0.0);
    if (num.hi == 0) return Interval::point(0.0);
    const Interval den = sub(constant(st2084::kC2), mul(constant(st2084::kC3), at));
    return div(num, den);
  };
  Interval l = hull(ratio(np.lo), ratio(np.hi));
  l.lo = std::max(l.lo, 0.0);
  Interval out = mul(pow_const(l, 1.0 / st2084::kM1), constant(st2084::kPeakNits));
  out.lo = std::max(out.lo, 0.0);
  return out;
}

Interval lut_encode_clamped(int output_device, Interval x) {
  if (uses_pq_shaper(output_device)) {
    Interval nits = spirv::mul(x, constant(kLinearToNitsScale));
    nits.lo = std::max(nits.lo, 0.0);
    return clamp01(pq_from_nits(nits));
  }
  return log_from_lin(spirv::add(x, black()));  // saturated: lut_clamp leaves it
}

Interval lut_decode(int output_device, Interval e) {
  if (uses_pq_shaper(output_device)) {
    Interval out = spirv::div(nits_from_pq(e), constant(kLinearToNitsScale));
    out.lo = std::max(out.lo, 0.0);  // non-negative operands: a non-negative quotient
    return out;
  }
  if (e.hi == 0.0) return Interval::point(0.0);
  // e == 0 decodes to 0 (lut_shaper.glsl); elsewhere lin_from_log(e) − black.
  Interval lin = spirv::sub(lin_from_log(e), black());
  if (e.lo == 0.0) lin = hull(lin, Interval::point(0.0));
  return lin;
}

ChannelRanges shaper_device_range(int output_device, const Vec3& x) {
  ChannelRanges r;
  for (int c = 0; c < 3; ++c) {
    // A NaN input, or a negative one under PQ (pow of a negative base): NaN on every device.
    if (std::isnan(x[c]) || (uses_pq_shaper(output_device) && x[c] < 0.0)) {
      r.valid[c] = false;
      continue;
    }
    r.c[c] = lut_decode(output_device, lut_encode_clamped(output_device, Interval::point(x[c])));
  }
  return r;
}

ChannelRanges linear_device_range(const ParamBlock& p, const Vec3& x) {
  ChannelRanges graded = shaper_device_range(p.output_device, x);
  if (p.output_device == 8) return graded;
  ChannelRanges r;
  for (int c = 0; c < 3; ++c)
    if (!graded.valid[c]) {
      for (int k = 0; k < 3; ++k) r.valid[k] = false;  // NaN reaches every row
      return r;
    }
  Interval ap1[3], out[3];
  for (int i = 0; i < 3; ++i) ap1[i] = dot_row(p.wcs_to_ap1, i, graded.c);
  for (int i = 0; i < 3; ++i) out[i] = dot_row(p.ap1_to_output, i, ap1);
  for (int c = 0; c < 3; ++c) {
    Interval v = out[c];
    if (v.hi < 0.0) {
      r.valid[c] = false;  // NaN on every device
      continue;
    }
    if (v.lo < 0.0) {
      r.nan[c] = true;  // pow of a negative base
      v.lo = 0.0;
    }
    r.c[c] = nits_from_pq(pq_from_nits(v));
  }
  return r;
}

std::vector<AdmissibleRange> per_pixel_device_ranges(StageId stage, const ParamBlock& p,
                                                     const Image& input, const Image& reference) {
  std::vector<AdmissibleRange> out;
  for (size_t i = 0; i < input.pixel_count(); ++i) {
    const double* in = &input.data[i * 4];
    const double* ref = &reference.data[i * 4];
    const Vec3 x{in[0], in[1], in[2]};
    const ChannelRanges r = stage == StageId::kLinearDevice
                                ? linear_device_range(p, x)
                                : shaper_device_range(p.output_device, x);
    AdmissibleRange a;
    a.pixel = i;
    bool wider = false;
    for (int c = 0; c < 4; ++c) {
      a.lo[c] = a.hi[c] = ref[c];
      if (c == 3 || !r.valid[c]) continue;
      if (std::isnan(ref[c])) {
        // NaN where the device range is finite: the reference's NaN stays admissible.
        a.lo[c] = r.c[c].lo;
        a.hi[c] = r.c[c].hi;
        a.nan_ok |= static_cast<uint8_t>(1u << c);
      } else {
        a.lo[c] = std::min(r.c[c].lo, ref[c]);
        a.hi[c] = std::max(r.c[c].hi, ref[c]);
        if (r.nan[c]) a.nan_ok |= static_cast<uint8_t>(1u << c);
      }
      wider = wider || a.lo[c] != ref[c] || a.hi[c] != ref[c] || (a.nan_ok >> c & 1u);
    }
    if (wider) out.push_back(a);
  }
  return out;
}

std::vector<AdmissibleRange> ui_composite_device_ranges(const ParamBlock& p, const Image& scene,
                                                        const Image& ui, const Image& reference) {
  const ui::UiCompositeParams u = ui_composite_params(p);
  if (u.composite_mode == 0) return {};
  return ui_composite_device_ranges_of(
      u.output_device, scene, reference, [&](size_t i, const Vec3& scene_nits) {
        const double* t = &ui.data[i * 4];
        const ui::Vec4 ui_nits = ui::compute_hdr_ui_color({t[0], t[1], t[2], t[3]}, u);
        return ui::apply_color_deficiency(ui::compose_ui_and_scene(scene_nits, ui_nits, u.ui_level),
                                          u.cvd);
      });
}

std::vector<AdmissibleRange> ui_composite_device_ranges_of(
    int output_device, const Image& scene, const Image& reference,
    const std::function<Vec3(size_t, const Vec3&)>& composed) {
  std::vector<AdmissibleRange> out;
  if (ui::back_buffer_encoding(output_device) == ui::BackBufferEncoding::kScRgb) {
    // scRGB: every step is linear (srgb_to_rec2020 · scene · 80, the compose, the CVD matrices,
    // rec2020_to_srgb · (x / 80)): no transfer function amplifies, the float32 arithmetic's
    // documented allowance kShaderNoise × the largest |channel| bounds it.
    for (size_t i = 0; i < reference.pixel_count(); ++i) {
      const double* ref = &reference.data[i * 4];
      const Vec3 v{ref[0], ref[1], ref[2]};
      Range3 r = Range3::point(v);
      if (!widen_noise(v, kShaderNoise, &r)) continue;
      AdmissibleRange a;
      a.pixel = i;
      for (int c = 0; c < 4; ++c) {
        a.lo[c] = c < 3 && std::isfinite(v[c]) ? r.lo[c] : ref[c];
        a.hi[c] = c < 3 && std::isfinite(v[c]) ? r.hi[c] : ref[c];
      }
      out.push_back(a);
    }
    return out;
  }
  for (size_t i = 0; i < scene.pixel_count(); ++i) {
    const double* s = &scene.data[i * 4];
    const double* ref = &reference.data[i * 4];
    bool finite = true;
    Interval nits[3];
    for (int c = 0; c < 3; ++c) {
      if (!(s[c] >= 0.0) || !std::isfinite(s[c])) finite = false;
      if (finite) nits[c] = nits_from_pq(Interval::point(s[c]));
    }
    if (!finite) continue;
    Range3 r;
    bool first = true;
    for (int corner = 0; corner < 8; ++corner) {
      Vec3 at;
      for (int c = 0; c < 3; ++c) at[c] = (corner >> c & 1) ? nits[c].hi : nits[c].lo;
      const Vec3 v = composed(i, at);
      if (first) {
        r = Range3::point(v);
        first = false;
      } else {
        r.include(v);
      }
    }
    Range3 noisy = r;
    for (int c = 0; c < 3; ++c)
      if (r.nan[c]) finite = false;
    if (!finite) continue;
    widen_noise(r.lo, kShaderNoise, &noisy);
    widen_noise(r.hi, kShaderNoise, &noisy);
    AdmissibleRange a;
    a.pixel = i;
    bool wider = false;
    for (int c = 0; c < 4; ++c) {
      a.lo[c] = a.hi[c] = ref[c];
      if (c == 3 || noisy.hi[c] < 0.0) continue;  // alpha as written; a negative range: NaN alone
      Interval v{noisy.lo[c], noisy.hi[c]};
      if (v.lo < 0.0) {
        a.nan_ok |= static_cast<uint8_t>(1u << c);
        v.lo = 0.0;
      }
      const Interval e = pq_from_nits(v);
      if (std::isnan(ref[c])) {
        a.lo[c] = e.lo;
        a.hi[c] = e.hi;
        a.nan_ok |= static_cast<uint8_t>(1u << c);
      } else {
        a.lo[c] = std::min(e.lo, ref[c]);
        a.hi[c] = std::max(e.hi, ref[c]);
      }
      wider = wider || a.lo[c] != ref[c] || a.hi[c] != ref[c] || (a.nan_ok >> c & 1u);
    }
    if (wider) out.push_back(a);
  }
  return out;
}

}  // namespace hdrc::ref::ue_device
