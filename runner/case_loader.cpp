#include "runner/case_loader.h"

#include <fnmatch.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "reference/combine_luts.h"
#include "reference/ue_cpp/resolve.h"
#include "runner/stimuli.h"

namespace hdrc {

namespace fs = std::filesystem;
// ordered_json keeps keys in file order, so matrix dimensions expand (and name ids) as written.
using json = nlohmann::ordered_json;

Tolerance default_tolerance() {
  Tolerance t;
  t.linear_rel = 1e-5;
  t.rel_floor = 1e-6;
  t.pq_code10 = 0.05;
  t.reason = "project default (docs/tolerances.md): float32 evaluation of double formulas";
  t.source = "default";
  return t;
}

bool matches_filter(const std::string& id, const std::string& glob) {
  return glob.empty() || fnmatch(glob.c_str(), id.c_str(), 0) == 0;
}

std::string InputSpec::describe() const {
  if (!file.empty()) return "file " + file;
  if (stimulus.empty()) return "lattice";
  return stimulus + " " + std::to_string(width) + "x" + std::to_string(height);
}

namespace {

std::string escape_pointer_token(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '~')
      out += "~0";
    else if (c == '/')
      out += "~1";
    else
      out += c;
  }
  return out;
}

std::string show(const json& v) {
  std::string s = v.dump();
  return s.size() > 60 ? s.substr(0, 57) + "..." : s;
}

