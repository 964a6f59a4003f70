#include "runner/case_loader.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "core/cube/cube.h"
#include "core/nearest.h"
#include "core/pipeline.h"
#include "core/utf8.h"
#include "runner/budget.h"
#include "runner/json_read.h"
#include "runner/pairwise.h"
#include "runner/stimuli.h"
#include "runner/tolerance.h"

namespace hdrc {

namespace fs = std::filesystem;
// ordered_json keeps keys in file order, so matrix dimensions expand (and name ids) as written.
using json = nlohmann::ordered_json;

Tolerance default_tolerance() {
  return default_tolerance_policy();
}

namespace {

// One pattern element at glob[*i] against the character c: '?', a [...] class ('!' or '^'
// negates, a-z ranges, ']' first is literal) or a literal (a backslash escapes). Advances *i past
// the element.
bool element_matches(const std::string& glob, size_t* i, char c) {
  const char g = glob[*i];
  if (g == '?') {
    ++*i;
    return true;
  }
  if (g == '[') {
    size_t j = *i + 1;
    const bool negate = j < glob.size() && (glob[j] == '!' || glob[j] == '^');
    if (negate) ++j;
    const size_t first = j;
    bool hit = false;
    for (; j < glob.size() && (glob[j] != ']' || j == first); ++j) {
      if (j + 2 < glob.size() && glob[j + 1] == '-' && glob[j + 2] != ']') {
        hit |= glob[j] <= c && c <= glob[j + 2];
        j += 2;
      } else {
        hit |= glob[j] == c;
      }
    }
    if (j < glob.size()) {  // a closed class
      *i = j + 1;
      return hit != negate;
    }
    // An unclosed '[' is a literal, as in fnmatch.
  }
  if (g == '\\' && *i + 1 < glob.size()) {
    *i += 2;
    return glob[*i - 1] == c;
  }
  ++*i;
  return g == c;
}

}  // namespace

// fnmatch(3) semantics without flags (no special '/', backslash escapes), matched in
// O(|glob| * |id|) with the classic single-backtrack algorithm: glibc's fnmatch backtracks
// exponentially on patterns such as '*a*a*a*a*a*a*a*a*a*b'.
bool matches_filter(const std::string& id, const std::string& glob) {
  if (glob.empty()) return true;
  size_t g = 0, s = 0, star = std::string::npos, star_s = 0;
  while (s < id.size()) {
    if (g < glob.size() && glob[g] == '*') {
      star = ++g;
      star_s = s;
      continue;
    }
    size_t next = g;
    if (g < glob.size() && element_matches(glob, &next, id[s])) {
      g = next;
      ++s;
      continue;
    }
    if (star == std::string::npos) return false;
    g = star;
    s = ++star_s;
  }
  while (g < glob.size() && glob[g] == '*') ++g;
  return g == glob.size();
}

bool is_suite_config_file(const std::string& cases_dir, const std::string& path) {
  static const std::set<std::string> kConfig = {"schema.json",
                                                "defaults.json",
                                                "coverage.json",
                                                "coverage_exhaustive.json",
                                                "known_limits.json",
                                                "tolerance_overlays.json",
                                                "tolerance_overlays_analytic.json"};
  std::error_code ec;
  const fs::path rel = fs::relative(path, cases_dir, ec);
  if (ec || rel.has_parent_path()) return false;
  const std::string name = rel.filename().string();
  // A pipeline's coverage declaration (runner/coverage.h: coverage_file_name).
  const bool pipeline_coverage = name.rfind("coverage_", 0) == 0 && name.size() > 14 &&
                                 name.compare(name.size() - 5, 5, ".json") == 0;
  return kConfig.count(name) != 0 || pipeline_coverage;
}

std::string InputSpec::describe() const {
  if (!file.empty()) return "file " + file;
  if (stimulus.empty()) return "lattice";
  std::string p;
  for (const auto& [k, v] : params) {
    p += (p.empty() ? " {" : ", ") + k + "=";
    for (size_t i = 0; i < v.size(); ++i) {
      std::ostringstream s;
      s << v[i];
      p += i ? "," : "";
      p += s.str();
    }
  }
  if (!p.empty()) p += "}";
  return stimulus + p + " " + std::to_string(width) + "x" + std::to_string(height);
}

std::string id_name(const std::string& name) {
  static const std::map<std::string, std::string> abbrev = {
      {"r.HDR.Display.OutputDevice", "dev"},
      {"r.HDR.Display.ColorGamut", "gamut"},
      {"r.HDR.Display.MaxLuminance", "max"},
      {"r.LUT.Size", "lut"},
      {"r.HDR.EnableHDROutput", "hdr"},
      {"r.HDR.Display.MinLuminanceLog10", "minlog"},
      {"r.HDR.Display.MidLuminance", "mid"},
      {"r.HDR.Aces.SceneColorMultiplier", "scm"},
      {"r.HDR.Aces.GamutCompression", "gc"},
      {"r.TonemapperGamma", "gamma"},
      {"r.Tonemapper.Sharpen", "sharpen"},
      {"r.BackbufferQuantizationDitheringOverride", "bits"},
      {"r.DefaultBackBufferPixelFormat", "bb"},
      {"r.Color.Min", "cmin"},
      {"r.Color.Mid", "cmid"},
      {"r.Color.Max", "cmax"},
      {"r.HDR.UI.CompositeMode", "uimode"},
      {"r.HDR.UI.Level", "uilevel"},
      {"r.HDR.UI.Luminance", "uinits"},
      {"r.EyeAdaptation.VisualizeDebugType", "debug"},
      {"LUTFormat", "fmt"},
      {"LUTLayout", "layout"},
      {"ColorVisionDeficiencyType", "cvd"},
      {"ColorVisionDeficiencySeverity", "severity"},
      {"ColorVisionDeficiencyCorrect", "correct"},
      {"ColorVisionDeficiencyShowCorrection", "show"},
      {"WhiteTemp", "temp"},
      {"WhiteTint", "tint"},
      {"TemperatureType", "ttype"},
      {"ExpandGamut", "expand"},
      {"BlueCorrection", "blue"},
      {"ToneCurveAmount", "curve"},
      {"FilmSlope", "slope"},
      {"FilmToe", "toe"},
      {"FilmShoulder", "shoulder"},
      {"FilmBlackClip", "black"},
      {"FilmWhiteClip", "white"},
      {"ColorSaturation", "sat"},
      {"ColorContrast", "con"},
      {"ColorGamma", "gam"},
      {"ColorGain", "gain"},
      {"ColorOffset", "off"},
  };
  auto it = abbrev.find(name);
  if (it != abbrev.end()) return it->second;
  std::string s = name.substr(name.rfind('.') + 1);
  std::transform(s.begin(), s.end(), s.begin(), ::tolower);
  return s;
}

namespace {

std::string show(const json& v) {
  std::string s = v.dump();
  return s.size() > 60 ? s.substr(0, 57) + "..." : s;
}

std::string json_type(const json& v) {
  return std::string(v.type_name());
}

std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
  return out;
}

// ", did you mean 'x'?" when the nearest valid name is plausibly what was meant (two edits, or
// at most a third of its letters), else "".
std::string did_you_mean(const std::string& name, const std::vector<std::string>& names) {
  const auto near = nearest_names(name, names, 1);
  if (near.empty()) return "";
  const size_t d = edit_distance(name, near[0]);
  if (d == 0 || d > std::max<size_t>(2, std::max(name.size(), near[0].size()) / 3)) return "";
  return ", did you mean '" + near[0] + "'?";
}

std::string format_value(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

class Parser {
 public:
  Parser(std::string file, std::string cases_dir, std::vector<Error>* errors)
      : file_(std::move(file)), cases_dir_(std::move(cases_dir)), errors_(errors) {}

  void fail(const std::string& pointer, const std::string& message,
            const std::string& choices = "") {
    errors_->push_back(Error{file_, pointer, message, choices});
    ok_ = false;
  }
  void fail(const Error& e) {
    errors_->push_back(e);
    ok_ = false;
  }
  bool ok() const { return ok_; }
  size_t error_count() const { return errors_->size(); }
  const std::string& file() const { return file_; }

  void check_keys(const json& obj, const std::string& pointer,
                  const std::vector<std::string>& allowed, const std::string& what = "") {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      if (std::find(allowed.begin(), allowed.end(), it.key()) == allowed.end()) {
        fail(pointer + "/" + escape_pointer_token(it.key()),
             "unknown key '" + it.key() + "'" + what + did_you_mean(it.key(), allowed),
             join(allowed));
      }
    }
  }

  bool number(const json& v, const std::string& pointer, double* out) {
    if (!v.is_number()) {
      fail(pointer, "expected a number, got " + json_type(v) + " " + show(v));
      return false;
    }
    *out = v.get<double>();
    return true;
  }

  bool cvar(const std::string& name, const json& v, const std::string& pointer, CvarValues* cv) {
    double value = 0;
    if (!number(v, pointer, &value)) return false;
    if (Status st = cv->set(name, value); !st) {
      fail(pointer, st.error().message, st.error().choices);
      return false;
    }
    return true;
  }

  bool setting(const std::string& name, const json& v, const std::string& pointer,
               SettingValues* sv) {
    Vec4d value{0, 0, 0, 0};
    int components = 0;
    if (v.is_string() && sv->choices(name)) {  // a named value (WorkingColorSpace presets)
      if (Status st = sv->set_choice(name, v.get<std::string>()); !st) {
        fail(pointer, st.error().message, st.error().choices);
        return false;
      }
      return true;
    }
    if (v.is_number()) {
      value[0] = v.get<double>();
      components = 1;
    } else if (v.is_array() && v.size() == 4 &&
               std::all_of(v.begin(), v.end(), [](const json& e) { return e.is_number(); })) {
      for (int i = 0; i < 4; ++i) value[i] = v[i].get<double>();
      components = 4;
    } else {
      fail(pointer, "expected a number or an array of 4 numbers, got " + show(v));
      return false;
    }
    if (Status st = sv->set(name, value, components); !st) {
      fail(pointer, st.error().message, st.error().choices);
      return false;
    }
    return true;
  }

  void cvar_object(const json& cv, const std::string& pointer, CvarValues* out) {
    if (!cv.is_object()) {
      fail(pointer, "expected an object of cvar: value, got " + show(cv));
      return;
    }
    for (auto it = cv.begin(); it != cv.end(); ++it)
      cvar(it.key(), it.value(), pointer + "/" + escape_pointer_token(it.key()), out);
  }

  void setting_object(const json& sv, const std::string& pointer, SettingValues* out) {
    if (!sv.is_object()) {
      fail(pointer, "expected an object of setting: value, got " + show(sv));
      return;
    }
    for (auto it = sv.begin(); it != sv.end(); ++it)
      setting(it.key(), it.value(), pointer + "/" + escape_pointer_token(it.key()), out);
  }

  // One stimulus parameter from JSON; false when invalid (errors recorded).
  bool stimulus_param(const StimulusInfo& info, const StimulusParam& sp, const json& v,
                      const std::string& pointer, StimulusParams* out) {
    std::vector<double> values;
    if (sp.kind == ParamKind::kChoice) {
      std::vector<std::string> choices(sp.choices.begin(), sp.choices.end());
      const auto it = v.is_string()
                          ? std::find(choices.begin(), choices.end(), v.get<std::string>())
                          : choices.end();
      if (it == choices.end()) {
        fail(pointer,
             "unknown " + std::string(sp.name) + " " + show(v) + " of stimulus " +
                 std::string(info.name) +
                 (v.is_string() ? did_you_mean(v.get<std::string>(), choices) : ""),
             join(choices));
        return false;
      }
      values.push_back(static_cast<double>(it - choices.begin()));
    } else if (sp.kind == ParamKind::kNumberList) {
      if (!v.is_array() || v.empty() ||
          !std::all_of(v.begin(), v.end(), [](const json& e) { return e.is_number(); })) {
        fail(pointer, "expected a non-empty array of numbers, got " + show(v),
             std::string(sp.description));
        return false;
      }
      for (const json& e : v) values.push_back(e.get<double>());
    } else {
      double x = 0;
      if (!number(v, pointer, &x)) return false;
      values.push_back(x);
    }
    StimulusParams one{{std::string(sp.name), values}};
    if (Status st = check_stimulus(info, one, 1 << 16, 1 << 16); !st) {
      fail(pointer, st.error().message, st.error().choices);
      return false;
    }
    (*out)[std::string(sp.name)] = values;
    return true;
  }

  // Returns false when invalid (errors recorded).
  bool input(const json& v, const std::string& pointer, InputSpec* in) {
    if (!v.is_object()) {
      fail(pointer, "expected an object, got " + json_type(v) + " " + show(v),
           "{\"stimulus\": NAME, \"width\": N, \"height\": N} or {\"file\": PATH}");
      return false;
    }
    const size_t before = errors_->size();
    if (v.contains("file") == v.contains("stimulus")) {
      fail(pointer, "an input names exactly one of \"stimulus\" or \"file\"",
           "stimulus: " + stimulus_names() + "; file: an image path under cases/");
      return false;
    }
    if (v.contains("name")) {
      const json& n = v["name"];
      if (!n.is_string() || n.get<std::string>().empty() ||
          n.get<std::string>().find_first_of("/ *?[]") != std::string::npos) {
        fail(pointer + "/name",
             "an input name is a non-empty string without '/', ' ' or glob "
             "characters, got " +
                 show(n));
      } else {
        in->label = n.get<std::string>();
      }
    }
    if (v.contains("stimulus")) {
      const json& s = v["stimulus"];
      std::vector<std::string> names;
      for (const auto& st : stimulus_table()) names.emplace_back(st.name);
      if (!s.is_string() || !find_stimulus(s.get<std::string>())) {
        fail(pointer + "/stimulus",
             "unknown stimulus " + show(s) +
                 (s.is_string() ? did_you_mean(s.get<std::string>(), names) : ""),
             stimulus_names());
        return false;
      }
      in->stimulus = s.get<std::string>();
      const StimulusInfo* info = find_stimulus(in->stimulus);
      std::vector<std::string> keys = {"stimulus", "width", "height", "name"};
      for (const auto& sp : info->params) keys.emplace_back(sp.name);
      check_keys(v, pointer, keys, " of stimulus " + in->stimulus);
      std::string auto_label = in->stimulus;
      for (auto it = v.begin(); it != v.end(); ++it) {
        const StimulusParam* sp = find_stimulus_param(*info, it.key());
        if (!sp) continue;
        if (!stimulus_param(*info, *sp, it.value(), pointer + "/" + it.key(), &in->params))
          continue;
        if (sp->kind == ParamKind::kChoice) {
          auto_label += "_" + it.value().get<std::string>();
        } else {
          auto_label += "_" + it.key();
          const auto& vals = in->params[it.key()];
          for (size_t i = 0; i < vals.size(); ++i)
            auto_label += (i ? "-" : "") + format_value(vals[i]);
        }
      }
      if (in->label.empty()) in->label = auto_label;
      stimulus_default_size(*info, in->params, &in->width, &in->height);
      for (const char* key : {"width", "height"}) {
        if (!v.contains(key)) continue;
        const json& d = v[key];
        if (!d.is_number_integer() || d.get<int64_t>() < 1 || d.get<int64_t>() > 8192) {
          fail(pointer + "/" + key, std::string(key) + " " + show(d) + " is not valid",
               "integers 1 to 8192");
          continue;
        }
        (std::string(key) == "width" ? in->width : in->height) = d.get<int>();
      }
      if (errors_->size() == before &&
          static_cast<size_t>(in->width) * static_cast<size_t>(in->height) > kMaxImagePixels) {
        fail(pointer,
             "a " + std::to_string(in->width) + "x" + std::to_string(in->height) +
                 " stimulus has more pixels than the limit",
             "width x height at most " + std::to_string(kMaxImagePixels) + " (4096x4096)");
      }
      if (errors_->size() == before) {
        if (Status st = check_stimulus(*info, in->params, in->width, in->height); !st)
          fail(pointer, st.error().message, st.error().choices);
      }
    } else {
      check_keys(v, pointer, {"file", "name"}, " of a file input");
      const json& f = v["file"];
      if (!f.is_string()) {
        fail(pointer + "/file", "expected a path string, got " + show(f));
        return false;
      }
      std::error_code ec;
      const fs::path root = fs::weakly_canonical(cases_dir_, ec);
      const fs::path p = fs::weakly_canonical(fs::path(cases_dir_) / f.get<std::string>(), ec);
      const std::string rel = fs::relative(p, root, ec).generic_string();
      if (rel.empty() || rel.rfind("..", 0) == 0 || fs::path(f.get<std::string>()).is_absolute()) {
        fail(pointer + "/file", "input path " + show(f) + " leaves the cases directory",
             "a relative path under " + cases_dir_);
        return false;
      }
      if (!fs::is_regular_file(p, ec)) {
        fail(pointer + "/file",
             "input file " + show(f) +
                 (fs::exists(p, ec) ? " is not a regular file" : " does not exist") +
                 " (looked for " + valid_utf8(p.generic_string()) + ")");
        return false;
      }
      in->file = p.generic_string();
      if (in->label.empty()) in->label = p.stem().string();
    }
    return errors_->size() == before;
  }

  // A user LUT path (`"lut"`, `"matrix": {"luts": [...]}`): read_user_lut's rules; each file is
  // read once per case file. Returns null when invalid (errors recorded).
  std::shared_ptr<const UserLut> lut(const json& v, const std::string& pointer,
                                     const StageInfo* stage) {
    if (!v.is_string() || v.get<std::string>().empty()) {
      fail(pointer, "expected a .cube path string, got " + show(v),
           user_lut_choices(cases_dir_, stage));
      return nullptr;
    }
    const std::string named = v.get<std::string>();
    if (auto it = luts_.find(named); it != luts_.end()) {
      if (Status st = check_user_lut_size(*it->second, stage, cases_dir_); !st) {
        fail(pointer, st.error().message, st.error().choices);
        return nullptr;
      }
      return it->second;
    }
    auto lut = read_user_lut(cases_dir_, named, stage);
    if (!lut) {
      fail(pointer, lut.error().message, lut.error().choices);
      // A wrong size is the stage's rule, not the file's: keep the file for other stages.
      return nullptr;
    }
    luts_[named] = *lut;
    return *lut;
  }

  // `"tolerance": NAME` (a set of defaults.json), or an object over the project default, or an
  // object with "base": NAME over that set.
  void tolerance(const json& v, const std::string& pointer, const SuiteDefaults& defaults,
                 Tolerance* t) {
    std::vector<std::string> names;
    for (const auto& [n, _] : defaults.tolerances) names.push_back(n);
    auto named = [&](const json& n, const std::string& at) -> const Tolerance* {
      if (n.is_string()) {
        auto it = defaults.tolerances.find(n.get<std::string>());
        if (it != defaults.tolerances.end()) return &it->second;
      }
      fail(at,
           "unknown tolerance set " + show(n) +
               (n.is_string() ? did_you_mean(n.get<std::string>(), names) : "") + " (sets are " +
               "defined in " + (defaults.file.empty() ? "cases/defaults.json" : defaults.file) +
               ": /tolerances)",
           names.empty() ? "none defined" : join(names));
      return nullptr;
    };
    if (v.is_string()) {
      if (const Tolerance* set = named(v, pointer)) *t = *set;
      return;
    }
    Tolerance base = default_tolerance_policy();
    json body = v;
    if (v.is_object() && v.contains("base")) {
      const Tolerance* set = named(v["base"], pointer + "/base");
      if (!set) return;
      base = *set;
      body.erase("base");
    }
    auto parsed = parse_tolerance(body, file_, pointer, base);
    if (!parsed) {
      fail(parsed.error());
      return;
    }
    *t = *parsed;
    if (v.is_object() && v.contains("base")) t->source += " over " + base.source;
  }

 private:
  std::string file_, cases_dir_;
  std::vector<Error>* errors_;
  bool ok_ = true;
  std::map<std::string, std::shared_ptr<const UserLut>> luts_;  // by the path as named
};

// A suite configuration file is absent only when nothing at all is there: a dangling symlink or
// a folder of that name is present, and reading it reports why it is unusable.
bool config_file_present(const fs::path& p) {
  std::error_code ec;
  return fs::symlink_status(p, ec).type() != fs::file_type::not_found;
}

// One matrix dimension: a cvar, a setting, or the inputs.
struct Dim {
  enum Kind { kCvar, kSetting, kInputs, kLuts } kind;
  std::string name;  // cvar or setting name; "inputs"; "luts"
  std::vector<json> values;
  std::string pointer;
  std::vector<std::shared_ptr<const UserLut>> luts;  // kLuts: the LUT of each value
};

constexpr size_t kMaxIdLength = 160;
constexpr size_t kMaxLutBlendSteps = 8;  // "lut_blend" entries a case may list

}  // namespace

