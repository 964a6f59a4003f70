// Colour-vision-deficiency simulation and correction as UE 5.5 applies it in the HDR UI composite
// (CompositeUIPixelShader.usf: ApplyColorDeficiency → ColorDeficiency.ush: ColorDeficiency),
// docs/ue55-decisions.md D8 / D8a, docs/spec/ue55.md §8.
//
// Model: Machado, Oliveira & Fernandes, "A Physiologically-based Model for Simulation of Color
// Vision Deficiency", IEEE TVCG 15(6), 2009, with the pre-computed matrices of Machado (2010), "A
// model for simulation of color vision deficiency and a color contrast enhancement technique for
// dichromats" (severity 0.0–1.0 in steps of 0.1 = UE severity 0–10). The UE tables are in
// color_deficiency.cpp; the correction ("daltonisation") is UE's RGB-space error redistribution.
#pragma once

#include "color/vec.h"

namespace hdrc::ref::ui {

// EColorVisionDeficiency (the shader's CDV_* codes). Values outside 0–3 behave as kNormalVision.
enum class CvdType : int { kNormalVision = 0, kDeuteranope = 1, kProtanope = 2, kTritanope = 3 };
inline constexpr int kCvdSeverityCount = 11;  // severities 0..10

// The Machado matrix UE uses for `type` at integer `severity` (0..10): RGB_2_Deuteranomaly for
// Deuteranope, RGB_2_Protanomaly for Protanope, RGB_2_Tritanomaly for Tritanope; identity for
// kNormalVision. Row-major, applied as deficient = M · rgb. Precondition: 0 <= severity <= 10.
const Mat3& machado_matrix(CvdType type, int severity);

// UE's daltonize matrix for `type` (RGB_DALTONIZE_{GREEN,RED,BLUE}_BLIND); the zero matrix for
// kNormalVision (UE adds no correction there).
const Mat3& daltonize_matrix(CvdType type);

// ColorDeficiency(rgb, Type, Severity, bCorrectDeficiency, bSimulateCorrectionWithDeficiency)
// on linear sRGB-primaries values (any scale: every step is linear):
//   M = machado_matrix(type, int(severity))   (severity truncated toward zero, as HLSL int())
//   deficient = M · rgb
//   not correct:  out = deficient                                   (simulation)
//   correct:      out = rgb + D_type · (rgb − deficient)            (daltonisation)
//                 simulate_with_deficiency: out = M · out           (what the viewer then sees)
// UE compares the float flags with == 1; so does this (flags are passed as 0.0 / 1.0 by UE).
// A truncated severity outside 0..10 reads outside UE's table (undefined there); the reference
// returns NaN in every channel so the case shows up instead of silently picking a row.
// No clamping: negatives, ±Inf and NaN propagate through the matrices (0 · Inf = NaN).
Vec3 color_deficiency(const Vec3& rgb, CvdType type, double severity, double correct,
                      double simulate_correction_with_deficiency);

}  // namespace hdrc::ref::ui
