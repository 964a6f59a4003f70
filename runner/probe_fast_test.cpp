// probe's fast parsing and printing (runner/probe.cpp) against the general path it replaces:
// every line printed as format_number (%.9g) of the reference's value, and the inputs the fast
// parser does not take handled exactly as before.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "reference/ue/cpp/resolve.h"
#include "reference/ue/tonemap.h"
#include "runner/probe.h"

namespace {

hdrc::ProbeOptions options() {
  hdrc::ProbeOptions o;
  o.set = {"r.HDR.EnableHDROutput=1", "r.HDR.Display.OutputDevice=3", "r.HDR.Display.ColorGamut=2"};
  return o;
}

std::string probe(const std::string& text, hdrc::Status* st = nullptr) {
  std::istringstream in(text);
  std::ostringstream out;
  hdrc::Status s = hdrc::run_probe(options(), in, out);
  if (st) *st = s;
  return out.str();
}

TEST(ProbeFast, PrintsFormatNumberOfTheReferenceValue) {
  hdrc::Case c;
  c.stage = hdrc::find_stage("tonemap");
  c.cvars.set("r.HDR.EnableHDROutput", 1);
  c.cvars.set("r.HDR.Display.OutputDevice", 3);
  c.cvars.set("r.HDR.Display.ColorGamut", 2);
  const hdrc::ParamBlock p = *hdrc::ref::resolve_params(c, 1, 1);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-7.0, 4.0);
  std::string text, want;
  char line[160];
  for (int i = 0; i < 2000; ++i) {
    double v[3];
    for (double& x : v) x = std::pow(10.0, u(rng)) * (i % 13 == 0 ? -1.0 : 1.0);
    std::snprintf(line, sizeof line, "%.17g\t%.17g  %.17g\r\n", v[0], v[1], v[2]);
    text += line;
    const auto o = hdrc::ref::tonemap_centre_pixel(p, {v[0], v[1], v[2]}, nullptr);
    want += hdrc::format_number(o[0]) + " " + hdrc::format_number(o[1]) + " " +
            hdrc::format_number(o[2]) + "\n";
  }
  text += "nan inf -inf\n";
  const auto o = hdrc::ref::tonemap_centre_pixel(p, {std::nan(""), INFINITY, -INFINITY}, nullptr);
  want += hdrc::format_number(o[0]) + " " + hdrc::format_number(o[1]) + " " +
          hdrc::format_number(o[2]) + "\n";
  EXPECT_EQ(probe(text), want);
}

TEST(ProbeFast, InputsTheFastParserLeavesBehaveAsBefore) {
  // A leading '+' (std::stod takes it, std::from_chars does not): the same value.
  EXPECT_EQ(probe("+0.18 +0.18 +0.18\n"), probe("0.18 0.18 0.18\n"));
  // A value that underflows to a subnormal, or overflows, is rejected as std::stod rejects it.
  for (const char* bad : {"1e-310 2 3\n", "1e400 2 3\n", "1 2\n", "1 2 3 4\n", "1 2 x\n"}) {
    hdrc::Status st;
    probe(bad, &st);
    EXPECT_FALSE(st.ok()) << bad;
  }
  // Lines before a bad line are printed.
  hdrc::Status st;
  EXPECT_EQ(probe("0.18 0.18 0.18\nbad\n", &st), probe("0.18 0.18 0.18\n"));
  EXPECT_FALSE(st.ok());
}

// `text` through probe twice with options `o`: the plain lines, then (--json) the document.
void probe_plain_and_json(hdrc::ProbeOptions o, const std::string& text, std::string* plain_text,
                          nlohmann::ordered_json* doc) {
  std::istringstream in(text);
  std::ostringstream plain;
  ASSERT_TRUE(hdrc::run_probe(o, in, plain).ok());
  *plain_text = plain.str();
  o.json = true;
  std::istringstream in2(text);
  std::ostringstream json_out;
  const hdrc::Status st = hdrc::run_probe(o, in2, json_out);
  ASSERT_TRUE(st.ok()) << st.error().to_string();
  *doc = nlohmann::ordered_json::parse(json_out.str());
}

