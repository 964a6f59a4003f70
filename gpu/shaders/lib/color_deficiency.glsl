// Colour-vision-deficiency simulation and correction as the HDR UI composite applies it:
// ColorDeficiency.ush: ColorDeficiency (5.x; the 4.22 body read in folgerwang/UnrealEngine
// Engine/Shaders/Private/SlatePostProcessColorDeficiencyPixelShader.usf, commit 2b46ba7b;
// docs/ue55-decisions.md D8). Reference: reference/ue/ui/color_deficiency.cpp color_deficiency.
//
// Tables: Machado, Oliveira & Fernandes (2009), the 2010 pre-computed matrices for severity 0.0 ..
// 1.0 in steps of 0.1, as UE stores them (RGB_2_Deuteranomaly / RGB_2_Protanomaly /
// RGB_2_Tritanomaly[11*3]: three rows per severity, deficient = M · rgb). The literals are UE's
// (6 decimals); a test reads every entry back through these functions and compares it with
// float(reference) (gpu/ui_shader_test.cpp).
#ifndef HDRC_COLOR_DEFICIENCY_GLSL
#define HDRC_COLOR_DEFICIENCY_GLSL

#include "d3d_math.glsl"

// EColorVisionDeficiency (the shader's CDV codes).
const int CVD_NORMAL_VISION = 0;
const int CVD_DEUTERANOPE = 1;
const int CVD_PROTANOPE = 2;
const int CVD_TRITANOPE = 3;
const int CVD_SEVERITY_COUNT = 11;  // severities 0..10