std::string user_lut_choices(const std::string& cases_dir, const StageInfo* stage) {
  return "a .cube file" + (cases_dir.empty() ? std::string() : " under " + cases_dir) +
         " with one 3-D table" +
         (stage && stage->user_lut > 0 ? " of LUT_3D_SIZE " + std::to_string(stage->user_lut)
                                       : std::string());
}

Status check_user_lut_size(const UserLut& lut, const StageInfo* stage,
                           const std::string& cases_dir) {
  if (!stage || stage->user_lut <= 0 || lut.size == stage->user_lut) return {};
  return Error{"", "",
               "LUT file \"" + lut.name + "\" has LUT_3D_SIZE " + std::to_string(lut.size) +
                   "; stage " + std::string(stage->name) + " takes a " +
                   std::to_string(stage->user_lut) + "^3 LUT",
               user_lut_choices(cases_dir, stage)};
}

Result<std::shared_ptr<const UserLut>> read_user_lut(const std::string& cases_dir,
                                                     const std::string& path,
                                                     const StageInfo* stage) {
  const std::string valid = user_lut_choices(cases_dir, stage);
  const std::string shown = show(json(path));
  auto fail = [&](const std::string& message, const std::string& choices) {
    return Error{"", "", message, choices};
  };
  std::error_code ec;
  fs::path p = fs::path(path);
  std::string rel = path;
  if (!cases_dir.empty()) {
    const fs::path root = fs::weakly_canonical(cases_dir, ec);
    p = fs::weakly_canonical(fs::path(cases_dir) / path, ec);
    rel = fs::relative(p, root, ec).generic_string();
    if (rel.empty() || rel.rfind("..", 0) == 0 || fs::path(path).is_absolute())
      return fail("LUT path " + shown + " leaves the cases directory", valid);
  }
  if (p.extension() != ".cube")
    return fail("LUT path " + shown + " does not name a .cube file", valid);
  if (!fs::is_regular_file(p, ec))
    return fail("LUT file " + shown +
                    (fs::exists(p, ec) ? " is not a regular file" : " does not exist") +
                    " (looked for " + valid_utf8(p.generic_string()) + ")",
                valid);
  auto cube = cube::read_cube_file(p.generic_string());
  if (!cube) {
    const Error& e = cube.error();
    return fail("LUT file " + shown + ": " + e.file + (e.pointer.empty() ? "" : ": " + e.pointer) +
                    ": " + e.message,
                e.choices.empty() ? valid : e.choices);
  }
  if (cube->size_3d == 0)
    return fail("LUT file " + shown + " has no 3-D table (LUT_1D_SIZE " +
                    std::to_string(cube->size_1d) + " only: a 1-D LUT)",
                valid);
  if (cube->size_1d != 0)
    return fail("LUT file " + shown + " has a 1-D shaper (LUT_1D_SIZE " +
                    std::to_string(cube->size_1d) +
                    ") before its 3-D table, which the strip texture has no place for",
                valid);
  auto lut = std::make_shared<UserLut>();
  lut->file = p.generic_string();
  lut->name = rel;
  lut->label = p.stem().string();
  lut->title = cube->title.value_or("");
  lut->size = cube->size_3d;
  lut->domain_min = cube->domain_min_3d;
  lut->domain_max = cube->domain_max_3d;
  lut->table = std::move(cube->table_3d);
  if (Status st = check_user_lut_size(*lut, stage, cases_dir); !st) return st.error();
  return std::shared_ptr<const UserLut>(std::move(lut));
}

