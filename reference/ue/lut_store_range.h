// The device-allowance steps CombineLUTs' bakes share (UE 5.5's reference/ue/combine_luts.cpp
// bake_lut_device and UE 5.8's reference/ue/ue58/ue58_combine_luts.cpp bake_outer_lut_device):
// the device encodes' pow error and the storage format's either-way rounding of a range
// (docs/precision.md, "Device allowances").
#pragma once

#include <cstdint>

#include "color/vec.h"
#include "reference/color/noise_range.h"

namespace hdrc::ref {

// The relative error of the device encodes' own pow (sRGB / Rec.709 / explicit gamma: pow(x, g)
// with g ≤ 1/1.8 and |log2 x| ≤ 24 over the LUT's range): inherited from exp2(g·log2 x), log2
// 3 ulp(24) = 5.7e-6 absolute, times g and ln 2: 2.2e-6; exp2 of |g·log2 x| ≤ 13: 29 ulp = 3.5e-6
// relative. Together under 2^-17 (7.6e-6), the figure applied.
inline constexpr double kEncodePowNoise = 1.0 / 131072.0;

// Each end of `r` moved outward by k times its magnitude.
Range3 widen_relative(Range3 r, double k);

// The storage format's either-way rounding of a range (the format's treatment of NaN as
// quantize_lut_value's: 10-bit UNORM stores 0, the float formats keep NaN): 10-bit UNORM the
// floor code of lo and the ceiling code of hi, RGBA16F either neighbouring half unless `fp16_rte`,
// RGBA32F either float. Bit c of `nan_flags` is set where NaN may be stored in channel c.
void store_either_way(int lut_format, bool fp16_rte, const Range3& r, Vec3* lo, Vec3* hi,
                      uint8_t* nan_flags);

}  // namespace hdrc::ref