// The tables as functions of the severity, one case per severity: mat3(row 0, row 1, row 2), i.e.
// the mat3's COLUMNS are M's rows (M · rgb = cvd_apply(m, rgb)). A switch over literal matrices,
// not a dynamically indexed constant array: llvmpipe turns such an array into a private
// per-invocation copy, and with the three tables its compile of the composite took minutes.
mat3 cvd_deuteranomaly_rows(int severity) {
  switch (severity) {
    case 0: return mat3(vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0),
                        vec3(0.0, 0.0, 1.0));
    case 1: return mat3(vec3(0.866435, 0.177704, -0.044139), vec3(0.049567, 0.939063, 0.011370),
                        vec3(-0.003453, 0.007233, 0.996220));
    case 2: return mat3(vec3(0.760729, 0.319078, -0.079807), vec3(0.090568, 0.889315, 0.020117),
                        vec3(-0.006027, 0.013325, 0.992702));
    case 3: return mat3(vec3(0.675425, 0.433850, -0.109275), vec3(0.125303, 0.847755, 0.026942),
                        vec3(-0.007950, 0.018572, 0.989378));
    case 4: return mat3(vec3(0.605511, 0.528560, -0.134071), vec3(0.155318, 0.812366, 0.032316),
                        vec3(-0.009376, 0.023176, 0.986200));
    case 5: return mat3(vec3(0.547494, 0.607765, -0.155259), vec3(0.181692, 0.781742, 0.036566),
                        vec3(-0.010410, 0.027275, 0.983136));
    case 6: return mat3(vec3(0.498864, 0.674741, -0.173604), vec3(0.205199, 0.754872, 0.039929),
                        vec3(-0.011131, 0.030969, 0.980162));
    case 7: return mat3(vec3(0.457771, 0.731899, -0.189670), vec3(0.226409, 0.731012, 0.042579),
                        vec3(-0.011595, 0.034333, 0.977261));
    case 8: return mat3(vec3(0.422823, 0.781057, -0.203881), vec3(0.245752, 0.709602, 0.044646),
                        vec3(-0.011843, 0.037423, 0.974421));
    case 9: return mat3(vec3(0.392952, 0.823610, -0.216562), vec3(0.263559, 0.690210, 0.046232),
                        vec3(-0.011910, 0.040281, 0.971630));
    case 10: return mat3(vec3(0.367322, 0.860646, -0.227968), vec3(0.280085, 0.672501, 0.047413),
                         vec3(-0.011820, 0.042940, 0.968881));
  }
  return mat3(hdrc_nan());  // outside UE's table
}
mat3 cvd_protanomaly_rows(int severity) {
  switch (severity) {
    case 0: return mat3(vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0),
                        vec3(0.0, 0.0, 1.0));
    case 1: return mat3(vec3(0.856167, 0.182038, -0.038205), vec3(0.029342, 0.955115, 0.015544),
                        vec3(-0.002880, -0.001563, 1.004443));
    case 2: return mat3(vec3(0.734766, 0.334872, -0.069637), vec3(0.051840, 0.919198, 0.028963),
                        vec3(-0.004928, -0.004209, 1.009137));
    case 3: return mat3(vec3(0.630323, 0.465641, -0.095964), vec3(0.069181, 0.890046, 0.040773),
                        vec3(-0.006308, -0.007724, 1.014032));
    case 4: return mat3(vec3(0.539009, 0.579343, -0.118352), vec3(0.082546, 0.866121, 0.051332),
                        vec3(-0.007136, -0.011959, 1.019095));
    case 5: return mat3(vec3(0.458064, 0.679578, -0.137642), vec3(0.092785, 0.846313, 0.060902),
                        vec3(-0.007494, -0.016807, 1.024301));
    case 6: return mat3(vec3(0.385450, 0.769005, -0.154455), vec3(0.100526, 0.829802, 0.069673),
                        vec3(-0.007442, -0.022190, 1.029632));
    case 7: return mat3(vec3(0.319627, 0.849633, -0.169261), vec3(0.106241, 0.815969, 0.077790),
                        vec3(-0.007025, -0.028051, 1.035076));
    case 8: return mat3(vec3(0.259411, 0.923008, -0.182420), vec3(0.110296, 0.804340, 0.085364),
                        vec3(-0.006276, -0.034346, 1.040622));
    case 9: return mat3(vec3(0.203876, 0.990338, -0.194214), vec3(0.112975, 0.794542, 0.092483),
                        vec3(-0.005222, -0.041043, 1.046265));
    case 10: return mat3(vec3(0.152286, 1.052583, -0.204868), vec3(0.114503, 0.786281, 0.099216),
                         vec3(-0.003882, -0.048116, 1.051998));
  }
  return mat3(hdrc_nan());  // outside UE's table
}
mat3 cvd_tritanomaly_rows(int severity) {
  switch (severity) {
    case 0: return mat3(vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0),
                        vec3(0.0, 0.0, 1.0));
    case 1: return mat3(vec3(0.926670, 0.092514, -0.019184), vec3(0.021191, 0.964503, 0.014306),
                        vec3(0.008437, 0.054813, 0.936750));
    case 2: return mat3(vec3(0.895720, 0.133330, -0.029050), vec3(0.029997, 0.945400, 0.024603),
                        vec3(0.013027, 0.104707, 0.882266));
    case 3: return mat3(vec3(0.905871, 0.127791, -0.033662), vec3(0.026856, 0.941251, 0.031893),
                        vec3(0.013410, 0.148296, 0.838294));
    case 4: return mat3(vec3(0.948035, 0.089490, -0.037526), vec3(0.014364, 0.946792, 0.038844),
                        vec3(0.010853, 0.193991, 0.795156));
    case 5: return mat3(vec3(1.017277, 0.027029, -0.044306), vec3(-0.006113, 0.958479, 0.047634),
                        vec3(0.006379, 0.248708, 0.744913));
    case 6: return mat3(vec3(1.104996, -0.046633, -0.058363), vec3(-0.032137, 0.971635, 0.060503),
                        vec3(0.001336, 0.317922, 0.680742));
    case 7: return mat3(vec3(1.193214, -0.109812, -0.083402), vec3(-0.058496, 0.979410, 0.079086),
                        vec3(-0.002346, 0.403492, 0.598854));
    case 8: return mat3(vec3(1.257728, -0.139648, -0.118081), vec3(-0.078003, 0.975409, 0.102594),
                        vec3(-0.003316, 0.501214, 0.502102));
    case 9: return mat3(vec3(1.278864, -0.125333, -0.153531), vec3(-0.084748, 0.957674, 0.127074),
                        vec3(-0.000989, 0.601151, 0.399838));
    case 10: return mat3(vec3(1.255528, -0.076749, -0.178779), vec3(-0.078411, 0.930809, 0.147602),
                         vec3(0.004733, 0.691367, 0.303900));
  }
  return mat3(hdrc_nan());  // outside UE's table
}

