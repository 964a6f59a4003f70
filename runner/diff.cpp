#include "runner/diff.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

#include "color/gamma_correction.h"
#include "color/st2084.h"
#include "reference/color/ue_log_shaper.h"
#include "reference/color/ue_matrices.h"
#include "runner/tolerance.h"

namespace hdrc {

namespace {

double pq_signal(double nits) {
  if (!(nits > 0)) return ref::st2084::pq_from_nits(0.0);
  return ref::st2084::pq_from_nits(std::fmin(nits, ref::st2084::kPeakNits));
}

bool consistent_nonfinite(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return a == b;  // both infinite: same sign
}

const char* channel_name(int c) {
  static const char* names[] = {"R", "G", "B", "A"};
  return c >= 0 && c < 4 ? names[c] : "?";
}

void census(double v, NonFiniteCensus::Side* s) {
  if (std::isnan(v))
    ++s->nan;
  else if (std::isinf(v))
    ++(v > 0 ? s->pos_inf : s->neg_inf);
  else if (v < 0)
    ++s->negative;
}

// Nearest-rank percentile: the index, in sorted order, of the smallest value with at least q of
// the n values at or below it.
size_t nearest_rank_index(size_t n, double q) {
  const double rank = std::ceil(q * static_cast<double>(n));
  const size_t i = rank < 1 ? 0 : static_cast<size_t>(rank) - 1;
  return std::min(i, n - 1);
}

// The value at sorted index `index` (NaN-free values) of each of `indices`: selection
// (std::nth_element) instead of a full sort, O(n) per rank. Indices are selected in increasing
// order, each within the part above the previous one, so every answer is the value a sort would
// put at that index.
std::vector<double> values_at(std::vector<double>& values, const std::vector<size_t>& indices) {
  std::vector<std::pair<size_t, size_t>> order;  // (index in sorted order, which one)
  for (size_t k = 0; k < indices.size(); ++k) order.push_back({indices[k], k});
  std::sort(order.begin(), order.end());
  std::vector<double> out(indices.size());
  auto from = values.begin();
  for (const auto& [index, k] : order) {
    const auto at = values.begin() + static_cast<std::ptrdiff_t>(index);
    if (at >= from) {
      std::nth_element(from, at, values.end());
      from = at + 1;
    }
    out[k] = *at;
  }
  return out;
}

// The statistics of one metric's values (one band, or all), without keeping every value: the
// count, sum, sum of squares, the largest value and where it is, how many exceed the limit, and
// the `keep` largest values, from which finish() selects the nearest-rank percentiles. The ranks
// asked for (p99, p99.9, 1 - allowed fraction) lie in the top (1 - q_min) n + 1 values of n, so a
// bound on n (the image's values) fixes how many are enough; every statistic is the one a sort of
// all values gives. Keeping all of them cost 8 bytes per value, 13 values per pixel (four metrics
// of three channels and ΔE_ITP), plus the overall copy of each metric: 130-230 bytes per pixel,
// the diff's largest share of a 4096x4096 case's memory (docs/performance.md, "Memory").
struct Accumulator {
  Accumulator() = default;
  // `bound`: the most values this accumulator (or the union it is part of) can take; `q_min`:
  // the lowest rank finish() is asked for; `limit`: values over it are counted (NaN: all).
  Accumulator(size_t bound, double q_min, double limit)
      : keep(static_cast<size_t>(std::ceil(static_cast<double>(bound) * (1.0 - q_min))) + 1),
        limit(limit) {}
  size_t keep = 1;
  double limit = 0;
  size_t count = 0, over = 0;
  double sum = 0, sum_sq = 0, values_max = 0;
  PixelRef worst;
  // The largest values seen; once pruned, every value dropped is at most `threshold`, which is at
  // most every value kept (ties are interchangeable), so `top` stays the largest top.size() values.
  std::vector<double> top;
  bool pruned = false;
  double threshold = 0;

