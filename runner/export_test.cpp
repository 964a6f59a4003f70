// The export format's parameter round trip (every ParamBlock field, non-finite values included)
// and the command-template splitting `verify --candidate-cmd` uses instead of a shell.
#include "runner/export.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "core/pipeline.h"
#include "runner/verify.h"

namespace {

TEST(Export, ParamsRoundTripExactlyIncludingNonFinite) {
  hdrc::ParamBlock p;
  p.output_device = 3;
  p.output_max_luminance = 1000.0 / 3.0;  // not a short decimal
  p.aces_coefs_high_4 = std::numeric_limits<double>::quiet_NaN();
  p.aces_min_max = {0.1, -std::numeric_limits<double>::infinity(), 1e-300, 5};
  p.ap1_to_output(1, 2) = std::nextafter(0.25, 1.0);
  const auto j = hdrc::params_json(p);
  EXPECT_EQ(j["aces_coefs_high_4"], "NaN");
  EXPECT_EQ(j["aces_min_max"][1], "-Infinity");
  const auto back =
      hdrc::params_from_json(nlohmann::ordered_json::parse(j.dump()), "p.json", "/params");
  ASSERT_TRUE(back.ok()) << back.error().to_string();
  EXPECT_EQ(back->output_device, 3);
  EXPECT_EQ(back->output_max_luminance, p.output_max_luminance);
  EXPECT_TRUE(std::isnan(back->aces_coefs_high_4));
  EXPECT_EQ(back->aces_min_max, p.aces_min_max);
  EXPECT_EQ(back->ap1_to_output.m, p.ap1_to_output.m);
  // Byte for byte: every field survives (NaN compares unequal, so compare the bytes of a copy
  // with the NaN replaced on both sides).
  hdrc::ParamBlock a = p, b = *back;
  a.aces_coefs_high_4 = b.aces_coefs_high_4 = 0;
  EXPECT_EQ(hdrc::params_json(a).dump(), hdrc::params_json(b).dump());
}

TEST(Export, MissingOrBadParameterIsLocated) {
  auto j = hdrc::params_json(hdrc::ParamBlock{});
  j.erase("film_slope");
  auto r = hdrc::params_from_json(j, "p.json", "/params");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().to_string(),
            "p.json: /params/film_slope: missing parameter film_slope; valid choices: every "
            "ParamBlock field");
  j = hdrc::params_json(hdrc::ParamBlock{});
  j["wcs_to_ap1"][2] = {1, 2};
  r = hdrc::params_from_json(j, "p.json", "/params");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().pointer, "/params/wcs_to_ap1/2");
}

// A table field (V4A(n), core/shader_interface.h) travels texel for texel: std430 offset aligned
// to 16 with a 16-byte stride, each component float(value) at base + 16 e + 4 c, the GLSL/HLSL
// declaration "vec4 name[n]" / "float4 name[n]", and the next field after its 16 n bytes.
TEST(ParamBlockTable, LayoutPackingAndDeclaration) {
  const auto layout = hdrc::param_block_layout();
  auto find = [&](const std::string& name) {
    for (size_t i = 0; i < layout.size(); ++i)
      if (layout[i].name == name) return i;
    ADD_FAILURE() << "no field " << name;
    return size_t{0};
  };
  const size_t cusp = find("ue58_cusp_table");
  EXPECT_EQ(layout[cusp].type, 'A');
  EXPECT_EQ(layout[cusp].size, 362u * 16u);
  EXPECT_EQ(layout[cusp].offset % 16, 0u);
  EXPECT_EQ(layout[cusp + 1].name, "ue58_gamma_table");
  EXPECT_EQ(layout[cusp + 1].offset, layout[cusp].offset + 362u * 16u);
  // A table after another field starts at the next multiple of 16 after it (std430 array
  // alignment), whatever that field is (a scalar since the UI composite's fields).
  const size_t params = find("ue58_aces2_params");
  const auto& before = layout[params - 1];
  EXPECT_EQ(layout[params].offset, (before.offset + before.size + 15) / 16 * 16) << before.name;
  hdrc::ParamBlock p;
  p.ue58_cusp_table[0] = {-1.5, 2.25, 1.0 / 3.0, 0.0};
  p.ue58_cusp_table[361] = {7.0, 8.0, 361.0 + 1e-3, 0.0};
  const auto bytes = hdrc::pack_std430(p);
  auto at = [&](size_t offset) {
    float f;
    std::memcpy(&f, &bytes[offset], 4);
    return f;
  };
  const size_t base = layout[cusp].offset;
  EXPECT_EQ(at(base + 0), -1.5f);
  EXPECT_EQ(at(base + 4), 2.25f);
  EXPECT_EQ(at(base + 8), static_cast<float>(1.0 / 3.0));
  EXPECT_EQ(at(base + 361 * 16 + 8), static_cast<float>(361.0 + 1e-3));
  EXPECT_EQ(at(base + 361 * 16 + 4), 8.0f);
  EXPECT_EQ(hdrc::shader_field_decl(hdrc::FieldKind::V4A, "t", false, 91), "vec4 t[91];");
  EXPECT_EQ(hdrc::shader_field_decl(hdrc::FieldKind::V4A, "t", true, 91), "float4 t[91];");
  const std::string glsl = hdrc::glsl_param_block();
  EXPECT_NE(glsl.find("  vec4 ue58_cusp_table[362];\n"), std::string::npos);
  EXPECT_NE(glsl.find("  vec4 ue58_reach_table_sdr[90];\n"), std::string::npos);
  EXPECT_EQ(hdrc::field_elements(p.ue58_gamma_table), 91u);
  EXPECT_EQ(hdrc::field_elements(p.width), 0u);
}