// Daltonize matrices (USE_RGB_SPACE_CDV_CORRECTION = 1, USE_SINGLE_DALTONIZE_MATRIX = 0), after
// daltonize.org: RGB_DALTONIZE_GREEN_BLIND (deuteranope), _RED_BLIND (protanope), _BLUE_BLIND
// (tritanope). correction = D · (rgb − deficient).
const vec3 CVD_DALTONIZE_GREEN_BLIND[3] =
    vec3[](vec3(0.5, 0.0, 0.5), vec3(1.0, 0.0, 1.0), vec3(0.5, 0.0, 0.5));
const vec3 CVD_DALTONIZE_RED_BLIND[3] =
    vec3[](vec3(0.5, 1.0, 1.0), vec3(0.5, 0.5, 0.5), vec3(0.5, 0.5, 0.5));
const vec3 CVD_DALTONIZE_BLUE_BLIND[3] =
    vec3[](vec3(0.5, 0.5, 0.5), vec3(0.5, 0.5, 0.5), vec3(1.0, 1.0, 0.5));

bool cvd_is_deficiency(int type) { return type >= CVD_DEUTERANOPE && type <= CVD_TRITANOPE; }

// The simulation matrix M for `type` at `severity` (0..10), rows as columns; identity for normal
// vision and unknown codes (UE's ConvertSourceRGBToDeficientRGB leaves the colour unchanged).
mat3 cvd_simulation_rows(int type, int severity) {
  if (type == CVD_DEUTERANOPE) return cvd_deuteranomaly_rows(severity);
  if (type == CVD_PROTANOPE) return cvd_protanomaly_rows(severity);
  if (type == CVD_TRITANOPE) return cvd_tritanomaly_rows(severity);
  return mat3(1.0);
}

// The daltonize matrix D for `type`, columns = D's rows (only called for the three types).
mat3 cvd_daltonize_rows(int type) {
  if (type == CVD_DEUTERANOPE) {
    return mat3(CVD_DALTONIZE_GREEN_BLIND[0], CVD_DALTONIZE_GREEN_BLIND[1],
                CVD_DALTONIZE_GREEN_BLIND[2]);
  }
  if (type == CVD_PROTANOPE) {
    return mat3(CVD_DALTONIZE_RED_BLIND[0], CVD_DALTONIZE_RED_BLIND[1], CVD_DALTONIZE_RED_BLIND[2]);
  }
  return mat3(CVD_DALTONIZE_BLUE_BLIND[0], CVD_DALTONIZE_BLUE_BLIND[1],
              CVD_DALTONIZE_BLUE_BLIND[2]);
}

// M · v for a matrix given by its rows as columns: one dot product per row.
vec3 cvd_apply(mat3 rows, vec3 v) { return vec3(dot(rows[0], v), dot(rows[1], v), dot(rows[2], v)); }

// ColorDeficiency(rgb, Type, Severity, bCorrectDeficiency, bSimulateCorrectionWithDeficiency) on
// linear sRGB-primaries values. UE passes all four as floats; the severity index is (int)Severity
// (truncation). The host hands integers here, so the truncation is the identity; a severity
// outside 0..10 reads outside UE's table (undefined there) and gives NaN, as the reference does.
//   simulate:  deficient = M · rgb
//   correct:   rgb + D · (rgb − deficient), then M · that when `show_correction`
// No clamping: negatives, ±Inf and NaN propagate through the matrices.
vec3 color_deficiency(vec3 rgb, int type, int severity, bool correct, bool show_correction) {
  if (severity < 0 || severity >= CVD_SEVERITY_COUNT) return vec3(hdrc_nan());
  // ConvertSourceRGBToDeficientRGB: M · rgb, or rgb itself for normal vision / unknown codes.
  bool deficiency = cvd_is_deficiency(type);
  mat3 m = cvd_simulation_rows(type, severity);
  vec3 deficient = deficiency ? cvd_apply(m, rgb) : rgb;
  if (!correct) return deficient;
  // UE starts from a literal zero correction and adds D · error only for the three types, so an
  // infinite error under normal vision does not become NaN (0 · Inf).
  vec3 corrected = rgb;
  if (deficiency) corrected += cvd_apply(cvd_daltonize_rows(type), rgb - deficient);
  return (show_correction && deficiency) ? cvd_apply(m, corrected) : corrected;
}

#endif
