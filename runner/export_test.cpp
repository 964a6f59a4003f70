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
#include <set>

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

// The schema's parameter list is the parameter block's (one source: core/shader_interface.h).
TEST(ParamsContract, SchemaListsEveryParameterBlockField) {
  std::vector<std::string> fields;
  const auto block = hdrc::params_json(hdrc::ParamBlock{});
  for (auto it = block.begin(); it != block.end(); ++it) fields.push_back(it.key());
  EXPECT_EQ(params_schema()["properties"]["params"]["required"].get<std::vector<std::string>>(),
            fields);
  // Its properties are every field of the block: UE 5.5's (required), then each other pipeline's,
  // which only that pipeline's cases carry.
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
  EXPECT_EQ(e[0].to_string(), "p.json: /format_version: expected 2, got 1");
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

}  // namespace