// params.json carries a table as n arrays of 4 numbers, round trip exact; anything but exactly n
// elements of 4 numbers is refused with the field's pointer and its declared size.
TEST(ParamBlockTable, JsonRoundTripAndBoundedErrors) {
  hdrc::ParamBlock p;
  for (size_t e = 0; e < p.ue58_reach_table.size(); ++e)
    p.ue58_reach_table[e] = {e * 4 + 0.1, e * 4 + 1.0 / 7.0, -1e-30, 1e30};
  p.ue58_gamma_table[90][3] = std::numeric_limits<double>::infinity();
  const auto j = hdrc::params_json(p, "ue58");
  ASSERT_TRUE(j.contains("ue58_reach_table"));
  EXPECT_EQ(j["ue58_reach_table"].size(), 90u);
  EXPECT_EQ(j["ue58_gamma_table"][90][3], "Infinity");
  EXPECT_FALSE(hdrc::params_json(p, "ue55").contains("ue58_reach_table"));
  auto back =
      hdrc::params_from_json(nlohmann::ordered_json::parse(j.dump()), "p.json", "/params", "ue58");
  ASSERT_TRUE(back.ok()) << back.error().to_string();
  EXPECT_EQ(back->ue58_reach_table, p.ue58_reach_table);
  EXPECT_EQ(back->ue58_gamma_table, p.ue58_gamma_table);
  auto refused = [&](const nlohmann::ordered_json& bad) {
    return hdrc::params_from_json(bad, "p.json", "/params", "ue58");
  };
  auto longer = j;
  longer["ue58_reach_table"].push_back({1, 2, 3, 4});
  auto r = refused(longer);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().pointer, "/params/ue58_reach_table");
  EXPECT_NE(r.error().to_string().find("expected an array of 90 vec4"), std::string::npos)
      << r.error().to_string();
  EXPECT_NE(r.error().to_string().find("got 91 elements"), std::string::npos);
  auto shorter = j;
  shorter["ue58_cusp_table"].erase(shorter["ue58_cusp_table"].size() - 1);
  r = refused(shorter);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().pointer, "/params/ue58_cusp_table");
  auto element = j;
  element["ue58_gamma_table"][17] = {1, 2, 3};
  r = refused(element);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().pointer, "/params/ue58_gamma_table/17");
  auto scalar = j;
  scalar["ue58_aces2_params"] = 5;
  r = refused(scalar);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().pointer, "/params/ue58_aces2_params");
  EXPECT_NE(r.error().to_string().find("got number"), std::string::npos) << r.error().to_string();
}

