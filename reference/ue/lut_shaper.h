// The shaper that maps scene-linear colour into CombineLUTs' [0, 1] lattice and back.
// Encode: PostProcessTonemap.usf: ColorLookupTable (docs/spec/ue55.md §6.1 step 7).
// Decode: PostProcessCombineLUTs.usf: CombineLUTsCommon (docs/spec/ue55.md §4.3).
#pragma once

#include "color/d3d_math.h"
#include "color/st2084.h"
#include "reference/color/ue_log_shaper.h"

namespace hdrc::ref {

// Devices 3–9 (every HDR and linear device) use the PQ shaper; 0–2 the log shaper
// (docs/spec/ue55.md §4.3).
inline bool uses_pq_shaper(int output_device) {
  return output_device >= 3;
}

// Scene-linear (working colour space) → lattice coordinate. PQ: LinearToST2084(x · 100), no
// max(0, ·) in 5.5, so negatives are NaN. Log: LinToLog(x + LogToLin(0)), saturated (NaN → 0).
inline double lut_encode(int output_device, double x) {
  if (uses_pq_shaper(output_device)) {
    const double nits = x * kLinearToNitsScale;
    if (std::isnan(nits) || nits < 0.0) return d3d::kNaN;  // pow of a negative base on D3D
    return st2084::pq_from_nits(nits);
  }
  return ue_log::log_from_lin(x + ue_log::lin_from_log(0.0));
}

// Lattice coordinate → the linear value CombineLUTs grades at that coordinate.
inline double lut_decode(int output_device, double e) {
  if (uses_pq_shaper(output_device)) return st2084::nits_from_pq(e) / kLinearToNitsScale;
  return ue_log::lin_from_log(e) - ue_log::lin_from_log(0.0);
}

}  // namespace hdrc::ref
