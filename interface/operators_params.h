// The `operators` pipeline's part of the shader parameter block (core/shader_interface.h appends
// it to HDRC_PARAM_BLOCK): X(type, name, meaning), types I = int32, F = float32, V4 = vec4,
// M3 = 3x3 matrix. Every field is prefixed `op_`; the reference reads them from ParamBlock and the
// shaders from the generated block `P`. derive_operators (reference/operators/operators_settings.h)
// fills them from the pipeline's settings; the UE filmic operator also reads the UE block's
// film_slope/film_toe/film_shoulder/film_black_clip/film_white_clip (the block is shared, so
// gpu/shaders/lib/film_tonemap.glsl runs unchanged), which derive_operators fills from FilmPreset.
#pragma once

// The fields of UE 5.5's part of the block that this pipeline reads (its shaders and reference):
// the image size and FilmToneMap's parameters. A case of this pipeline carries these and its own
// op_* fields, nothing else of UE's (param_carried_by, core/shader_interface.h).
#define HDRC_OPERATORS_SHARED_PARAMS(Y) \
  Y(width)                              \
  Y(height) Y(film_slope) Y(film_toe) Y(film_shoulder) Y(film_black_clip) Y(film_white_clip)

#define HDRC_OPERATORS_PARAMS(X)                                                                   \
  X(I, op_operator,                                                                                \
    "classic operator: 0 Reinhard, 1 ReinhardWhite, 2 Hable, 3 AcesNarkowicz, 4 UnityNeutral, "    \
    "5 UeFilmic")                                                                                  \
  X(F, op_exposure, "Key / AdaptedLuminance: scales the input of every operator (Reinhard eq. 2)") \
  X(F, op_white_point, "ReinhardWhite L_white: the input mapped to 1 (Reinhard eq. 4)")            \
  X(F, op_hable_a, "Hable A, shoulder strength")                                                   \
  X(F, op_hable_b, "Hable B, linear strength")                                                     \
  X(F, op_hable_c, "Hable C, linear angle")                                                        \
  X(F, op_hable_d, "Hable D, toe strength")                                                        \
  X(F, op_hable_e, "Hable E, toe numerator")                                                       \
  X(F, op_hable_f, "Hable F, toe denominator")                                                     \
  X(F, op_hable_w, "Hable W, linear white: out = f(bias x) / f(W)")                                \
  X(F, op_hable_exposure_bias, "Hable exposure bias: multiplies the input of f")                   \
  X(F, op_narkowicz_pre_scale, "Narkowicz ACES fit: multiplies its input (1 = published form)")    \
  X(M3, op_rec709_to_ap1, "UeFilmic: Rec.709 -> AP1, UE's sRGB WorkingColorSpace.ToAP1")           \
  X(M3, op_ap1_to_rec709, "UeFilmic: AP1 -> Rec.709, UE's sRGB WorkingColorSpace.FromAP1")