// Found by fuzz/params_fuzzer (UBSan: 4.44444e+88 outside the range of int): an integer field
// with a value no int32 holds, or a fraction, is refused with its pointer, not cast.
TEST(Export, IntegerParameterOutOfRangeOrFractionalIsRefused) {
  for (const double bad : {4.44444e88, -3e9, 2147483648.0, 1.5}) {
    auto j = hdrc::params_json(hdrc::ParamBlock{});
    j["lut_size"] = bad;
    auto r = hdrc::params_from_json(j, "p.json", "/params");
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_EQ(r.error().pointer, "/params/lut_size") << bad;
    EXPECT_NE(r.error().to_string().find("an integer in [-2147483648, 2147483647]"),
              std::string::npos)
        << r.error().to_string();
  }
  auto j = hdrc::params_json(hdrc::ParamBlock{});
  j["lut_size"] = 33.0;  // integral: accepted
  auto r = hdrc::params_from_json(j, "p.json", "/params");
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->lut_size, 33);
}

TEST(Verify, CommandTemplateSplitsLikeAShellWithoutOne) {
  auto w = hdrc::split_command_template(
      R"(my_port --in {input} 'a b' "c \"d\" \\" e\ f $HOME;rm `x` *)");
  ASSERT_TRUE(w.ok());
  const std::vector<std::string> want = {"my_port", "--in",     "{input}", "a b", "c \"d\" \\",
                                         "e f",     "$HOME;rm", "`x`",     "*"};
  EXPECT_EQ(*w, want);
  EXPECT_FALSE(hdrc::split_command_template("x 'open").ok());
  EXPECT_FALSE(hdrc::split_command_template("x \"open").ok());
  EXPECT_FALSE(hdrc::split_command_template("   ").ok());
  // Placeholders are replaced inside words after splitting: a value with spaces or shell
  // characters stays one argument.
  const auto argv = hdrc::expand_placeholders({"p", "--out={output}", "{id}"}, "in.exr", "p.json",
                                              "/o dir/$(x).exr", "a/b c");
  EXPECT_EQ(argv, (std::vector<std::string>{"p", "--out=/o dir/$(x).exr", "a/b c"}));
  // A misspelt placeholder is named; the four, a shell's ${name} and other braces are not.
  EXPECT_EQ(hdrc::unknown_placeholder({"p", "--out={ouput}", "{output}"}), "{ouput}");
  EXPECT_EQ(hdrc::unknown_placeholder({"p", "{input}{params}", "x{output}y", "{id}"}), "");
  EXPECT_EQ(hdrc::unknown_placeholder({"sh", "-c", "echo ${HOME} {} {A} {a b} {"}), "");
  EXPECT_EQ(hdrc::unknown_placeholder({"p", "{output_2}"}), "{output_2}");
  // The sandbox: its own PID namespace, dying with the runner, the case folder absolute.
  const auto sb = hdrc::sandbox_argv({"p", "x"}, "rel/case");
  for (const char* flag : {"--unshare-pid", "--die-with-parent", "--new-session"})
    EXPECT_NE(std::find(sb.begin(), sb.end(), flag), sb.end()) << flag;
  const std::string abs = std::filesystem::absolute("rel/case").lexically_normal().string();
  EXPECT_NE(std::find(sb.begin(), sb.end(), abs), sb.end());
  EXPECT_EQ(std::vector<std::string>(sb.end() - 3, sb.end()),
            (std::vector<std::string>{"--", "p", "x"}));
}

TEST(Verify, RunCommandReportsExitSignalAndTimeout) {
  const std::string log = ::testing::TempDir() + "/hdrc_cmd.log";
  auto r = hdrc::run_command({"sh", "-c", "echo hi; exit 7"}, log, 10);
  EXPECT_EQ(r.exit_status, 7);
  EXPECT_FALSE(r.timed_out);
  r = hdrc::run_command({"sh", "-c", "kill -TERM $$"}, log, 10);
  EXPECT_EQ(r.signal, 15);
  r = hdrc::run_command({"sleep", "20"}, log, 0.2);
  EXPECT_TRUE(r.timed_out);
  r = hdrc::run_command({"/nonexistent/program"}, log, 10);
  EXPECT_EQ(r.exit_status, 127);
}

}  // namespace

// ---- params.json as a versioned contract (runner/params.schema.json) ----------------------------

#include "runner/case_loader.h"
#include "runner/json_schema.h"

#ifndef HDRC_SOURCE_DIR
#error "HDRC_SOURCE_DIR must be defined"
#endif

