// "Fake wide gamut" (ExpandGamut) of the CombineLUTs pass (docs/spec/ue55.md §4.5): bright
// saturated AP1 colours are pushed towards a gamut between P3 and AP1.
//
// Source: Engine/Shaders/Private/PostProcessCombineLUTs.usf: CombineLUTsCommon (no public 5.5 copy;
// read in Mephisto1024/Toon_Engine ~5.1/5.2, commit 2dc09e8226da45ca87f8fcb812453ad02a75987b; the
// same block is in the 4.27 and 5.8 copies — docs/ue55-decisions.md D1).
#pragma once

#include "color/vec.h"

namespace hdrc::ref::grading {

// Wide_2_XYZ_MAT literal (primaries R 0.6965/0.3065, G 0.245/0.718, B 0.1302/0.0456, white
// 0.3127/0.329, as UE's comment lists them).
extern const Mat3 kWideToXyz;

// ExpandMat = (XYZ_2_AP1_MAT · Wide_2_XYZ_MAT) · AP1_2_sRGB, where AP1_2_sRGB is the shader-literal
// product XYZ_2_sRGB_MAT · D60_2_D65_CAT · AP1_2_XYZ_MAT (not the working colour space's FromAP1).
// AP1 → AP1. Evaluated in double from the literals.
Mat3 expand_gamut_matrix();

// ExpandAmount = (1 − 2^(−4·|Chroma − 1|²)) · (1 − 2^(−4·ExpandGamut·LumaAP1²)),
// Chroma = ColorAP1 / LumaAP1, LumaAP1 = dot(ColorAP1, AP1_RGB2Y).
//
// LumaAP1 == 0: UE divides without a guard, so black gives 0/0 = NaN and ExpandAmount = NaN·0.
// docs/ue55-decisions.md D-NaN: the reference returns 0 there (the D3D outcome after ColorCorrect's
// max(0, ·) and saturate(NaN) = 0 clean the NaN). For a non-black colour with zero luma and no zero
// component UE itself gets 0 (|Chroma|² = ∞ makes the first factor 1, the second is 0), so the
// guard agrees with UE there too. NaN input gives NaN.
double expand_gamut_amount(const Vec3& color_ap1, double expand_gamut);

// ColorAP1 = lerp(ColorAP1, ExpandMat · ColorAP1, ExpandAmount). AP1 in, AP1 out.
Vec3 expand_gamut(const Vec3& color_ap1, double expand_gamut);

}  // namespace hdrc::ref::grading
