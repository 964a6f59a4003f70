#version 450
#extension GL_GOOGLE_include_directive : require
// Unity URP's colour grading in the uber pass (Common.hlsl ApplyColorGrading, no user LUT), one
// invocation per pixel: post exposure, then the lookup of the strip lut_bake.comp wrote (bound as
// the `lut_2d` sampler) at saturate(LogC(x)) (HDR grading) or at ApplyTonemap(x) (LDR grading),
// with ApplyLut2D's two bilinear taps lerped across the blue slices. Alpha passes through.
// Reference: reference/unity_urp/unity_urp.cpp (apply_color_grading, grade_image).
#include "hdrc/interface.glsl"
#include "../lib/unity_lut.glsl"

layout(local_size_x = HDRC_LOCAL_SIZE_X) in;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(P.width * P.height)) return;
  vec4 x = in_px[i];
  out_px[i] = vec4(urp_apply_color_grading(x.rgb), x.a);
}
