// Prints the constants and matrices the shaders get from the generated include hdrc/interface.glsl
// (gpu/shader_constants.cpp glsl_shared_constants(): float(reference value), 9 significant
// digits), one declaration a line, for bench/constant_sweep.py, which plants each of them rounded
// to the digits a porter types. No arguments.
#include <cstdio>

#include "gpu/shader_constants.h"

int main() {
  std::fputs(hdrc::gpu::glsl_shared_constants().c_str(), stdout);
  return 0;
}
