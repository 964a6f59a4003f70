// UE's log shaper for the SDR LUT (devices 0–2) and the linear↔nits scale of the PQ shaper.
// UE: Engine/Shaders/Private/TonemapCommon.ush — LogToLin, LinToLog, LinearToNitsScale
// (docs/spec/ue55.md §3.2, §3.4).
#pragma once

#include <cmath>

namespace hdrc::ref::ue_log {

inline constexpr double kLinearRange = 14.0;    // stops covered by [0, 1]
inline constexpr double kLinearGrey = 0.18;     // scene grey
inline constexpr double kExposureGrey = 444.0;  // grey lands on code 444/1023
inline constexpr double kGreyCode = kExposureGrey / 1023.0;

// HLSL saturate() on D3D returns 0 for NaN (D3D11 functional spec, 16.12 float rules); the
// reference follows D3D, which is what UE ships on (docs/ue55-decisions.md).
inline double saturate_d3d(double x) {
  if (std::isnan(x)) return 0.0;
  return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x);
}

// LogToLin(x) = 2^((x − 444/1023)·14) · 0.18.
inline double lin_from_log(double x) {
  return std::exp2((x - kGreyCode) * kLinearRange) * kLinearGrey;
}

// LinToLog(L) = saturate(log2(L)/14 − log2(0.18)/14 + 444/1023).
inline double log_from_lin(double lin) {
  return saturate_d3d(std::log2(lin) / kLinearRange - std::log2(kLinearGrey) / kLinearRange +
                      kGreyCode);
}

}  // namespace hdrc::ref::ue_log

namespace hdrc::ref {
// TonemapCommon.ush: LinearToNitsScale — scene-linear 1.0 is 100 nits for the PQ shaper.
inline constexpr double kLinearToNitsScale = 100.0;
}  // namespace hdrc::ref