Status attach_user_lut(const std::shared_ptr<const UserLut>& lut, ResolvedCase* r) {
  r->spec.lut = lut;
  std::array<std::shared_ptr<const UserLut>, kUserLutSlots> slots{};
  slots[0] = lut;
  return attach_user_luts(slots, r);
}

Status attach_user_luts(const std::array<std::shared_ptr<const UserLut>, kUserLutSlots>& slots,
                        ResolvedCase* r) {
  for (Image& img : r->user_luts) img = Image();
  r->params.user_lut_size = 0;
  r->params.user_lut_domain_min = {0, 0, 0, 0};
  r->params.user_lut_domain_max = {0, 0, 0, 0};
  const bool unorm8 = r->spec.stage && r->spec.stage->user_lut_unorm8;
  for (size_t s = 0; s < slots.size(); ++s) {
    const std::shared_ptr<const UserLut>& lut = slots[s];
    if (!lut) continue;
    Image strip = user_lut_strip(*lut);
    if (strip.data.empty() ||
        (r->params.user_lut_size != 0 && lut->size != r->params.user_lut_size))
      return Error{r->spec.file, "/lut", "LUT \"" + lut->name + "\" has an inconsistent table", ""};
    // 8-bit UNORM storage (StageInfo::user_lut_unorm8): rounded once here, for both engines.
    if (unorm8)
      for (double& v : strip.data) v = unorm8_value(v);
    r->user_luts[s] = std::move(strip);
    if (r->params.user_lut_size != 0) continue;
    r->params.user_lut_size = lut->size;
    for (int i = 0; i < 3; ++i) {
      r->params.user_lut_domain_min[i] = lut->domain_min[i];
      r->params.user_lut_domain_max[i] = lut->domain_max[i];
    }
  }
  return {};
}