namespace {

nlohmann::ordered_json read_json(const std::string& path) {
  std::ifstream f(path);
  return nlohmann::ordered_json::parse(f);
}

const nlohmann::ordered_json& params_schema() {
  static const auto s = read_json(std::string(HDRC_SOURCE_DIR) + "/runner/params.schema.json");
  return s;
}

hdrc::ResolvedCase resolved(const std::string& id) {
  auto loaded = hdrc::load_cases(std::string(HDRC_SOURCE_DIR) + "/cases");
  for (const auto& c : loaded.cases)
    if (c.id == id) {
      auto rc = hdrc::resolve_case(c);
      if (rc) return *rc;
      ADD_FAILURE() << rc.error().to_string();
    }
  ADD_FAILURE() << "no case " << id;
  return {};
}

// Every case of the suite, exported as `export` writes it, is valid under the schema.
TEST(ParamsContract, EveryExportedParamsJsonMatchesTheSchema) {
  auto loaded = hdrc::load_cases(std::string(HDRC_SOURCE_DIR) + "/cases");
  ASSERT_TRUE(loaded.errors.empty());
  ASSERT_GT(loaded.cases.size(), 500u);
  size_t checked = 0;
  std::set<std::string> stages;
  for (const auto& c : loaded.cases) {
    auto rc = hdrc::resolve_case(c);
    ASSERT_TRUE(rc.ok()) << rc.error().to_string();
    // Through text, as a port reads it.
    const auto doc = nlohmann::ordered_json::parse(hdrc::case_export_json(*rc).dump());
    const auto errors = hdrc::validate_json(doc, params_schema(), c.id + "/params.json");
    for (const auto& e : errors) ADD_FAILURE() << e.to_string();
    if (!errors.empty()) break;
    ++checked;
    stages.insert(doc["stage"].get<std::string>());
  }
  EXPECT_EQ(checked, loaded.cases.size());
  size_t every_stage = 0;
  for (const hdrc::Pipeline* p : hdrc::pipeline_table()) every_stage += p->stages().size();
  EXPECT_EQ(stages.size(), every_stage) << "every stage of every pipeline exported";
  RecordProperty("params_json_validated", std::to_string(checked));
}

// The schema's parameter lists are the parameter block's (one source: core/shader_interface.h):
// one oneOf branch per pipeline, requiring exactly the fields its cases carry (param_carried_by)
// and refusing the others.
TEST(ParamsContract, SchemaListsEveryParameterBlockField) {
  std::set<std::string> branches;
  for (const auto& branch : params_schema()["oneOf"]) {
    const std::string pipeline = branch["properties"]["pipeline"]["const"].get<std::string>();
    branches.insert(pipeline);
    SCOPED_TRACE(pipeline);
    std::vector<std::string> fields;
    const auto block = hdrc::params_json(hdrc::ParamBlock{}, pipeline);
    for (auto it = block.begin(); it != block.end(); ++it) fields.push_back(it.key());
    const auto& params = branch["properties"]["params"];
    EXPECT_EQ(params["required"].get<std::vector<std::string>>(), fields);
    EXPECT_EQ(params["additionalProperties"], false);
    std::vector<std::string> allowed;
    for (const auto& [k, v] : params["properties"].items()) allowed.push_back(k);
    EXPECT_EQ(allowed, fields);
  }
  std::set<std::string> pipelines;
  for (const hdrc::Pipeline* p : hdrc::pipeline_table()) pipelines.insert(std::string(p->name));
  EXPECT_EQ(branches, pipelines);
  // Its properties are every field of the block: UE 5.5's, then each other pipeline's, which only
  // that pipeline's cases carry.
  std::vector<std::string> all;
  hdrc::ParamBlock p;
  hdrc::for_each_param(p, [&](hdrc::FieldKind, const char* name, auto&) { all.push_back(name); });
  std::vector<std::string> listed;
  for (const auto& [k, v] : params_schema()["properties"]["params"]["properties"].items())
    listed.push_back(k);
  std::sort(listed.begin(), listed.end());
  std::sort(all.begin(), all.end());
  EXPECT_EQ(listed, all);
}

// Each field's description in the schema is the interface header's meaning of it (one source:
// interface/*_params.h), with the pipeline note for fields only one pipeline's cases carry. A
// porter reads the schema; the headers are what the shaders and the reference are built from.
TEST(ParamsContract, SchemaDescriptionsAreTheInterfaceHeadersMeanings) {
  std::vector<std::pair<std::string, std::string>> meanings;
#define HDRC_MEANING(type, name, doc) meanings.emplace_back(#name, doc);
  HDRC_PARAM_BLOCK(HDRC_MEANING)
#undef HDRC_MEANING
  const auto& props = params_schema()["properties"]["params"]["properties"];
  ASSERT_EQ(props.size(), meanings.size());
  const std::regex note(R"( \(pipeline [a-z0-9_]+: carried by its cases only\)$)");
  for (const auto& [name, doc] : meanings) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(props.contains(name));
    const std::string description = props[name].value("description", "");
    EXPECT_EQ(std::regex_replace(description, note, ""), doc);
  }
}

