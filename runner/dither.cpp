#include "runner/dither.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace hdrc {

namespace {

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

const char* channel_letter(int c) {
  return c == 0 ? "R" : c == 1 ? "G" : "B";
}

// The amplitude bound of one value: the amount, plus float32 noise of the amount (its own
// rounding and the product's) and of the value (the input's rounding to float32 and the sum's),
// each well under 2^-20 (kFloat32Noise) of it.
double amplitude_bound(double amount, double undithered, double candidate) {
  return amount * (1.0 + kFloat32Noise) +
         kFloat32Noise * std::fmax(std::fabs(undithered), std::fabs(candidate));
}

// The Kolmogorov–Smirnov distance of `t` (sorted here) to the triangular CDF.
double ks_distance(std::vector<double>& t) {
  std::sort(t.begin(), t.end());
  const double n = static_cast<double>(t.size());
  double d = 0;
  for (size_t i = 0; i < t.size(); ++i) {
    const double f = triangular_cdf(t[i]);
    d = std::fmax(d, std::fmax(static_cast<double>(i + 1) / n - f, f - static_cast<double>(i) / n));
  }
  return d;
}

}  // namespace

double triangular_cdf(double t) {
  if (!(t > -1.0)) return 0.0;
  if (t >= 1.0) return 1.0;
  return t <= 0.0 ? 0.5 * (1.0 + t) * (1.0 + t) : 1.0 - 0.5 * (1.0 - t) * (1.0 - t);
}

DitherStats dither_stats(const Image& undithered, const Image& candidate, double amount,
                         const DitherCriterion& criterion) {
  DitherStats s;
  s.amount = amount;
  const size_t pixels = undithered.pixel_count();
  const size_t block = static_cast<size_t>(std::max(1, criterion.block_pixels));
  // Blocks of `block` pixels in raster order; a last partial block joins the one before it.
  const size_t blocks = std::max<size_t>(1, pixels / block);
  std::array<std::vector<double>, 3> t;  // resolved t per channel
  std::array<std::vector<double>, 3> block_sum, block_n;
  for (int c = 0; c < 3; ++c) {
    block_sum[c].assign(blocks, 0.0);
    block_n[c].assign(blocks, 0.0);
  }
  double worst_used = -1;
  for (size_t i = 0; i < pixels; ++i) {
    const double* u = &undithered.data[i * Image::kChannels];
    const double* v = &candidate.data[i * Image::kChannels];
    const size_t b = std::min(i / block, blocks - 1);
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(u[c]) || !std::isfinite(v[c])) continue;  // the census judges those
      ++s.values;
      const double d = v[c] - u[c];
      const double bound = amplitude_bound(amount, u[c], v[c]);
      const double used = bound > 0 ? std::fabs(d) / bound : (d == 0 ? 0.0 : kNotJudged);
      if (!(used <= 1.0)) ++s.over_amplitude;
      if (!(used <= worst_used)) {
        worst_used = used;
        s.max_amplitude = used;
        s.worst_x = static_cast<int>(i % static_cast<size_t>(undithered.width));
        s.worst_y = static_cast<int>(i / static_cast<size_t>(undithered.width));
        s.worst_channel = c;
        s.worst_undithered = u[c];
        s.worst_candidate = v[c];
      }
      const double spacing = 0x1p-23 * std::fmax(std::fabs(u[c]), std::fabs(v[c]));
      if (!(amount > 0) || !(spacing <= kDitherResolution * amount)) continue;
      ++s.resolved;
      const double x = d / amount;
      t[c].push_back(x);
      block_sum[c][b] += x;
      block_n[c][b] += 1;
    }
  }
  if (amount > 0 && worst_used >= 0)
    s.max_amplitude = std::fabs(s.worst_candidate - s.worst_undithered) / amount;
  if (!(amount > 0)) return s;
  for (int c = 0; c < 3; ++c) {
    DitherChannelStats& ch = s.channel[c];
    ch.n = t[c].size();
    // Block means: each within mean_sigmas standard errors sqrt(1 / (6 n)) of 0, plus the
    // rounding of t (at most kDitherRounding per value, so of their mean).
    for (size_t b = 0; b < blocks; ++b) {
      const double n = block_n[c][b];
      if (n < static_cast<double>(kDitherMinValues)) continue;
      ++ch.blocks;
      const double mean = block_sum[c][b] / n;
      const double sigma = std::sqrt(kTriangularVariance / n);
      const double z = std::fabs(mean) / sigma;
      const double bound = criterion.mean_sigmas * sigma + kDitherRounding;
      if (!(std::fabs(mean) <= bound)) ch.mean_over = true;
      ch.mean_used = std::fmax(ch.mean_used, std::fabs(mean) / bound);
      if (ch.worst_block < 0 || z > ch.mean_z) {
        ch.mean_z = z;
        ch.worst_block = static_cast<int>(b);
      }
    }
    if (ch.n < kDitherMinValues) continue;
    ch.judged = true;
    s.statistics = true;
    const double n = static_cast<double>(ch.n);
    double sum = 0, sum2 = 0;
    for (double x : t[c]) sum += x;
    const double mean = sum / n;
    for (double x : t[c]) sum2 += (x - mean) * (x - mean);
    ch.std_ratio = std::sqrt(sum2 / (n - 1.0) / kTriangularVariance);
    // The sample standard deviation's standard error, relative: sqrt((kurtosis − 1) / (4 n))
    // (the delta method on the variance's, sigma² sqrt((kurtosis − 1) / n)); each value's
    // rounding moves the std by at most kDitherRounding, sqrt(6) kDitherRounding relative.
    ch.std_bound = criterion.std_sigmas * std::sqrt((kTriangularKurtosis - 1.0) / (4.0 * n)) +
                   std::sqrt(6.0) * kDitherRounding;
    // Kolmogorov's asymptotic quantile over sqrt(n); a shift of kDitherRounding moves the
    // empirical CDF against the triangular one (density <= 1) by at most as much.
    ch.ks = ks_distance(t[c]);
    ch.ks_bound = criterion.ks_c / std::sqrt(n) + kDitherRounding;
  }
  return s;
}