namespace {

// "stage (pipeline), ...": the stages a case may give a user LUT.
std::string user_lut_stage_names() {
  std::string out;
  for (const Pipeline* pl : pipeline_table())
    for (const StageInfo& st : pl->stages())
      if (st.user_lut != 0)
        out +=
            (out.empty() ? "" : ", ") + std::string(st.name) + " (" + std::string(pl->name) + ")";
  return out.empty() ? "no stage takes one" : "stages that take one: " + out;
}

// The stages that take a case's bloom and bloom dirt images (StageInfo::bloom_inputs).
std::string bloom_stage_names() {
  std::string out;
  for (const Pipeline* pl : pipeline_table())
    for (const StageInfo& st : pl->stages())
      if (st.bloom_inputs) out += (out.empty() ? "" : ", ") + std::string(st.name);
  return out;
}

std::string value_label(const json& v) {
  if (v.is_array()) {
    std::string s;
    for (size_t i = 0; i < v.size(); ++i) s += (i ? "-" : "") + format_value(v[i].get<double>());
    return s;
  }
  return format_value(v.get<double>());
}

}  // namespace

SuiteDefaults load_suite_defaults(const std::string& cases_dir, std::vector<Error>* errors) {
  SuiteDefaults d;
  const fs::path path = fs::path(cases_dir) / "defaults.json";
  if (!config_file_present(path)) return d;
  d.file = path.generic_string();
  Parser p(d.file, cases_dir, errors);
  auto parsed = read_json_file<json>(d.file, "defaults file");
  if (!parsed) {
    errors->push_back(parsed.error());
    return d;
  }
  json doc = std::move(*parsed);
  if (!doc.is_object()) {
    p.fail("", "the defaults file is a JSON object, got " + json_type(doc));
    return d;
  }
  p.check_keys(doc, "", {"$schema", "description", "tolerances", "presets"});
  if (doc.contains("tolerances")) {
    const json& ts = doc["tolerances"];
    if (!ts.is_object()) {
      p.fail("/tolerances", "expected an object of name: tolerance, got " + show(ts));
    } else {
      for (auto it = ts.begin(); it != ts.end(); ++it) {
        auto t =
            parse_tolerance(it.value(), d.file, "/tolerances/" + escape_pointer_token(it.key()));
        if (!t)
          p.fail(t.error());
        else
          d.tolerances[it.key()] = *t;
      }
    }
  }
  if (doc.contains("presets")) {
    const json& ps = doc["presets"];
    if (!ps.is_object()) {
      p.fail("/presets", "expected an object of name: preset, got " + show(ps));
    } else {
      for (auto it = ps.begin(); it != ps.end(); ++it) {
        const std::string at = "/presets/" + escape_pointer_token(it.key());
        if (!it.value().is_object()) {
          p.fail(at, "expected an object with cvars and settings, got " + show(it.value()));
          continue;
        }
        p.check_keys(it.value(), at, {"description", "cvars", "settings"});
        Preset preset;
        if (it.value().contains("cvars"))
          p.cvar_object(it.value()["cvars"], at + "/cvars", &preset.cvars);
        if (it.value().contains("settings"))
          p.setting_object(it.value()["settings"], at + "/settings", &preset.settings);
        d.presets[it.key()] = preset;
      }
    }
  }
  return d;
}

std::vector<Case> parse_case_file(const std::string& file, const std::string& text,
                                  const std::string& cases_dir, const std::string& name,
                                  std::vector<Error>* errors) {
  const SuiteDefaults defaults = load_suite_defaults(cases_dir, errors);
  return parse_case_file(file, text, cases_dir, name, defaults, errors);
}

