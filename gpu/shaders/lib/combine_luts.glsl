// The colour function of one CombineLUTs texel (PostProcessCombineLUTs.usf: CombineLUTsCommon,
// docs/spec/ue55.md §4), composed from one file per concept, and the lattice coordinate of a texel (docs/spec/ue55.md §4.2).
// Reference: reference/ue/combine_luts.cpp (combine_luts_texel, lattice_coordinate).
// Needs the generated interface ("hdrc/interface.glsl") included first.
#ifndef HDRC_COMBINE_LUTS_GLSL
#define HDRC_COMBINE_LUTS_GLSL

#include "aces_output.glsl"
#include "color_correct.glsl"
#include "color_polynomial.glsl"
#include "expand_gamut.glsl"
#include "film_path.glsl"
#include "lut_shaper.glsl"
#include "matrix.glsl"
#include "output_device.glsl"
#include "ue_lut_blend.glsl"
#include "white_balance.glsl"

// UE stores OutDeviceColor / 1.05 and the tonemapper multiplies by 1.05 again (docs/spec/ue55.md §4.12).
const float LUT_SCALE = 1.05;

// OutDeviceColor for the lattice coordinate (each channel in [0, 1]) of P.output_device.
vec3 combine_luts_device_color(vec3 lattice) {
  int device = P.output_device;
  // §4.3 decode; §4.4 white balance; §4.5 to AP1 and fake wide gamut; §4.6 ColorCorrectAll.
  vec3 decoded = lut_decode(device, lattice);
  vec3 ap1 = mul_rows(P.wcs_to_ap1, white_balance(decoded));
  vec3 color_corrected = color_correct_all(expand_gamut(ap1, P.expand_gamut));

  // The HDR and linear devices 3-8 start from GradedColor (§4.7); the branch is uniform over
  // the dispatch, so only the path the device needs is evaluated.
  if (device >= 3 && device <= 8) {
    vec3 graded = apply_fade(mul_rows(P.wcs_from_ap1, color_corrected));
    if (device == 7) return encode_linear_exr(graded);
    if (device == 8) return encode_linear_no_tone_curve(graded);
    return encode_aces_pq(device, aces_output_transforms_1000(graded));
  }

  // The SDR film path (devices 0-2 and 9, §4.8, §4.10, §4.11): FilmColorNoGamma, with the user
  // LUT blend (BLENDCOUNT > 1, docs/ue55-lut-blend-spec.md §3) between the film tone curve and
  // r.Color's polynomial. The branch is uniform over the dispatch.
  vec3 film_tone_mapped = film_color(color_corrected);
  if (P.lut_blend_count > 1) film_tone_mapped = ue_lut_blend(film_tone_mapped);
  vec3 film = apply_fade(apply_mapping_polynomial(film_tone_mapped));
  if (device == 9) return encode_linear_with_tone_curve(film);
  vec3 film_gamma = apply_film_gamma(film);
  if (device == 0) return encode_sdr_srgb(film_gamma);
  if (device == 1) return encode_sdr_rec709(film_gamma);
  return encode_explicit_gamma(film_gamma);
}

// The value CombineLUTs stores for a lattice coordinate, before the storage format's rounding.
vec3 combine_luts_texel(vec3 lattice) { return combine_luts_device_color(lattice) / LUT_SCALE; }

// The neutral lattice coordinate of texel (r, g, b) of an N-edge LUT (docs/spec/ue55.md §4.2):
//  volume (layout 0): (r, g, b) / (N − 1)  (the compute shader's DispatchThreadId / (N − 1));
//  2-D unwrapped (layout 1, N² × N): the pixel shader's UV = ((x, y) + 0.5) / (N², N), x = r + N·b,
//  y = g, minus (0.49999/N², 0.49999/N) "to avoid getting into negative values"; r = frac(UV.x·N),
//  b = UV.x − r/N, g = UV.y, all × N/(N − 1) (PostProcessCombineLUTs.usf, MainPS). In exact
//  arithmetic that is r = (r + ε)/(N − 1), g = (g + ε)/(N − 1), b = b/(N − 1) with ε = 0.5 − 0.49999
//  = 1e-5: UE's bias on r and g (b's cancels), which the reference evaluates as UE writes it
//  (reference/ue/combine_luts.cpp lattice_coordinate).
//  The port evaluates the closed form (docs/ue55-decisions.md D-UV). UE's own form is ill-conditioned
//  at r = 0: UV.x·N = b + ε/N lies within one float ulp of the integer b (ε/N = 3e-7 at N = 33, the
//  ulp of 8 is 9.5e-7), so the 2.5-ULP division Vulkan allows can round it to just under b, whose
//  frac is ≈ 1: texel (0, g, b) then holds the colour of (1, g, b − 1). An NVIDIA H200 did exactly
//  that (lut/storage/lut33_dev0_fmt2_layout1, texel (0, 0, 8)); the worst-case device model
//  (--device-model worst) shows it on lavapipe.
vec3 lut_lattice_coordinate(int lut_layout, int n, ivec3 texel) {
  float n1 = float(n) - 1.0;
  if (lut_layout == 0) return vec3(texel) / n1;
  const float kBias = 1.0e-5;  // 0.5 − 0.49999
  return vec3(float(texel.r) + kBias, float(texel.g) + kBias, float(texel.b)) / n1;
}

#endif
