#version 450
#extension GL_GOOGLE_include_directive : require
// The per-pixel port bakes no LUT: the tonemap stage's first pass does nothing (tonemap.comp
// evaluates CombineLUTs per pixel). The combine_luts stage itself is not implemented here.
#include "hdrc/interface.glsl"

layout(local_size_x = HDRC_LOCAL_SIZE_X) in;

void main() {}