std::vector<Case> parse_case_file(const std::string& file, const std::string& text,
                                  const std::string& cases_dir, const std::string& name,
                                  const SuiteDefaults& defaults, std::vector<Error>* errors) {
  std::vector<Case> out;
  Parser p(file, cases_dir, errors);
  auto parsed = parse_json_text<json>(file, text);
  if (!parsed) {
    errors->push_back(parsed.error());
    return out;
  }
  json doc = std::move(*parsed);
  if (!doc.is_object()) {
    p.fail("", "a case file is a JSON object, got " + json_type(doc));
    return out;
  }
  p.check_keys(
      doc, "",
      {"$schema", "description", "pipeline", "stage", "preset", "cvars", "settings", "input",
       "bloom", "bloom_dirt", "lut", "lut_blend", "matrix", "tolerance", "pins_nonfinite", "tier"});

  Case base;
  base.file = file;
  base.tolerance = default_tolerance();
  if (doc.contains("tier")) {
    const json& t = doc["tier"];
    if (t != "quick" && t != "exhaustive")
      p.fail("/tier",
             "unknown tier " + show(t) +
                 (t.is_string() ? did_you_mean(t.get<std::string>(), suite_names()) : ""),
             "quick, exhaustive");
    else
      base.tier = t.get<std::string>();
  }
  // The pipeline (UE 5.5's unless the file names another), then its stage.
  const Pipeline* pipeline = &default_pipeline();
  if (doc.contains("pipeline")) {
    const json& pl = doc["pipeline"];
    std::vector<std::string> names;
    for (const Pipeline* q : pipeline_table()) names.emplace_back(q->name);
    if (!pl.is_string() || !find_pipeline(pl.get<std::string>()))
      p.fail("/pipeline",
             "unknown pipeline " + show(pl) +
                 (pl.is_string() ? did_you_mean(pl.get<std::string>(), names) : ""),
             pipeline_names());
    else
      pipeline = find_pipeline(pl.get<std::string>());
  }
  base.settings = pipeline->new_settings();
  std::vector<std::string> stage_list;
  for (const auto& s : pipeline->stages()) stage_list.emplace_back(s.name);
  if (!doc.contains("stage")) {
    p.fail("/stage", "missing stage", stage_names(*pipeline));
  } else if (!doc["stage"].is_string() || !find_stage(*pipeline, doc["stage"].get<std::string>())) {
    const StageInfo* elsewhere =
        doc["stage"].is_string() ? find_stage(doc["stage"].get<std::string>()) : nullptr;
    p.fail(
        "/stage",
        "unknown stage " + show(doc["stage"]) +
            (pipeline == &default_pipeline() ? "" : " of pipeline " + std::string(pipeline->name)) +
            (elsewhere ? " (it is a stage of pipeline " + std::string(elsewhere->pipeline) +
                             ": set \"pipeline\": \"" + std::string(elsewhere->pipeline) + "\")"
             : doc["stage"].is_string() ? did_you_mean(doc["stage"].get<std::string>(), stage_list)
                                        : ""),
        stage_names(*pipeline));
  } else {
    base.stage = find_stage(*pipeline, doc["stage"].get<std::string>());
  }
  if (pipeline->cvars().empty()) {
    for (const char* key : {"cvars", "preset"})
      if (doc.contains(key))
        p.fail(
            std::string("/") + key,
            "pipeline " + std::string(pipeline->name) + " has no cvars" +
                (std::string(key) == "preset" ? " (presets set UE 5.5's cvars and settings)" : ""),
            "\"settings\": " + std::string(pipeline->name) +
                "'s settings (hdrconform cvars "
                "--pipeline " +
                std::string(pipeline->name) + ")");
    if (doc.contains("matrix") && doc["matrix"].is_object() && doc["matrix"].contains("cvars"))
      p.fail("/matrix/cvars", "pipeline " + std::string(pipeline->name) + " has no cvars",
             "\"settings\"");
  }
  // Presets first: the case's own cvars and settings, then its matrix, override them.
  if (doc.contains("preset") && !pipeline->cvars().empty()) {
    const json& pr = doc["preset"];
    std::vector<std::pair<json, std::string>> refs;
    if (pr.is_array()) {
      for (size_t i = 0; i < pr.size(); ++i)
        refs.emplace_back(pr[i], "/preset/" + std::to_string(i));
    } else {
      refs.emplace_back(pr, "/preset");
    }
    std::vector<std::string> names;
    for (const auto& [n, _] : defaults.presets) names.push_back(n);
    for (const auto& [ref, at] : refs) {
      auto it =
          ref.is_string() ? defaults.presets.find(ref.get<std::string>()) : defaults.presets.end();
      if (it == defaults.presets.end()) {
        p.fail(at,
               "unknown preset " + show(ref) +
                   (ref.is_string() ? did_you_mean(ref.get<std::string>(), names) : "") +
                   " (presets are defined in " +
                   (defaults.file.empty() ? "cases/defaults.json" : defaults.file) + ": /presets)",
               names.empty() ? "none defined" : join(names));
        continue;
      }
      for (const auto& [k, v] : it->second.cvars.explicit_values()) base.cvars.set(k, v);
      for (const auto& [k, v] : it->second.settings.explicit_values()) {
        const SettingInfo* info = find_setting(k);
        base.settings.set(k, v, info ? info->components : 1);
      }
    }
  }
  if (doc.contains("cvars") && !pipeline->cvars().empty())
    p.cvar_object(doc["cvars"], "/cvars", &base.cvars);
  if (doc.contains("settings")) p.setting_object(doc["settings"], "/settings", &base.settings);
  for (const char* key : {"bloom", "bloom_dirt"}) {
    if (!doc.contains(key)) continue;
    if (base.stage && !base.stage->bloom_inputs) {
      p.fail(std::string("/") + key, std::string(key) + " is an input of a Tonemap stage only",
             bloom_stage_names());
      continue;
    }
    p.input(doc[key], std::string("/") + key,
            std::string(key) == "bloom" ? &base.bloom : &base.bloom_dirt);
  }
  if (doc.contains("lut")) {
    if (base.stage && base.stage->user_lut == 0)
      p.fail("/lut", "stage " + std::string(base.stage->name) + " takes no user LUT",
             user_lut_stage_names());
    else
      base.lut = p.lut(doc["lut"], "/lut", base.stage);
  } else if (base.stage && base.stage->user_lut != 0 && !base.stage->user_lut_optional &&
             !(doc.contains("matrix") && doc["matrix"].is_object() &&
               doc["matrix"].contains("luts"))) {
    p.fail("/lut", "stage " + std::string(base.stage->name) + " needs a user LUT",
           "\"lut\": a .cube path under cases/, or \"matrix\": {\"luts\": [...]}");
  }
  if (doc.contains("lut_blend")) {
    // Further post-process sources' LUTs, each a LerpTo(LUT, weight) after the case's "lut"
    // (docs/cases.md): only for a stage that binds several LUTs.
    const json& l = doc["lut_blend"];
    if (base.stage && base.stage->user_lut_slots <= 1) {
      std::string takers;
      for (const Pipeline* pl : pipeline_table())
        for (const StageInfo& st : pl->stages())
          if (st.user_lut_slots > 1) takers += (takers.empty() ? "" : ", ") + std::string(st.name);
      p.fail("/lut_blend", "stage " + std::string(base.stage->name) + " blends no LUTs",
             "stages that do: " + takers);
    } else if (!l.is_array() || l.empty() || l.size() > kMaxLutBlendSteps) {
      p.fail("/lut_blend", "expected an array of 1-" + std::to_string(kMaxLutBlendSteps) +
                               " {\"lut\": PATH, \"weight\": W} objects, got " + show(l));
    } else {
      for (size_t i = 0; i < l.size(); ++i) {
        const std::string at = "/lut_blend/" + std::to_string(i);
        const json& e = l[i];
        if (!e.is_object() || !e.contains("lut") || !e.contains("weight") || e.size() != 2) {
          p.fail(at, "expected {\"lut\": PATH, \"weight\": W}, got " + show(e), "keys lut, weight");
          continue;
        }
        const json& w = e["weight"];
        if (!w.is_number() || !(w.get<double>() >= 0.0 && w.get<double>() <= 1.0)) {
          p.fail(at + "/weight", "expected a LerpTo weight in [0, 1], got " + show(w),
                 "a number in [0, 1]");
          continue;
        }
        auto lut = p.lut(e["lut"], at + "/lut", base.stage);
        if (lut) base.lut_blend.push_back({lut, w.get<double>()});
      }
    }
  }
  if (doc.contains("tolerance"))
    p.tolerance(doc["tolerance"], "/tolerance", defaults, &base.tolerance);
  if (doc.contains("pins_nonfinite")) {
    const json& why = doc["pins_nonfinite"];
    if (!why.is_string() || why.get<std::string>().empty())
      p.fail("/pins_nonfinite",
             "expected the reason the case pins non-finite behaviour, got " + show(why),
             "a non-empty string");
    else
      base.pins_nonfinite = why.get<std::string>();
  }

  // Dimensions to expand: cvar and setting value lists, then the inputs.
  std::vector<Dim> dims;
  std::vector<InputSpec> inputs;
  std::string mode = "full";
  int strength = 2;  // "covering" matrices: the t of the t-way covering array
  std::vector<std::string> full_names;
  std::string full_pointer = "/matrix/full";
  if (doc.contains("matrix")) {
    const json& m = doc["matrix"];
    if (!m.is_object()) {
      p.fail("/matrix", "expected an object, got " + show(m));
    } else {
      p.check_keys(m, "/matrix",
                   {"mode", "full", "cvars", "settings", "inputs", "luts", "strength"});
      if (m.contains("mode")) {
        const json& md = m["mode"];
        if (md != "full" && md != "pairwise" && md != "covering") {
          p.fail("/matrix/mode",
                 "unknown matrix mode " + show(md) +
                     (md.is_string()
                          ? did_you_mean(md.get<std::string>(), {"full", "pairwise", "covering"})
                          : ""),
                 "full, pairwise, covering");
        } else {
          mode = md.get<std::string>();
        }
      }
      if (mode == "covering") {
        const json* st = m.contains("strength") ? &m["strength"] : nullptr;
        if (!st || !st->is_number_integer() || st->get<int>() < 2 || st->get<int>() > 4)
          p.fail("/matrix/strength",
                 st ? "invalid strength " + show(*st) : "a covering matrix needs a strength",
                 "an integer 2 to 4 (the t of the t-way covering array)");
        else
          strength = st->get<int>();
      } else if (m.contains("strength")) {
        p.fail("/matrix/strength", "\"strength\" applies to covering matrices only",
               "\"mode\": \"covering\"");
      }
      for (const char* group : {"cvars", "settings"}) {
        if (!m.contains(group)) continue;
        const bool is_cvar = std::string(group) == "cvars";
        const std::string gptr = std::string("/matrix/") + group;
        if (!m[group].is_object()) {
          p.fail(gptr, std::string("expected an object of ") + (is_cvar ? "cvar" : "setting") +
                           ": [values], got " + show(m[group]));
          continue;
        }
        for (auto it = m[group].begin(); it != m[group].end(); ++it) {
          const std::string ptr = gptr + "/" + escape_pointer_token(it.key());
          if (!it.value().is_array() || it.value().empty()) {
            p.fail(ptr, "expected a non-empty array of values, got " + show(it.value()));
            continue;
          }
          if (doc.contains(group) && doc[group].is_object() && doc[group].contains(it.key())) {
            p.fail(ptr, std::string(is_cvar ? "cvar " : "setting ") + it.key() +
                            " is set in both /" + group + " and " + gptr);
          }
          Dim d{is_cvar ? Dim::kCvar : Dim::kSetting, it.key(), {}, ptr, {}};
          std::set<std::string> seen;
          for (size_t i = 0; i < it.value().size(); ++i) {
            const json& val = it.value()[i];
            const std::string vptr = ptr + "/" + std::to_string(i);
            CvarValues cprobe;
            SettingValues sprobe = pipeline->new_settings();
            const bool valid = is_cvar ? p.cvar(it.key(), val, vptr, &cprobe)
                                       : p.setting(it.key(), val, vptr, &sprobe);
            if (!valid) continue;
            if (!is_cvar && val.is_string()) {  // a named value: expand with its number
              const json number = sprobe.get(it.key());
              if (!seen.insert(number.dump()).second) {
                p.fail(vptr, "value " + show(val) + " is listed twice");
                continue;
              }
              d.values.push_back(number);
              continue;
            }
            if (!seen.insert(val.dump()).second) {
              p.fail(vptr, "value " + show(val) + " is listed twice");
              continue;
            }
            d.values.push_back(val);
          }
          dims.push_back(std::move(d));
        }
      }
      if (m.contains("inputs")) {
        if (!m["inputs"].is_array() || m["inputs"].empty()) {
          p.fail("/matrix/inputs",
                 "expected a non-empty array of inputs, got " + show(m["inputs"]));
        } else {
          for (size_t i = 0; i < m["inputs"].size(); ++i) {
            InputSpec in;
            if (p.input(m["inputs"][i], "/matrix/inputs/" + std::to_string(i), &in))
              inputs.push_back(in);
          }
        }
      }
      if (m.contains("luts")) {
        const json& l = m["luts"];
        if (doc.contains("lut")) p.fail("/matrix/luts", "a case names either /lut or /matrix/luts");
        if (base.stage && base.stage->user_lut == 0) {
          p.fail("/matrix/luts", "stage " + std::string(base.stage->name) + " takes no user LUT",
                 user_lut_stage_names());
        } else if (!l.is_array() || l.empty()) {
          p.fail("/matrix/luts", "expected a non-empty array of .cube paths, got " + show(l));
        } else {
          Dim d{Dim::kLuts, "luts", {}, "/matrix/luts", {}};
          std::set<std::string> seen;
          for (size_t i = 0; i < l.size(); ++i) {
            const std::string at = "/matrix/luts/" + std::to_string(i);
            auto lut = p.lut(l[i], at, base.stage);
            if (!lut) continue;
            if (!seen.insert(lut->label).second) {
              p.fail(at, "LUT " + show(l[i]) + " is listed twice (or shares its file name)",
                     "distinct .cube file names");
              continue;
            }
            d.values.push_back(l[i]);
            d.luts.push_back(lut);
          }
          dims.push_back(std::move(d));
        }
      }
      if (m.contains("full")) {
        const json& f = m["full"];
        if (mode != "pairwise" && mode != "covering") {
          p.fail("/matrix/full",
                 "\"full\" names the dimensions a pairwise matrix crosses exhaustively; this "
                 "matrix is already full",
                 "\"mode\": \"pairwise\" or \"covering\"");
        } else if (!f.is_array()) {
          p.fail("/matrix/full", "expected an array of dimension names, got " + show(f));
        } else {
          std::vector<std::string> names;
          for (const Dim& d : dims) names.push_back(d.name);
          if (m.contains("inputs")) names.push_back("inputs");
          for (size_t i = 0; i < f.size(); ++i) {
            const std::string at = "/matrix/full/" + std::to_string(i);
            if (!f[i].is_string() ||
                std::find(names.begin(), names.end(), f[i].get<std::string>()) == names.end()) {
              p.fail(at,
                     "unknown matrix dimension " + show(f[i]) +
                         (f[i].is_string() ? did_you_mean(f[i].get<std::string>(), names) : ""),
                     join(names));
              continue;
            }
            full_names.push_back(f[i].get<std::string>());
          }
        }
      }
    }
  }
  if (doc.contains("input")) {
    if (!inputs.empty() ||
        (doc.contains("matrix") && doc["matrix"].is_object() && doc["matrix"].contains("inputs"))) {
      p.fail("/input", "a case names either /input or /matrix/inputs, not both");
    }
    InputSpec in;
    if (p.input(doc["input"], "/input", &in)) inputs.push_back(in);
  } else if (base.stage && !base.stage->takes_input) {
    inputs.push_back(InputSpec{});  // the output depends on the parameters only
  } else if (!(doc.contains("matrix") && doc["matrix"].is_object() &&
               doc["matrix"].contains("inputs"))) {
    p.fail("/input", "missing input",
           "{\"stimulus\": " + stimulus_names() + "} or {\"file\": PATH}");
  }
  if (!p.ok()) return {};

  // The inputs are the last dimension (only when there is more than one).
  const bool input_dim = inputs.size() > 1;
  std::vector<int> sizes;
  for (const Dim& d : dims) sizes.push_back(static_cast<int>(d.values.size()));
  if (input_dim) sizes.push_back(static_cast<int>(inputs.size()));
  std::vector<int> full_idx;
  for (const std::string& f : full_names) {
    for (size_t d = 0; d < dims.size(); ++d)
      if (dims[d].name == f) full_idx.push_back(static_cast<int>(d));
    if (f == "inputs" && input_dim) full_idx.push_back(static_cast<int>(dims.size()));
  }
  // Refuse a matrix too large before expanding it (a full matrix of 20 dimensions of 3 values
  // is 3.5e9 cases). Pairwise (covering t-way): the full dimensions' product times the two (t)
  // largest others'.
  {
    double estimate = 1;
    std::vector<int> others;
    for (size_t d = 0; d < sizes.size(); ++d) {
      const bool full = mode == "full" || std::find(full_idx.begin(), full_idx.end(),
                                                    static_cast<int>(d)) != full_idx.end();
      if (full)
        estimate *= sizes[d];
      else
        others.push_back(sizes[d]);
    }
    std::sort(others.rbegin(), others.rend());
    const size_t t = mode == "covering" ? static_cast<size_t>(strength) : 2;
    for (size_t i = 0; i < std::min<size_t>(t, others.size()); ++i) estimate *= others[i];
    if (estimate > static_cast<double>(kMaxCasesPerFile)) {
      p.fail(doc.contains("matrix") ? "/matrix" : "",
             "the matrix expands to about " + format_number(estimate) + " cases (" + mode + ")",
             "at most " + std::to_string(kMaxCasesPerFile) +
                 " per file: fewer values, \"mode\": \"pairwise\", or several files");
      return {};
    }
  }
  const std::vector<std::vector<int>> rows = mode == "pairwise" ? pairwise_rows(sizes, full_idx)
                                             : mode == "covering"
                                                 ? covering_rows(sizes, strength, full_idx)
                                                 : full_rows(sizes);

  for (const auto& row : rows) {
    Case c = base;
    std::string suffix;
    for (size_t d = 0; d < dims.size(); ++d) {
      const json& val = dims[d].values[row[d]];
      if (dims[d].kind == Dim::kLuts) {
        c.lut = dims[d].luts[row[d]];
        suffix += (suffix.empty() ? "" : "_") + std::string("lut") + c.lut->label;
        continue;
      }
      if (dims[d].kind == Dim::kCvar) {
        c.cvars.set(dims[d].name, val.get<double>());
      } else {
        Vec4d v{0, 0, 0, 0};
        int comps = 1;
        if (val.is_array()) {
          for (int i = 0; i < 4; ++i) v[i] = val[i].get<double>();
          comps = 4;
        } else {
          v[0] = val.get<double>();
        }
        c.settings.set(dims[d].name, v, comps);
      }
      suffix += (suffix.empty() ? "" : "_") + id_name(dims[d].name) + value_label(val);
    }
    const InputSpec& input = inputs[input_dim ? row.back() : 0];
    const int device = c.cvars.get_int("r.HDR.Display.OutputDevice");
    const auto& allowed = base.stage->devices;  // empty: the stage has no output-device cvar
    if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), device) == allowed.end()) {
      std::string where = "/cvars/r.HDR.Display.OutputDevice";
      for (size_t d = 0; d < dims.size(); ++d)
        if (dims[d].name == "r.HDR.Display.OutputDevice")
          where = dims[d].pointer + "/" + std::to_string(row[d]);
      std::string choices;
      for (int a : allowed) choices += (choices.empty() ? "" : ", ") + std::to_string(a);
      const std::string msg = "stage " + std::string(base.stage->name) +
                              " is not defined for output device " + std::to_string(device);
      if (std::none_of(errors->begin(), errors->end(), [&](const Error& e) {
            return e.file == file && e.pointer == where && e.message == msg;
          }))
        p.fail(where, msg, choices);
      continue;
    }
    c.input = input;
    if (input_dim || !input.stimulus.empty()) suffix += (suffix.empty() ? "" : "_") + input.label;
    c.id = name + (suffix.empty() ? "" : "/" + suffix);
    // Ids name files (goldens/, the run's per-case images): keep them well under NAME_MAX.
    if (c.id.size() > kMaxIdLength) {
      p.fail(doc.contains("matrix") ? "/matrix" : "",
             "case id '" + c.id.substr(0, 60) + "...' is " + std::to_string(c.id.size()) +
                 " characters long",
             "at most " + std::to_string(kMaxIdLength) +
                 ": fewer matrix dimensions per file, or input \"name\"s");
      break;
    }
    out.push_back(std::move(c));
  }
  if (!p.ok()) return {};
  return out;
}