// The validator catches what a port would trip on: a wrong version, a missing block, a wrong
// type, an unknown key, each located by JSON pointer.
TEST(ParamsContract, ValidatorLocatesViolations) {
  auto doc = nlohmann::ordered_json::parse(
      hdrc::case_export_json(resolved("tonemap/linear_dev7/gamut2_log_ramp")).dump());
  ASSERT_TRUE(hdrc::validate_json(doc, params_schema(), "p.json").empty());
  auto bad = doc;
  bad["format_version"] = 1;
  auto e = hdrc::validate_json(bad, params_schema(), "p.json");
  ASSERT_FALSE(e.empty());
  EXPECT_EQ(e[0].to_string(), "p.json: /format_version: expected 3, got 1");
  bad = doc;
  bad["output"].erase("quantisation");
  e = hdrc::validate_json(bad, params_schema(), "p.json");
  ASSERT_FALSE(e.empty());
  EXPECT_EQ(e[0].pointer, "/output/quantisation");
  bad = doc;
  bad["params"]["ap1_to_output"][1] = {1, 2};
  e = hdrc::validate_json(bad, params_schema(), "p.json");
  ASSERT_FALSE(e.empty());
  EXPECT_EQ(e[0].pointer, "/params/ap1_to_output/1");
  bad = doc;
  bad["resolved"]["max_nits"] = 1000;
  e = hdrc::validate_json(bad, params_schema(), "p.json");
  ASSERT_FALSE(e.empty());
  EXPECT_EQ(e[0].to_string(),
            "p.json: /resolved/max_nits: unknown key \"max_nits\"; valid choices: output_device, "
            "output_gamut, max_luminance_nits, aces_tone_scale, shaper, output_encoding");
  bad = doc;
  bad["params"]["output_device"] = "NaN";
  EXPECT_FALSE(hdrc::validate_json(bad, params_schema(), "p.json").empty());
  // A UE 5.5 export without one of UE's fields, and a pipeline's export with a field of UE 5.5's it
  // does not read (or UE's cvar resolution), match no branch of the schema.
  bad = doc;
  bad["params"].erase("output_gamut");
  EXPECT_FALSE(hdrc::validate_json(bad, params_schema(), "p.json").empty());
  auto loaded = hdrc::load_cases(std::string(HDRC_SOURCE_DIR) + "/cases");
  const hdrc::Case* op_case = nullptr;
  for (const auto& c : loaded.cases)
    if (!op_case && c.stage->pipeline == "operators") op_case = &c;
  ASSERT_TRUE(op_case);
  auto ops =
      nlohmann::ordered_json::parse(hdrc::case_export_json(*hdrc::resolve_case(*op_case)).dump());
  ASSERT_TRUE(hdrc::validate_json(ops, params_schema(), "p.json").empty());
  bad = ops;
  bad["params"]["output_device"] = 0;
  e = hdrc::validate_json(bad, params_schema(), "p.json");
  ASSERT_FALSE(e.empty());
  EXPECT_NE(e[0].message.find("alternatives of oneOf"), std::string::npos) << e[0].to_string();
  bad = ops;
  bad["resolved"] = doc["resolved"];
  EXPECT_FALSE(hdrc::validate_json(bad, params_schema(), "p.json").empty());
}

