#include "runner/golden_compare.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>

namespace hdrc {

long long ulp_distance(float a, float b) {
  int32_t ia, ib;
  std::memcpy(&ia, &a, 4);
  std::memcpy(&ib, &b, 4);
  // Map to a monotonic integer line (negative floats mirrored).
  if (ia < 0) ia = INT32_MIN - ia;
  if (ib < 0) ib = INT32_MIN - ib;
  return std::llabs(static_cast<long long>(ia) - ib);
}

GoldenScale golden_scale(const Image& golden) {
  GoldenScale s;
  for (size_t i = 0; i < golden.data.size(); ++i) {
    const double v = std::fabs(static_cast<double>(static_cast<float>(golden.data[i])));
    if (!std::isfinite(v)) continue;
    double& m = i % Image::kChannels == 3 ? s.alpha : s.colour;
    m = std::max(m, v);
  }
  return s;
}

double golden_deviation(float golden, float value, double scale) {
  if (std::isnan(golden) || std::isnan(value))
    return std::isnan(golden) && std::isnan(value) ? 0 : std::numeric_limits<double>::infinity();
  if (golden == value) return 0;
  if (std::isinf(golden) || std::isinf(value)) return std::numeric_limits<double>::infinity();
  const double relative = static_cast<double>(ulp_distance(golden, value)) / kGoldenUlps;
  const double floor = kGoldenScaleFloor * std::ldexp(scale, -24);
  const double absolute = floor > 0 ? std::fabs(static_cast<double>(golden) - value) / floor
                                    : std::numeric_limits<double>::infinity();
  return std::min(relative, absolute);
}

bool golden_value_close(float golden, float value, double scale) {
  return golden_deviation(golden, value, scale) <= 1.0;
}

GoldenDiff compare_with_golden(const Image& golden, const Image& reference) {
  GoldenDiff d;
  const GoldenScale s = golden_scale(golden);
  const size_t n = std::min(golden.data.size(), reference.data.size());
  for (size_t i = 0; i < n; ++i) {
    const double dev =
        golden_deviation(static_cast<float>(golden.data[i]), static_cast<float>(reference.data[i]),
                         i % Image::kChannels == 3 ? s.alpha : s.colour);
    if (dev > d.largest) {
      d.largest = dev;
      d.largest_at = i;
    }
    if (dev > 1.0 && d.differ++ == 0) d.first = i;
  }
  return d;
}

}  // namespace hdrc
