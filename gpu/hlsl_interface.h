// The GPU interface for HLSL ports (docs/gpu-interface.md, "HLSL"): the virtual include
// "hdrc/interface.hlsl", generated from the same sources as the GLSL one (core/shader_interface.h,
// gpu/shader_constants.cpp), so an HLSL compute shader compiled by glslang's HLSL front end sees
// the same parameter block layout, bindings and constants.
#pragma once

#include <string>

namespace hdrc::gpu {

// The parameter block as an HLSL struct read from a StructuredBuffer (std430, as the GLSL block),
// `P` as a macro for element 0, the resources with explicit [[vk::binding(N, 0)]] registers, and
// the shared constants as `static const float`.
std::string generated_interface_hlsl();

}  // namespace hdrc::gpu
