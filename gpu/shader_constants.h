// Constants the shaders share with the reference, taken from the reference's own definitions and
// printed losslessly (max_digits10) into the generated include — one source for both sides.
#pragma once

#include <string>
#include <vector>

#include "color/vec.h"

namespace hdrc::gpu {

struct SharedConstant {
  std::string name;  // GLSL identifier
  double value;      // the reference's (double) value; the shader gets float(value)
  std::string source;
};

const std::vector<SharedConstant>& shared_constants();

// Matrices the shaders share with the reference (UE's literal matrices and the products UE's
// shaders build from them), from the reference's one table (reference/color/ue_matrices.h and the
// functions that multiply its literals). Printed as the GLSL declaration the library code uses:
//   kRows:       const vec3 NAME[3] = vec3[3](row0, row1, row2);   out = (dot(NAME[i], v))
//   kHlslLiteral: const mat3 NAME = mat3(m00, m01, ..., m22);     HLSL's row-major literal list,
//                so GLSL holds M transposed and HLSL mul(M, v) is `v * NAME` (aces_common.glsl).
struct SharedMatrix {
  enum Form { kRows, kHlslLiteral } form;
  std::string name;
  ref::Mat3 value;  // out = value · in; the shader gets float(entry)
  std::string source;
};
const std::vector<SharedMatrix>& shared_matrices();

// "const float NAME = <float(value) printed with 9 significant digits>;" per constant, then the
// matrices of shared_matrices().
std::string glsl_shared_constants();

}  // namespace hdrc::gpu
