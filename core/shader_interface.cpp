#include "core/shader_interface.h"

#include <cstring>
#include <sstream>
#include <type_traits>

namespace hdrc {

std::string_view param_owner(std::string_view name) {
#define HDRC_NAME(type, field, doc) #field,
  static const std::vector<std::pair<std::string_view, std::vector<std::string_view>>> owners = {
      {"ue55", {HDRC_UE55_PARAMS(HDRC_NAME)}},  // with HDRC_USER_LUT_PARAMS
      {"operators", {HDRC_OPERATORS_PARAMS(HDRC_NAME)}},
      {"unity_urp", {HDRC_UNITY_URP_PARAMS(HDRC_NAME)}},
      {"pq_grading", {HDRC_PQ_GRADING_PARAMS(HDRC_NAME)}},
      {"ue58", {HDRC_UE58_PARAMS(HDRC_NAME)}},
  };
#undef HDRC_NAME
  for (const auto& [owner, fields] : owners)
    for (std::string_view f : fields)
      if (f == name) return owner;
  return "";
}

bool param_carried_by(std::string_view name, std::string_view pipeline) {
#define HDRC_SHARED_NAME(field) #field,
  static const std::vector<std::pair<std::string_view, std::vector<std::string_view>>> shared = {
      {"operators", {HDRC_OPERATORS_SHARED_PARAMS(HDRC_SHARED_NAME)}},
      {"unity_urp", {HDRC_UNITY_URP_SHARED_PARAMS(HDRC_SHARED_NAME)}},
      {"pq_grading", {HDRC_PQ_GRADING_SHARED_PARAMS(HDRC_SHARED_NAME)}},
      {"ue58", {HDRC_UE58_SHARED_PARAMS(HDRC_SHARED_NAME)}},
  };
#undef HDRC_SHARED_NAME
  const std::string_view owner = param_owner(name);
  if (owner == pipeline) return true;
  if (owner != "ue55") return false;
  if (pipeline == "ue55") return true;
  for (const auto& [p, fields] : shared)
    if (p == pipeline)
      for (std::string_view f : fields)
        if (f == name) return true;
  return false;
}

namespace {
// std430 rules for the field kinds: scalars align to 4 bytes; a vec4 and an array of vec4 (a
// matrix's rows, a V4A table) align to 16, with a 16-byte stride.
uint32_t align_up(uint32_t v, uint32_t a) {
  return (v + a - 1) / a * a;
}

std::vector<FieldLayout> compute_layout() {
  std::vector<FieldLayout> out;
  uint32_t offset = 0;
  const ParamBlock block;
  for_each_param(block, [&](FieldKind kind, const char* name, const auto& v) {
    char type = 'I';
    uint32_t size = 4;
    switch (kind) {
      case FieldKind::I:
        break;
      case FieldKind::F:
        type = 'F';
        break;
      case FieldKind::V4:
        type = 'V';
        size = 16;
        break;
      case FieldKind::M3:
        type = 'M';
        size = 48;
        break;
      case FieldKind::V4A:
        type = 'A';
        size = static_cast<uint32_t>(16 * field_elements(v));
        break;
    }
    const uint32_t align = (type == 'I' || type == 'F') ? 4 : 16;
    offset = align_up(offset, align);
    out.push_back({name, type, offset, size});
    offset += size;
  });
  return out;
}

uint32_t block_size(const std::vector<FieldLayout>& layout) {
  const auto& last = layout.back();
  return align_up(last.offset + last.size, 16);
}
}  // namespace

std::vector<FieldLayout> param_block_layout() {
  static const std::vector<FieldLayout> layout = compute_layout();
  return layout;
}

std::vector<uint8_t> pack_std430(const ParamBlock& p) {
  const auto layout = param_block_layout();
  std::vector<uint8_t> bytes(block_size(layout), 0);
  size_t i = 0;
  auto put_float = [&](uint32_t at, double v) {
    const float f = static_cast<float>(v);
    std::memcpy(&bytes[at], &f, 4);
  };
  for_each_param(p, [&](FieldKind, const char*, const auto& v) {
    using T = std::decay_t<decltype(v)>;
    const uint32_t base = layout[i++].offset;
    if constexpr (std::is_same_v<T, int32_t>) {
      std::memcpy(&bytes[base], &v, 4);
    } else if constexpr (std::is_same_v<T, double>) {
      put_float(base, v);
    } else if constexpr (std::is_same_v<T, std::array<double, 4>>) {
      for (int c = 0; c < 4; ++c) put_float(base + c * 4, v[c]);
    } else if constexpr (kIsVec4Array<T>) {
      for (size_t e = 0; e < v.size(); ++e)
        for (int c = 0; c < 4; ++c)
          put_float(base + static_cast<uint32_t>(e * 16 + c * 4), v[e][c]);
    } else {
      static_assert(std::is_same_v<T, ref::Mat3>);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) put_float(base + r * 16 + c * 4, v(r, c));
    }
  });
  return bytes;
}