bool float32_exact_device(const DeviceInfo& d) {
  if (d.precision.float32_exact) return true;
  if (d.engine == "reference") return true;
  return d.engine == "vulkan" && d.device.rfind("llvmpipe", 0) == 0 && d.precision.model.empty();
}

bool exact_pattern_judged(const DitherCriterion& c, const DeviceInfo& device) {
  if (c.exact_pattern == "never") return false;
  return c.exact_pattern == "always" || float32_exact_device(device);
}

Verdict judge_dither(const DiffStats& s, const DitherStats& d, const Tolerance& tol,
                     bool exact_pattern, bool pins_nonfinite) {
  // The non-finite census and "something compared" as for every case: judge() with no metric.
  Tolerance census = tol;
  for (int m = 0; m < kMetricCount; ++m) {
    census.max(static_cast<Metric>(m)) = kNotJudged;
    census.allowed_fraction[m] = 0;
    census.hard[m] = kNotJudged;
    census.warn[m] = kNotJudged;
  }
  Verdict v = judge(s, census, pins_nonfinite);
  if (!v.pass) return v;
  const Verdict pattern = judge(s, tol, pins_nonfinite);
  v = Verdict{};
  // The amplitude's share is left out of the budget while it holds: every correct grain reaches
  // ±amount (its largest |t| is 1 − O(1/sqrt(n))), so it would always read 100 %.
  double used = 0;
  const std::string amount = "amount " + fmt(d.amount);
  if (d.over_amplitude > 0) {
    v.budget_used = d.amount > 0
                        ? std::fabs(d.worst_candidate - d.worst_undithered) /
                              amplitude_bound(d.amount, d.worst_undithered, d.worst_candidate)
                        : kNotJudged;
    char where[64];
    std::snprintf(where, sizeof where, "(%d, %d) %s", d.worst_x, d.worst_y,
                  channel_letter(d.worst_channel));
    v.reason = "dither amplitude: " + std::to_string(d.over_amplitude) + " of " +
               std::to_string(d.values) + " values differ from the undithered value by more than " +
               amount + (d.amount > 0 ? ", up to " + fmt(d.max_amplitude) + " x it" : "") +
               ", at " + where + ": undithered " + format_number(d.worst_undithered) +
               " candidate " + format_number(d.worst_candidate);
    return v;
  }
  std::string props = "dither amplitude <= " + amount;
  if (d.amount > 0) props += " (max " + fmt(d.max_amplitude) + " x)";
  if (d.statistics) {
    double mean_z = 0, std_dev = 0, ks_n = 0;
    for (int c = 0; c < 3; ++c) {
      const DitherChannelStats& ch = d.channel[c];
      const std::string name = std::string(channel_letter(c));
      if (ch.mean_over) {
        v.budget_used = ch.mean_used;
        v.reason = "dither mean: block " + std::to_string(ch.worst_block) + " (" +
                   std::to_string(tol.dither.block_pixels) + " pixels) of " + name +
                   " has a mean noise of " + fmt(ch.mean_z) + " standard errors, over " +
                   fmt(tol.dither.mean_sigmas) + " (a biased grain)";
        return v;
      }
      used = std::fmax(used, ch.mean_used);
      mean_z = std::fmax(mean_z, ch.mean_z);
      if (!ch.judged) continue;
      const double std_used = std::fabs(ch.std_ratio - 1.0) / ch.std_bound;
      if (!(std_used <= 1.0)) {
        v.budget_used = std_used;
        v.reason = "dither std: " + name + "'s noise has " + fmt(ch.std_ratio) +
                   " x the triangular distribution's standard deviation amount/sqrt(6) over " +
                   std::to_string(ch.n) + " values, allowed 1 +- " + fmt(ch.std_bound) +
                   " (a wrong amplitude or quantisation step)";
        return v;
      }
      const double ks_used = ch.ks / ch.ks_bound;
      if (!(ks_used <= 1.0)) {
        v.budget_used = ks_used;
        v.reason = "dither histogram: " + name + "'s noise is " + fmt(ch.ks) +
                   " (Kolmogorov-Smirnov) from the triangular distribution over " +
                   std::to_string(ch.n) + " values, allowed " + fmt(ch.ks_bound);
        return v;
      }
      used = std::fmax(used, std::fmax(std_used, ks_used));
      std_dev = std::fmax(std_dev, std::fabs(ch.std_ratio - 1.0));
      ks_n = std::fmax(ks_n, ch.ks * std::sqrt(static_cast<double>(ch.n)));
    }
    props += ", block means <= " + fmt(mean_z) + " sigma, std within " + fmt(100.0 * std_dev) +
             " %, KS sqrt(n) D <= " + fmt(ks_n) + " (" + std::to_string(d.resolved) + " of " +
             std::to_string(d.values) + " values resolved)";
  } else if (d.amount > 0) {
    props += " (no channel with " + std::to_string(kDitherMinValues) +
             " values float32 resolves at this amount: statistics not judged)";
  }
  if (exact_pattern) {
    if (!pattern.pass) {
      v.budget_used = std::fmax(used, pattern.budget_used);
      v.reason = "exact pattern (the reference's grain, judged on this device): " + pattern.reason;
      return v;
    }
    used = std::fmax(used, pattern.budget_used);
    v.warnings = pattern.warnings;
  }
  v.pass = true;
  v.budget_used = used;
  v.reason = props + "; exact pattern " +
             (exact_pattern ? std::string("judged: ")
                            : std::string("reported, not judged (device not float32-exact): ")) +
             pattern.reason;
  return v;
}

}  // namespace hdrc
