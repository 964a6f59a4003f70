// Colour matrices exactly as UE 5.5 uses them (docs/spec/ue55.md §2).
//
// Two kinds, never confused (STYLE.md habit 2):
//  * ue_literal::*  — the truncated literals of UE's shaders (Engine/Shaders/Private/ACES.ush and
//    TonemapCommon.ush) and their shader-side products. A port must match these, not the ideal.
//  * standard::*    — matrices derived in double from primaries and white points (Bradford where
//    white points differ), used to measure the gap to the literals and as independent checks.
#pragma once

#include <string>

#include "color/vec.h"

namespace hdrc::ref {

namespace ue_literal {
// ACES.ush literals as UE 5.3.2 and 5.5.1 write them (10 decimals; docs/spec/ue55.md §2.1 erratum
// in docs/ue55-decisions.md).
extern const Mat3 kAp0ToXyz;      // AP0_2_XYZ_MAT
extern const Mat3 kXyzToAp0;      // XYZ_2_AP0_MAT
extern const Mat3 kAp1ToXyz;      // AP1_2_XYZ_MAT
extern const Mat3 kXyzToAp1;      // XYZ_2_AP1_MAT
extern const Mat3 kAp0ToAp1;      // AP0_2_AP1_MAT
extern const Mat3 kAp1ToAp0;      // AP1_2_AP0_MAT
extern const Mat3 kXyzToSrgb;     // XYZ_2_sRGB_MAT
extern const Mat3 kSrgbToXyz;     // sRGB_2_XYZ_MAT
extern const Mat3 kXyzToRec2020;  // XYZ_2_Rec2020_MAT
extern const Mat3 kRec2020ToXyz;  // Rec2020_2_XYZ_MAT
extern const Mat3 kXyzToP3D65;    // XYZ_2_P3D65_MAT
extern const Mat3 kP3D65ToXyz;    // P3D65_2_XYZ_MAT
extern const Mat3 kD65ToD60Cat;   // D65_2_D60_CAT
extern const Mat3 kD60ToD65Cat;   // D60_2_D65_CAT
extern const Vec3 kAp1RgbToY;     // AP1_RGB2Y (row 1 of AP1_2_XYZ_MAT)
}  // namespace ue_literal

// EDisplayColorGamut (docs/spec/ue55.md §7.3).
enum class OutputGamut : int {
  kSrgbD65 = 0,
  kDciP3D65 = 1,
  kRec2020D65 = 2,
  kAcesD60 = 3,
  kAcesCgD60 = 4
};
inline constexpr int kOutputGamutCount = 5;
const char* output_gamut_name(int gamut);

// TonemapCommon.ush: OuputGamutMappingMatrix(OutputGamut) — AP1 to the output gamut as a product
// of the literals, evaluated in double (docs/spec/ue55.md §2.2). Values outside 0–4 fall back to
// AP1→sRGB.
Mat3 ap1_to_output_gamut(int gamut);

struct Chromaticities {
  double rx, ry, gx, gy, bx, by, wx, wy;
};

namespace standard {
extern const Chromaticities kSrgb;     // IEC 61966-2-1 / BT.709, D65
extern const Chromaticities kRec2020;  // BT.2020, D65
extern const Chromaticities kP3D65;    // SMPTE EG 432-1, D65
extern const Chromaticities kAp0;      // SMPTE ST 2065-1, ACES white
extern const Chromaticities kAp1;      // S-2014-004, ACES white
extern const Chromaticities kP3Dci;    // SMPTE RP 431-2 primaries, DCI calibration white
// RGB→XYZ from chromaticities (SMPTE RP 177 normalised primary matrix), in double.
Mat3 rgb_to_xyz(const Chromaticities& c);
// Bradford chromatic adaptation from white XYZ `src` to white XYZ `dst` (exact inverse cone
// matrix).
Mat3 bradford(const Vec3& src_white_xyz, const Vec3& dst_white_xyz);
// Src RGB → Dst RGB with Bradford adaptation unless the two white XYZ (RGB→XYZ · (1, 1, 1)) agree
// within 1e-7 per component (ColorSpace.cpp: CalcColorSpaceTransformMatrix, docs/spec/ue55.md
// §2.3).
Mat3 rgb_to_rgb(const Chromaticities& src, const Chromaticities& dst);
}  // namespace standard

// The project's Working Color Space (Project Settings → Rendering; RendererSettings.h:
// EWorkingColorSpace, UE's numbering): the presets build FColorSpace(EColorSpace) from
// ColorSpace.cpp: FColorSpace::MakeChromaticities, Custom builds it from the four chromaticity
// coordinates (RendererSettings.cpp: UpdateWorkingColorSpaceAndChromaticities).
enum class WorkingColorSpacePreset : int {
  kSrgb = 1,
  kRec2020 = 2,
  kAcesAp0 = 3,
  kAcesAp1 = 4,
  kP3Dci = 5,
  kP3D65 = 6,
  kCustom = 7
};
inline constexpr int kWorkingColorSpaceFirst = 1, kWorkingColorSpaceLast = 7;
// UE's enumerator name ("sRGB", "Rec2020", "ACESAP0", "ACESAP1", "P3DCI", "P3D65", "Custom"), or
// nullptr outside 1–7.
const char* working_color_space_name(int preset);
// The chromaticities of a preset (nullptr for Custom and values outside 1–6).
const Chromaticities* working_color_space_chromaticities(int preset);

// The WorkingColorSpace uniform buffer as UE 5.5's CPU fills it (SceneManagement.cpp:
// FDefaultWorkingColorSpaceUniformBuffer::Update, docs/spec/ue55.md §2.3): built in double from
// chromaticities, cast to float; FromAP1 is the inverse of the float ToAP1, cast to float.
struct WorkingColorSpace {
  Chromaticities chroma;
  Mat3 to_xyz, from_xyz, to_ap1, from_ap1, to_ap0;
  bool is_srgb = true;
};
// Custom chromaticities: bIsSRGB when they equal sRGB's within 1e-7 (ColorSpace.cpp:
// IsSRGBChromaticities).
WorkingColorSpace make_working_color_space(const Chromaticities& c);
// A preset 1–6 (FColorSpace(EColorSpace) sets bIsSRGB for the sRGB preset only); Custom and
// values outside 1–6 give sRGB.
WorkingColorSpace make_working_color_space(WorkingColorSpacePreset preset);
// Why custom chromaticities cannot make a colour space ("" when they can): a white with y <= 0,
// collinear primaries, or a white that needs a non-positive amount of a primary. UE does not
// check; its matrices would be singular or non-finite.
std::string chromaticities_problem(const Chromaticities& c);

}  // namespace hdrc::ref
