// UE's log shaper (TonemapCommon.ush LogToLin / LinToLog, docs/spec/ue55.md §3.2).
#ifndef HDRC_UE_LOG_SHAPER_GLSL
#define HDRC_UE_LOG_SHAPER_GLSL

#include "d3d_math.glsl"

float lin_from_log(float x) { return exp2((x - LOG_GREY_CODE) * LOG_LINEAR_RANGE) * LOG_LINEAR_GREY; }

float log_from_lin(float lin) {
  return saturate_d3d(log2(lin) / LOG_LINEAR_RANGE - log2(LOG_LINEAR_GREY) / LOG_LINEAR_RANGE +
                      LOG_GREY_CODE);
}

#endif