// The resolved values a renderer needs: device 4 with MaxLuminance unset runs at 1000 nits (UE's
// HDRSettingChangedSinkCallback fallback), its tone scale is 1e-4 / 15 / 1000 nits (the cvars'
// defaults MinLuminanceLog10 = -4 and MidLuminance = 15), and a combine_luts output says it is
// OutDeviceColor / 1.05 quantised to the LUT format, laid out N² × N.
TEST(ParamsContract, ResolvedValuesAndOutputBlock) {
  auto loaded = hdrc::load_cases(std::string(HDRC_SOURCE_DIR) + "/cases");
  const hdrc::Case* dev4 = nullptr;
  const hdrc::Case* lut = nullptr;
  for (const auto& c : loaded.cases) {
    if (!dev4 && c.stage->id == hdrc::StageId::kTonemap &&
        c.cvars.get_int("r.HDR.Display.OutputDevice") == 4 &&
        c.cvars.get("r.HDR.Display.MaxLuminance") == 0 &&
        c.cvars.get("r.HDR.Display.MidLuminance") == 15 &&
        c.cvars.get("r.HDR.Display.MinLuminanceLog10") == -4 &&
        c.cvars.get_int("r.HDR.Display.ColorGamut") == 2 &&
        c.cvars.get_int("r.HDR.EnableHDROutput") == 1)
      dev4 = &c;
    if (!lut && c.stage->id == hdrc::StageId::kCombineLuts && c.settings.get("LUTFormat") == 0 &&
        c.settings.get("LUTLayout") == 0)
      lut = &c;
  }
  ASSERT_TRUE(dev4 && lut);
  auto doc = hdrc::case_export_json(*hdrc::resolve_case(*dev4));
  const auto& r = doc["resolved"];
  EXPECT_EQ(r["output_device"]["value"], 4);
  EXPECT_EQ(r["output_device"]["name"], "HDR_ACES_2000nit_ST2084");
  EXPECT_EQ(r["max_luminance_nits"]["value"], 1000.0);
  EXPECT_NE(r["max_luminance_nits"]["from"].get<std::string>().find("falls back to 1000 nits"),
            std::string::npos);
  EXPECT_EQ(r["aces_tone_scale"]["mid_nits"], 15.0);
  EXPECT_EQ(r["aces_tone_scale"]["max_nits"], 1000.0);
  EXPECT_EQ(static_cast<float>(r["aces_tone_scale"]["min_nits"].get<double>()), 1e-4f);
  EXPECT_EQ(r["output_encoding"]["name"], "PQ EOTF, Rec2020_D65");
  EXPECT_FALSE(doc["settings"].contains("LUTFormat"));

  doc = hdrc::case_export_json(*hdrc::resolve_case(*lut));
  const int n = doc["storage"]["lut_size"];
  EXPECT_EQ(doc["output"]["width"], n * n);
  EXPECT_EQ(doc["output"]["height"], n);
  EXPECT_EQ(doc["output"]["layout"]["name"], "lut_unwrapped");
  EXPECT_EQ(doc["output"]["quantisation"]["name"], "A2B10G10R10 UNORM");
  EXPECT_EQ(doc["output"]["formula"], "OutDeviceColor / 1.05, rounded to the LUT format");
  EXPECT_TRUE(doc["resolved"]["output_encoding"]["name"].get<std::string>().rfind("texel x 1.05, ",
                                                                                  0) == 0);
}

