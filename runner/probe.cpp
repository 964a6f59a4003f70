#include "runner/probe.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <istream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <sstream>

#include "color/d3d_math.h"
#include "core/named_value.h"
#include "core/pipeline.h"
#include "reference/reference_engine.h"
#include "reference/ue/combine_luts.h"
#include "reference/ue/cpp/resolve.h"
#include "reference/ue/lut_shaper.h"
#include "reference/ue/tonemap.h"
#include "reference/ue/visualize/visualize_hdr.h"
#include "runner/case_loader.h"

namespace hdrc {

namespace {

const std::vector<std::string>& stages() {
  static const std::vector<std::string> s = {
      "lattice",         "decoded", "white_balanced", "ap1",          "expanded",
      "color_corrected", "film",    "graded",         "aces_nits",    "device",
      "stored",          "lut",     "output",         "ui_composite", "visualize_false_colour"};
  return s;
}

std::optional<double> parse_number(const std::string& s) {
  try {
    size_t used = 0;
    const double v = std::stod(s, &used);
    if (used != s.size()) return std::nullopt;
    return v;
  } catch (...) {
    return std::nullopt;
  }
}

// The three numbers of an "R G B" line, quickly: whitespace-separated tokens, each parsed whole
// by std::from_chars (correctly rounded, as strtod). Anything else — another token count, a sign
// or hex form from_chars does not take, a value out of range — returns false and the line goes
// through the general parser below, which gives every answer and error message as before.
bool parse_rgb_fast(const std::string& line, double out[3]) {
  const char* p = line.data();
  const char* const end = p + line.size();
  int n = 0;
  while (p < end) {
    while (p < end && std::isspace(static_cast<unsigned char>(*p))) ++p;
    if (p == end) break;
    const char* q = p;
    while (q < end && !std::isspace(static_cast<unsigned char>(*q))) ++q;
    if (n == 3) return false;
    const auto r = std::from_chars(p, q, out[n]);
    if (r.ec != std::errc() || r.ptr != q) return false;
    // std::stod rejects a result that underflows to a subnormal (ERANGE); so does this path.
    if (out[n] != 0.0 && std::fabs(out[n]) < std::numeric_limits<double>::min()) return false;
    ++n;
    p = q;
  }
  return n == 3;
}

// A number for JSON, which has no NaN or Inf: those as the strings "NaN", "Infinity", "-Infinity"
// (as params.json writes them).
nlohmann::ordered_json json_number(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "Infinity" : "-Infinity";
  return v;
}

// Appends "a b c\n" with format_number's %.9g: std::to_chars with a precision formats as printf
// does in the "C" locale ([charconv.to.chars]), without a std::string per number.
void append_line(std::string& buf, const ref::Vec3& v) {
  char tmp[96];
  char* p = tmp;
  for (int k = 0; k < 3; ++k) {
    if (k) *p++ = ' ';
    p = std::to_chars(p, tmp + sizeof tmp, v[k], std::chars_format::general, 9).ptr;
  }
  *p++ = '\n';
  buf.append(tmp, p);
}

ref::Vec3 pick(const std::string& stage, const ref::CombineLutsTrace& c,
               const ref::TonemapTrace& t) {
  if (stage == "lattice") return c.lattice;
  if (stage == "decoded") return c.decoded;
  if (stage == "white_balanced") return c.white_balanced;
  if (stage == "ap1") return c.ap1;
  if (stage == "expanded") return c.expanded;
  if (stage == "color_corrected") return c.color_corrected;
  if (stage == "film") return c.film;
  if (stage == "graded") return c.graded;
  if (stage == "aces_nits") return c.aces_nits;
  if (stage == "device") return c.device;
  if (stage == "stored") return c.stored;
  if (stage == "lut") return t.lut;
  return t.output;
}

}  // namespace

bool read_bounded_line(std::istream& in, std::string* line, size_t max_length) {
  line->clear();
  std::streambuf* sb = in.rdbuf();
  for (;;) {
    const int c = sb->sbumpc();
    if (c == std::char_traits<char>::eof()) {
      in.setstate(std::ios::eofbit);
      return !line->empty();
    }
    if (c == '\n') return true;
    line->push_back(static_cast<char>(c));
    if (line->size() > max_length) return true;
  }
}

std::string probe_stage_names() {
  std::string out;
  for (const auto& s : stages()) out += (out.empty() ? "" : ", ") + s;
  return out;
}

namespace {

constexpr size_t kMaxProbeLine = kMaxInputLine;

}  // namespace

namespace {

// "R G B" from a line, or nullopt.
std::optional<ref::Vec3> parse_rgb_line(const std::string& line) {
  double fast[3];
  if (parse_rgb_fast(line, fast)) return ref::Vec3{fast[0], fast[1], fast[2]};
  std::istringstream fields(line);
  std::string a, b, d, extra;
  fields >> a >> b >> d;
  const auto r = parse_number(a), g = parse_number(b), bl = parse_number(d);
  if (!r || !g || !bl || (fields >> extra)) return std::nullopt;
  return ref::Vec3{*r, *g, *bl};
}

// --ui r,g,b,a: the premultiplied UI pixel of a UI composite stage.
Result<std::array<double, 4>> parse_ui_pixel(const std::string& text) {
  std::array<double, 4> ui{0, 0, 0, 0};
  std::stringstream list(text);
  int n = 0;
  for (std::string part; std::getline(list, part, ',');) {
    const auto x = parse_number(part);
    if (!x || n == 4) return Error{"--ui", text, "expected r,g,b,a (premultiplied)", ""};
    ui[n++] = *x;
  }
  if (n != 4) return Error{"--ui", text, "expected r,g,b,a (premultiplied)", ""};
  return ui;
}

// --setting NAME=VALUE (a number, r,g,b,a, or a named value) into `settings`.
Status parse_probe_setting(const std::string& kv, SettingValues* settings) {
  const size_t eq = kv.find('=');
  if (eq == std::string::npos) return Error{"--setting", kv, "expected NAME=VALUE", ""};
  if (settings->choices(kv.substr(0, eq)) && !parse_number(kv.substr(eq + 1))) {  // a name
    if (Status st = settings->set_choice(kv.substr(0, eq), kv.substr(eq + 1)); !st)
      return Error{"--setting", kv, st.error().message, st.error().choices};
    return {};
  }
  Vec4d v{0, 0, 0, 0};
  int n = 0;
  std::stringstream list(kv.substr(eq + 1));
  for (std::string part; std::getline(list, part, ',');) {
    const auto x = parse_number(part);
    if (!x || n == 4) return Error{"--setting", kv, "expected a number or r,g,b,a", ""};
    v[n++] = *x;
  }
  if (Status st = settings->set(kv.substr(0, eq), v, n); !st)
    return Error{"--setting", kv, st.error().message, st.error().choices};
  return {};
}

// --set CVAR=NUMBER (repeatable) into the case's cvars: a number, and a cvar of the pipeline's
// table with a valid value, or the cvar table's error naming the choices.
Status apply_set_cvars(const std::vector<std::string>& sets, Case* c) {
  for (const std::string& kv : sets) {
    const size_t eq = kv.find('=');
    const auto value = eq == std::string::npos ? std::nullopt : parse_number(kv.substr(eq + 1));
    if (!value) return Error{"--set", kv, "expected CVAR=NUMBER", ""};
    if (Status st = c->cvars.set(kv.substr(0, eq), *value); !st)
      return Error{"--set", kv, st.error().message, st.error().choices};
  }
  return {};
}

// probe for a pipeline other than UE 5.5: the colours as one row of pixels through the pipeline's
// reference for the chosen stage.
Status run_pipeline_probe(const Pipeline& pipeline, const ProbeOptions& o, std::istream& in,
                          std::ostream& out) {
  Case c;
  c.id = "probe";
  c.settings = pipeline.new_settings();
  std::string choices;
  for (const StageInfo& s : pipeline.stages())
    if (s.takes_input) {
      choices += (choices.empty() ? "" : ", ") + std::string(s.name);
      c.stage = &s;  // the default: the last stage that takes an input
    }
  if (o.stage != "output") {
    const StageInfo* s = find_stage(pipeline, o.stage);
    if (!s || !s->takes_input)
      return Error{"--stage", o.stage,
                   "not a stage of pipeline " + std::string(pipeline.name) + " that reads colours",
                   choices};
    c.stage = s;
  }
  if (!c.stage)
    return Error{"--pipeline", std::string(pipeline.name), "no stage of it reads colours", ""};
  if (!o.set.empty() && pipeline.cvars().empty())
    return Error{
        "--set", o.set.front(), "pipeline " + std::string(pipeline.name) + " has no cvars",
        "--setting NAME=VALUE (hdrconform cvars --pipeline " + std::string(pipeline.name) + ")"};
  // A pipeline with UE's cvars (ue58): --set CVAR=NUMBER as for UE 5.5.
  if (Status st = apply_set_cvars(o.set, &c); !st) return st;
  // A UI composite stage (ue58_ui_composite): --ui is the UI pixel over every colour.
  std::array<double, 4> ui_pixel{0, 0, 0, 0};
  if (c.stage->id == StageId::kUiComposite) {
    const auto parsed_ui = parse_ui_pixel(o.ui);
    if (!parsed_ui) return parsed_ui.error();
    ui_pixel = *parsed_ui;
  }
  if (o.json && !pipeline.named_values) {
    std::string named = "ue55";
    for (const Pipeline* p : pipeline_table())
      if (p->named_values) named += ", " + std::string(p->name);
    return Error{"--json", "",
                 "JSON output is for the pipelines whose specification names each intermediate "
                 "value",
                 "--pipeline " + named + "; plain \"R G B\" lines"};
  }
  for (const std::string& kv : o.setting)
    if (Status st = parse_probe_setting(kv, &c.settings); !st) return st;
  // The user LUT (docs/cases.md): required where the stage takes one, refused elsewhere.
  if (!o.cube.empty()) {
    if (c.stage->user_lut == 0)
      return Error{"--cube", o.cube, "stage " + std::string(c.stage->name) + " takes no user LUT",
                   ""};
    auto lut = read_user_lut("", o.cube, c.stage);
    if (!lut) return Error{"--cube", o.cube, lut.error().message, lut.error().choices};
    c.lut = *lut;
  } else if (c.stage->user_lut != 0 && !c.stage->user_lut_optional) {
    return Error{"--cube", "", "stage " + std::string(c.stage->name) + " needs a user LUT",
                 user_lut_choices("", c.stage)};
  }

  std::vector<ref::Vec3> colours;
  std::vector<int> numbers;  // each colour's input line
  std::string line;
  for (int number = 1; read_bounded_line(in, &line, kMaxInputLine); ++number) {
    if (line.size() > kMaxInputLine)
      return Error{"<stdin>", "line " + std::to_string(number),
                   "longer than " + std::to_string(kMaxInputLine) + " characters",
                   "\"R G B\" lines"};
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const auto rgb = parse_rgb_line(line);
    if (!rgb)
      return Error{"<stdin>", "line " + std::to_string(number),
                   "expected three numbers \"R G B\", got \"" + line + "\"", ""};
    if (colours.size() == kMaxProbeColours)
      return Error{"<stdin>", "line " + std::to_string(number), "too many colours",
                   "at most " + std::to_string(kMaxProbeColours) + " per run"};
    colours.push_back(*rgb);
    numbers.push_back(number);
  }
  if (colours.empty()) return {};
  ResolvedCase rc;
  rc.spec = c;
  rc.input = Image(static_cast<int>(colours.size()), 1);
  for (size_t i = 0; i < colours.size(); ++i) {
    double* px = rc.input.px(static_cast<int>(i), 0);
    for (int k = 0; k < 3; ++k) px[k] = colours[i][k];
    px[3] = 1.0;
  }
  if (c.stage->id == StageId::kUiComposite) {
    rc.ui = Image(rc.input.width, 1);
    for (int x = 0; x < rc.ui.width; ++x)
      for (int k = 0; k < 4; ++k) rc.ui.px(x, 0)[k] = ui_pixel[k];
  }
  auto resolution = pipeline.resolve(c, rc.input.width, 1);
  if (!resolution) return resolution.error();
  rc.params = resolution->params;
  if (c.stage->id == StageId::kUiComposite) {
    // As for UE 5.5's: HDR back buffers only, and the composite's own checks (its reference).
    const std::vector<int>& devices = c.stage->devices;
    if (std::find(devices.begin(), devices.end(), rc.params.output_device) == devices.end())
      return Error{"--stage", std::string(c.stage->name),
                   "the HDR UI composite runs on HDR back buffers only (output device " +
                       std::to_string(rc.params.output_device) + ")",
                   "r.HDR.Display.OutputDevice 3, 4 (PQ), 5, 6 (scRGB), with "
                   "r.HDR.EnableHDROutput=1"};
    if (o.json)  // the plain output's reference checks them below
      if (auto checked = pipeline.reference(rc, false); !checked) return checked.error();
  }
  rc.spec.lut = c.lut;
  if (c.stage->user_lut_slots > 1) {
    if (Status st = attach_user_luts(resolution->user_luts, &rc); !st) return st;
  } else if (Status st = attach_user_lut(c.lut, &rc); !st) {
    return st;
  }
  if (o.json) {
    // Every named intermediate value of docs/spec/<pipeline>.md (its worked pixels' rows), from
    // the reference's own stage functions (Pipeline::named_values); "out" is the value the plain
    // output prints.
    const std::vector<std::vector<NamedValue>> all = pipeline.named_values(rc, colours);
    if (std::all_of(all.begin(), all.end(), [](const auto& v) { return v.empty(); }))
      return Error{"--stage", std::string(c.stage->name),
                   "docs/spec/" + std::string(pipeline.name) +
                       ".md names no intermediate values of this stage",
                   "plain \"R G B\" lines (without --json)"};
    nlohmann::ordered_json rows = nlohmann::ordered_json::array();
    for (size_t i = 0; i < colours.size() && i < all.size(); ++i) {
      const std::vector<NamedValue>& values = all[i];
      nlohmann::ordered_json v = nlohmann::ordered_json::object();
      for (const NamedValue& n : values) {
        nlohmann::ordered_json numbers_json = nlohmann::ordered_json::array();
        for (double x : n.v) numbers_json.push_back(json_number(x));
        v[n.name] = n.v.size() == 1 ? numbers_json[0] : numbers_json;
      }
      rows.push_back({{"line", numbers[i]}, {"values", v}});
    }
    const nlohmann::ordered_json doc = {
        {"pipeline", std::string(pipeline.name)},
        {"stage", std::string(c.stage->name)},
        {"names", "docs/spec/" + std::string(pipeline.name) + ".md (the worked pixels' rows)"},
        {"rows", rows}};
    out << doc.dump(2) << '\n';
    return {};
  }
  auto image = pipeline.reference(rc, /*analytic_lut=*/false);
  if (!image) return image.error();
  std::string pending;
  for (size_t i = 0; i < colours.size(); ++i) {
    const double* px = image->px(static_cast<int>(i), 0);
    append_line(pending, ref::Vec3{px[0], px[1], px[2]});
    if (pending.size() > (1u << 16)) {
      out.write(pending.data(), static_cast<std::streamsize>(pending.size()));
      pending.clear();
    }
  }
  out.write(pending.data(), static_cast<std::streamsize>(pending.size()));
  out.flush();
  return {};
}

}  // namespace

Status run_probe(const ProbeOptions& o, std::istream& in, std::ostream& out) {
  const Pipeline* pipeline = find_pipeline(o.pipeline);
  if (!pipeline) return Error{"--pipeline", o.pipeline, "unknown pipeline", pipeline_names()};
  if (pipeline != &default_pipeline()) return run_pipeline_probe(*pipeline, o, in, out);
  Case c;
  c.id = "probe";
  c.stage = find_stage("tonemap");
  if (Status st = apply_set_cvars(o.set, &c); !st) return st;
  for (const std::string& kv : o.setting)
    if (Status st = parse_probe_setting(kv, &c.settings); !st) return st;
  if (o.lut != "analytic" && o.lut != "baked")
    return Error{"--lut", o.lut, "unknown LUT mode", "analytic, baked"};
  if (std::find(stages().begin(), stages().end(), o.stage) == stages().end())
    return Error{"--stage", o.stage, "unknown stage", probe_stage_names()};

  auto resolution = ref::resolve(c, 1, 1);
  if (!resolution) return resolution.error();
  const ParamBlock& p = resolution->params;
  const auto parsed_ui = parse_ui_pixel(o.ui);
  if (!parsed_ui) return parsed_ui.error();
  const ref::ui::Vec4 ui_pixel = *parsed_ui;
  const ref::ui::UiCompositeParams ui_params = ref::ui_composite_params(p);
  if (o.stage == "ui_composite") {
    if (p.output_device < 3 || p.output_device > 6)
      return Error{"--stage", o.stage,
                   "the HDR UI composite runs on HDR back buffers only (output device " +
                       std::to_string(p.output_device) + ")",
                   "r.HDR.Display.OutputDevice 3, 4 (PQ), 5, 6 (scRGB)"};
    if (Status st = ref::ui::validate(ui_params); !st)
      return Error{"--stage", o.stage, st.error().message, st.error().choices};
  }
  const ref::visualize::EyeAdaptationParameters eye = ref::eye_adaptation_parameters(p);
  std::optional<ref::BakedLut> lut;
  if (o.lut == "baked") lut = ref::bake_lut(p);
  const ref::TexelEvaluator texel(p);  // the analytic lookup, unpacked once

  // Output is written in blocks, and whenever the input has nothing more buffered (so that a
  // line typed at a terminal is answered at once).
  std::string pending;
  auto flush = [&](bool force) {
    if (!pending.empty() && (force || pending.size() > (1u << 16) || in.rdbuf()->in_avail() <= 0)) {
      out.write(pending.data(), static_cast<std::streamsize>(pending.size()));
      out.flush();
      pending.clear();
    }
  };

  nlohmann::json rows = nlohmann::json::array();
  std::string line;
  for (int number = 1; read_bounded_line(in, &line, kMaxProbeLine); ++number) {
    if (line.size() > kMaxProbeLine)  // e.g. /dev/zero as standard input: no newline ever
      return Error{"<stdin>", "line " + std::to_string(number),
                   "longer than " + std::to_string(kMaxProbeLine) + " characters",
                   "\"R G B\" lines"};
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const auto parsed = parse_rgb_line(line);
    if (!parsed) {
      flush(true);
      return Error{"<stdin>", "line " + std::to_string(number),
                   "expected three numbers \"R G B\", got \"" + line + "\"", ""};
    }
    const ref::Vec3 rgb = *parsed;
    if (o.stage == "ui_composite" || o.stage == "visualize_false_colour") {
      ref::Vec3 v;
      if (o.stage == "ui_composite") {
        // The line is a back-buffer colour (PQ signals for devices 3/4, scRGB for 5/6).
        const auto c4 =
            ref::ui::composite_pixel({rgb[0], rgb[1], rgb[2], 1.0}, ui_pixel, ui_params);
        v = {c4[0], c4[1], c4[2]};
      } else {
        // VisualizeHDR's false colour: Colorize(histogram position of the eye-adaptation
        // luminance of the pre-exposed scene colour).
        const ref::Vec3 scene{rgb[0] / p.pre_exposure, rgb[1] / p.pre_exposure,
                              rgb[2] / p.pre_exposure};
        const double pos = ref::visualize::histogram_position_from_luminance(
            ref::visualize::eye_adaptation_luminance(scene, eye), eye);
        v = ref::visualize::colorize(pos);
      }
      if (o.json) {
        rows.push_back(
            {{"line", number}, {"input", {rgb[0], rgb[1], rgb[2]}}, {o.stage, {v[0], v[1], v[2]}}});
      } else {
        append_line(pending, v);
        flush(false);
      }
      continue;
    }
    ref::TonemapTrace t;
    ref::tonemap_centre_pixel(p, rgb, lut ? &*lut : nullptr, &t, &texel);
    // The CombineLUTs intermediates at the coordinate the lookup reads (clamped as the sampler
    // addresses it); with --lut baked they are evaluated analytically there.
    ref::CombineLutsTrace ct;
    if (o.stage != "lut" && o.stage != "output") {  // those two come from the tonemap trace
      ref::Vec3 e;
      for (int k = 0; k < 3; ++k) e[k] = ref::d3d::clamp_address(t.encoded[k]);
      ref::combine_luts_texel(p, e, &ct);
    }
    const ref::Vec3 v = pick(o.stage, ct, t);
    if (o.json) {
      rows.push_back(
          {{"line", number}, {"input", {rgb[0], rgb[1], rgb[2]}}, {o.stage, {v[0], v[1], v[2]}}});
    } else {
      append_line(pending, v);
      flush(false);
    }
  }
  flush(true);
  if (o.json) {
    nlohmann::json doc = {{"stage", o.stage},
                          {"lut", o.lut},
                          {"output_device", p.output_device},
                          {"output_gamut", p.output_gamut},
                          {"output_max_luminance", p.output_max_luminance},
                          {"degenerate", resolution->degenerate},
                          {"rows", rows}};
    out << doc.dump(2) << '\n';
  } else if (!resolution->degenerate.empty()) {
    out << "# degenerate: " << resolution->degenerate << '\n';
  }
  return {};
}

}  // namespace hdrc
