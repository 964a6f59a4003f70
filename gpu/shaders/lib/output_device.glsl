// CombineLUTs' device encodings (PostProcessCombineLUTs.usf: CombineLUTsCommon, docs/spec/ue55.md §4.12;
// docs/ue55-decisions.md D1): OutDeviceColor for each EDisplayOutputFormat from the graded
// colours. Reference: reference/ue/combine_luts.cpp (combine_luts_texel). Matrices come from the
// parameter block: P.wcs_to_ap1 (WorkingColorSpace.ToAP1) and P.ap1_to_output
// (OuputGamutMappingMatrix(OutputGamut)); each is applied as its own product, as UE does.
// Needs the generated interface included first.
#ifndef HDRC_OUTPUT_DEVICE_GLSL
#define HDRC_OUTPUT_DEVICE_GLSL

#include "d3d_math.glsl"
#include "gamma_correction.glsl"
#include "matrix.glsl"
#include "st2084.glsl"

// Linear working colour space → the output gamut: OutputGamutMappingMatrix · (ToAP1 · C).
vec3 wcs_to_output_gamut(vec3 linear_wcs) {
  return mul_rows(P.ap1_to_output, mul_rows(P.wcs_to_ap1, linear_wcs));
}

// LinearToST2084 per channel. No max(0, ·) in UE: a negative or NaN value is NaN, as HLSL pow of
// a negative base (pow_d3d inside pq_from_nits).
vec3 pq_from_nits(vec3 nits) {
  return vec3(pq_from_nits(nits.r), pq_from_nits(nits.g), pq_from_nits(nits.b));
}

// Device 0 (SDR_sRGB): LinearToSrgb of FilmColor; the gamut conversion is skipped when the
// working colour space is sRGB (WorkingColorSpace.bIsSRGB).
vec3 encode_sdr_srgb(vec3 film_gamma) {
  return linear_to_srgb(P.wcs_is_srgb != 0 ? film_gamma : wcs_to_output_gamut(film_gamma));
}

// Device 1 (SDR_Rec709): LinearTo709Branchless in the output gamut.
vec3 encode_sdr_rec709(vec3 film_gamma) {
  return linear_to_rec709_branchless(wcs_to_output_gamut(film_gamma));
}

// Device 2 (SDR_ExplicitGammaMapping, also the shader's final else): pow(C, InverseGamma.z) in
// the output gamut.
vec3 encode_explicit_gamma(vec3 film_gamma) {
  return pow_d3d(wcs_to_output_gamut(film_gamma), P.inverse_gamma.z);
}

// Devices 3-6: the ACES output transform's nits (AP1) PQ-encoded, in the output gamut for the
// ST 2084 devices 3/4; the scRGB devices 5/6 keep AP1 (the tonemapper converts, docs/spec/ue55.md §3.5).
vec3 encode_aces_pq(int device, vec3 aces_nits_ap1) {
  return pq_from_nits(device <= 4 ? mul_rows(P.ap1_to_output, aces_nits_ap1) : aces_nits_ap1);
}

// Device 7 (HDR_LinearEXR): GradedColor PQ-encoded in the output gamut (no tone curve).
vec3 encode_linear_exr(vec3 graded) { return pq_from_nits(wcs_to_output_gamut(graded)); }

// Device 8 (HDR_LinearNoToneCurve): GradedColor, the working colour space, unencoded.
vec3 encode_linear_no_tone_curve(vec3 graded) { return graded; }

// Device 9 (HDR_LinearWithToneCurve): FilmColorNoGamma (film path, polynomial and fade, no film
// gamma) in the output gamut.
vec3 encode_linear_with_tone_curve(vec3 film_no_gamma) { return wcs_to_output_gamut(film_no_gamma); }

#endif
