// The `pq_grading` pipeline's part of the shader parameter block (core/shader_interface.h appends
// it to HDRC_PARAM_BLOCK): X(type, name, meaning), types I = int32, F = float32, V4 = vec4,
// M3 = 3x3 matrix. Every field is prefixed `pq_`; derive_pq_grading (pq_grading.h) fills them from
// the pipeline's settings. The HDR display mapping also reads the UE block's film_* fields (UE's
// FilmToneMap, gpu/shaders/lib/film_tonemap.glsl, runs unchanged) and the LUT step the user LUT
// fields (user_lut_size, user_lut_domain_min/max) and binding user_lut.
#pragma once

// The fields of UE 5.5's part of the block that this pipeline reads: the image size, FilmToneMap's
// parameters and the user LUT's geometry. A case of this pipeline carries these and its own pq_*
// fields, nothing else of UE's (param_carried_by, core/shader_interface.h).
#define HDRC_PQ_GRADING_SHARED_PARAMS(Y) \
  Y(width)                               \
  Y(height)                              \
  Y(film_slope)                          \
  Y(film_toe)                            \
  Y(film_shoulder)                       \
  Y(film_black_clip)                     \
  Y(film_white_clip)                     \
  Y(user_lut_size)                       \
  Y(user_lut_domain_min)                 \
  Y(user_lut_domain_max)

#define HDRC_PQ_GRADING_PARAMS(X)                                                               \
  X(I, pq_display, "display mapping: 0 SDR (Narkowicz's ACES fit), 1 HDR (UE's FilmToneMap)")   \
  X(I, pq_back_buffer,                                                                          \
    "output encoding: 0 R10G10B10A2 (PQ), 1 RGBA16F (scRGB linear), 2 sRGB8 (sRGB encode at "   \
    "store), 3 RGB8 UNORM (gamma 2.2)")                                                         \
  X(F, pq_amplify, "Amplify: multiplies the graded colour after its division by ExposureFract") \
  X(F, pq_exposure_fract,                                                                       \
    "ExposureFract = 1e-4 * Amplify: scene colour -> PQ's [0, 1] (x 10000 nits)")               \
  X(F, pq_white_nits,                                                                           \
    "nits of display value 1.0 in the PQ and RGBA16F encodings: PeakNits (HDR) or 100 (SDR)")   \
  X(M3, pq_rec709_to_ap1, "HDR mapping: Rec.709 -> AP1, UE's sRGB WorkingColorSpace.ToAP1")     \
  X(M3, pq_ap1_to_rec709, "HDR mapping: AP1 -> Rec.709, UE's sRGB WorkingColorSpace.FromAP1")