std::string json_type(const json& v) {
  return std::string(v.type_name());
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
  bool ok() const { return ok_; }

  void check_keys(const json& obj, const std::string& pointer,
                  const std::vector<std::string>& allowed) {
    std::string list;
    for (const auto& k : allowed) list += (list.empty() ? "" : ", ") + k;
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      if (std::find(allowed.begin(), allowed.end(), it.key()) == allowed.end()) {
        fail(pointer + "/" + escape_pointer_token(it.key()), "unknown key '" + it.key() + "'",
             list);
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

  void cvar(const std::string& name, const json& v, const std::string& pointer, CvarValues* cv) {
    double value = 0;
    if (!number(v, pointer, &value)) return;
    if (Status st = cv->set(name, value); !st)
      fail(pointer, st.error().message, st.error().choices);
  }

  // Returns false when invalid (errors recorded).
  bool input(const json& v, const std::string& pointer, InputSpec* in) {
    if (!v.is_object()) {
      fail(pointer, "expected an object, got " + json_type(v) + " " + show(v),
           "{\"stimulus\": NAME, \"width\": N, \"height\": N} or {\"file\": PATH}");
      return false;
    }
    const size_t before = errors_->size();
    check_keys(v, pointer, {"stimulus", "width", "height", "file"});
    if (v.contains("file") == v.contains("stimulus")) {
      fail(pointer, "an input names exactly one of \"stimulus\" or \"file\"",
           "stimulus: " + stimulus_names() + "; file: an image path under cases/");
      return false;
    }
    if (v.contains("stimulus")) {
      const json& s = v["stimulus"];
      if (!s.is_string() || !find_stimulus(s.get<std::string>())) {
        fail(pointer + "/stimulus", "unknown stimulus " + show(s), stimulus_names());
        return false;
      }
      in->stimulus = s.get<std::string>();
      const StimulusInfo* info = find_stimulus(in->stimulus);
      in->width = info->default_width;
      in->height = info->default_height;
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
    } else {
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
      if (!fs::is_regular_file(p)) {
        fail(pointer + "/file",
             "input file " + show(f) + " does not exist (looked for " + p.generic_string() + ")");
        return false;
      }
      in->file = p.generic_string();
    }
    return errors_->size() == before;
  }

  void setting(const std::string& name, const json& v, const std::string& pointer,
               SettingValues* sv) {
    Vec4d value{0, 0, 0, 0};
    int components = 0;
    if (v.is_number()) {
      value[0] = v.get<double>();
      components = 1;
    } else if (v.is_array() && v.size() == 4 &&
               std::all_of(v.begin(), v.end(), [](const json& e) { return e.is_number(); })) {
      for (int i = 0; i < 4; ++i) value[i] = v[i].get<double>();
      components = 4;
    } else {
      fail(pointer, "expected a number or an array of 4 numbers, got " + show(v));
      return;
    }
    if (Status st = sv->set(name, value, components); !st)
      fail(pointer, st.error().message, st.error().choices);
  }

  void tolerance(const json& v, const std::string& pointer, Tolerance* t) {
    if (!v.is_object()) {
      fail(pointer, "expected an object, got " + show(v));
      return;
    }
    check_keys(v, pointer, {"linear_rel", "rel_floor", "pq_code10", "reason"});
    for (const char* key : {"linear_rel", "rel_floor", "pq_code10"}) {
      if (!v.contains(key)) continue;
      double x = 0;
      if (!number(v[key], pointer + "/" + key, &x)) continue;
      if (!(x >= 0)) {
        fail(pointer + "/" + key, std::string(key) + " " + show(v[key]) + " is negative",
             "a number >= 0");
        continue;
      }
      if (std::string(key) == "linear_rel") t->linear_rel = x;
      if (std::string(key) == "rel_floor") t->rel_floor = x;
      if (std::string(key) == "pq_code10") t->pq_code10 = x;
    }
    if (!v.contains("reason") || !v["reason"].is_string() ||
        v["reason"].get<std::string>().empty()) {
      fail(pointer + "/reason", "a tolerance must say why (measured error and its cause)",
           "a non-empty string");
    } else {
      t->reason = v["reason"].get<std::string>();
    }
    t->source = file_ + ": " + pointer;
  }

 private:
  std::string file_, cases_dir_;
  std::vector<Error>* errors_;
  bool ok_ = true;
};

std::string short_cvar(const std::string& name) {
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
      {"r.Color.Min", "cmin"},
      {"r.Color.Mid", "cmid"},
      {"r.Color.Max", "cmax"},
      {"r.HDR.UI.CompositeMode", "uimode"},
      {"r.HDR.UI.Level", "uilevel"},
      {"r.HDR.UI.Luminance", "uinits"},
      {"r.EyeAdaptation.VisualizeDebugType", "debug"},
  };
  auto it = abbrev.find(name);
  if (it != abbrev.end()) return it->second;
  std::string s = name.substr(name.rfind('.') + 1);
  std::transform(s.begin(), s.end(), s.begin(), ::tolower);
  return s;
}

std::string format_value(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

std::vector<Case> parse_case_file(const std::string& file, const std::string& text,
                                  const std::string& cases_dir, const std::string& name,
                                  std::vector<Error>* errors) {
  std::vector<Case> out;
  Parser p(file, cases_dir, errors);
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::parse_error& e) {
    errors->push_back(Error{file, "", std::string("malformed JSON: ") + e.what(), ""});
    return out;
  }
  if (!doc.is_object()) {
    p.fail("", "a case file is a JSON object, got " + json_type(doc));
    return out;
  }
  p.check_keys(doc, "",
               {"$schema", "description", "stage", "cvars", "settings", "input", "bloom",
                "bloom_dirt", "matrix", "tolerance"});

  Case base;
  base.file = file;
  base.tolerance = default_tolerance();
  if (!doc.contains("stage")) {
    p.fail("/stage", "missing stage", stage_names());
  } else if (!doc["stage"].is_string() || !find_stage(doc["stage"].get<std::string>())) {
    p.fail("/stage", "unknown stage " + show(doc["stage"]), stage_names());
  } else {
    base.stage = find_stage(doc["stage"].get<std::string>());
  }
  if (doc.contains("cvars")) {
    const json& cv = doc["cvars"];
    if (!cv.is_object()) {
      p.fail("/cvars", "expected an object of cvar: value, got " + show(cv));
    } else {
      for (auto it = cv.begin(); it != cv.end(); ++it)
        p.cvar(it.key(), it.value(), "/cvars/" + escape_pointer_token(it.key()), &base.cvars);
    }
  }
  if (doc.contains("settings")) {
    const json& sv = doc["settings"];
    if (!sv.is_object()) {
      p.fail("/settings", "expected an object of setting: value, got " + show(sv));
    } else {
      for (auto it = sv.begin(); it != sv.end(); ++it)
        p.setting(it.key(), it.value(), "/settings/" + escape_pointer_token(it.key()),
                  &base.settings);
    }
  }
  for (const char* key : {"bloom", "bloom_dirt"}) {
    if (!doc.contains(key)) continue;
    if (base.stage && base.stage->id != StageId::kTonemap) {
      p.fail(std::string("/") + key, std::string(key) + " is an input of the tonemap stage only",
             "tonemap");
      continue;
    }
    p.input(doc[key], std::string("/") + key,
            std::string(key) == "bloom" ? &base.bloom : &base.bloom_dirt);
  }
  if (doc.contains("tolerance")) p.tolerance(doc["tolerance"], "/tolerance", &base.tolerance);

  // Dimensions to expand: cvar value lists and input lists (matrix mode "full": cross product).
  struct Dim {
    std::string cvar;  // "" for the input dimension
    std::vector<json> values;
    std::string pointer;
  };
  std::vector<Dim> dims;
  std::vector<InputSpec> inputs;
  if (doc.contains("matrix")) {
    const json& m = doc["matrix"];
    if (!m.is_object()) {
      p.fail("/matrix", "expected an object, got " + show(m));
    } else {
      p.check_keys(m, "/matrix", {"mode", "cvars", "inputs"});
      if (m.contains("mode") && m["mode"] != "full") {
        p.fail("/matrix/mode", "unknown matrix mode " + show(m["mode"]), "full");
      }
      if (m.contains("cvars")) {
        if (!m["cvars"].is_object()) {
          p.fail("/matrix/cvars", "expected an object of cvar: [values], got " + show(m["cvars"]));
        } else {
          for (auto it = m["cvars"].begin(); it != m["cvars"].end(); ++it) {
            const std::string ptr = "/matrix/cvars/" + escape_pointer_token(it.key());
            if (!it.value().is_array() || it.value().empty()) {
              p.fail(ptr, "expected a non-empty array of values, got " + show(it.value()));
              continue;
            }
            if (doc.contains("cvars") && doc["cvars"].is_object() &&
                doc["cvars"].contains(it.key())) {
              p.fail(ptr, "cvar " + it.key() + " is set in both /cvars and /matrix/cvars");
            }
            Dim d{it.key(), {}, ptr};
            for (size_t i = 0; i < it.value().size(); ++i) {
              CvarValues probe;
              p.cvar(it.key(), it.value()[i], ptr + "/" + std::to_string(i), &probe);
              d.values.push_back(it.value()[i]);
            }
            dims.push_back(std::move(d));
          }
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
    }
  }
  if (doc.contains("input")) {
    if (!inputs.empty() || (doc.contains("matrix") && doc["matrix"].contains("inputs"))) {
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

  // Cross product, last dimension fastest; inputs are the final dimension.
  size_t total = 1;
  for (const Dim& d : dims) total *= d.values.size();
  for (size_t k = 0; k < total; ++k) {
    std::vector<size_t> idx(dims.size());
    size_t rest = k;
    for (size_t d = dims.size(); d-- > 0;) {
      idx[d] = rest % dims[d].values.size();
      rest /= dims[d].values.size();
    }
    for (const InputSpec& input : inputs) {
      Case c = base;
      std::string suffix;
      for (size_t d = 0; d < dims.size(); ++d) {
        const double v = dims[d].values[idx[d]].get<double>();
        c.cvars.set(dims[d].cvar, v);
        suffix += (suffix.empty() ? "" : "_") + short_cvar(dims[d].cvar) + format_value(v);
      }
      const int device = c.cvars.get_int("r.HDR.Display.OutputDevice");
      const auto& allowed = base.stage->devices;
      if (std::find(allowed.begin(), allowed.end(), device) == allowed.end()) {
        std::string where = "/cvars/r.HDR.Display.OutputDevice";
        for (size_t d = 0; d < dims.size(); ++d)
          if (dims[d].cvar == "r.HDR.Display.OutputDevice")
            where = dims[d].pointer + "/" + std::to_string(idx[d]);
        std::string choices;
        for (int a : allowed) choices += (choices.empty() ? "" : ", ") + std::to_string(a);
        p.fail(where,
               "stage " + std::string(base.stage->name) + " is not defined for output device " +
                   std::to_string(device),
               choices);
        continue;
      }
      c.input = input;
      if (inputs.size() > 1 || !input.stimulus.empty()) {
        const std::string in_name =
            input.stimulus.empty() ? fs::path(input.file).stem().string() : input.stimulus;
        suffix += (suffix.empty() ? "" : "_") + in_name;
      }
      c.id = name + (suffix.empty() ? "" : "/" + suffix);
      out.push_back(std::move(c));
    }
  }
  if (!p.ok()) return {};
  return out;
}

LoadedCases load_cases(const std::string& cases_dir) {
  LoadedCases result;
  std::error_code ec;
  if (!fs::is_directory(cases_dir, ec)) {
    result.errors.push_back(Error{cases_dir, "", "cases directory does not exist", ""});
    return result;
  }
  std::vector<fs::path> files;
  for (auto it = fs::recursive_directory_iterator(cases_dir, ec);
       it != fs::recursive_directory_iterator(); ++it) {
    if (it->is_regular_file() && it->path().extension() == ".json" &&
        it->path().filename() != "schema.json" && it->path().filename() != "known_limits.json")
      files.push_back(it->path());
  }
  std::sort(files.begin(), files.end());
  std::map<std::string, std::string> seen;  // id -> file
  for (const auto& f : files) {
    std::ifstream in(f, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    std::string name = fs::relative(f, cases_dir, ec).replace_extension().generic_string();
    auto cases = parse_case_file(f.generic_string(), text.str(), cases_dir, name, &result.errors);
    for (auto& c : cases) {
      auto [it, inserted] = seen.emplace(c.id, c.file);
      if (!inserted) {
        result.errors.push_back(
            Error{c.file, "", "case id '" + c.id + "' is also produced by " + it->second, ""});
        continue;
      }
      result.cases.push_back(std::move(c));
    }
  }
  std::sort(result.cases.begin(), result.cases.end(),
            [](const Case& a, const Case& b) { return a.id < b.id; });
  return result;
}

std::vector<KnownLimit> load_known_limits(const std::string& cases_dir,
                                          std::vector<Error>* errors) {
  std::vector<KnownLimit> out;
  const fs::path file = fs::path(cases_dir) / "known_limits.json";
  if (!fs::exists(file)) return out;
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  Parser p(file.generic_string(), cases_dir, errors);
  json doc;
  try {
    doc = json::parse(text.str());
  } catch (const json::parse_error& e) {
    errors->push_back(
        Error{file.generic_string(), "", std::string("malformed JSON: ") + e.what(), ""});
    return out;
  }
  if (!doc.is_object() || !doc.contains("limits") || !doc["limits"].is_array()) {
    p.fail("/limits", "expected {\"limits\": [{\"cases\", \"engine\", \"reason\"}, ...]}");
    return out;
  }
  for (size_t i = 0; i < doc["limits"].size(); ++i) {
    const json& l = doc["limits"][i];
    const std::string ptr = "/limits/" + std::to_string(i);
    if (!l.is_object()) {
      p.fail(ptr, "expected an object");
      continue;
    }
    p.check_keys(l, ptr, {"cases", "engine", "reason"});
    KnownLimit k;
    for (const char* key : {"cases", "engine", "reason"}) {
      if (!l.contains(key) || !l[key].is_string() || l[key].get<std::string>().empty()) {
        p.fail(ptr + "/" + key, std::string("missing ") + key, "a non-empty string");
        continue;
      }
      const std::string v = l[key].get<std::string>();
      if (std::string(key) == "cases") k.cases = v;
      if (std::string(key) == "engine") k.engine = v;
      if (std::string(key) == "reason") k.reason = v;
    }
    if (!k.engine.empty() && k.engine != "vulkan" && k.engine != "reference")
      p.fail(ptr + "/engine", "unknown engine \"" + k.engine + "\"", "vulkan, reference");
    out.push_back(k);
  }
  return out;
}

Result<ResolvedCase> resolve_case(const Case& c) {
  ResolvedCase r;
  r.spec = c;
  if (!c.stage->takes_input) {
    // The "input" of a LUT texel is its lattice coordinate (reported with the worst pixel).
    const int n = c.cvars.get_int("r.LUT.Size");
    const int layout = static_cast<int>(c.settings.get("LUTLayout"));
    r.input = Image(n * n, n);
    for (int b = 0; b < n; ++b)
      for (int g = 0; g < n; ++g)
        for (int rr = 0; rr < n; ++rr) {
          const auto v = ref::lattice_coordinate(layout, n, rr, g, b);
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
    auto img = make_stimulus(c.input.stimulus, c.input.width, c.input.height);
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
      auto img = make_stimulus(spec->stimulus, r.input.width, r.input.height);
      if (!img) return img.error();
      *out = std::move(*img);
    }
  }
  if (c.stage->id == StageId::kUiComposite) {
    auto ui = make_stimulus("ui_overlay", r.input.width, r.input.height);
    if (!ui) return ui.error();
    r.ui = std::move(*ui);
  }
  auto resolution = ref::resolve(c, r.input.width, r.input.height);
  if (!resolution) return resolution.error();
  r.params = resolution->params;
  r.degenerate = resolution->degenerate;
  return r;
}

}  // namespace hdrc