// probe --json for operators, pq_grading and unity_urp (Pipeline::named_values): one row per input
// line with every named value of the pipeline's specification page (docs/spec/*.md, the worked
// pixels' rows), whose "out" is what the plain output prints; non-finite values as strings. (A
// pipeline without named values refuses --json; every pipeline in the table has them now.)
TEST(ProbeJson, OperatorsPqGradingAndUnityUrpPrintTheSpecsNamedValues) {
  const std::string text = "4 0.18 0.02\n# a comment\nnan 1 -inf\n";
  struct Row {
    const char* pipeline;
    std::vector<std::string> setting;
    std::string cube;
    std::vector<const char*> names;  // some of the page's names, in its order
  };
  const std::string cube = std::string(HDRC_SOURCE_DIR) + "/cases/lut/cube/pq_look_33.cube";
  for (const Row& r :
       {Row{"operators", {"Operator=UeFilmic"}, "", {"input", "x", "ap1", "hue_weight", "out"}},
        Row{"operators", {"Operator=Hable"}, "", {"input", "exposure", "f_bias_x", "f_w", "out"}},
        Row{"pq_grading", {}, cube, {"stored", "lut_coord", "slice_f", "graded", "ap1", "out"}},
        Row{"pq_grading", {"Display=SDR"}, cube, {"pq", "tap1", "display", "out"}},
        Row{"unity_urp",
            {"GradingMode=HighDynamicRange", "Tonemapping.mode=ACES"},
            "",
            {"input", "exposed", "logc", "uvw", "slice", "tap0", "tap1", "out"}},
        Row{"unity_urp",
            {"GradingMode=LowDynamicRange", "Tonemapping.mode=Neutral"},
            "",
            {"exposed", "uvw", "slice_frac", "u", "v", "out"}}}) {
    SCOPED_TRACE(std::string(r.pipeline) + " " + (r.setting.empty() ? "" : r.setting[0]));
    hdrc::ProbeOptions o;
    o.pipeline = r.pipeline;
    o.setting = r.setting;
    o.cube = r.cube;
    std::string plain_text;
    nlohmann::ordered_json doc;
    probe_plain_and_json(o, text, &plain_text, &doc);
    if (::testing::Test::HasFatalFailure()) return;
    ASSERT_EQ(doc["rows"].size(), 2u);
    EXPECT_EQ(doc["rows"][0]["line"], 1);
    EXPECT_EQ(doc["rows"][1]["line"], 3);
    std::string from_json;
    for (const auto& row : doc["rows"]) {
      const auto& v = row["values"];
      std::vector<std::string> keys;
      for (auto it = v.begin(); it != v.end(); ++it) keys.push_back(it.key());
      size_t at = 0;
      for (const char* name : r.names) {
        const auto found = std::find(keys.begin() + at, keys.end(), name);
        EXPECT_NE(found, keys.end()) << name;
        at = found == keys.end() ? at : size_t(found - keys.begin());
      }
      for (int k = 0; k < 3; ++k) {
        const auto& x = v["out"][k];
        // Two appends: GCC 12's -Wrestrict false positive on operator+(const char*, string&&)
        // at -O3 (Release) is avoided.
        if (k) from_json += " ";
        from_json += x.is_string() ? std::string("nan") : hdrc::format_number(x.get<double>());
      }
      from_json += "\n";
    }
    // The plain output prints NaN as "nan" or "-nan"; the JSON's "NaN" strings are compared as
    // "nan".
    for (size_t at; (at = plain_text.find("-nan")) != std::string::npos;) plain_text.erase(at, 1);
    EXPECT_EQ(from_json, plain_text);
    EXPECT_EQ(doc["rows"][1]["values"]["input"][0], "NaN");
    EXPECT_EQ(doc["rows"][1]["values"]["input"][2], "-Infinity");
  }
}

// probe --pipeline ue58 --stage ue58_ui_composite --json (docs/spec/ue58.md §1's worked pixels):
// the UI pixel from --ui, cvars from --set; every step of the shader in order, "out" what the
// plain output prints. Translucent white UI (1 at a = 0.5: 203 nits) over 100 nits in the gamma
// blend, by hand with the host's float gammas (2.4f, 1.f / 2.4f): g(100) = 0.01^0.41666666 =
// 0.146779933, g(203) = 0.0203^0.41666666 = 0.197146936, lerp 0.171963435, ^2.4f x 10000 =
// 146.233406 nits. Refused: an SDR device, a stage the page names no values of.
TEST(ProbeJson, Ue58UiCompositePrintsEveryStepOfTheShader) {
  hdrc::ProbeOptions o;
  o.pipeline = "ue58";
  o.stage = "ue58_ui_composite";
  o.set = {"r.HDR.EnableHDROutput=1", "r.HDR.Display.OutputDevice=3"};
  o.ui = "0.5,0.5,0.5,0.5";
  const std::string text = "0.508078422 0.508078422 0.508078422\n0.1 0.2 0.3\n";  // PQ(100 nits)
  std::string plain_text;
  nlohmann::ordered_json doc;
  probe_plain_and_json(o, text, &plain_text, &doc);
  if (::testing::Test::HasFatalFailure()) return;
  o.json = true;  // the refusals below are of --json
  ASSERT_EQ(doc["rows"].size(), 2u);
  const auto& v = doc["rows"][0]["values"];
  std::vector<std::string> keys;
  for (auto it = v.begin(); it != v.end(); ++it) keys.push_back(it.key());
  EXPECT_EQ(keys,
            (std::vector<std::string>{"input", "ui_unpremultiplied", "ui_linear", "ui", "ui_alpha",
                                      "scene_nits", "ui_levelled", "blend_scene", "blend_ui",
                                      "blend_lerp", "composed", "after_cvd", "out", "out_alpha"}));
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(v["scene_nits"][k].get<double>(), 100.0, 1e-5);
    EXPECT_NEAR(v["blend_scene"][k].get<double>(), 0.146779933, 1e-8);
    EXPECT_NEAR(v["blend_ui"][k].get<double>(), 0.197146936, 1e-8);
    EXPECT_NEAR(v["composed"][k].get<double>(), 146.233406, 1e-5);
  }
  EXPECT_EQ(v["out_alpha"], 0.5);
  std::string from_json;
  for (const auto& row : doc["rows"])
    for (int k = 0; k < 3; ++k) {
      if (k) from_json += " ";
      from_json += hdrc::format_number(row["values"]["out"][k].get<double>());
      if (k == 2) from_json += "\n";
    }
  EXPECT_EQ(from_json, plain_text);

  std::ostringstream refused;
  o.set = {};  // device 0: no HDR UI composite
  std::istringstream in3(text);
  hdrc::Status sdr = hdrc::run_probe(o, in3, refused);
  ASSERT_FALSE(sdr.ok());
  EXPECT_NE(sdr.error().to_string().find("HDR back buffers only"), std::string::npos);
  o.stage = "ue58_dither";
  std::istringstream in4(text);
  hdrc::Status none = hdrc::run_probe(o, in4, refused);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().to_string().find("names no intermediate values"), std::string::npos);
}

}  // namespace
