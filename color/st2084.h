// SMPTE ST 2084:2014 perceptual quantiser (PQ), as UE 5.5 writes it.
// UE: Engine/Shaders/Private/GammaCorrectionCommon.ush — LinearToST2084, ST2084ToLinear (spec
// §3.1). Constants in the standard's fractional form (ST 2084 §5.3, equations 5.2/5.3).
#pragma once

#include <cmath>

namespace hdrc::ref::st2084 {

inline constexpr double kM1 = 2610.0 / 16384.0;         // 0.1593017578125
inline constexpr double kM2 = 2523.0 / 4096.0 * 128.0;  // 78.84375
inline constexpr double kC1 = 3424.0 / 4096.0;          // 0.8359375 (= c3 - c2 + 1)
inline constexpr double kC2 = 2413.0 / 4096.0 * 32.0;   // 18.8515625
inline constexpr double kC3 = 2392.0 / 4096.0 * 32.0;   // 18.6875
inline constexpr double kPeakNits = 10000.0;            // nits at code value 1.0

// UE's LinearToST2084(L): L in nits, returns the PQ signal. No clamp, as in UE: a negative input
// makes pow() of a negative base, which is NaN (docs/spec/ue55.md §3.1, §12.5); +Inf gives
// Inf·rcp(Inf) = NaN.
inline double pq_from_nits(double nits) {
  const double lm = std::pow(nits / kPeakNits, kM1);
  return std::pow((kC1 + kC2 * lm) * (1.0 / (1.0 + kC3 * lm)), kM2);
}

// UE's ST2084ToLinear(N): PQ signal in, nits out. max(Np - c1, 0) clamps below black; N above 1
// is extrapolated (and turns NaN where c2 - c3·Np < 0, as in UE).
inline double nits_from_pq(double pq) {
  const double np = std::pow(pq, 1.0 / kM2);
  const double l = std::fmax(np - kC1, 0.0) / (kC2 - kC3 * np);
  return std::pow(l, 1.0 / kM1) * kPeakNits;
}

}  // namespace hdrc::ref::st2084
