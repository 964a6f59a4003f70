// The tail of the CombineLUTs film path (docs/spec/ue55.md §4.10, §4.11): the r.Color.Min/Mid/Max
// polynomial, the camera fade (ColorScale / OverlayColor) and the "gamma" adjustment, with the
// host-side parameters computed as UE 5.5's C++ does.
//
// Sources: PostProcessCombineLUTs.cpp: GetMappingPolynomial (5.5; same body in the 5.8 copy);
// PostProcessCommon.ush: ColorCorrection; PostProcessCombineLUTs.usf: CombineLUTsCommon (fade and
// pow by InverseGamma.y, Toon_Engine ~5.1/5.2 copy); PostProcessTonemap.cpp:
// GetTonemapperOutputDeviceParameters (izzy2lost/UnrealEngineUWP 5.5, commit
// 032eb102616dedd0b486c16819f857c76b4db983) for InverseGamma.
//
// Host values are computed in float, as UE's C++ computes them, and returned as double: these are
// the exact numbers the shader receives.
#pragma once

#include <array>

#include "color/vec.h"

namespace hdrc::ref::grading {

// r.Color.Min / r.Color.Mid / r.Color.Max (PostProcessCombineLUTs.cpp; defaults 0, 0.5, 1).
struct ColorRemapCvars {
  double min = 0.0;
  double mid = 0.5;
  double max = 1.0;
};

// y = a·x² + b·x + c through (0, Min), (0.5, Mid), (1, Max).
struct MappingPolynomial {
  double a, b, c;
};

// PostProcessCombineLUTs.cpp: GetMappingPolynomial — each cvar clamped to [−10, 10], then
// c = Min, b = 4·Mid − 3·Min − Max, a = Max − Min − b (float arithmetic).
MappingPolynomial get_mapping_polynomial(const ColorRemapCvars& cvars);

// PostProcessCommon.ush: ColorCorrection — a·C² + b·C + c per channel, linear working colour space.
Vec3 apply_mapping_polynomial(const Vec3& film_color, const MappingPolynomial& p);

// View.ColorScale and View.OverlayColor (camera fade; defaults (1,1,1) and (0,0,0,0)).
struct Fade {
  Vec3 color_scale{1.0, 1.0, 1.0};
  std::array<double, 4> overlay_color{0.0, 0.0, 0.0, 0.0};  // rgb, a = blend amount
};

// lerp(C·ColorScale, OverlayColor.rgb, OverlayColor.a) — used for FilmColorNoGamma and GradedColor.
Vec3 apply_fade(const Vec3& color, const Fade& f);

// PostProcessTonemap.cpp: GetTonemapperOutputDeviceParameters —
// (1/DisplayGamma, 2.2/DisplayGamma, 1/max(Gamma, 1)) in float. DisplayGamma is the render
// target's (GEngine->DisplayGamma, default 2.2); tonemapper_gamma is r.TonemapperGamma after UE's
// fallback (0 becomes 2.2 on Apple platforms or for OutputDevice 2), which the caller applies.
struct InverseGamma {
  double x, y, z;
};
InverseGamma get_inverse_gamma(double display_gamma, double tonemapper_gamma);

// CombineLUTsCommon: FilmColor = pow(max(0, FilmColorNoGamma), InverseGamma.y). max is D3D
// maxNum, so NaN becomes 0.
Vec3 apply_film_gamma(const Vec3& film_color_no_gamma, const InverseGamma& g);

}  // namespace hdrc::ref::grading