  void add(double v, const PixelRef& at) {
    if (count == 0 || v > values_max) {
      values_max = v;
      worst = at;
    }
    ++count;
    sum += v;
    sum_sq += v * v;
    if (std::isnan(limit) || v > limit) ++over;
    if (pruned && !(v > threshold)) return;
    top.push_back(v);
    if (top.size() >= keep + keep / 2 + 1024) prune();
  }
  // Keeps the `keep` largest values (std::nth_element, O(n)).
  void prune() {
    if (top.size() <= keep) return;
    std::nth_element(top.begin(), top.begin() + static_cast<std::ptrdiff_t>(keep - 1), top.end(),
                     std::greater<>());
    top.resize(keep);
    threshold = top[keep - 1];
    pruned = true;
  }
  // Takes in another accumulator's values (a band's into the overall one): the largest `keep` of
  // the union are among the union of each one's largest `keep`.
  void merge(const Accumulator& a) {
    if (a.count == 0) return;
    if (count == 0 || a.values_max > values_max) {
      values_max = a.values_max;
      worst = a.worst;
    }
    count += a.count;
    over += a.over;
    sum += a.sum;
    sum_sq += a.sum_sq;
    top.insert(top.end(), a.top.begin(), a.top.end());
    prune();
  }
  MetricStats finish(double allowed_fraction) {
    MetricStats m;
    m.count = count;
    if (count == 0) return m;
    const double n = static_cast<double>(count);
    m.max = values_max;
    m.mean = sum / n;
    m.rms = std::sqrt(sum_sq / n);
    m.over = over;
    // Sorted index i of all `count` values is index i - (count - top.size()) of the kept ones.
    const size_t dropped = count - top.size();
    std::vector<size_t> at;
    for (double q : {0.99, 0.999, 1.0 - allowed_fraction})
      at.push_back(nearest_rank_index(count, q) - std::min(dropped, nearest_rank_index(count, q)));
    const auto ranks = values_at(top, at);
    m.p99 = ranks[0];
    m.p999 = ranks[1];
    m.at_allowed_fraction = ranks[2];
    m.fraction_over = static_cast<double>(m.over) / n;
    m.worst = worst;
    return m;
  }
};

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

}  // namespace

const char* band_name(int band) {
  static const char* names[kBandCount] = {"<0.1", "0.1-1", "1-10", "10-100", "100-1000", ">=1000"};
  return band >= 0 && band < kBandCount ? names[band] : "?";
}

int band_of_nits(double nits) {
  if (!(nits >= 0.1)) return 0;
  if (nits < 1) return 1;
  if (nits < 10) return 2;
  if (nits < 100) return 3;
  if (nits < 1000) return 4;
  return 5;
}

ref::Vec3 ictcp_from_rec2020_nits(const ref::Vec3& rgb) {
  return ictcp_from_rec2020_nits_with(rgb, pq_signal);
}

double delta_e_itp(const ref::Vec3& a, const ref::Vec3& b) {
  // ITU-R BT.2124-0 eq. 1–2: T = 0.5·Ct, P = Cp; ΔE_ITP = 720·sqrt(ΔI² + ΔT² + ΔP²).
  const double di = a[0] - b[0];
  const double dt = 0.5 * (a[1] - b[1]);
  const double dp = a[2] - b[2];
  return 720.0 * std::sqrt(di * di + dt * dt + dp * dp);
}

std::string describe_pixel(const PixelRef& p) {
  const std::string band =
      p.band >= 0 ? std::string(", ") + band_name(p.band) + " nits" : std::string();
  char where[96];
  if (p.lut_size > 0)
    std::snprintf(where, sizeof where, "lattice (r %d, g %d, b %d) = pixel (%d, %d)",
                  p.x % p.lut_size, p.y, p.x / p.lut_size, p.x, p.y);
  else
    std::snprintf(where, sizeof where, "(%d, %d)", p.x, p.y);
  std::string out = std::string(where) + " " + channel_name(p.channel) + band + ": input " +
                    format_number(p.input) + " reference " + format_number(p.reference) +
                    " candidate " + format_number(p.candidate);
  auto rgb = [](const std::array<double, 3>& v) {
    std::string s = "(";  // appended: GCC 12 -O3 -Wrestrict false positive (bug 105329)
    s += format_number(v[0]);
    s += ", ";
    s += format_number(v[1]);
    s += ", ";
    s += format_number(v[2]);
    s += ")";
    return s;
  };
  out += "; pixel RGB input " + rgb(p.input_rgb) + " reference " + rgb(p.reference_rgb) +
         " candidate " + rgb(p.candidate_rgb);
  if (std::isfinite(p.delta_e_itp)) out += ", pixel ΔE_ITP " + fmt(p.delta_e_itp);
  return out;
}

std::string nonfinite_rule(StageId stage, int device, const PixelRef& p) {
  if (!p.valid() || std::isfinite(p.reference)) return "";
  const double in = p.input;
  const bool pq_shaper = device >= 3;
  const bool shaped = stage == StageId::kShaper || stage == StageId::kLinearDevice ||
                      stage == StageId::kTonemap || stage == StageId::kVisualizeHdr;
  const bool any_input_nan =
      std::isnan(p.input_rgb[0]) || std::isnan(p.input_rgb[1]) || std::isnan(p.input_rgb[2]);
  if (stage != StageId::kCombineLuts && std::isnan(in))
    return "the input is NaN: NaN propagates through every step";
  if (shaped && pq_shaper) {
    if (in < 0)
      return "LinearToST2084 of a negative value (" + format_number(in) +
             " x 100 nits): pow of a negative base is NaN; UE 5.5 has no max(0, x) there "
             "(spec 3.1, docs/ue55-decisions.md D-NF)";
    if (std::isinf(in) && in > 0)
      return "LinearToST2084(+Inf): (c1 + c2 Inf) * rcp(1 + c3 Inf) = Inf * 0 = NaN (spec 3.1)";
    if (stage == StageId::kTonemap && any_input_nan)
      return "another channel of the pixel is NaN: the LUT lookup of a NaN coordinate is NaN in "
             "every channel (docs/ue55-decisions.md D-NF)";
    if ((stage == StageId::kTonemap || stage == StageId::kVisualizeHdr) &&
        (device == 3 || device == 4) && in >= 0)
      return "LinearToST2084 of a negative value of the ACES output in the output gamut (this "
             "colour maps outside it): pow of a negative base is NaN (spec 4.12, devices 3/4; a "
             "baked 10-bit LUT stores such a texel as 0)";
    if (stage == StageId::kLinearDevice && device == 7)
      return "LinearToST2084 of a negative output-gamut value: AP1_2_Output * ToAP1 turns this "
             "out-of-gamut colour negative, and pow of a negative base is NaN (spec 4.12, row 7)";
  }
  if (stage == StageId::kCombineLuts)
    return "the device encode (PQ / gamma) of a negative output-gamut value at this lattice "
           "point: pow of a negative base is NaN, stored as NaN by the half and float formats "
           "(spec 4.12)";
  return "";
}

size_t resolve_admissible(const AdmissibleRange& range, const double* reference,
                          const double* candidate, double* out) {
  size_t changed = 0;
  for (int ch = 0; ch < Image::kChannels; ++ch) {
    const double r = reference[ch], c = candidate[ch];
    const double lo = range.lo[static_cast<size_t>(ch)], hi = range.hi[static_cast<size_t>(ch)];
    double v = r;
    if (std::isnan(c)) {
      if (range.nan_ok & (1u << ch)) v = c;
    } else if (lo <= hi) {  // false for a NaN bound: the point value alone
      v = std::clamp(c, lo, hi);
    }
    const bool same = std::isnan(v) ? std::isnan(r) : v == r;
    if (!same) ++changed;
    out[ch] = v;
  }
  return changed;
}

DiffStats diff_images(const Image& input, const Image& reference, const Image& candidate,
                      const OutputEncoding& enc, const Tolerance& tol) {
  DiffStats s;
  // Luminance Y of BT.2020 RGB: row 2 of its RGB→XYZ matrix (BT.2020 Table 4 primaries).
  const ref::Mat3 rec2020_to_xyz = ref::standard::rgb_to_xyz(ref::standard::kRec2020);
  const ref::Vec3 y_row{rec2020_to_xyz(1, 0), rec2020_to_xyz(1, 1), rec2020_to_xyz(1, 2)};
  // Every accumulator keeps enough of its largest values for the lowest rank asked for, over as
  // many values as the image has: three per pixel, one (ΔE_ITP) per pixel.
  std::array<std::array<Accumulator, kMetricCount>, kBandCount> acc;
  for (int m = 0; m < kMetricCount; ++m) {
    const Metric metric = static_cast<Metric>(m);
    const size_t bound = reference.pixel_count() * (metric == Metric::kDeltaEItp ? 1 : 3);
    const double q_min = std::min(0.99, 1.0 - tol.allowed_fraction[m]);
    for (int b = 0; b < kBandCount; ++b) acc[b][m] = Accumulator(bound, q_min, tol.max(metric));
  }
  const bool has_input = input.width == reference.width && input.height == reference.height;
  // combine_luts outputs the N² × N unwrapped LUT: messages name lattice points.
  const int lut_size = enc.stage == StageId::kCombineLuts && reference.height > 0 &&
                               reference.width == reference.height * reference.height
                           ? reference.height
                           : 0;
  // The reference's admissible ranges (core/image.h), in pixel order: the candidate is judged
  // against the nearest admissible value.
  auto next_range = reference.admissible.begin();
  double resolved[Image::kChannels];
  for (int y = 0; y < reference.height; ++y) {
    for (int x = 0; x < reference.width; ++x) {
      const double* r = reference.px(x, y);
      const double* c = candidate.px(x, y);
      const size_t index = static_cast<size_t>(y) * reference.width + x;
      while (next_range != reference.admissible.end() && next_range->pixel < index) ++next_range;
      if (next_range != reference.admissible.end() && next_range->pixel == index) {
        const size_t changed = resolve_admissible(*next_range, r, c, resolved);
        if (changed > 0 && s.admissible == 0) {
          s.first_admissible.x = x;
          s.first_admissible.y = y;
          s.first_admissible.lut_size = lut_size;
          for (int ch = 0; ch < 3; ++ch) {
            s.first_admissible.reference_rgb[ch] = r[ch];
            s.first_admissible.candidate_rgb[ch] = c[ch];
          }
        }
        s.admissible += changed;
        r = resolved;
      }
      const double* in = has_input ? input.px(x, y) : nullptr;
      ++s.pixels;
      // Each finite colour value in nits, decoded once (0 for a non-finite one), and the pixel's
      // largest |nits| over them: the scale of the float32 noise for the sign-boundary rule.
      ref::Vec3 ref_nits{0, 0, 0}, cand_nits{0, 0, 0};
      double pixel_scale = 0;
      for (int ch = 0; ch < 3; ++ch) {
        if (std::isfinite(r[ch])) {
          ref_nits[ch] = enc.to_nits(r[ch]);
          pixel_scale = std::fmax(pixel_scale, std::fabs(ref_nits[ch]));
        }
        if (std::isfinite(c[ch])) {
          cand_nits[ch] = enc.to_nits(c[ch]);
          pixel_scale = std::fmax(pixel_scale, std::fabs(cand_nits[ch]));
        }
      }
      // The whole pixel, for the messages of whichever value turns out worst.
      PixelRef whole;
      whole.x = x;
      whole.y = y;
      whole.lut_size = lut_size;
      for (int ch = 0; ch < 3; ++ch) {
        whole.input_rgb[ch] = in ? in[ch] : 0.0;
        whole.reference_rgb[ch] = r[ch];
        whole.candidate_rgb[ch] = c[ch];
      }
      auto at_channel = [&](int ch, int band) {
        PixelRef p = whole;
        p.channel = ch;
        p.input = in ? in[ch] : 0.0;
        p.reference = r[ch];
        p.candidate = c[ch];
        p.band = band;
        return p;
      };
      bool rgb_finite = true;
      for (int ch = 0; ch < 4; ++ch) {
        census(r[ch], &s.nonfinite.reference);
        census(c[ch], &s.nonfinite.candidate);
        const bool rf = std::isfinite(r[ch]), cf = std::isfinite(c[ch]);
        if (rf && cf) continue;
        if (ch < 3) rgb_finite = false;
        if (!rf && !cf && consistent_nonfinite(r[ch], c[ch])) {
          ++s.nonfinite.consistent;
        } else if (ch < 3 && enc.nan_marks_negative() && (std::isnan(r[ch]) || std::isnan(c[ch])) &&
                   (rf || cf) &&
                   std::fabs(rf ? ref_nits[ch] : cand_nits[ch]) <
                       kSignBoundaryNoise * pixel_scale) {
          if (s.nonfinite.sign_boundary == 0) s.nonfinite.first_sign_boundary = at_channel(ch, -1);
          ++s.nonfinite.sign_boundary;
        } else {
          if (s.nonfinite.mismatch == 0) s.nonfinite.first_mismatch = at_channel(ch, -1);
          ++s.nonfinite.mismatch;
        }
      }
      // The reference pixel's luminance decides the band (non-finite pixels: none).
      const ref::Vec3 ref2020 = enc.to_rec2020 * ref_nits;
      const int band = band_of_nits(ref::dot(y_row, ref2020));
      if (rgb_finite) ++s.band_pixels[band];
      const double de = rgb_finite
                            ? delta_e_itp(ictcp_from_rec2020_nits(enc.to_rec2020 * cand_nits),
                                          ictcp_from_rec2020_nits(ref2020))
                            : std::numeric_limits<double>::quiet_NaN();
      whole.delta_e_itp = de;
      if (s.nonfinite.mismatch > 0 && s.nonfinite.first_mismatch.x == x &&
          s.nonfinite.first_mismatch.y == y)
        s.nonfinite.first_mismatch.delta_e_itp = de;
      // The near-black floor (docs/tolerances.md, "The near-black floor"): where the pixel's
      // ΔE_ITP and every channel's linear error pass, PQ judges no channel below it.
      double pq_floor_nits = 0;
      if (tol.pq_near_black > 0 && rgb_finite && tol.delta_e_itp < kNotJudged &&
          de <= tol.delta_e_itp) {
        bool linear_ok = tol.linear_rel < kNotJudged || tol.linear_abs < kNotJudged;
        for (int ch = 0; ch < 3 && linear_ok; ++ch) {
          const double abs = std::fabs(c[ch] - r[ch]);
          const double rel = abs == 0 ? 0.0 : abs / std::fmax(std::fabs(r[ch]), tol.rel_floor);
          linear_ok = (!(tol.linear_rel < kNotJudged) || rel <= tol.linear_rel) &&
                      (!(tol.linear_abs < kNotJudged) || abs <= tol.linear_abs);
        }
        if (linear_ok) pq_floor_nits = tol.pq_near_black;
      }
      for (int ch = 0; ch < 3; ++ch) {
        if (!std::isfinite(r[ch]) || !std::isfinite(c[ch])) continue;
        ++s.values;
        const PixelRef at = at_channel(ch, band);
        const double abs = std::fabs(c[ch] - r[ch]);
        // abs > 0 over a zero denominator (rel_floor 0, reference 0) is an infinite relative
        // error.
        const double rel = abs == 0 ? 0.0 : abs / std::fmax(std::fabs(r[ch]), tol.rel_floor);
        // PQ's slope is unbounded at 0, so it is evaluated no lower than the pixel's float32
        // noise floor (docs/diff-metrics.md, "PQ noise floor"): values both below it agree; nor,
        // where the tolerance sets one and the other metrics pass, below the near-black floor.
        const double floor_nits = std::fmax(kSignBoundaryNoise * pixel_scale, pq_floor_nits);
        const double pq = std::fabs(pq_signal(std::fmax(cand_nits[ch], floor_nits)) -
                                    pq_signal(std::fmax(ref_nits[ch], floor_nits)));
        auto& a = acc[band];
        a[static_cast<int>(Metric::kLinearAbs)].add(abs, at);
        a[static_cast<int>(Metric::kLinearRel)].add(rel, at);
        a[static_cast<int>(Metric::kPqCode10)].add(pq * 1023.0, at);
        a[static_cast<int>(Metric::kPqCode12)].add(pq * 4095.0, at);
      }
      if (rgb_finite) {
        int worst_ch = 0;
        for (int ch = 1; ch < 3; ++ch)
          if (std::fabs(c[ch] - r[ch]) > std::fabs(c[worst_ch] - r[worst_ch])) worst_ch = ch;
        acc[band][static_cast<int>(Metric::kDeltaEItp)].add(de, at_channel(worst_ch, band));
      }
    }
  }
  s.nonfinite.rule = nonfinite_rule(enc.stage, enc.device, s.nonfinite.first_mismatch);
  // Per band, then overall from the union of the bands.
  for (int m = 0; m < kMetricCount; ++m) {
    const Metric metric = static_cast<Metric>(m);
    Accumulator all;
    all.keep = acc[0][m].keep;  // the bound is the image's, for a band as for the union
    for (int b = 0; b < kBandCount; ++b) {
      Accumulator& a = acc[b][m];
      all.merge(a);
      s.band[b][m] = a.finish(tol.allowed_fraction[m]);
      a.top = std::vector<double>();
    }
    s.metric[m] = all.finish(tol.allowed_fraction[m]);
    s.over_limit[m] = tol.max(metric);
  }
  // The worst value: of the metric using most of its max.
  double most = -1;
  for (int m = 0; m < kMetricCount; ++m) {
    const double limit = tol.max(static_cast<Metric>(m));
    if (!(limit < kNotJudged) || !s.metric[m].worst.valid()) continue;
    const double used =
        limit > 0 ? s.metric[m].max / limit : (s.metric[m].max > 0 ? kNotJudged : 0);
    if (used > most) {
      most = used;
      s.worst = s.metric[m].worst;
      s.worst_metric = static_cast<Metric>(m);
    }
  }
  if (most < 0) s.worst = s[Metric::kLinearRel].worst;
  s.max_rel = s[Metric::kLinearRel].max;
  s.max_pq10 = s[Metric::kPqCode10].max;
  s.worst_rel = s[Metric::kLinearRel].worst;
  return s;
}

double budget_used(const DiffStats& s, const Tolerance& tol) {
  if (s.nonfinite.mismatch > 0) return kNotJudged;
  double used = 0;
  for (int m = 0; m < kMetricCount; ++m) {
    const MetricStats& st = s.metric[m];
    const double limit = tol.max(static_cast<Metric>(m));
    if (limit < kNotJudged) {
      // With an allowed fraction, the value that fraction may exceed is what max limits.
      const double at = tol.allowed_fraction[m] > 0 ? st.at_allowed_fraction : st.max;
      used = std::fmax(used, limit > 0 ? at / limit : (at > 0 ? kNotJudged : 0.0));
      if (std::isnan(at)) used = kNotJudged;
      // Every criterion counts: with an allowed fraction also the share of it used (a LUT case
      // whose values are exact but for one-code flips uses its fraction and cap, not 0 %).
      if (tol.allowed_fraction[m] > 0)
        used = std::fmax(used, st.fraction_over / tol.allowed_fraction[m]);
    }
    if (tol.hard[m] < kNotJudged)
      used =
          std::fmax(used, tol.hard[m] > 0 ? st.max / tol.hard[m] : (st.max > 0 ? kNotJudged : 0));
  }
  return used;
}

Verdict judge(const DiffStats& s, const Tolerance& tol, bool pins_nonfinite) {
  Verdict v;
  v.budget_used = budget_used(s, tol);
  if (s.nonfinite.mismatch > 0) {
    v.reason = std::to_string(s.nonfinite.mismatch) + " non-finite mismatch(es); first at " +
               describe_pixel(s.nonfinite.first_mismatch);
    if (!s.nonfinite.rule.empty())
      v.reason += "; the reference's value comes from " + s.nonfinite.rule;
    return v;
  }
  // A case that compares nothing cannot fail: not a PASS (docs/diff-metrics.md).
  const size_t colour_values = 3 * s.pixels;
  std::string boundary = s.nonfinite.sign_boundary == 0
                             ? ""
                             : std::string("; ") + std::to_string(s.nonfinite.sign_boundary) +
                                   " NaN vs zero within float32 noise (sign boundary), first at " +
                                   describe_pixel(s.nonfinite.first_sign_boundary);
  if (s.admissible > 0)
    boundary += "; " + std::to_string(s.admissible) +
                " values judged against the reference's admissible range (a sign or a rounding "
                "float32 cannot "
                "decide), first at pixel (" +
                std::to_string(s.first_admissible.x) + ", " + std::to_string(s.first_admissible.y) +
                ")";
  if (pins_nonfinite && s.nonfinite.consistent == 0) {
    v.error = true;
    v.reason = "the case pins non-finite behaviour, but no value is non-finite on both sides";
    return v;
  }
  if (s.values == 0) {
    if (!pins_nonfinite) {
      v.error = true;
      v.reason = "nothing compared: " + std::to_string(colour_values - s.values) + " of " +
                 std::to_string(colour_values) + " values are non-finite on both sides";
      return v;
    }
    v.pass = true;
    v.reason = "non-finite census: " + std::to_string(s.nonfinite.consistent) +
               " consistent non-finite values, no mismatch" + boundary;
    return v;
  }
  std::string passing;
  bool any_max = false, all_small = true;
  for (int m = 0; m < kMetricCount; ++m) {
    const Metric metric = static_cast<Metric>(m);
    const MetricStats& st = s.metric[m];
    const std::string key = metric_key(metric);
    const double limit = tol.max(metric);
    const std::string unit = metric == Metric::kDeltaEItp ? "pixels" : "values";
    if (!(st.max <= tol.hard[m])) {
      v.reason = key + " " + fmt(st.max) + " over its hard cap " + fmt(tol.hard[m]) + " at " +
                 describe_pixel(st.worst);
      return v;
    }
    // With no allowed fraction the max decides (exact for any tolerance); with one, the count
    // over max, which diff_images made against the same tolerance.
    const bool counted_here =
        s.over_limit[m] == limit || (std::isnan(limit) && std::isnan(s.over_limit[m]));
    if (tol.allowed_fraction[m] > 0 && !counted_here) {
      v.reason = key + ": the statistics were counted against max " + fmt(s.over_limit[m]) +
                 ", not " + fmt(limit);
      return v;
    }
    const bool over = tol.allowed_fraction[m] > 0 ? !(st.fraction_over <= tol.allowed_fraction[m])
                                                  : !(st.max <= limit);
    if (over) {
      char buf[128];
      std::snprintf(buf, sizeof buf, ": %zu of %zu %s over (%.3g %%, allowed %.3g %%)", st.over,
                    st.count, unit.c_str(), 100.0 * st.fraction_over,
                    100.0 * tol.allowed_fraction[m]);
      v.reason =
          key + " " + fmt(st.max) + " > " + fmt(limit) + buf + " at " + describe_pixel(st.worst);
      return v;
    }
    if (!(st.max <= tol.warn[m]))
      v.warnings.push_back(key + " " + fmt(st.max) + " over its warn level " + fmt(tol.warn[m]) +
                           " at " + describe_pixel(st.worst));
    if (limit < kNotJudged) {
      any_max = true;
      double used = limit > 0 ? st.at_allowed_fraction / limit
                              : (st.at_allowed_fraction > 0 ? kNotJudged : 0.0);
      // Every criterion counts: with an allowed fraction also the share of it used and the hard
      // cap (a LUT case whose values are exact but for one-code flips uses its cap, not 0 %).
      if (tol.allowed_fraction[m] > 0)
        used = std::fmax(used, st.fraction_over / tol.allowed_fraction[m]);
      if (tol.hard[m] < kNotJudged && tol.hard[m] > 0) used = std::fmax(used, st.max / tol.hard[m]);
      if (!(used < 0.1)) all_small = false;
      passing += passing.empty() ? "" : ", ";
      if (tol.allowed_fraction[m] > 0)  // max may exceed the limit here: say what was judged
        passing += key + " " + fmt(100.0 * st.fraction_over) + " % of " + unit + " over " +
                   fmt(limit) + " (allowed " + fmt(100.0 * tol.allowed_fraction[m]) + " %), max " +
                   fmt(st.max) + " <= hard " + fmt(tol.hard[m]);
      else
        passing += key + " " + fmt(st.max) + " <= " + fmt(limit);
    }
  }
  v.pass = true;
  v.could_be_tightened = any_max && all_small;
  v.reason = (passing.empty() ? "no metric judged" : passing) + boundary;
  return v;
}

}  // namespace hdrc
