#include "gpu/shader_constants.h"

#include <cstdio>
#include <limits>

#include "color/st2084.h"
#include "reference/color/ue_log_shaper.h"
#include "reference/color/ue_matrices.h"
#include "reference/ue/grading/expand_gamut.h"
#include "reference/ue/grading/film_tonemap.h"
#include "reference/ue/ui/composite.h"

namespace hdrc::gpu {

const std::vector<SharedConstant>& shared_constants() {
  namespace pq = ref::st2084;
  namespace lg = ref::ue_log;
  static const std::vector<SharedConstant> table = {
      {"PQ_M1", pq::kM1, "ST 2084 m1"},
      {"PQ_M2", pq::kM2, "ST 2084 m2"},
      {"PQ_C1", pq::kC1, "ST 2084 c1"},
      {"PQ_C2", pq::kC2, "ST 2084 c2"},
      {"PQ_C3", pq::kC3, "ST 2084 c3"},
      {"PQ_PEAK_NITS", pq::kPeakNits, "ST 2084 peak luminance"},
      {"LOG_LINEAR_RANGE", lg::kLinearRange, "TonemapCommon.ush LinearRange"},
      {"LOG_LINEAR_GREY", lg::kLinearGrey, "TonemapCommon.ush LinearGrey"},
      {"LOG_GREY_CODE", lg::kGreyCode, "TonemapCommon.ush ExposureGrey/1023"},
      {"LINEAR_TO_NITS_SCALE", ref::kLinearToNitsScale, "TonemapCommon.ush LinearToNitsScale"},
  };
  return table;
}

const std::vector<SharedMatrix>& shared_matrices() {
  namespace lit = ref::ue_literal;
  namespace g = ref::grading;
  using F = SharedMatrix;
  static const std::vector<SharedMatrix> table = {
      // ACES.ush literals (aces_common.glsl applies them with aces_mul).
      {F::kHlslLiteral, "AP1_2_XYZ_MAT", lit::kAp1ToXyz, "ACES.ush AP1_2_XYZ_MAT"},
      {F::kHlslLiteral, "XYZ_2_AP1_MAT", lit::kXyzToAp1, "ACES.ush XYZ_2_AP1_MAT"},
      {F::kHlslLiteral, "AP0_2_AP1_MAT", lit::kAp0ToAp1, "ACES.ush AP0_2_AP1_MAT"},
      {F::kHlslLiteral, "AP1_2_AP0_MAT", lit::kAp1ToAp0, "ACES.ush AP1_2_AP0_MAT"},
      // Products the shaders build from the literals, evaluated in double and rounded once.
      {F::kRows, "EXPAND_GAMUT_MAT", g::expand_gamut_matrix(),
       "PostProcessCombineLUTs.usf ExpandMat = Wide_2_AP1 · AP1_2_sRGB "
       "(grading::expand_gamut_matrix)"},
      {F::kRows, "BLUE_CORRECT_AP1", g::blue_correct_ap1(),
       "PostProcessCombineLUTs.usf BlueCorrectAP1 (grading::blue_correct_ap1)"},
      {F::kRows, "BLUE_CORRECT_INV_AP1", g::blue_correct_inv_ap1(),
       "PostProcessCombineLUTs.usf BlueCorrectInvAP1 (grading::blue_correct_inv_ap1)"},
      {F::kRows, "FILM_AP1_TO_AP0", lit::kXyzToAp0 * lit::kAp1ToXyz,
       "TonemapCommon.ush FilmToneMap AP1_2_AP0 = XYZ_2_AP0_MAT · AP1_2_XYZ_MAT"},
      {F::kRows, "AP1_TO_SRGB", ref::ap1_to_output_gamut(0),
       "TonemapCommon.ush ST2084ToScRGB AP1_2_sRGB = XYZ_2_sRGB_MAT · D60_2_D65_CAT · "
       "AP1_2_XYZ_MAT"},
      {F::kRows, "SRGB_TO_REC2020", ref::ui::srgb_to_rec2020(),
       "CompositeUIPixelShader.usf sRGB_2_Rec2020 = XYZ_2_Rec2020_MAT · sRGB_2_XYZ_MAT"},
      {F::kRows, "REC2020_TO_SRGB", ref::ui::rec2020_to_srgb(),
       "CompositeUIPixelShader.usf Rec2020_2_sRGB = XYZ_2_sRGB_MAT · Rec2020_2_XYZ_MAT"},
  };
  return table;
}

namespace {
std::string float_literal(double value) {
  char number[64];
  std::snprintf(number, sizeof number, "%.*g", std::numeric_limits<float>::max_digits10,
                static_cast<float>(value));
  std::string literal = number;
  if (literal.find_first_of(".e") == std::string::npos) literal += ".0";
  return literal;
}
}  // namespace

std::string glsl_shared_constants() {
  std::string out;
  for (const auto& c : shared_constants())
    out += "const float " + c.name + " = " + float_literal(c.value) + ";  // " + c.source + "\n";
  for (const auto& m : shared_matrices()) {
    out += "// " + m.source + "\n";
    if (m.form == SharedMatrix::kHlslLiteral) {
      out += "const mat3 " + m.name + " = mat3(";
      for (int i = 0; i < 9; ++i) out += (i ? ", " : "") + float_literal(m.value.m[i]);
      out += ");\n";
    } else {
      out += "const vec3 " + m.name + "[3] = vec3[3](";
      for (int r = 0; r < 3; ++r) {
        out += std::string(r ? ", " : "") + "vec3(";
        for (int c = 0; c < 3; ++c) out += (c ? ", " : "") + float_literal(m.value(r, c));
        out += ")";
      }
      out += ");\n";
    }
  }
  return out;
}

}  // namespace hdrc::gpu
