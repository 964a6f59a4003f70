// Constants the shaders share with the reference, taken from the reference's own definitions and
// printed losslessly (max_digits10) into the generated include — one source for both sides.
#pragma once

#include <string>
#include <vector>

namespace hdrc::gpu {

struct SharedConstant {
  std::string name;  // GLSL identifier
  double value;      // the reference's (double) value; the shader gets float(value)
  std::string source;
};

const std::vector<SharedConstant>& shared_constants();

// "const float NAME = <float(value) printed with 9 significant digits>;" per constant.
std::string glsl_shared_constants();

}  // namespace hdrc::gpu