// Every ParamBlock field the GLSL of a pipeline reads as P.<field>: in `file` and the files it
// #includes (the generated hdrc/interface.glsl aside), counted in the pipeline's own folder
// (gpu/shaders/<pipeline>/) and the shared gpu/shaders/lib/, not in another pipeline's library
// and what only that library includes: unity_urp includes operators.glsl for Unity's Neutral, whose
// other functions (UE's FilmToneMap, P.film_*) are the operators pipeline's. A pass shader a
// stage of the pipeline names (`pass`) is the pipeline's wherever it lives: ue58_dither runs UE
// 5.5's stages/dither.comp (docs/ue58-decisions.md J), ue58_visualize_hdr 5.5's
// stages/visualize_*.comp.
void shader_fields(const std::filesystem::path& file, const std::string& pipeline, bool count,
                   std::map<std::string, bool>* visited, std::set<std::string>* out,
                   bool pass = false) {
  const std::string key = file.lexically_normal().string();
  const std::string shaders = (std::filesystem::path(HDRC_SOURCE_DIR) / "gpu/shaders/").string();
  const std::string rel = key.substr(std::min(key.size(), shaders.size()));
  if (!pass && rel.find('/') != std::string::npos && rel.rfind("lib/", 0) != 0 &&
      rel.rfind(pipeline + "/", 0) != 0)
    count = false;  // another pipeline's folder
  const auto seen = visited->find(key);
  if (seen != visited->end() && (seen->second || !count)) return;
  (*visited)[key] = count;
  std::ifstream in(file);
  ASSERT_TRUE(in) << file;
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  static const std::regex field(R"(\bP\.([a-z_0-9]+))");
  if (count)
    for (auto it = std::sregex_iterator(s.begin(), s.end(), field); it != std::sregex_iterator();
         ++it)
      out->insert((*it)[1]);
  static const std::regex include(R"re(#include\s+"([^"]+)")re");
  for (auto it = std::sregex_iterator(s.begin(), s.end(), include); it != std::sregex_iterator();
       ++it) {
    const std::string inc = (*it)[1];
    if (inc.rfind("hdrc/", 0) == 0) continue;
    shader_fields(file.parent_path() / inc, pipeline, count, visited, out);
  }
}

// A pipeline other than UE 5.5 exports only what applies to it (issue 28): of UE 5.5's fields
// exactly those its shaders read (P.<field> in its stages' GLSL, shader_fields) or its host
// derivation sets (a value other than the block's default in one of its cases), so a UE-only
// field (output_device, the ACES coefficients, ...) in such an export fails here; no "resolved"
// block (UE's cvar resolution); "storage" only with a LUT of its own; output.formula a docs
// section, not a source file; case_file relative to the cases folder, naming no folder above it.
TEST(ParamsContract, OtherPipelinesExportOnlyWhatApplies) {
  auto loaded = hdrc::load_cases(std::string(HDRC_SOURCE_DIR) + "/cases");
  ASSERT_TRUE(loaded.errors.empty());
  std::map<std::string, std::set<std::string>> used;  // pipeline -> UE fields read or set
  std::map<std::string, size_t> cases;
  const hdrc::ParamBlock defaults;
  for (const hdrc::Pipeline* p : hdrc::pipeline_table()) {
    const std::string name(p->name);
    if (name == "ue55") continue;
    std::map<std::string, bool> visited;
    std::set<std::string> fields;
    for (const hdrc::StageInfo& st : p->stages())
      for (const hdrc::StagePass& pass : st.passes)
        shader_fields(std::filesystem::path(HDRC_SOURCE_DIR) / "gpu/shaders" / pass.shader, name,
                      true, &visited, &fields, true);
    for (const std::string& f : fields)
      if (hdrc::param_owner(f) == "ue55") used[name].insert(f);
  }
  for (const auto& c : loaded.cases) {
    const std::string pipeline(c.stage->pipeline);
    if (pipeline == "ue55") continue;
    auto rc = hdrc::resolve_case(c);
    ASSERT_TRUE(rc.ok()) << rc.error().to_string();
    ++cases[pipeline];
    const auto set = hdrc::params_json(rc->params, "ue55");
    const auto def = hdrc::params_json(defaults, "ue55");
    for (auto it = set.begin(); it != set.end(); ++it)
      if (it.value() != def[it.key()]) used[pipeline].insert(it.key());
    const auto doc = hdrc::case_export_json(*rc);
    SCOPED_TRACE(c.id);
    EXPECT_TRUE(doc["resolved"].is_null());
    EXPECT_EQ(doc["storage"].is_null(), !used[pipeline].count("lut_size"));
    std::set<std::string> carried_ue;
    for (auto it = doc["params"].begin(); it != doc["params"].end(); ++it)
      if (hdrc::param_owner(it.key()) == "ue55") carried_ue.insert(it.key());
    EXPECT_EQ(carried_ue, used[pipeline]) << "UE 5.5 fields in a " << pipeline << " export";
    const std::string formula = doc["output"]["formula"];
    EXPECT_EQ(formula.rfind("docs/", 0), 0u) << formula;
    for (const char* ext : {".h", ".cpp", ".glsl", ".comp"})
      EXPECT_EQ(formula.find(ext), std::string::npos) << formula;
    const std::string case_file = doc["case_file"];
    EXPECT_NE(case_file.front(), '/');
    EXPECT_EQ(case_file.find(".."), std::string::npos) << case_file;
    EXPECT_TRUE(std::filesystem::equivalent(
        std::filesystem::path(HDRC_SOURCE_DIR) / "cases" / case_file, c.file))
        << case_file;
  }
  EXPECT_GT(cases["operators"], 0u);
  EXPECT_GT(cases["pq_grading"], 0u);
  EXPECT_GT(cases["unity_urp"], 0u);
  EXPECT_EQ(used["operators"],
            (std::set<std::string>{"width", "height", "film_slope", "film_toe", "film_shoulder",
                                   "film_black_clip", "film_white_clip"}));
}

}  // namespace