Status check_case_id(const std::string& id) {
  auto bad = [&](const std::string& why) {
    return Error{"", "", "case id '" + valid_utf8(id) + "' " + why,
                 "ids are relative paths of printable UTF-8 names, none of them '.' or '..'"};
  };
  if (id.empty()) return bad("is empty");
  if (!is_valid_utf8(id)) return bad("is not valid UTF-8");
  for (unsigned char c : id)
    if (c < 0x20 || c == 0x7F || c == '\\') return bad("holds a control character or '\\'");
  if (id.front() == '/') return bad("is an absolute path");
  size_t at = 0;
  for (;;) {
    const size_t slash = id.find('/', at);
    const std::string part = id.substr(at, slash == std::string::npos ? slash : slash - at);
    if (part.empty() || part == "." || part == "..") return bad("has a '" + part + "' component");
    if (slash == std::string::npos) break;
    at = slash + 1;
  }
  return {};
}

const std::vector<std::string>& suite_names() {
  static const std::vector<std::string> names = {"quick", "exhaustive"};
  return names;
}

LoadedCases load_cases(const std::string& cases_dir, const std::string& suite) {
  LoadedCases result;
  if (std::find(suite_names().begin(), suite_names().end(), suite) == suite_names().end()) {
    result.errors.push_back(
        Error{"", "--suite", "unknown suite '" + suite + "'" + did_you_mean(suite, suite_names()),
              "quick, exhaustive"});
    return result;
  }
  std::error_code ec;
  const fs::file_status dir_status = fs::status(cases_dir, ec);
  if (!fs::is_directory(dir_status)) {
    result.errors.push_back(Error{valid_utf8(cases_dir), "",
                                  fs::exists(dir_status) ? "the cases path is not a folder"
                                                         : "the cases folder does not exist",
                                  "a folder of case files"});
    return result;
  }
  const fs::path root = fs::canonical(cases_dir, ec);
  result.defaults = load_suite_defaults(cases_dir, &result.errors);
  auto skip = [&](const fs::path& p, const std::string& why) {
    result.errors.push_back(Error{valid_utf8(p.generic_string()), "", why, ""});
  };
  std::vector<fs::path> files;
  size_t visited = 0;
  fs::recursive_directory_iterator it(cases_dir, ec), end;
  if (ec) skip(cases_dir, "cannot list the cases folder: " + ec.message());
  for (; !ec && it != end; it.increment(ec)) {
    if (++visited > kMaxCaseDirEntries) {
      skip(cases_dir, "more than " + std::to_string(kMaxCaseDirEntries) +
                          " entries under the cases folder; nothing was loaded past them");
      break;
    }
    const fs::path& p = it->path();
    const bool json_name = p.extension() == ".json";
    const fs::file_type type = it->symlink_status(ec).type();
    if (ec) break;
    if (type == fs::file_type::directory) continue;
    if (type == fs::file_type::symlink) {
      std::error_code tec;
      const fs::file_status target = fs::status(p, tec);
      if (!fs::exists(target)) {
        skip(p, "dangling symlink (its target " +
                    valid_utf8(fs::read_symlink(p, tec).generic_string()) +
                    " does not exist); not loaded");
        continue;
      }
      const fs::path real = fs::canonical(p, tec);
      const fs::path rel = real.lexically_relative(root);
      if (tec || rel.empty() || *rel.begin() == "..") {
        skip(p, "symlink to " + valid_utf8(real.generic_string()) + ", outside the cases folder " +
                    valid_utf8(root.generic_string()) + "; not loaded");
        continue;
      }
      if (fs::is_directory(target)) {
        skip(p, "symlinked folder: not followed; case files sit in the cases folder itself");
        continue;
      }
      if (!fs::is_regular_file(target)) {
        if (json_name) skip(p, "is a symlink to something that is not a regular file");
        continue;
      }
    } else if (type != fs::file_type::regular) {
      if (json_name) skip(p, "is not a regular file (a FIFO, socket or device); not loaded");
      continue;
    }
    if (json_name && !is_suite_config_file(cases_dir, p.string())) files.push_back(p);
  }
  if (ec) skip(cases_dir, "cannot list the cases folder: " + ec.message());
  std::sort(files.begin(), files.end());
  std::map<std::string, std::string> seen;  // id -> file
  size_t total = 0;
  for (const auto& f : files) {
    // Lexically: a symlink's own name, never its target's.
    std::string name = f.lexically_relative(cases_dir).replace_extension().generic_string();
    if (Status st = check_case_id(name); !st) {
      skip(f, "the file's name is not a valid case id: " + st.error().message);
      continue;
    }
    auto text = read_bounded_file(f.string(), kMaxJsonFileBytes, "case file");
    if (!text) {
      result.errors.push_back(text.error());
      continue;
    }
    auto cases = parse_case_file(valid_utf8(f.generic_string()), *text, cases_dir, name,
                                 result.defaults, &result.errors);
    for (auto& c : cases) {
      if (suite == "quick" && c.tier != "quick") continue;  // validated, not run
      if (Status st = check_case_id(c.id); !st) {
        result.errors.push_back(Error{c.file, "", st.error().message, st.error().choices});
        continue;
      }
      // Its memory and time, estimated before any work (runner/budget.h).
      if (Status st = check_case_budget(c); !st) {
        result.errors.push_back(st.error());
        continue;
      }
      auto [it, inserted] = seen.emplace(c.id, c.file);
      if (!inserted) {
        result.errors.push_back(
            Error{c.file, "", "case id '" + c.id + "' is also produced by " + it->second,
                  "give the inputs distinct \"name\"s or the matrix distinct values"});
        continue;
      }
      if (++total > kMaxCases) {
        result.errors.push_back(Error{
            c.file, "", "the suite expands to more than " + std::to_string(kMaxCases) + " cases",
            "at most " + std::to_string(kMaxCases) + " cases in all"});
        break;
      }
      result.cases.push_back(std::move(c));
    }
    if (total > kMaxCases) break;
  }
  std::sort(result.cases.begin(), result.cases.end(),
            [](const Case& a, const Case& b) { return a.id < b.id; });
  return result;
}

