#include "core/case.h"

#include <algorithm>
#include <cmath>

namespace hdrc {

Image user_lut_strip(const UserLut& lut) {
  const int n = lut.size;
  if (n < 1 || lut.table.size() != static_cast<size_t>(n) * n * n) return Image();
  Image strip(n * n, n);
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r) {
        const auto& row = lut.table[static_cast<size_t>(r) + static_cast<size_t>(n) * (g + n * b)];
        double* px = strip.px(r + n * b, g);
        px[0] = row[0];
        px[1] = row[1];
        px[2] = row[2];
        px[3] = 1.0;
      }
  return strip;
}

double unorm8_value(double v) {
  if (std::isnan(v)) return 0.0;
  return std::nearbyint(std::clamp(v, 0.0, 1.0) * 255.0) / 255.0;
}

}  // namespace hdrc
