// The shaper that maps scene-linear colour into CombineLUTs' [0, 1] lattice and back.
// Encode: PostProcessTonemap.usf: ColorLookupTable (docs/spec/ue55.md §6.1 step 7).
// Decode: PostProcessCombineLUTs.usf: CombineLUTsCommon (docs/spec/ue55.md §4.3).
#pragma once

#include <algorithm>
#include <cmath>

#include "color/d3d_math.h"
#include "color/st2084.h"
#include "reference/color/ue_log_shaper.h"

namespace hdrc::ref {

// Devices 3–9 (every HDR and linear device) use the PQ shaper; 0–2 the log shaper
// (docs/spec/ue55.md §4.3).
inline bool uses_pq_shaper(int output_device) {
  return output_device >= 3;
}

// How the Tonemap pass addresses the LUT (PostProcessTonemap.usf: ColorLookupTable). UE 5.5: PQ
// for devices 3-9, log otherwise, no clamp before the PQ encode. UE 5.8: PQ iff r.LUT.Shaper = 1
// (LUTShaper), for every device, and the PQ branch encodes clamp(x · 100, 0, 10000)
// (docs/ue58-differences.md L7, T2).
struct LutShaper {
  bool pq = false;
  bool clamp_nits = false;  // 5.8: LinearToST2084(clamp(x · LinearToNitsScale, 0, 10000))
};

inline LutShaper ue55_lut_shaper(int output_device) {
  return {uses_pq_shaper(output_device), false};
}

// Scene-linear (working colour space) → lattice coordinate. PQ: LinearToST2084(x · 100); without
// the clamp (5.5) a negative is NaN (pow of a negative base on D3D); with it (5.8) a NaN or
// negative goes to 0 (D3D's max/min ignore a NaN operand) and +Inf to 10000 nits. Log:
// LinToLog(x + LogToLin(0)), saturated (NaN → 0).
inline double lut_encode(const LutShaper& shaper, double x) {
  if (shaper.pq) {
    double nits = x * kLinearToNitsScale;
    if (shaper.clamp_nits) nits = std::isnan(nits) ? 0.0 : std::clamp(nits, 0.0, 10000.0);
    if (std::isnan(nits) || nits < 0.0) return d3d::kNaN;  // pow of a negative base on D3D
    return st2084::pq_from_nits(nits);
  }
  return ue_log::log_from_lin(x + ue_log::lin_from_log(0.0));
}

// UE 5.5's encode for an output device.
inline double lut_encode(int output_device, double x) {
  return lut_encode(ue55_lut_shaper(output_device), x);
}

// Lattice coordinate → the linear value CombineLUTs grades at that coordinate.
inline double lut_decode(int output_device, double e) {
  if (uses_pq_shaper(output_device)) return st2084::nits_from_pq(e) / kLinearToNitsScale;
  return ue_log::lin_from_log(e) - ue_log::lin_from_log(0.0);
}

}  // namespace hdrc::ref