std::vector<KnownLimit> parse_known_limits(const json& doc, const std::string& file,
                                           const std::vector<std::string>& engines, bool device_key,
                                           std::vector<Error>* errors) {
  std::vector<KnownLimit> out;
  Parser p(file, "", errors);
  const std::string form = std::string("{\"limits\": [{\"cases\", \"engine\", ") +
                           (device_key ? "\"device\" (optional), " : "") + "\"reason\"}, ...]}";
  if (!doc.is_object()) {
    p.fail("", "expected " + form + ", got " + json_type(doc) + " " + show(doc));
    return out;
  }
  p.check_keys(doc, "", {"$schema", "description", "limits"});
  const auto limits = doc.find("limits");
  if (limits == doc.end() || !limits->is_array()) {
    p.fail("/limits",
           limits == doc.end() ? "missing limits, expected " + form
                               : "expected an array of limits, got " + show(*limits),
           form);
    return out;
  }
  if (limits->size() > kMaxKnownLimits) {
    p.fail("/limits", "more than " + std::to_string(kMaxKnownLimits) + " limits");
    return out;
  }
  std::vector<std::string> keys = {"cases", "engine", "reason"};
  if (device_key) keys.push_back("device");
  for (size_t i = 0; i < limits->size(); ++i) {
    const json& l = (*limits)[i];
    const std::string ptr = "/limits/" + std::to_string(i);
    if (!l.is_object()) {
      p.fail(ptr, "expected an object, got " + json_type(l) + " " + show(l), form);
      continue;
    }
    p.check_keys(l, ptr, keys);
    KnownLimit k;
    bool ok = true;
    if (device_key && l.contains("device")) {
      if (!l["device"].is_string() || l["device"].get<std::string>().empty()) {
        p.fail(
            ptr + "/device",
            "expected a non-empty glob over the candidate device's name, got " + show(l["device"]),
            "e.g. \"*worst-case device model\"");
        ok = false;
      } else {
        k.device = l["device"].get<std::string>();
      }
    }
    for (const char* key : {"cases", "engine", "reason"}) {
      if (!l.contains(key) || !l[key].is_string() || l[key].get<std::string>().empty()) {
        p.fail(ptr + "/" + key,
               std::string("missing ") + key + (l.contains(key) ? ", got " + show(l[key]) : ""),
               std::string(key) == "engine" ? join(engines) : "a non-empty string");
        ok = false;
        continue;
      }
      const std::string v = l[key].get<std::string>();
      if (std::string(key) == "cases") k.cases = v;
      if (std::string(key) == "engine") k.engine = v;
      if (std::string(key) == "reason") k.reason = v;
    }
    if (!k.engine.empty() && std::find(engines.begin(), engines.end(), k.engine) == engines.end()) {
      p.fail(ptr + "/engine",
             "unknown engine \"" + k.engine + "\"" + did_you_mean(k.engine, engines),
             join(engines));
      ok = false;
    }
    if (ok) out.push_back(k);
  }
  return out;
}

