#include "runner/export.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <type_traits>

#include "core/atomic_file.h"
#include "core/cube/cube.h"
#include "core/pipeline.h"
#include "reference/color/ue_matrices.h"
#include "runner/case_loader.h"
#include "runner/diff.h"
#include "runner/json_read.h"
#include "runner/run.h"

namespace hdrc {

using json = nlohmann::ordered_json;
namespace fs = std::filesystem;

namespace {
// JSON has no NaN or Inf, and UE leaves some derived values non-finite (e.g. ACES coefficients
// it never initialises for an out-of-range knot): they travel as "NaN", "Infinity", "-Infinity".
json number(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "Infinity" : "-Infinity";
  return v;
}
json row(const ref::Mat3& m, int r) {
  return json::array({number(m(r, 0)), number(m(r, 1)), number(m(r, 2))});
}
json vec4(const std::array<double, 4>& v) {
  return json::array({number(v[0]), number(v[1]), number(v[2]), number(v[3])});
}
}  // namespace

json params_json(const ParamBlock& p, std::string_view pipeline) {
  json j = json::object();
  for_each_param(p, [&](FieldKind, const char* name, const auto& v) {
    if (!param_carried_by(name, pipeline)) return;
    using T = std::decay_t<decltype(v)>;
    if constexpr (std::is_same_v<T, int32_t>)
      j[name] = v;
    else if constexpr (std::is_same_v<T, double>)
      j[name] = number(v);
    else if constexpr (std::is_same_v<T, std::array<double, 4>>)
      j[name] = vec4(v);
    else if constexpr (kIsVec4Array<T>) {
      json a = json::array();
      for (const auto& e : v) a.push_back(vec4(e));
      j[name] = std::move(a);
    } else
      j[name] = json::array({row(v, 0), row(v, 1), row(v, 2)});
  });
  return j;
}

namespace {

// A number, or one of the strings "NaN", "Infinity", "-Infinity".
bool as_number(const json& v, double* out) {
  if (v.is_number()) {
    *out = v.get<double>();
    return true;
  }
  if (!v.is_string()) return false;
  const std::string s = v.get<std::string>();
  if (s == "NaN")
    *out = std::numeric_limits<double>::quiet_NaN();
  else if (s == "Infinity")
    *out = std::numeric_limits<double>::infinity();
  else if (s == "-Infinity")
    *out = -std::numeric_limits<double>::infinity();
  else
    return false;
  return true;
}

Status read_number(const json& j, const std::string& key, const std::string& file,
                   const std::string& pointer, double* out) {
  const std::string at = pointer + "/" + key;
  if (!j.contains(key))
    return Error{file, at, "missing parameter " + key, "every ParamBlock field"};
  if (!as_number(j[key], out))
    return Error{file, at, key + " must be a number, got " + j[key].dump(),
                 "a number, \"NaN\", \"Infinity\" or \"-Infinity\""};
  return {};
}

Status read_array(const json& j, const std::string& file, const std::string& at, size_t n,
                  double* out) {
  if (!j.is_array() || j.size() != n)
    return Error{file, at,
                 "expected an array of " + std::to_string(n) + " numbers, got " + j.dump(), ""};
  for (size_t i = 0; i < n; ++i)
    if (!as_number(j[i], &out[i]))
      return Error{file, at + "/" + std::to_string(i), "expected a number, got " + j[i].dump(),
                   "a number, \"NaN\", \"Infinity\" or \"-Infinity\""};
  return {};
}

}  // namespace

Result<ParamBlock> params_from_json(const json& j, const std::string& file,
                                    const std::string& pointer, std::string_view pipeline) {
  if (!j.is_object()) return Error{file, pointer, "expected an object of parameters", ""};
  ParamBlock p;
  Status status;  // the first error; the fields after it are not read
  for_each_param(p, [&](FieldKind, const char* name, auto& field) {
    if (!status || !param_carried_by(name, pipeline)) return;
    using T = std::decay_t<decltype(field)>;
    const std::string at = pointer + "/" + name;
    if constexpr (std::is_same_v<T, int32_t> || std::is_same_v<T, double>) {
      double v = 0;
      status = read_number(j, name, file, pointer, &v);
      if constexpr (std::is_same_v<T, int32_t>) {
        // An integer field: a non-integral or out-of-range value has no int32 (the cast would
        // be undefined behaviour), so it is refused.
        if (status && !(v >= -2147483648.0 && v <= 2147483647.0 && v == std::trunc(v))) {
          status = Error{file, at, "expected an integer, got " + j[name].dump(),
                         "an integer in [-2147483648, 2147483647]"};
          return;
        }
      }
      if (status) field = static_cast<T>(v);
    } else if (!j.contains(name)) {
      status = Error{file, at, std::string("missing parameter ") + name, ""};
    } else if constexpr (std::is_same_v<T, std::array<double, 4>>) {
      status = read_array(j[name], file, at, 4, field.data());
    } else if constexpr (kIsVec4Array<T>) {
      // A table: exactly its declared number of vec4 (the type's n), nothing longer is read.
      const size_t n = field.size();
      if (!j[name].is_array() || j[name].size() != n) {
        status = Error{file, at,
                       "expected an array of " + std::to_string(n) + " vec4 (" + name + " is V4A(" +
                           std::to_string(n) + ")), got " +
                           (j[name].is_array() ? std::to_string(j[name].size()) + " elements"
                                               : std::string(j[name].type_name())),
                       "an array of exactly " + std::to_string(n) + " arrays of 4 numbers"};
        return;
      }
      for (size_t e = 0; e < n && status; ++e)
        status = read_array(j[name][e], file, at + "/" + std::to_string(e), 4, field[e].data());
    } else {
      if (!j[name].is_array() || j[name].size() != 3) {
        status = Error{file, at, "expected 3 rows of 3 numbers", ""};
        return;
      }
      for (int r = 0; r < 3 && status; ++r)
        status = read_array(j[name][r], file, at + "/" + std::to_string(r), 3, &field.m[r * 3]);
    }
  });
  if (!status) return status.error();
  return p;
}

namespace {

struct AuxImage {
  const char* name;
  const Image* image;
};

std::vector<AuxImage> images_of(const ResolvedCase& rc) {
  std::vector<AuxImage> out{{"input", &rc.input}};
  if (rc.ui.width > 0) out.push_back({"ui", &rc.ui});
  if (rc.bloom.width > 0) out.push_back({"bloom", &rc.bloom});
  if (rc.bloom_dirt.width > 0) out.push_back({"bloom_dirt", &rc.bloom_dirt});
  // The user-LUT slots: user_lut, user_lut_1, user_lut_2, user_lut_3 (kBindingUserLut's elements).
  static const char* const kUserLutNames[kUserLutSlots] = {"user_lut", "user_lut_1", "user_lut_2",
                                                           "user_lut_3"};
  for (size_t s = 0; s < kUserLutSlots; ++s)
    if (rc.user_luts[s].width > 0) out.push_back({kUserLutNames[s], &rc.user_luts[s]});
  return out;
}

json explicit_cvars(const Case& c) {
  json j = json::object();
  for (const auto& [k, v] : c.cvars.explicit_values()) j[k] = v;
  return j;
}

// Settings that say how the LUT is stored, not how colours are graded (params.json "storage").
bool is_storage_setting(const std::string& name) {
  return name == "LUTFormat" || name == "LUTLayout";
}

json explicit_settings(const Case& c) {
  json j = json::object();
  for (const auto& [k, v] : c.settings.explicit_values()) {
    if (is_storage_setting(k)) continue;
    const SettingInfo* info = find_setting(k);
    if (info && info->components == 1)
      j[k] = v[0];
    else
      j[k] = v;
  }
  return j;
}

const char* device_name(int d) {
  // EDisplayOutputFormat's names (the OutputDevice table, docs/ue55-decisions.md D10).
  static const char* names[] = {"SDR_sRGB",
                                "SDR_Rec709",
                                "SDR_ExplicitGammaMapping",
                                "HDR_ACES_1000nit_ST2084",
                                "HDR_ACES_2000nit_ST2084",
                                "HDR_ACES_1000nit_ScRGB",
                                "HDR_ACES_2000nit_ScRGB",
                                "HDR_LinearEXR",
                                "HDR_LinearNoToneCurve",
                                "HDR_LinearWithToneCurve"};
  return d >= 0 && d <= 9 ? names[d] : "?";
}

bool aces_device(int d) {
  return d >= 3 && d <= 6;
}

// The formula that turns the stage's result into the stored value (its name, to look up in
// docs/candidate-*.md and the spec).
std::string formula_name(StageId stage, int device) {
  switch (stage) {
    case StageId::kShaper:
      return device >= 3 ? "ST2084ToLinear(LinearToST2084(x * 100)) / 100 (PQ shaper round trip)"
                         : "LogToLin(LinToLog(x + LogToLin(0))) - LogToLin(0) (log shaper round "
                           "trip)";
    case StageId::kLinearDevice:
      return device == 7 ? "ST2084ToLinear(LinearToST2084(AP1_2_Output * ToAP1 * x)) (nits)"
                         : "x (HDR_LinearNoToneCurve: working colour space as is)";
    case StageId::kCombineLuts:
      return "OutDeviceColor / 1.05, rounded to the LUT format";
    case StageId::kUiComposite:
      return (device == 5 || device == 6) ? "scRGB (Rec.709 linear / 80 nits)"
                                          : "LinearToST2084 (SMPTE ST 2084 inverse EOTF)";
    case StageId::kDither:
      return "x + (triangular grain) * BackbufferQuantizationDithering";
    case StageId::kTonemap:
    case StageId::kVisualizeHdr:
    case StageId::kOther:  // another pipeline's stage: case_export_json names its sources
      break;
  }
  switch (device) {
    case 0:
      return "LinearToSrgb (sRGB inverse EOTF)";
    case 1:
      return "LinearTo709Branchless (Rec.709 OETF)";
    case 2:
      return "pow(x, InverseGamma.z) (explicit display gamma)";
    case 3:
    case 4:
      return "LinearToST2084 (SMPTE ST 2084 inverse EOTF) of ACES output nits";
    case 5:
    case 6:
      return "ST2084ToScRGB (scRGB: Rec.709 linear, 1.0 = 80 nits)";
    case 7:
      return "ST2084ToLinear(LinearToST2084(nits)): nits";
    case 8:
      return "x (scene-linear working colour space)";
    default:
      return "AP1_2_Output * ToAP1 * FilmColorNoGamma (scene-linear, tone curve applied)";
  }
}

std::string output_value(StageId stage) {
  switch (stage) {
    case StageId::kShaper:
      return "each input colour after the LUT shaper's encode, the sampler's clamp to [0, 1] and "
             "CombineLUTs' decode (scene-linear, working colour space)";
    case StageId::kLinearDevice:
      return "each input colour through the shaper round trip, then the device 7/8 encode and the "
             "tonemapper's decode";
    case StageId::kCombineLuts:
      return "the LUT CombineLUTs bakes: the stored texel of each lattice point (r, g, b)";
    case StageId::kTonemap:
      return "the Tonemap pass's colour for each input pixel before the dither (steps 1-9)";
    case StageId::kDither:
      return "each input colour plus the quantisation dither";
    case StageId::kUiComposite:
      return "the back buffer (the input) with the UI layer (ui.exr) composited over it";
    case StageId::kVisualizeHdr:
      return "VisualizeHDR's image of the input scene (panel, histogram, meters)";
    case StageId::kOther:  // another pipeline's stage: case_export_json uses its description
      break;
  }
  return "";
}

std::string output_alpha(StageId stage) {
  switch (stage) {
    case StageId::kCombineLuts:
      return "0 (CombineLUTs writes alpha 0)";
    case StageId::kTonemap:
      return "OutLuminance = dot(OutDevice, (0.299, 0.587, 0.114))";
    default:
      return "what the stage writes (judged only for NaN/Inf consistency)";
  }
}

const char* lut_format_name(int f) {
  static const char* names[] = {"A2B10G10R10 UNORM", "RGBA16F", "RGBA32F", "RGBA8 UNORM"};
  return f >= 0 && f <= 3 ? names[f] : "?";
}

json quantisation(StageId stage, const ParamBlock& p) {
  if (stage != StageId::kCombineLuts)
    return {{"name", "none"}, {"rule", "float32 as computed; no rounding"}};
  switch (p.lut_format) {
    case 0:
      return {{"name", lut_format_name(0)},
              {"rule", "round(saturate(v) * 1023) / 1023 per channel; NaN stores 0 (D3D)"}};
    case 1:
      return {{"name", lut_format_name(1)},
              {"rule", "v rounded to the nearest IEEE half (10-bit mantissa)"}};
    default:
      return {{"name", lut_format_name(2)}, {"rule", "v rounded to float32"}};
  }
}

json layout(StageId stage, const ResolvedCase& rc) {
  if (stage != StageId::kCombineLuts)
    return {
        {"name", "pixels"},
        {"rule", "the input's pixels, row-major, (0, 0) top-left: output (x, y) is input (x, y)"}};
  const int n = rc.params.lut_size;
  return {{"name", "lut_unwrapped"},
          {"lut_size", n},
          {"rule", "an N^2 x N image (N = " + std::to_string(n) +
                       "): lattice point (r, g, b) at pixel (r + N * b, g); input.exr holds each "
                       "point's lattice coordinate"}};
}

// What a renderer needs that the raw cvars do not say directly (docs/candidate-protocol.md).
json resolved_values(const ResolvedCase& rc, const OutputEncoding& enc) {
  const Case& c = rc.spec;
  const ParamBlock& p = rc.params;
  const int d = p.output_device;
  const int requested = c.cvars.get_int("r.HDR.Display.OutputDevice");
  const bool hdr = c.cvars.get_int("r.HDR.EnableHDROutput") != 0;
  const double cvar_max = c.cvars.get("r.HDR.Display.MaxLuminance");
  std::string lum_source = "r.HDR.Display.MaxLuminance = " + format_number(cvar_max);
  if (cvar_max == 0 && hdr)
    lum_source =
        "r.HDR.Display.MaxLuminance is 0 (unset) with HDR output on: UE falls back to "
        "1000 nits (HDRSettingChangedSinkCallback), whatever the device's name says";
  else if (cvar_max == 0)
    lum_source = "r.HDR.Display.MaxLuminance is 0 with HDR output off: left at 0";
  json tone_scale = nullptr;
  if (aces_device(d)) {
    // ConfigureACESTonemapParams' inputs, as float32 (RenderCore.cpp), in nits.
    const float min_nits =
        std::pow(10.0f, static_cast<float>(c.cvars.get("r.HDR.Display.MinLuminanceLog10")));
    tone_scale = {
        {"min_nits", number(min_nits)},
        {"mid_nits", number(static_cast<float>(c.cvars.get("r.HDR.Display.MidLuminance")))},
        {"max_nits", number(static_cast<float>(p.output_max_luminance))},
        {"from",
         "10^r.HDR.Display.MinLuminanceLog10, r.HDR.Display.MidLuminance, the effective "
         "max luminance (float32, as ConfigureACESTonemapParams takes them)"}};
  }
  std::string device_note = "r.HDR.Display.OutputDevice = " + std::to_string(requested);
  if (requested != d)
    device_note += ", resolved to " + std::to_string(d) +
                   " by r.TonemapperGamma (GetTonemapperOutputDeviceParameters)";
  return {
      {"output_device", {{"value", d}, {"name", device_name(d)}, {"from", device_note}}},
      {"output_gamut",
       {{"value", p.output_gamut}, {"name", ref::output_gamut_name(p.output_gamut)}}},
      {"max_luminance_nits", {{"value", number(p.output_max_luminance)}, {"from", lum_source}}},
      {"aces_tone_scale", tone_scale},
      {"shaper", d >= 3 ? "PQ (LinearToST2084 of x * 100)" : "log (LinToLog)"},
      {"output_encoding", {{"name", enc.describe()}, {"formula", formula_name(c.stage->id, d)}}},
  };
}

json storage_json(const ResolvedCase& rc) {
  const ParamBlock& p = rc.params;
  const auto& passes = rc.spec.stage->passes;
  const bool uses_lut = std::any_of(passes.begin(), passes.end(), [](const StagePass& pass) {
    return pass.domain == Dispatch::kLutTexels;
  });
  const std::string pipeline(rc.spec.stage->pipeline);
  return {{"lut_size", p.lut_size},
          {"lut_format", {{"value", p.lut_format}, {"name", lut_format_name(p.lut_format)}}},
          {"lut_layout",
           {{"value", p.lut_layout},
            {"name", p.lut_layout == 0 ? "volume N^3" : "2-D unwrapped N^2 x N"}}},
          {"used_by_stage", uses_lut},
          {"from", pipeline == "ue55" ? "r.LUT.Size, the LUTFormat and LUTLayout settings"
                                      : "the settings of pipeline " + pipeline +
                                            " (hdrconform cvars --pipeline " + pipeline + ")"}};
}

// The user LUT a case names (null when none): the .cube written beside the case, the strip texture
// the engines bind (images/user_lut) and how it is sampled.
json user_lut_json(const ResolvedCase& rc) {
  const UserLut* lut = rc.spec.lut.get();
  if (!lut && !rc.has_user_lut()) return nullptr;
  const ParamBlock& p = rc.params;
  json textures = json::array();
  for (size_t s = 0; s < kUserLutSlots; ++s)
    if (rc.user_luts[s].width > 0)
      textures.push_back(s == 0 ? std::string("user_lut.exr")
                                : "user_lut_" + std::to_string(s) + ".exr");
  const bool unorm8 = rc.spec.stage && rc.spec.stage->user_lut_unorm8;
  return {{"cube", lut ? json("user_lut.cube") : json(nullptr)},
          {"source", lut ? json(lut->name) : json(nullptr)},
          {"title", lut ? json(lut->title) : json(nullptr)},
          {"textures", textures},
          {"slots", "binding " + std::to_string(kBindingUserLut) + " is sampler2D user_lut[" +
                        std::to_string(kUserLutSlots) +
                        "]: textures[i] in element i, a 1-texel dummy in the rest"},
          {"size", p.user_lut_size},
          {"domain_min",
           {p.user_lut_domain_min[0], p.user_lut_domain_min[1], p.user_lut_domain_min[2]}},
          {"domain_max",
           {p.user_lut_domain_max[0], p.user_lut_domain_max[1], p.user_lut_domain_max[2]}},
          {"texture", "user_lut.exr"},
          {"layout", "strip N^2 x N: .cube row (r, g, b) at texel (r + N b, g), alpha 1"},
          {"binding", kBindingUserLut},
          {"format", unorm8 ? "VK_FORMAT_R32G32B32A32_SFLOAT holding 8-bit UNORM values k/255 "
                              "(rounded once by the host; the texels of UE's BGRA8 texture)"
                            : "VK_FORMAT_R32G32B32A32_SFLOAT"},
          {"sampler", "linear filtering, clamp-to-edge, normalised coordinates"}};
}

}  // namespace

json case_export_json(const ResolvedCase& rc) {
  const Case& c = rc.spec;
  json passes = json::array();
  for (const StagePass& p : c.stage->passes) passes.push_back(std::string(p.shader));
  json images = json::object();
  for (const AuxImage& a : images_of(rc))
    images[a.name] = {{"file", std::string(a.name) + ".exr"},
                      {"width", a.image->width},
                      {"height", a.image->height}};
  const OutputEncoding enc = output_encoding(*c.stage, rc.params);
  const StageId stage = c.stage->id;
  const std::string pipeline(c.stage->pipeline);
  json doc = {
      {"format_version", kExportFormatVersion},
      {"format", "hdrconform case export " + std::to_string(kExportFormatVersion)},
      {"schema", "runner/params.schema.json"},
      {"id", c.id},
      {"case_file", c.file_in_cases},
      {"pipeline", std::string(c.stage->pipeline)},
      {"stage", std::string(c.stage->name)},
      {"passes", passes},
      {"cvars", explicit_cvars(c)},
      {"settings", explicit_settings(c)},
      {"storage", param_carried_by("lut_size", pipeline) ? storage_json(rc) : json(nullptr)},
      {"resolved", pipeline == "ue55" ? resolved_values(rc, enc) : json(nullptr)},
      {"images", images},
      {"output",
       {{"width", rc.input.width},
        {"height", rc.input.height},
        {"channel_count", 4},
        {"channels", "RGBA"},
        {"format", "OpenEXR, 32-bit float, channels R G B A (RGB alone is accepted)"},
        {"value",
         stage == StageId::kOther ? std::string(c.stage->description) : output_value(stage)},
        {"alpha", output_alpha(stage)},
        {"encoding", enc.describe()},
        // A stage's own specification section first (every stage of a pipeline other than
        // UE 5.5 names a docs page, also one of the UE family's stage ids: ue58_ui_composite).
        {"formula", !c.stage->output_spec.empty() ? std::string(c.stage->output_spec)
                    : stage != StageId::kOther    ? formula_name(stage, rc.params.output_device)
                                                  : std::string(pipeline_of(*c.stage).sources)},
        {"quantisation", quantisation(stage, rc.params)},
        {"layout", layout(stage, rc)}}},
      {"user_lut", user_lut_json(rc)},
      {"degenerate", rc.degenerate.empty() ? json(nullptr) : json(rc.degenerate)},
      {"params", params_json(rc.params, c.stage->pipeline)},
  };
  return doc;
}

Status export_case(const ResolvedCase& rc, const std::string& dir) {
  for (const AuxImage& a : images_of(rc))
    if (Status st = write_exr(dir + "/" + a.name + ".exr", *a.image); !st) return st;
  if (const UserLut* lut = rc.spec.lut.get()) {
    cube::CubeLut c;
    if (!lut->title.empty()) c.title = lut->title;
    c.size_3d = lut->size;
    c.domain_min_3d = lut->domain_min;
    c.domain_max_3d = lut->domain_max;
    c.table_3d = lut->table;
    auto text = cube::write_cube(c);
    if (!text) return text.error();
    if (Status st = write_file_atomic(dir + "/user_lut.cube", *text); !st) return st;
  }
  return write_file_atomic(dir + "/params.json", dump_json(case_export_json(rc), 2) + "\n");
}

Result<ResolvedCase> load_exported_case(const std::string& params_path) {
  auto parsed = read_json_file<json>(params_path, "params file");
  if (!parsed) return parsed.error();
  json doc = std::move(*parsed);
  ResolvedCase rc;
  if (!doc.is_object() || !doc.contains("stage") || !doc["stage"].is_string() ||
      !find_stage(doc["stage"].get<std::string>()))
    return Error{params_path, "/stage", "missing or unknown stage", stage_names()};
  rc.spec.stage = find_stage(doc["stage"].get<std::string>());
  if (doc.contains("id") && doc["id"].is_string()) rc.spec.id = doc["id"].get<std::string>();
  if (!doc.contains("params")) return Error{params_path, "/params", "missing params", ""};
  auto params = params_from_json(doc["params"], params_path, "/params", rc.spec.stage->pipeline);
  if (!params) return params.error();
  rc.params = *params;
  const fs::path dir = fs::path(params_path).parent_path();
  if (!doc.contains("images") || !doc["images"].is_object())
    return Error{params_path, "/images", "missing images", ""};
  for (auto it = doc["images"].begin(); it != doc["images"].end(); ++it) {
    const std::string& name = it.key();
    Image* target = name == "input"        ? &rc.input
                    : name == "ui"         ? &rc.ui
                    : name == "bloom"      ? &rc.bloom
                    : name == "bloom_dirt" ? &rc.bloom_dirt
                    : name == "user_lut"   ? &rc.user_luts[0]
                    : name == "user_lut_1" ? &rc.user_luts[1]
                    : name == "user_lut_2" ? &rc.user_luts[2]
                    : name == "user_lut_3" ? &rc.user_luts[3]
                                           : nullptr;
    if (!target)
      return Error{params_path, "/images/" + name, "unknown image '" + name + "'",
                   "input, ui, bloom, bloom_dirt, user_lut, user_lut_1, user_lut_2, user_lut_3"};
    if (!it.value().contains("file") || !it.value()["file"].is_string())
      return Error{params_path, "/images/" + name + "/file", "missing file name", ""};
    auto img = read_image((dir / it.value()["file"].get<std::string>()).string());
    if (!img) return img.error();
    *target = std::move(*img);
  }
  if (doc.contains("degenerate") && doc["degenerate"].is_string())
    rc.degenerate = doc["degenerate"].get<std::string>();
  return rc;
}

ExportSummary export_cases(const std::vector<Case>& cases, const std::string& out_dir) {
  ExportSummary summary;
  json list = json::array();
  for (const Case& c : cases) {
    auto rc = resolve_case(c);
    if (!rc) {
      summary.errors.push_back(rc.error());
      continue;
    }
    const std::string rel = case_image_dir(c.id);
    if (Status st = export_case(*rc, out_dir + "/" + rel); !st) {
      summary.errors.push_back(st.error());
      continue;
    }
    ++summary.cases;
    summary.degenerate += !rc->degenerate.empty();
    list.push_back({{"id", c.id},
                    {"pipeline", std::string(c.stage->pipeline)},
                    {"stage", std::string(c.stage->name)},
                    {"dir", rel},
                    {"degenerate", !rc->degenerate.empty()}});
  }
  const json manifest = {
      {"tool", "hdrconform"},
      {"format_version", kExportFormatVersion},
      {"format", "hdrconform case export " + std::to_string(kExportFormatVersion)},
      {"cases", list}};
  if (Status st = write_file_atomic(out_dir + "/manifest.json", dump_json(manifest, 2) + "\n"); !st)
    summary.errors.push_back(st.error());
  return summary;
}

}  // namespace hdrc
