// The specification pages (docs/spec/*.md) against the code, so the two cannot drift.
//
// Every fenced block of a page whose info string starts with `worked-pixel` is a worked pixel:
//
//   ```worked-pixel PIPELINE [Setting=Value ...] [cube=cases/lut/cube/FILE.cube]
//   input      0.5 0.25 0.125
//   x          0.5 0.25 0.125
//   ...
//   ```
//
// PIPELINE is `operators`, `pq_grading`, `film_tonemap` (FilmToneMap alone: AP1 in, AP1 out,
// its parameters from the operators' FilmPreset setting), `ue55` (`r.*=` cvars and settings
// resolved as a one-pixel case, `stage=` tonemap | ui_composite | visualize_false_colour, `ui=`
// the UI pixel: reference/ue/ue55/ue55_named_values.h), `unity_urp` (settings, `stage=`
// color_grading | lut_texel: reference/unity_urp/unity_urp.h) or `ue58` (settings and `r.*=` cvars
// resolved by resolve58 as a one-pixel case, `stage=` ui_composite | vignette, `ui=` the UI pixel:
// reference/ue/ue58/ue58_named_values.h). Values are r,g,b,a lists where a
// setting has components. Each row is an intermediate value's name
// and its one or three numbers; the test evaluates the pixel with the reference's own stage
// functions (their traces, by name: reference/named_values.h), and every row must equal the code's
// value to the 9 significant digits printed, and every intermediate value the code names for that
// pixel must be in the block (the FilmToneMap steps inside another pipeline's pixel are optional
// there: film_tonemap.md lists them). A block whose info string starts with `spec-constants` lists
// parameter-block fields by their params.json names (M3: nine numbers, row-major) for the settings
// given, checked the same way. On a mismatch the test prints the block as the code computes it.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "core/case.h"
#include "core/cube/cube.h"
#include "core/pipeline.h"
#include "core/settings.h"
#include "core/shader_interface.h"
#include "reference/operators/operators.h"
#include "reference/operators/operators_settings.h"
#include "reference/pq_grading/pq_grading.h"
#include "reference/ue/cpp/resolve.h"
#include "reference/ue/grading/film_tonemap.h"
#include "reference/ue/ue55/ue55_named_values.h"
#include "reference/ue/ue58/ue58_named_values.h"
#include "reference/ue/ue58/ue58_pipeline.h"
#include "reference/unity_urp/unity_urp.h"
#include "reference/unity_urp/unity_urp_settings.h"