std::string shader_field_decl(FieldKind kind, const char* name, bool hlsl, size_t elements) {
  const std::string n = name;
  switch (kind) {
    case FieldKind::I:
      return "int " + n + ";";
    case FieldKind::F:
      return "float " + n + ";";
    case FieldKind::V4:
      return (hlsl ? "float4 " : "vec4 ") + n + ";";
    case FieldKind::M3:
      return (hlsl ? "float4 " : "vec4 ") + n + "[3];";
    case FieldKind::V4A:
      return (hlsl ? "float4 " : "vec4 ") + n + "[" + std::to_string(elements) + "];";
  }
  return "";
}

std::array<uint32_t, kSpecCount> specialisation_constants(const ParamBlock& p) {
  std::array<uint32_t, kSpecCount> v{};
  v[kSpecTonemapFringe] = static_cast<float>(p.fringe[3]) != 0.0f;
  v[kSpecTonemapSharpen] = static_cast<float>(p.sharpen_div6) > 0.0f;
  v[kSpecTonemapBloom] = p.aux0_width > 0 && p.aux0_height > 0;
  v[kSpecTonemapBloomDirt] = p.aux1_width > 0 && p.aux1_height > 0;
  v[kSpecTonemapPost] = p.output_device == 5 || p.output_device == 6 || p.output_device == 7;
  v[kSpecTonemapLutLayout] = static_cast<uint32_t>(p.lut_layout);
  return v;
}

std::string glsl_param_block() {
  std::ostringstream s;
  s << "// Generated by hdrconform from core/shader_interface.h; do not edit.\n";
  s << "#define HDRC_BINDING_PARAMS " << kBindingParams << "\n";
  s << "#define HDRC_BINDING_INPUT " << kBindingInput << "\n";
  s << "#define HDRC_BINDING_OUTPUT " << kBindingOutput << "\n";
  s << "#define HDRC_LOCAL_SIZE_X " << kLocalSizeX << "\n";
  s << "#define HDRC_SPEC_TONEMAP_FRINGE " << kSpecTonemapFringe << "\n";
  s << "#define HDRC_SPEC_TONEMAP_SHARPEN " << kSpecTonemapSharpen << "\n";
  s << "#define HDRC_SPEC_TONEMAP_BLOOM " << kSpecTonemapBloom << "\n";
  s << "#define HDRC_SPEC_TONEMAP_BLOOM_DIRT " << kSpecTonemapBloomDirt << "\n";
  s << "#define HDRC_SPEC_TONEMAP_POST " << kSpecTonemapPost << "\n";
  s << "#define HDRC_SPEC_TONEMAP_LUT_LAYOUT " << kSpecTonemapLutLayout << "\n";
  s << "layout(std430, set = 0, binding = HDRC_BINDING_PARAMS) readonly buffer HdrcParams {\n";
  const ParamBlock block;
  for_each_param(block, [&](FieldKind kind, const char* name, const auto& v) {
    s << "  " << shader_field_decl(kind, name, false, field_elements(v)) << "\n";
  });
  s << "} P;\n";
  s << "layout(std430, set = 0, binding = HDRC_BINDING_INPUT) readonly buffer HdrcInput "
       "{ vec4 in_px[]; };\n";
  s << "layout(std430, set = 0, binding = HDRC_BINDING_OUTPUT) writeonly buffer HdrcOutput "
       "{ vec4 out_px[]; };\n";
  s << "#define HDRC_BINDING_LUT_STORE_3D " << kBindingLutStore3d << "\n";
  s << "#define HDRC_BINDING_LUT_STORE_2D " << kBindingLutStore2d << "\n";
  s << "#define HDRC_BINDING_LUT_3D " << kBindingLut3d << "\n";
  s << "#define HDRC_BINDING_LUT_2D " << kBindingLut2d << "\n";
  s << "#define HDRC_BINDING_AUX0 " << kBindingAux0 << "\n";
  s << "#define HDRC_BINDING_AUX1 " << kBindingAux1 << "\n";
  s << "#define HDRC_BINDING_SCRATCH " << kBindingScratch << "\n";
  s << "#define HDRC_BINDING_USER_LUT " << kBindingUserLut << "\n";
  s << "#define HDRC_USER_LUT_SLOTS " << kUserLutSlots << "\n";
  s << "layout(set = 0, binding = HDRC_BINDING_LUT_STORE_3D) writeonly uniform image3D "
       "lut_store_3d;\n";
  s << "layout(set = 0, binding = HDRC_BINDING_LUT_STORE_2D) writeonly uniform image2D "
       "lut_store_2d;\n";
  s << "layout(set = 0, binding = HDRC_BINDING_LUT_3D) uniform sampler3D lut_3d;\n";
  s << "layout(set = 0, binding = HDRC_BINDING_LUT_2D) uniform sampler2D lut_2d;\n";
  s << "layout(set = 0, binding = HDRC_BINDING_USER_LUT) uniform sampler2D "
       "user_lut[HDRC_USER_LUT_SLOTS];\n";
  s << "layout(std430, set = 0, binding = HDRC_BINDING_AUX0) readonly buffer HdrcAux0 "
       "{ vec4 aux0_px[]; };\n";
  s << "layout(std430, set = 0, binding = HDRC_BINDING_AUX1) readonly buffer HdrcAux1 "
       "{ vec4 aux1_px[]; };\n";
  s << "layout(std430, set = 0, binding = HDRC_BINDING_SCRATCH) buffer HdrcScratch "
       "{ vec4 scratch_px[]; };\n";
  return s.str();
}

}  // namespace hdrc
