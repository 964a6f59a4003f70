// One axis of a linear (bilinear, trilinear) texture fetch with clamp-to-edge addressing, as the
// Vulkan specification's "Texel Filtering" and Direct3D define it: the texel-space coordinate
// t = uv · size − 0.5, its two neighbours floor(t) and floor(t) + 1 clamped into [0, size − 1],
// weighted by the fraction t − floor(t). Shared by the reference's LUT lookups (CombineLUTs'
// volume and unwrapped LUT, UE's user LUT strip, pq_grading's .cube strip).
#pragma once

#include <algorithm>
#include <cmath>

namespace hdrc::ref {

struct LinearTap {
  int i0, i1;  // the two texels, clamped into [0, size − 1]
  double f;    // the weight of i1
};

// `t` is already in texel space (uv · size − 0.5).
inline LinearTap linear_tap(double t, int size) {
  const double fl = std::floor(t);
  const int i = static_cast<int>(fl);
  return {std::clamp(i, 0, size - 1), std::clamp(i + 1, 0, size - 1), t - fl};
}

}  // namespace hdrc::ref
