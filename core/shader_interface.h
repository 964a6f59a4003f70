// The host↔shader interface, declared once (STYLE.md habit 5).
//
// HDRC_PARAM_BLOCK lists every parameter the stages receive, in order. From this one list come:
//   * the C++ struct `ParamBlock` (double precision; the reference engine reads it directly),
//   * the std430 byte image the GPU engine uploads (`pack_std430`), float32/int32 per field,
//   * the GLSL declaration of the block (`glsl_param_block`), injected into every shader.
// Matrices (type M3) are row-major and travel as three vec4 rows: GLSL `vec4 name[3]`.
// Fixed-size tables (type V4A(n)) travel as n vec4: GLSL `vec4 name[n]`, texel for texel (a
// pipeline's host-built lookup tables, e.g. UE 5.8's ACES 2.0 tables, docs/gpu-interface.md).
// A test compiles the declaration and reads every field back from the GPU.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include "color/vec.h"
#include "interface/operators_params.h"
#include "interface/pq_grading_params.h"
#include "interface/ue58_params.h"
#include "interface/ue_params.h"
#include "interface/unity_urp_params.h"

namespace hdrc {

// X(type, name, meaning). Types: I = int32, F = float32, V4 = vec4, M3 = 3×3 matrix,
// V4A(n) = array of n vec4 (n is part of the type token: `X(V4A(91), name, "...")`).
// Host-derived values (matrices, ACES coefficients, InverseGamma, ...) are computed once by
// reference/ue/cpp/resolve.cpp, as UE's C++ does, and both engines read them from here.
// UE 5.5's fields come first (the layout ports of UE's pipeline read), then every other
// pipeline's, each from its own header. Adding a pipeline adds one line here.
#define HDRC_PARAM_BLOCK(X) \
  HDRC_UE55_PARAMS(X)       \
  HDRC_OPERATORS_PARAMS(X)  \
  HDRC_UNITY_URP_PARAMS(X) HDRC_PQ_GRADING_PARAMS(X) HDRC_UE58_PARAMS(X)

// The C++ type of a V4A(n) field: n vec4 in double, zero-initialised.
template <size_t N>
using Vec4Array = std::array<std::array<double, 4>, N>;

template <class T>
struct IsVec4Array : std::false_type {};
template <size_t N>
struct IsVec4Array<Vec4Array<N>> : std::true_type {};
template <class T>
inline constexpr bool kIsVec4Array = IsVec4Array<T>::value;

struct ParamBlock {
#define HDRC_X_I(name) int32_t name = 0;
#define HDRC_X_F(name) double name = 0.0;
#define HDRC_X_V4(name) std::array<double, 4> name{0, 0, 0, 0};
#define HDRC_X_M3(name) ref::Mat3 name = ref::Mat3::identity();
// V4A(n): `HDRC_X_V4A(n)` declares the type, and the rescan meets `HDRC_X_V4A_NAME(name)`.
#define HDRC_X_V4A(n) Vec4Array<n> HDRC_X_V4A_NAME
#define HDRC_X_V4A_NAME(name) name{};
#define HDRC_X(type, name, doc) HDRC_X_##type(name)
  HDRC_PARAM_BLOCK(HDRC_X)
#undef HDRC_X
#undef HDRC_X_I
#undef HDRC_X_F
#undef HDRC_X_V4
#undef HDRC_X_M3
#undef HDRC_X_V4A
#undef HDRC_X_V4A_NAME
};

// The kinds of field, as the block declares them: int32_t, double, std::array<double, 4>, Mat3,
// Vec4Array<n> (the element count is the field's type: field_elements).
enum class FieldKind { I, F, V4, M3, V4A };

// The vec4 elements of a V4A field (its declared n); 0 for the other kinds.
template <class T>
constexpr size_t field_elements(const T&) {
  if constexpr (kIsVec4Array<T>)
    return std::tuple_size_v<T>;
  else
    return 0;
}

// Calls f(kind, name, field) for every field of `p` in declaration order (the std430 order), with
// `field` a reference to p's member. The one walk over the block that everything else uses: the
// layout, std430 packing, the generated GLSL and HLSL declarations, params.json both ways and the
// LUT cache's key. `Block` is ParamBlock or const ParamBlock.
template <class Block, class F>
void for_each_param(Block& p, F&& f) {
#define HDRC_KIND_I FieldKind::I
#define HDRC_KIND_F FieldKind::F
#define HDRC_KIND_V4 FieldKind::V4
#define HDRC_KIND_M3 FieldKind::M3
#define HDRC_KIND_V4A(n) FieldKind::V4A
#define HDRC_X(type, name, doc) f(HDRC_KIND_##type, #name, p.name);
  HDRC_PARAM_BLOCK(HDRC_X)
#undef HDRC_X
#undef HDRC_KIND_I
#undef HDRC_KIND_F
#undef HDRC_KIND_V4
#undef HDRC_KIND_M3
#undef HDRC_KIND_V4A
}

// The pipeline whose header declares field `name`: "ue55" (whose fields include what every
// pipeline's shaders read: image size, LUT geometry, aux image sizes), "operators", "unity_urp"; ""
// for no field.
std::string_view param_owner(std::string_view name);
// True when `pipeline`'s cases carry field `name` (params.json): its own fields, and of UE 5.5's
// those it reads (every one for "ue55"; HDRC_<PIPELINE>_SHARED_PARAMS in the pipeline's params
// header for the others), so that an export holds only what applies to its pipeline.
bool param_carried_by(std::string_view name, std::string_view pipeline);

// A field's declaration in the generated shader interface: "int", "float", "vec4"/"float4", a
// matrix as three rows ("vec4 name[3]"/"float4 name[3]") and a V4A field as its `elements` vec4
// ("vec4 name[n]"), ending in ";".
std::string shader_field_decl(FieldKind kind, const char* name, bool hlsl, size_t elements = 0);

// Descriptor bindings of every stage shader (set 0). One layout serves every pass of every stage;
// an engine binds all of them (a 1-texel dummy where a pass has nothing to bind). Documented in
// docs/gpu-interface.md.
inline constexpr uint32_t kBindingParams = 0;  // readonly std430 buffer `P`: the ParamBlock
inline constexpr uint32_t kBindingInput = 1;   // readonly std430 buffer: vec4 in_px[], row-major
inline constexpr uint32_t kBindingOutput = 2;  // writeonly std430 buffer: vec4 out_px[], row-major
inline constexpr uint32_t kBindingLutStore3d = 3;  // writeonly image3D lut_store_3d (formatless):
                                                   // CombineLUTs' volume LUT, N x N x N
inline constexpr uint32_t kBindingLutStore2d = 4;  // writeonly image2D lut_store_2d (formatless):
                                                   // CombineLUTs' unwrapped LUT, N^2 x N
inline constexpr uint32_t kBindingLut3d = 5;       // sampler3D lut_3d: the same volume LUT, linear
                                                   // filtering, clamp-to-edge (the Tonemap pass)
inline constexpr uint32_t kBindingLut2d = 6;       // sampler2D lut_2d: the unwrapped LUT, linear,
                                                   // clamp-to-edge
inline constexpr uint32_t kBindingAux0 = 7;      // readonly buffer vec4 aux0_px[]: bloom (tonemap),
                                                 // the UI layer (ui_composite); P.aux0_width/height
inline constexpr uint32_t kBindingAux1 = 8;      // readonly buffer vec4 aux1_px[]: bloom dirt mask;
                                                 // P.aux1_width/height
inline constexpr uint32_t kBindingScratch = 9;   // read-write buffer vec4 scratch_px[]: data passed
                                                 // between the passes of one stage
inline constexpr uint32_t kBindingUserLut = 10;  // sampler2D user_lut[kUserLutSlots]: the
                                                 // case's user LUTs (.cube) as strips N^2 x N,
                                                 // texel (r + N b, g), RGBA32F or 8-bit UNORM
                                                 // (StageInfo::user_lut_unorm8), linear filtering,
                                                 // clamp-to-edge; P.user_lut_size (a 1-texel
                                                 // dummy in every slot without one)
inline constexpr uint32_t kBindingCount = 11;
inline constexpr uint32_t kUserLutSlots = 4;  // elements of binding kBindingUserLut (UE's
                                              // Textures_1..4)
inline constexpr uint32_t kLocalSizeX = 64;   // compute workgroup size (1-D over pixels/texels)

// Specialisation constant ids (SPIR-V SpecId) of the Tonemap pass (gpu/shaders/lib/
// tonemap_variant.glsl): each flag tells the compiler whether a branch of the pass that depends on
// a uniform-level value can be taken at all in this case, so that code which cannot run is not
// compiled (a software device such as llvmpipe runs both sides of every branch, masked). Each
// is 1 (the default: the branch is compiled and the uniform decides, as without specialisation)
// or 0 (the engine has seen from the case's ParamBlock that the uniform condition is false).
// The engine passes these values to every shader that declares them (VulkanEngine::run).
inline constexpr uint32_t kSpecTonemapFringe = 0;     // P.fringe.w != 0
inline constexpr uint32_t kSpecTonemapSharpen = 1;    // P.sharpen_div6 > 0
inline constexpr uint32_t kSpecTonemapBloom = 2;      // P.aux0_width > 0 && P.aux0_height > 0
inline constexpr uint32_t kSpecTonemapBloomDirt = 3;  // P.aux1_width > 0 && P.aux1_height > 0
inline constexpr uint32_t kSpecTonemapPost = 4;       // P.output_device is 5, 6 or 7
// Not a flag: the value of P.lut_layout itself (the shader's default, -1, reads the uniform).
inline constexpr uint32_t kSpecTonemapLutLayout = 5;
inline constexpr uint32_t kSpecCount = 6;

// The ParamBlock as the std430 bytes the shaders read.
std::vector<uint8_t> pack_std430(const ParamBlock& p);

// The specialisation constants for a block (index = SpecId, kSpecTonemap*): for a flag, 0 where
// the uniform condition it stands for is false as the shader sees the block (the float32 and int32
// values pack_std430 writes), else 1; kSpecTonemapLutLayout is P.lut_layout.
std::array<uint32_t, kSpecCount> specialisation_constants(const ParamBlock& p);

// GLSL text declaring the block, the bindings and the workgroup size.
std::string glsl_param_block();

// Field names and their std430 byte offsets, in declaration order (for tests and docs).
struct FieldLayout {
  std::string name;
  char type;  // 'I', 'F', 'V', 'M' or 'A' (V4A)
  uint32_t offset;
  uint32_t size = 0;  // bytes: 4, 16, 48 or 16 n
};
std::vector<FieldLayout> param_block_layout();

}  // namespace hdrc