std::vector<KnownLimit> load_known_limits(const std::string& cases_dir,
                                          std::vector<Error>* errors) {
  const fs::path file = fs::path(cases_dir) / "known_limits.json";
  if (!config_file_present(file)) return {};
  auto parsed = read_json_file<json>(file.generic_string(), "known limits file");
  if (!parsed) {
    errors->push_back(parsed.error());
    return {};
  }
  return parse_known_limits(*parsed, file.generic_string(), {"vulkan", "reference"},
                            /*device_key=*/true, errors);
}

Result<ResolvedCase> resolve_case(const Case& c) {
  ResolvedCase r;
  r.spec = c;
  const Pipeline& pipeline = pipeline_of(*c.stage);
  if (!c.stage->takes_input) {
    // The "input" of a LUT texel is its lattice coordinate (reported with the worst pixel); the
    // LUT's size and layout come from the pipeline's parameters.
    auto sized = pipeline.resolve(c, 1, 1);
    if (!sized) return sized.error();
    const ParamBlock& lp = sized->params;
    const int n = lp.lut_size;
    if (n < 2 || n > 256)
      return Error{c.file, "", "LUT size " + std::to_string(n) + " is out of range", "2 to 256"};
    r.input = Image(n * n, n);
    for (int b = 0; b < n; ++b)
      for (int g = 0; g < n; ++g)
        for (int rr = 0; rr < n; ++rr) {
          const auto v = pipeline.lattice(lp, rr, g, b);
          double* px = r.input.px(rr + n * b, g);
          px[0] = v[0];
          px[1] = v[1];
          px[2] = v[2];
          px[3] = 1.0;
        }
  } else if (!c.input.file.empty()) {
    auto img = read_image(c.input.file);
    if (!img) return img.error();
    r.input = std::move(*img);
  } else {
    auto img = make_stimulus(c.input.stimulus, c.input.width, c.input.height, c.input.params);
    if (!img) return Error{c.file, "/input/stimulus", img.error().message, img.error().choices};
    r.input = std::move(*img);
  }
  // Both engines get the same float32 pixels: every input value is rounded to float32 once, here,
  // and float32 denormals are flushed to (signed) zero, as D3D's float32 arithmetic does
  // (docs/ue55-decisions.md, "Non-finite values and denormals").
  for (double& v : r.input.data) {
    float f = static_cast<float>(v);
    if (std::fpclassify(f) == FP_SUBNORMAL) f = std::copysign(0.0f, f);
    v = f;
  }
  // Bloom and dirt textures: stimuli at the scene's size, or image files.
  for (auto [spec, out] :
       {std::pair{&c.bloom, &r.bloom}, std::pair{&c.bloom_dirt, &r.bloom_dirt}}) {
    if (!spec->file.empty()) {
      auto img = read_image(spec->file);
      if (!img) return img.error();
      *out = std::move(*img);
    } else if (!spec->stimulus.empty()) {
      auto img = make_stimulus(spec->stimulus, r.input.width, r.input.height, spec->params);
      if (!img) return img.error();
      *out = std::move(*img);
    }
  }
  if (c.stage->id == StageId::kUiComposite) {
    auto ui = make_stimulus("ui_overlay", r.input.width, r.input.height);
    if (!ui) return ui.error();
    r.ui = std::move(*ui);
  }
  auto resolution = pipeline.resolve(c, r.input.width, r.input.height);
  if (!resolution) return resolution.error();
  r.params = resolution->params;
  r.degenerate = resolution->degenerate;
  // The user LUTs, for every pipeline alike: the strip textures of the LUTs the host derivation
  // chose for the slots (by default the case's "lut" alone), and P.user_lut_*.
  r.spec.lut = c.lut;
  std::array<std::shared_ptr<const UserLut>, kUserLutSlots> slots = resolution->user_luts;
  if (c.stage->user_lut_slots <= 1) slots = {c.lut, nullptr, nullptr, nullptr};
  if (Status st = attach_user_luts(slots, &r); !st) return st.error();
  return r;
}

}  // namespace hdrc