namespace {

namespace fs = std::filesystem;
using hdrc::ParamBlock;
using hdrc::ref::Vec3;
namespace ops = hdrc::ref::operators;
namespace pqg = hdrc::ref::pq_grading;
namespace grading = hdrc::ref::grading;

const fs::path kRoot = HDRC_SOURCE_DIR;
const fs::path kSpecDir = kRoot / "docs" / "spec";

struct Block {
  std::string file;
  int line = 0;      // of the opening fence
  std::string kind;  // worked-pixel | spec-constants
  std::string pipeline;
  std::vector<std::pair<std::string, std::string>> options;  // Setting=Value, cube=...
  std::vector<std::pair<std::string, std::vector<double>>> rows;
};

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<fs::path> spec_pages() {
  std::vector<fs::path> out;
  if (fs::is_directory(kSpecDir))
    for (const auto& e : fs::directory_iterator(kSpecDir))
      if (e.path().extension() == ".md") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

// The marked blocks of one page. A malformed row (no name, a value that is not a number) fails
// the test at its line.
std::vector<Block> blocks_of(const fs::path& page) {
  std::vector<Block> out;
  std::istringstream text(read_text(page));
  std::string line;
  Block* open = nullptr;
  bool in_other_fence = false;
  for (int number = 1; std::getline(text, line); ++number) {
    const bool fence = line.rfind("```", 0) == 0;
    if (open) {
      if (fence) {
        open = nullptr;
        continue;
      }
      std::istringstream fields(line);
      std::string name;
      if (!(fields >> name) || name[0] == '#') continue;
      std::vector<double> values;
      for (std::string v; fields >> v;) {
        char* end = nullptr;
        const double d = std::strtod(v.c_str(), &end);
        if (end != v.c_str() + v.size()) {
          ADD_FAILURE() << page.string() << ":" << number << ": '" << v << "' is not a number";
          break;
        }
        values.push_back(d);
      }
      open->rows.push_back({name, values});
      continue;
    }
    if (!fence) continue;
    if (in_other_fence) {
      in_other_fence = false;
      continue;
    }
    std::istringstream info(line.substr(3));
    std::string kind;
    info >> kind;
    if (kind != "worked-pixel" && kind != "spec-constants") {
      in_other_fence = true;
      continue;
    }
    Block b;
    b.file = page.filename().string();
    b.line = number;
    b.kind = kind;
    info >> b.pipeline;
    for (std::string opt; info >> opt;) {
      const size_t eq = opt.find('=');
      if (eq == std::string::npos) {
        ADD_FAILURE() << page.string() << ":" << number << ": option '" << opt
                      << "' is not NAME=VALUE";
        continue;
      }
      b.options.push_back({opt.substr(0, eq), opt.substr(eq + 1)});
    }
    out.push_back(std::move(b));
    open = &out.back();
  }
  return out;
}

std::vector<Block> all_blocks() {
  std::vector<Block> out;
  for (const fs::path& p : spec_pages())
    for (Block& b : blocks_of(p)) out.push_back(std::move(b));
  return out;
}

// The code's values of one pixel: name → numbers, and whether the block must list it.
struct Computed {
  std::map<std::string, std::vector<double>> values;
  std::set<std::string> optional;
  std::vector<std::string> order;  // for the printed block
  void add(const std::string& name, std::vector<double> v, bool required = true) {
    if (!values.count(name)) order.push_back(name);
    values[name] = std::move(v);
    if (!required) optional.insert(name);
  }
  void add(const std::string& name, const Vec3& v, bool required = true) {
    add(name, std::vector<double>{v[0], v[1], v[2]}, required);
  }
  void add(const std::string& name, double v, bool required = true) {
    add(name, std::vector<double>{v}, required);
  }
};

// Settings NAME=VALUE (a number or a named value) into `s`; other options are left to the caller.
void apply_settings(const Block& b, hdrc::SettingValues* s) {
  for (const auto& [name, value] : b.options) {
    if (name == "cube") continue;
    // A number, r,g,b,a (up to four numbers), or a named value.
    hdrc::Vec4d v{0, 0, 0, 0};
    int n = 0;
    std::stringstream list(value);
    for (std::string part; n >= 0 && std::getline(list, part, ',');) {
      char* end = nullptr;
      const double d = std::strtod(part.c_str(), &end);
      if (part.empty() || end != part.c_str() + part.size() || n == 4)
        n = -1;
      else
        v[n++] = d;
    }
    const hdrc::Status st = n > 0 ? s->set(name, v, n) : s->set_choice(name, value);
    EXPECT_TRUE(bool(st)) << b.file << ":" << b.line << ": " << name << "=" << value << ": "
                          << (st ? "" : st.error().message);
  }
}

ParamBlock operators_params(const Block& b) {
  hdrc::SettingValues s = ops::operators_settings();
  apply_settings(b, &s);
  ParamBlock p;
  ops::derive_operators(s, &p);
  return p;
}

// The reference's named values of a pixel as the block's Computed (`detail` values optional).
Computed computed_from(const std::vector<hdrc::ref::NamedValue>& values) {
  Computed c;
  for (const auto& v : values) c.add(v.name, v.v, !v.detail);
  return c;
}

Vec3 input_of(const Block& b) {
  for (const auto& [name, v] : b.rows)
    if (name == "input" && v.size() == 3) return {v[0], v[1], v[2]};
  ADD_FAILURE() << b.file << ":" << b.line << ": no 'input' row of three numbers";
  return {0, 0, 0};
}

Computed compute_film_tonemap(const Block& b) {
  const ParamBlock p = operators_params(b);
  const grading::FilmParams film{p.film_slope, p.film_toe, p.film_shoulder, p.film_black_clip,
                                 p.film_white_clip};
  return computed_from(grading::film_tone_map_named_values(input_of(b), film));
}

Computed compute_operators(const Block& b) {
  return computed_from(ops::named_values(operators_params(b), input_of(b)));
}

// The .cube as the loader hands it to the engines (its table as the strip texture).
struct LoadedLut {
  hdrc::UserLut lut;
  hdrc::Image strip;
};

Computed compute_pq_grading(const Block& b) {
  hdrc::SettingValues s(&pqg::pq_grading_setting_table(), &pqg::pq_grading_setting_choices);
  apply_settings(b, &s);
  ParamBlock p;
  pqg::derive_pq_grading(s, &p);
  std::string cube_path;
  for (const auto& [name, value] : b.options)
    if (name == "cube") cube_path = value;
  auto cube = hdrc::cube::read_cube_file((kRoot / cube_path).string());
  if (cube_path.empty() || !cube) {
    ADD_FAILURE() << b.file << ":" << b.line << ": cube=" << cube_path << " cannot be read";
    return {};
  }
  LoadedLut l;
  l.lut.size = cube->size_3d;
  l.lut.domain_min = cube->domain_min_3d;
  l.lut.domain_max = cube->domain_max_3d;
  l.lut.table = cube->table_3d;
  l.strip = hdrc::user_lut_strip(l.lut);
  p.user_lut_size = l.lut.size;
  for (int i = 0; i < 3; ++i) {
    p.user_lut_domain_min[i] = l.lut.domain_min[i];
    p.user_lut_domain_max[i] = l.lut.domain_max[i];
  }
  const pqg::StripLut lut = pqg::strip_lut(l.strip, p);
  return computed_from(pqg::named_values(p, lut, input_of(b)));
}

// UE 5.5: options `stage=` (tonemap, the default; ui_composite; visualize_false_colour),
// `ui=r,g,b,a` (ui_composite's premultiplied UI pixel), `r.*=` cvars, other NAME=VALUE settings (a
// number, r,g,b,a, or a named value), resolved as a case of one pixel (reference/ue/cpp/resolve.h).
// UE 5.5's parameter block for a block's options (`stage=` and `ui=` are returned, not applied).
struct Ue55Options {
  std::string stage = "tonemap";
  std::array<double, 4> ui{0, 0, 0, 0};
};
ParamBlock ue55_params(const Block& b, Ue55Options* o) {
  hdrc::Case c;
  c.id = "spec";
  c.stage = hdrc::find_stage("tonemap");
  const std::string where = b.file + ":" + std::to_string(b.line);
  auto numbers = [&](const std::string& text) {
    std::vector<double> v;
    std::stringstream list(text);
    for (std::string part; std::getline(list, part, ',');) {
      char* end = nullptr;
      const double d = std::strtod(part.c_str(), &end);
      if (part.empty() || end != part.c_str() + part.size()) return std::vector<double>{};
      v.push_back(d);
    }
    return v;
  };
  for (const auto& [name, value] : b.options) {
    const std::vector<double> v = numbers(value);
    if (name == "stage") {
      o->stage = value;
    } else if (name == "ui") {
      EXPECT_EQ(v.size(), 4u) << where << ": ui=" << value << " is not r,g,b,a";
      for (size_t i = 0; i < 4 && i < v.size(); ++i) o->ui[i] = v[i];
    } else if (name.rfind("r.", 0) == 0) {
      EXPECT_EQ(v.size(), 1u) << where << ": " << name << "=" << value << " is not a number";
      const hdrc::Status st = c.cvars.set(name, v.empty() ? 0.0 : v[0]);
      EXPECT_TRUE(bool(st)) << where << ": " << name << ": " << (st ? "" : st.error().message);
    } else {
      hdrc::Vec4d x{0, 0, 0, 0};
      for (size_t i = 0; i < 4 && i < v.size(); ++i) x[i] = v[i];
      const hdrc::Status st = v.empty() ? c.settings.set_choice(name, value)
                                        : c.settings.set(name, x, static_cast<int>(v.size()));
      EXPECT_TRUE(bool(st)) << where << ": " << name << "=" << value << ": "
                            << (st ? "" : st.error().message);
    }
  }
  auto resolution = hdrc::ref::resolve(c, 1, 1);
  if (!resolution) {
    ADD_FAILURE() << where << ": " << resolution.error().message;
    return {};
  }
  return resolution->params;
}

// UE 5.5: options `stage=` (tonemap, the default; ui_composite; visualize_false_colour),
// `ui=r,g,b,a` (ui_composite's premultiplied UI pixel), `r.*=` cvars, other NAME=VALUE settings (a
// number, r,g,b,a, or a named value), resolved as a case of one pixel (reference/ue/cpp/resolve.h).
Computed compute_ue55(const Block& b) {
  Ue55Options o;
  const ParamBlock p = ue55_params(b, &o);
  const std::string& stage = o.stage;
  const std::array<double, 4>& ui = o.ui;
  namespace ue55 = hdrc::ref::ue55;
  if (stage == "tonemap") return computed_from(ue55::tonemap_named_values(p, input_of(b)));
  if (stage == "ui_composite")
    return computed_from(ue55::ui_composite_named_values(p, input_of(b), ui));
  if (stage == "visualize_false_colour")
    return computed_from(ue55::visualize_false_colour_named_values(p, input_of(b)));
  ADD_FAILURE() << b.file << ":" << b.line << ": stage=" << stage
                << ": valid: tonemap, ui_composite, visualize_false_colour";
  return {};
}

// UE 5.8: option `stage=` (ui_composite, the default; vignette: the Tonemap pass's vignette mask,
// whose input row is the screen position and the viewport's height / width; dither: the dither
// stage's host values, for spec-constants; visualize: VisualizeHDR over a view of `width=` x
// `height=` pixels of the input colour), `ui=r,g,b,a` (the premultiplied UI pixel); every other
// NAME=VALUE is one of the ue58 pipeline's settings when its table names it (its own r.HDR.UI.*
// console variables among them, docs/ue58-decisions.md E4), else a cvar (`r.*=`), resolved by the
// pipeline's host derivation as a case of one pixel of the stage. UE 5.8's parameter block for a
// block's options (`stage=` and `ui=` are returned, not applied).
struct Ue58Options {
  std::string stage = "ui_composite";
  std::array<double, 4> ui{0, 0, 0, 0};
  int width = 1, height = 1;  // the case's image (visualize: the view VisualizeHDR draws on)
};
ParamBlock ue58_params(const Block& b, Ue58Options* o) {
  const hdrc::Pipeline& pipeline = hdrc::ref::ue58::ue58_pipeline();
  const std::string where = b.file + ":" + std::to_string(b.line);
  hdrc::Case c;
  c.id = "spec";
  c.settings = pipeline.new_settings();
  Block settings = b;
  settings.options.clear();
  for (const auto& option : b.options) {
    const std::string& name = option.first;
    const std::string& value = option.second;
    const bool is_setting = std::any_of(pipeline.settings().begin(), pipeline.settings().end(),
                                        [&](const hdrc::SettingInfo& i) { return i.name == name; });
    if (name == "stage") {
      o->stage = value;
    } else if (name == "width" || name == "height") {
      (name == "width" ? o->width : o->height) = std::atoi(value.c_str());
    } else if (name == "ui") {
      int n = 0;
      std::stringstream list(value);
      for (std::string part; std::getline(list, part, ',') && n < 4;)
        o->ui[n++] = std::strtod(part.c_str(), nullptr);
      EXPECT_EQ(n, 4) << where << ": ui=" << value << " is not r,g,b,a";
    } else if (!is_setting && name.rfind("r.", 0) == 0) {
      char* end = nullptr;
      const double v = std::strtod(value.c_str(), &end);
      EXPECT_TRUE(!value.empty() && end == value.c_str() + value.size())
          << where << ": " << name << "=" << value << " is not a number";
      const hdrc::Status st = c.cvars.set(name, v);
      EXPECT_TRUE(bool(st)) << where << ": " << name << ": " << (st ? "" : st.error().message);
    } else {
      settings.options.push_back({name, value});
    }
  }
  apply_settings(settings, &c.settings);
  const std::map<std::string, std::string> stages = {{"ui_composite", "ue58_ui_composite"},
                                                     {"vignette", "ue58_tonemap"},
                                                     {"dither", "ue58_dither"},
                                                     {"visualize", "ue58_visualize_hdr"}};
  if (!stages.count(o->stage)) {
    ADD_FAILURE() << where << ": stage=" << o->stage
                  << ": valid: ui_composite, vignette, dither, visualize";
    return {};
  }
  c.stage = hdrc::find_stage(pipeline, stages.at(o->stage));
  auto resolution = pipeline.resolve(c, o->width, o->height);
  if (!resolution) {
    ADD_FAILURE() << where << ": " << resolution.error().message;
    return {};
  }
  return resolution->params;
}

Computed compute_ue58(const Block& b) {
  namespace ue58 = hdrc::ref::ue58;
  Ue58Options o;
  const ParamBlock p = ue58_params(b, &o);
  const Vec3 in = input_of(b);
  if (o.stage == "vignette")  // the input is the screen position and height / width
    return computed_from(ue58::vignette_named_values(p, in[0], in[1], in[2]));
  if (o.stage == "ui_composite") return computed_from(ue58::ui_composite_named_values(p, in, o.ui));
  if (o.stage == "visualize") {  // the input is the colour of every pixel of the view
    hdrc::ResolvedCase rc;
    rc.spec.stage = hdrc::find_stage(ue58::ue58_pipeline(), "ue58_visualize_hdr");
    rc.params = p;
    rc.input = hdrc::Image(o.width, o.height);
    for (size_t i = 0; i < rc.input.pixel_count(); ++i)
      for (int c = 0; c < 4; ++c) rc.input.data[i * 4 + c] = c < 3 ? in[c] : 1.0;
    const auto values = ue58::visualize_named_values(rc);
    EXPECT_FALSE(values.empty()) << b.file << ":" << b.line << ": the reference failed";
    return computed_from(values);
  }
  ADD_FAILURE() << b.file << ":" << b.line << ": stage=" << o.stage
                << " names no per-pixel values; valid: ui_composite, vignette, visualize";
  return {};
}

// Unity URP: option `stage=` (color_grading, the default: the input is a scene colour; lut_texel:
// the input is a lattice code), other NAME=VALUE settings (unity_urp_settings.h).
Computed compute_unity_urp(const Block& b) {
  namespace urp = hdrc::ref::unity_urp;
  hdrc::SettingValues s(&hdrc::unity_urp_setting_table(), &hdrc::unity_urp_setting_choices);
  Block settings = b;
  std::string stage = "color_grading";
  settings.options.clear();
  for (const auto& o : b.options) {
    if (o.first == "stage")
      stage = o.second;
    else
      settings.options.push_back(o);
  }
  apply_settings(settings, &s);
  ParamBlock p;
  hdrc::derive_unity_urp(s, &p);
  if (stage == "lut_texel") return computed_from(urp::texel_named_values(p, input_of(b)));
  if (stage == "color_grading")
    return computed_from(urp::named_values(p, urp::bake_lut_strip(p), input_of(b)));
  ADD_FAILURE() << b.file << ":" << b.line << ": stage=" << stage
                << ": valid: color_grading, lut_texel";
  return {};
}

Computed compute_constants(const Block& b) {
  Computed c;
  ParamBlock p;
  if (b.pipeline == "operators") {
    p = operators_params(b);
  } else if (b.pipeline == "pq_grading") {
    hdrc::SettingValues s(&pqg::pq_grading_setting_table(), &pqg::pq_grading_setting_choices);
    apply_settings(b, &s);
    pqg::derive_pq_grading(s, &p);
  } else if (b.pipeline == "ue55") {
    Ue55Options o;
    p = ue55_params(b, &o);
  } else if (b.pipeline == "ue58") {
    Ue58Options o;
    p = ue58_params(b, &o);
  } else {
    ADD_FAILURE() << b.file << ":" << b.line << ": unknown pipeline '" << b.pipeline
                  << "'; valid: operators, pq_grading, ue55, ue58";
    return c;
  }
  hdrc::for_each_param(p, [&](hdrc::FieldKind, const char* name, const auto& v) {
    using T = std::decay_t<decltype(v)>;
    if constexpr (std::is_same_v<T, int32_t> || std::is_same_v<T, double>)
      c.add(name, static_cast<double>(v), false);
    else if constexpr (std::is_same_v<T, std::array<double, 4>>)
      c.add(name, std::vector<double>(v.begin(), v.end()), false);
    else if constexpr (hdrc::kIsVec4Array<T>) {
      std::vector<double> flat;
      for (const auto& e : v) flat.insert(flat.end(), e.begin(), e.end());
      c.add(name, flat, false);
    } else
      c.add(name, std::vector<double>(v.m.begin(), v.m.end()), false);
  });
  return c;
}

// %.9g, with NaN and ±Inf written as the pages write them (strtod reads both forms).
std::string g9(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "Inf" : "-Inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

// 9 significant digits: the printed value is within half a unit of the 9th digit, 5e-9 relative.
bool same(double doc, double code) {
  if (std::isnan(doc) || std::isnan(code)) return std::isnan(doc) && std::isnan(code);
  if (doc == code) return true;
  return std::fabs(doc - code) <= 6e-9 * std::fabs(code);
}

void check_block(const Block& b, const Computed& c) {
  const std::string where = b.file + ":" + std::to_string(b.line);
  bool ok = true;
  std::set<std::string> listed;
  for (const auto& [name, doc] : b.rows) {
    listed.insert(name);
    const auto it = c.values.find(name);
    if (it == c.values.end()) {
      ADD_FAILURE() << where << ": '" << name << "' is not an intermediate value the code names";
      ok = false;
      continue;
    }
    const std::vector<double>& code = it->second;
    bool row_ok = doc.size() == code.size();
    for (size_t i = 0; row_ok && i < doc.size(); ++i) row_ok = same(doc[i], code[i]);
    if (!row_ok) {
      std::string d, k;
      for (double v : doc) d += " " + g9(v);
      for (double v : code) k += " " + g9(v);
      ADD_FAILURE() << where << ": " << name << ": the page says" << d << ", the code gives" << k;
      ok = false;
    }
  }
  for (const std::string& name : c.order)
    if (!c.optional.count(name) && !listed.count(name)) {
      ADD_FAILURE() << where << ": the block does not list '" << name << "'";
      ok = false;
    }
  if (!ok) {
    std::string text;
    for (const std::string& name : c.order) {
      if (c.optional.count(name) && !listed.count(name)) continue;
      text += name;
      for (double v : c.values.at(name)) {
        // Two appends, not `" " + g9(v)`: GCC 12 at -O3 warns (-Wrestrict) about the inlined
        // operator+(const char*, string&&) (a false positive of that compiler).
        text += ' ';
        text += g9(v);
      }
      text += "\n";
    }
    ADD_FAILURE() << where << ": the code's values of this pixel:\n" << text;
  }
}

TEST(SpecPages, EveryWorkedPixelMatchesTheCode) {
  const std::vector<Block> blocks = all_blocks();
  int pixels = 0;
  for (const Block& b : blocks) {
    SCOPED_TRACE(b.file + ":" + std::to_string(b.line) + " " + b.kind + " " + b.pipeline);
    if (b.kind == "spec-constants") {
      check_block(b, compute_constants(b));
      continue;
    }
    ++pixels;
    if (b.pipeline == "operators")
      check_block(b, compute_operators(b));
    else if (b.pipeline == "pq_grading")
      check_block(b, compute_pq_grading(b));
    else if (b.pipeline == "film_tonemap")
      check_block(b, compute_film_tonemap(b));
    else if (b.pipeline == "ue55")
      check_block(b, compute_ue55(b));
    else if (b.pipeline == "unity_urp")
      check_block(b, compute_unity_urp(b));
    else if (b.pipeline == "ue58")
      check_block(b, compute_ue58(b));
    else
      ADD_FAILURE() << b.file << ":" << b.line << ": unknown pipeline '" << b.pipeline
                    << "'; valid: operators, pq_grading, film_tonemap, ue55, unity_urp, ue58";
  }
  // operators: one per operator; pq_grading: HDR and SDR; film_tonemap: one; ue55: one per stage
  // and device path (docs/spec/ue55.md §15); unity_urp: each grading and tone-mapping mode, bake
  // and lookup (docs/spec/unity_urp.md §9); ue58: the UI composite's five, VisualizeHDR's two and
  // the Texture vignette's four (docs/spec/ue58.md §1, §3, §4).
  EXPECT_GE(pixels, 9 + 9 + 10 + 5 + 2 + 4);
}

// Each pipeline page has at least one worked pixel, and links the shared semantics page.
TEST(SpecPages, EveryPipelinePageHasAWorkedPixelAndLinksTheSemantics) {
  for (const char* page :
       {"operators.md", "pq_grading.md", "film_tonemap.md", "ue55.md", "unity_urp.md", "ue58.md"}) {
    SCOPED_TRACE(page);
    ASSERT_TRUE(fs::exists(kSpecDir / page));
    int pixels = 0;
    for (const Block& b : blocks_of(kSpecDir / page)) pixels += b.kind == "worked-pixel";
    EXPECT_GE(pixels, 1);
    EXPECT_NE(read_text(kSpecDir / page).find("(semantics.md)"), std::string::npos);
  }
}

// The anchors of a page's headings as GitHub makes them: lower case, every character but letters,
// digits, spaces, '-' and '_' dropped, spaces as '-'.
std::set<std::string> anchors_of(const fs::path& page) {
  std::set<std::string> out;
  std::istringstream text(read_text(page));
  bool fenced = false;
  for (std::string line; std::getline(text, line);) {
    if (line.rfind("```", 0) == 0) fenced = !fenced;
    if (fenced || line.empty() || line[0] != '#') continue;
    const size_t start = line.find_first_not_of('#');
    std::string slug;
    for (char ch : line.substr(line.find_first_not_of(' ', start))) {
      const unsigned char u = static_cast<unsigned char>(ch);
      if (std::isalnum(u) || ch == '-' || ch == '_')
        slug += static_cast<char>(std::tolower(u));
      else if (ch == ' ')
        slug += '-';
      else if (u >= 0x80)
        slug += ch;  // UTF-8 letters stay
    }
    out.insert(slug);
  }
  return out;
}

// The spec pages and the pages a port starts from (the candidate protocol, every stage's candidate
// page, the diagnosis hints) link only files of this repository: every relative link resolves, to
// a heading where it names one, and no link or cited path is absolute.
TEST(SpecPages, LinksStayInsideTheRepository) {
  std::vector<fs::path> pages = spec_pages();
  // and the pages that cite sections of docs/spec/ue55.md and unity_urp.md by link.
  for (const char* p : {"operators.md", "pq_grading.md", "candidate-protocol.md", "unity_urp.md",
                        "diagnosis.md", "ue55-decisions.md", "unity_urp-spec.md",
                        "ue55-lut-blend-spec.md", "diff-metrics.md", "cases.md"})
    pages.push_back(kRoot / "docs" / p);
  for (const auto& e : fs::directory_iterator(kRoot / "docs" / "candidates"))
    if (e.path().extension() == ".md") pages.push_back(e.path());
  const std::regex link(R"(\]\(([^)#\s]*)(#[^)\s]*)?\))");
  for (const fs::path& page : pages) {
    const std::string text = read_text(page);
    for (auto it = std::sregex_iterator(text.begin(), text.end(), link);
         it != std::sregex_iterator(); ++it) {
      const std::string target = (*it)[1];
      if (target.rfind("http", 0) == 0) continue;
      EXPECT_TRUE(target.empty() || target[0] != '/')
          << page.filename() << ": absolute link " << target;
      const fs::path file = target.empty() ? page : page.parent_path() / target;
      EXPECT_TRUE(fs::exists(file))
          << page.filename() << ": link to " << target << " does not resolve";
      const std::string anchor = (*it)[2];
      if (!anchor.empty() && file.extension() == ".md" && fs::exists(file)) {
        EXPECT_TRUE(anchors_of(file).count(anchor.substr(1)))
            << page.filename() << ": " << target << anchor << " names no heading";
      }
    }
    // No path of the machine that wrote the page: neither this checkout's own folder nor any
    // absolute path in a code span (a porter has the clone only).
    EXPECT_EQ(text.find(HDRC_SOURCE_DIR), std::string::npos)
        << page.filename() << " names this checkout's absolute path";
    static const std::regex absolute_span("`/[^`\\s]+`");
    std::smatch m;
    EXPECT_FALSE(std::regex_search(text, m, absolute_span))
        << page.filename() << " names a path outside the repository: " << m.str();
  }
}

}  // namespace
