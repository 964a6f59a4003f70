// The reference's fast paths: shortcuts that skip work without changing a single bit of any
// result (docs/performance.md). They are on by default; `set_fast_paths(false)` selects the plain
// evaluation, so a test can compare both paths of the same build over many colours
// (reference/ue/fast_paths_test.cpp) — that comparison, not a stored digest, is what holds the
// shortcuts to bit identity while the formulas themselves keep changing.
#pragma once

#include <atomic>

#include "color/d3d_math.h"

namespace hdrc::ref {

inline std::atomic<bool> g_fast_paths{true};

inline bool fast_paths() {
  return g_fast_paths.load(std::memory_order_relaxed);
}
inline void set_fast_paths(bool on) {
  g_fast_paths.store(on, std::memory_order_relaxed);
}

// d3d::pow(x, y) with the exponent-1 shortcut: for x ≥ 0 (not NaN) glibc's pow(x, 1) is x
// exactly (its result is within 0.52 ulp and x is representable; reference/ue/fast_paths_test.cpp
// checks it over 1e6 doubles), so returning x is bit-identical. Every other case, negative, NaN
// and zero bases included, goes to d3d::pow and keeps its edge-case rules.
inline double pow_exp1_shortcut(double x, double y) {
  if (y == 1.0 && x >= 0.0 && fast_paths()) return x;
  return d3d::pow(x, y);
}

}  // namespace hdrc::ref
