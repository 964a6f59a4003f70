// The Tonemap pass's specialisation constants (ids: core/shader_interface.h kSpecTonemap*, set
// by the engine from the case's ParamBlock: core specialisation_constants). Each flag says whether a
// branch of the pass on a uniform-level value can be taken at all; `false` only where the engine
// has seen that the uniform condition is false for the case. The uniform condition is still
// tested wherever one of these is, so a variant computes what the unspecialised pass computes:
// the constants only drop code that cannot run (UE drops it with permutations: USE_COLOR_FRINGE,
// USE_SHARPEN, and per output device; llvmpipe runs both sides of every branch, masked).
// Needs the generated interface ("hdrc/interface.glsl") included first.
#ifndef HDRC_TONEMAP_VARIANT_GLSL
#define HDRC_TONEMAP_VARIANT_GLSL

layout(constant_id = HDRC_SPEC_TONEMAP_FRINGE) const bool TONEMAP_MAY_FRINGE = true;
layout(constant_id = HDRC_SPEC_TONEMAP_SHARPEN) const bool TONEMAP_MAY_SHARPEN = true;
layout(constant_id = HDRC_SPEC_TONEMAP_BLOOM) const bool TONEMAP_MAY_BLOOM = true;
layout(constant_id = HDRC_SPEC_TONEMAP_BLOOM_DIRT) const bool TONEMAP_MAY_BLOOM_DIRT = true;
layout(constant_id = HDRC_SPEC_TONEMAP_POST) const bool TONEMAP_MAY_POST = true;
// The LUT's layout, P.lut_layout, where the engine specialised the pass on it; -1: read the
// uniform (tonemap_lut_layout).
layout(constant_id = HDRC_SPEC_TONEMAP_LUT_LAYOUT) const int TONEMAP_LUT_LAYOUT = -1;

int tonemap_lut_layout() { return TONEMAP_LUT_LAYOUT >= 0 ? TONEMAP_LUT_LAYOUT : P.lut_layout; }

#endif
