#include "runner/export.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/atomic_file.h"
#include "runner/case_loader.h"
#include "runner/diff.h"
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

json params_json(const ParamBlock& p) {
  json j = json::object();
#define HDRC_J_I(name) j[#name] = p.name;
#define HDRC_J_F(name) j[#name] = number(p.name);
#define HDRC_J_V4(name) j[#name] = vec4(p.name);
#define HDRC_J_M3(name) j[#name] = json::array({row(p.name, 0), row(p.name, 1), row(p.name, 2)});
#define HDRC_X(type, name, doc) HDRC_J_##type(name)
  HDRC_PARAM_BLOCK(HDRC_X)
#undef HDRC_X
#undef HDRC_J_I
#undef HDRC_J_F
#undef HDRC_J_V4
#undef HDRC_J_M3
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
                                    const std::string& pointer) {
  if (!j.is_object()) return Error{file, pointer, "expected an object of parameters", ""};
  ParamBlock p;
  double v = 0;
#define HDRC_R_I(name)                                                              \
  if (Status st = read_number(j, #name, file, pointer, &v); !st) return st.error(); \
  p.name = static_cast<int32_t>(v);
#define HDRC_R_F(name)                                                              \
  if (Status st = read_number(j, #name, file, pointer, &v); !st) return st.error(); \
  p.name = v;
#define HDRC_R_V4(name)                                                                            \
  if (!j.contains(#name)) return Error{file, pointer + "/" #name, "missing parameter " #name, ""}; \
  if (Status st = read_array(j[#name], file, pointer + "/" #name, 4, p.name.data()); !st)          \
    return st.error();
#define HDRC_R_M3(name)                                                                            \
  if (!j.contains(#name)) return Error{file, pointer + "/" #name, "missing parameter " #name, ""}; \
  if (!j[#name].is_array() || j[#name].size() != 3)                                                \
    return Error{file, pointer + "/" #name, "expected 3 rows of 3 numbers", ""};                   \
  for (int r = 0; r < 3; ++r)                                                                      \
    if (Status st = read_array(j[#name][r], file, pointer + "/" #name "/" + std::to_string(r), 3,  \
                               &p.name.m[r * 3]);                                                  \
        !st)                                                                                       \
      return st.error();
#define HDRC_X(type, name, doc) HDRC_R_##type(name)
  HDRC_PARAM_BLOCK(HDRC_X)
#undef HDRC_X
#undef HDRC_R_I
#undef HDRC_R_F
#undef HDRC_R_V4
#undef HDRC_R_M3
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
  return out;
}

json explicit_cvars(const Case& c) {
  json j = json::object();
  for (const auto& [k, v] : c.cvars.explicit_values()) j[k] = v;
  return j;
}

json explicit_settings(const Case& c) {
  json j = json::object();
  for (const auto& [k, v] : c.settings.explicit_values()) {
    const SettingInfo* info = find_setting(k);
    if (info && info->components == 1)
      j[k] = v[0];
    else
      j[k] = v;
  }
  return j;
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
  const OutputEncoding enc = OutputEncoding::of(c.stage->id, rc.params);
  json doc = {
      {"format", "hdrconform case export 1"},
      {"id", c.id},
      {"case_file", c.file},
      {"stage", std::string(c.stage->name)},
      {"passes", passes},
      {"cvars", explicit_cvars(c)},
      {"settings", explicit_settings(c)},
      {"images", images},
      {"output",
       {{"width", rc.input.width},
        {"height", rc.input.height},
        {"channels", "RGBA"},
        {"format", "OpenEXR, 32-bit float, channels R G B A"},
        {"encoding", enc.describe()}}},
      {"degenerate", rc.degenerate.empty() ? json(nullptr) : json(rc.degenerate)},
      {"params", params_json(rc.params)},
  };
  return doc;
}

Status export_case(const ResolvedCase& rc, const std::string& dir) {
  for (const AuxImage& a : images_of(rc))
    if (Status st = write_exr(dir + "/" + a.name + ".exr", *a.image); !st) return st;
  return write_file_atomic(dir + "/params.json", case_export_json(rc).dump(2) + "\n");
}

Result<ResolvedCase> load_exported_case(const std::string& params_path) {
  std::ifstream f(params_path);
  if (!f) return Error{params_path, "", "cannot open the file", ""};
  std::stringstream s;
  s << f.rdbuf();
  json doc;
  try {
    doc = json::parse(s.str());
  } catch (const json::exception& e) {
    return Error{params_path, "", std::string("malformed JSON: ") + e.what(), ""};
  }
  ResolvedCase rc;
  if (!doc.is_object() || !doc.contains("stage") || !doc["stage"].is_string() ||
      !find_stage(doc["stage"].get<std::string>()))
    return Error{params_path, "/stage", "missing or unknown stage", stage_names()};
  rc.spec.stage = find_stage(doc["stage"].get<std::string>());
  if (doc.contains("id") && doc["id"].is_string()) rc.spec.id = doc["id"].get<std::string>();
  if (!doc.contains("params")) return Error{params_path, "/params", "missing params", ""};
  auto params = params_from_json(doc["params"], params_path, "/params");
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
                                           : nullptr;
    if (!target)
      return Error{params_path, "/images/" + name, "unknown image '" + name + "'",
                   "input, ui, bloom, bloom_dirt"};
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
                    {"stage", std::string(c.stage->name)},
                    {"dir", rel},
                    {"degenerate", !rc->degenerate.empty()}});
  }
  const json manifest = {
      {"tool", "hdrconform"}, {"format", "hdrconform case export 1"}, {"cases", list}};
  if (Status st = write_file_atomic(out_dir + "/manifest.json", manifest.dump(2) + "\n"); !st)
    summary.errors.push_back(st.error());
  return summary;
}

}  // namespace hdrc
