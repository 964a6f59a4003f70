// The host↔shader interface, declared once (STYLE.md habit 5).
//
// HDRC_PARAM_BLOCK lists every parameter the stages receive, in order. From this one list come:
//   * the C++ struct `ParamBlock` (double precision; the reference engine reads it directly),
//   * the std430 byte image the GPU engine uploads (`pack_std430`), float32/int32 per field,
//   * the GLSL declaration of the block (`glsl_param_block`), injected into every shader.
// Matrices (type M3) are row-major and travel as three vec4 rows: GLSL `vec4 name[3]`.
// A test compiles the declaration and reads every field back from the GPU.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "reference/color/vec.h"

namespace hdrc {

// X(type, name, meaning). Types: I = int32, F = float32, M3 = 3×3 matrix.
#define HDRC_PARAM_BLOCK(X)                                                 \
  X(I, width, "image width in pixels")                                      \
  X(I, height, "image height in pixels")                                    \
  X(I, output_device, "EDisplayOutputFormat after cvar resolution (0-9)")   \
  X(I, output_gamut, "EDisplayColorGamut after cvar resolution (0-4)")      \
  X(M3, wcs_to_ap1, "WorkingColorSpace.ToAP1, float as UE's CPU builds it") \
  X(M3, ap1_to_output, "OuputGamutMappingMatrix(output_gamut), product of UE's literals")

struct ParamBlock {
#define HDRC_X_I(name) int32_t name = 0;
#define HDRC_X_F(name) double name = 0.0;
#define HDRC_X_M3(name) ref::Mat3 name = ref::Mat3::identity();
#define HDRC_X(type, name, doc) HDRC_X_##type(name)
  HDRC_PARAM_BLOCK(HDRC_X)
#undef HDRC_X
#undef HDRC_X_I
#undef HDRC_X_F
#undef HDRC_X_M3
};

// Descriptor bindings of every stage shader (set 0).
inline constexpr uint32_t kBindingParams = 0;  // readonly std430 buffer: the ParamBlock
inline constexpr uint32_t kBindingInput = 1;   // readonly std430 buffer: vec4 pixels, row-major
inline constexpr uint32_t kBindingOutput = 2;  // writeonly std430 buffer: vec4 pixels, row-major
inline constexpr uint32_t kLocalSizeX = 64;    // compute workgroup size (1-D over pixels)

// The ParamBlock as the std430 bytes the shaders read.
std::vector<uint8_t> pack_std430(const ParamBlock& p);

// GLSL text declaring the block, the bindings and the workgroup size.
std::string glsl_param_block();

// Field names and their std430 byte offsets, in declaration order (for tests and docs).
struct FieldLayout {
  std::string name;
  char type;  // 'I', 'F' or 'M'
  uint32_t offset;
};
std::vector<FieldLayout> param_block_layout();

}  // namespace hdrc
