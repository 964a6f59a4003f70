// Builds the results directory the browser test opens: a small real run (the runner's executor,
// diff, judge, results.json, junit.xml, case EXRs and report) of the reference engine against a
// candidate that is the reference rounded to float32 with defects planted at known pixels. It
// holds every kind of case the report must show:
//
//   fixture/linear/dev{7,8}_gamut{0,1,2}_log_ramp
//                                          a 2 × 3 cvar matrix: dev8_gamut2 FAILS (pixel (13, 2) G
//                                          × 1.01), dev7_gamut1 PASSES with a warning and a near
//                                          miss (pixel (40, 1) R × (1 + 6e-5)); the rest pass
//   fixture/lut                            a 16³ CombineLUTs LUT, passing, one lattice point
//                                          bumped by 0.03 %
//   fixture/known/log_ramp                 KNOWN_LIMIT (listed for the planted engine)
//   fixture/degenerate                     DEGENERATE (an ACES device with HDR output off)
//   fixture/skipped/log_ramp               SKIP (from a second run whose candidate cannot start)
//   <script>alert(1)</script>/log_ramp     a hostile case id; passes
//   fixture/aces/log_ramp                  an ACES regression (issue 14): ACES 1000-nit device 3,
//                                          the candidate compresses every output over 200 nits
//                                          (PQ signal − 0.04 above PQ(200 nits)); FAILS
//   fixture/hue/hue_sweep                  hue sweeps for the chromaticity plot; passes
// and a golden check with one regression (fixture/lut), recorded as the runner records it.
//
// Usage: report_fixture OUT_DIR. Also writes OUT_DIR/expect.json: what the fixture planted, for
// the browser test to check the report against (independently of results.json).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "reference/reference_engine.h"
#include "runner/case_loader.h"
#include "runner/results.h"
#include "runner/run.h"

namespace {

using hdrc::Case;
using hdrc::Image;

struct Plant {
  int x, y, channel;
  double factor;
};

// The planted defects, by case id.
const std::map<std::string, Plant>& plants() {
  static const std::map<std::string, Plant> p = {
      {"fixture/linear/dev8_gamut2_log_ramp", {13, 2, 1, 1.01}},
      {"fixture/linear/dev7_gamut1_log_ramp", {40, 1, 0, 1.0 + 6e-5}},
      {"fixture/lut", {5 + 16 * 7, 9, 2, 1.0003}},  // lattice (r 5, g 9, b 7), blue
  };
  return p;
}

const std::string kAcesId = "fixture/aces/log_ramp";

// The reference engine, its output rounded to float32 as a GPU would store it, plus the defects.
class PlantedEngine final : public hdrc::Engine {
 public:
  explicit PlantedEngine(bool available) : available_(available) {}
  std::string name() const override { return "planted"; }
  hdrc::Status init() override {
    if (!available_)
      return hdrc::Error{"", "", "the planted engine is switched off for this run (fixture)", ""};
    return ref_.init();
  }
  hdrc::DeviceInfo device() const override {
    return {"planted", "reference rounded to float32, defects planted (report fixture)", "—", "—"};
  }
  hdrc::Result<Image> run(const hdrc::ResolvedCase& c) override {
    auto img = ref_.run(c);
    if (!img) return img;
    for (double& v : img->data) v = static_cast<float>(v);
    if (c.spec.id == kAcesId) {
      // A highlight regression: PQ signals over PQ(200 nits) = 0.5791 lowered by 0.04.
      for (size_t i = 0; i < img->pixel_count(); ++i)
        for (int ch = 0; ch < 3; ++ch) {
          double& v = img->data[i * Image::kChannels + ch];
          if (v > 0.5791) v = static_cast<float>(v - 0.04);
        }
    }
    if (auto it = plants().find(c.spec.id); it != plants().end()) {
      const Plant& p = it->second;
      double& v = img->px(p.x, p.y)[p.channel];
      v = static_cast<float>(v * p.factor);
    }
    return img;
  }

 private:
  bool available_;
  hdrc::ref::ReferenceEngine ref_;
};

const char* kLinear = R"({
  "stage": "linear_device",
  "cvars": {"r.HDR.EnableHDROutput": 1},
  "matrix": {"mode": "full", "cvars": {"r.HDR.Display.OutputDevice": [7, 8],
                                       "r.HDR.Display.ColorGamut": [0, 1, 2]}},
  "input": {"stimulus": "log_ramp", "width": 64, "height": 4},
  "tolerance": {"linear_rel": {"max": 1e-4, "warn": 1e-5}, "rel_floor": 1e-4, "pq_code10": 0.05,
                "reason": "report fixture: float32 rounding of the reference is ~6e-8"}
})";

const char* kLut = R"({
  "stage": "combine_luts",
  "cvars": {"r.HDR.EnableHDROutput": 1, "r.HDR.Display.OutputDevice": 3, "r.LUT.Size": 16},
  "settings": {"LUTFormat": 2, "LUTLayout": 1},
  "tolerance": {"linear_rel": 5e-3, "rel_floor": 1e-4, "pq_code10": 0.5,
                "reason": "report fixture: one lattice point bumped by 0.2 %"}
})";

const char* kShaper = R"({
  "stage": "shaper",
  "input": {"stimulus": "log_ramp", "width": 32, "height": 2},
  "tolerance": {"linear_rel": 1e-4, "rel_floor": 1e-4, "pq_code10": 0.05,
                "reason": "report fixture"}
})";

const char* kAces = R"({
  "stage": "tonemap",
  "cvars": {"r.HDR.EnableHDROutput": 1, "r.HDR.Display.OutputDevice": 3,
            "r.HDR.Display.ColorGamut": 2, "r.HDR.Display.MaxLuminance": 1000},
  "input": {"stimulus": "log_ramp", "width": 256, "height": 4},
  "tolerance": {"pq_code10": 0.5, "linear_rel": null,
                "reason": "report fixture: an ACES highlight regression is planted"}
})";

const char* kHue = R"({
  "stage": "linear_device",
  "cvars": {"r.HDR.EnableHDROutput": 1, "r.HDR.Display.OutputDevice": 7,
            "r.HDR.Display.ColorGamut": 2},
  "input": {"stimulus": "hue_sweep", "width": 96, "height": 8},
  "tolerance": {"linear_rel": 1e-4, "rel_floor": 1e-4, "pq_code10": 0.05,
                "reason": "report fixture"}
})";

const char* kDegenerate = R"({
  "stage": "combine_luts",
  "cvars": {"r.HDR.EnableHDROutput": 0, "r.HDR.Display.OutputDevice": 3,
            "r.HDR.Display.MaxLuminance": 0, "r.LUT.Size": 16},
  "tolerance": {"linear_rel": 1e-4, "rel_floor": 1e-4, "pq_code10": 0.05,
                "reason": "report fixture"}
})";

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: report_fixture OUT_DIR\n");
    return 2;
  }
  namespace fs = std::filesystem;
  const std::string out = argv[1];
  std::error_code ec;
  fs::remove_all(out, ec);
  fs::create_directories(out, ec);
  if (ec) {
    std::fprintf(stderr, "error: %s: %s\n", out.c_str(), ec.message().c_str());
    return 1;
  }

  const std::string cases_dir = HDRC_SOURCE_DIR "/cases";
  std::vector<hdrc::Error> errors;
  std::vector<Case> main_cases, skipped_cases;
  auto add = [&](std::vector<Case>* to, const char* text, const std::string& name) {
    for (auto& c :
         hdrc::parse_case_file("report-fixture/" + name + ".json", text, cases_dir, name, &errors))
      to->push_back(std::move(c));
  };
  add(&main_cases, kLinear, "fixture/linear");
  add(&main_cases, kLut, "fixture/lut");
  add(&main_cases, kShaper, "fixture/known");
  add(&main_cases, kDegenerate, "fixture/degenerate");
  add(&main_cases, kShaper, "<script>alert(1)</script>");
  add(&main_cases, kAces, "fixture/aces");
  add(&main_cases, kHue, "fixture/hue");
  add(&skipped_cases, kShaper, "fixture/skipped");
  if (!errors.empty()) {
    for (const auto& e : errors) std::fprintf(stderr, "error: %s\n", e.to_string().c_str());
    return 1;
  }

  hdrc::RunOptions opt;
  opt.jobs = 1;
  opt.image_dir = out;
  opt.known_limits.push_back({"fixture/known/*", "planted", "report fixture: listed as a limit"});
  auto reference = [] { return std::make_unique<hdrc::ref::ReferenceEngine>(); };
  hdrc::RunReport report = hdrc::run_cases(
      main_cases, reference, [] { return std::make_unique<PlantedEngine>(true); }, opt);
  hdrc::RunReport skipped = hdrc::run_cases(
      skipped_cases, reference, [] { return std::make_unique<PlantedEngine>(false); }, opt);
  for (auto& c : skipped.cases) report.cases.push_back(std::move(c));
  if (hdrc::Status st = hdrc::write_run_outputs(report, out); !st) {
    std::fprintf(stderr, "error: %s\n", st.error().to_string().c_str());
    return 1;
  }
  // The golden check as `run` records it (runner/results.h: finish_run_outputs): one regression.
  {
    nlohmann::json g = {{"goldens_dir", "goldens"}, {"reference_version", "fixture"}};
    for (const auto& c : report.cases)
      if (c.images.count("reference"))
        g["cases"].push_back(
            {{"id", c.spec.id},
             {"outcome", c.spec.id == "fixture/lut" ? "regression" : "match"},
             {"message",
              c.spec.id == "fixture/lut" ? "golden regression: 1 value(s) differ (planted)" : ""}});
    std::ofstream(out + "/goldens.json") << g.dump(2) << "\n";
    hdrc::finish_run_outputs(out, hdrc::kExitFail, /*goldens_checked=*/true, "all");
  }

  // What the browser test checks, from the fixture's own design and the images it ran.
  nlohmann::json expect = {
      {"verdicts", {{"PASS", 8}, {"FAIL", 2}, {"KNOWN_LIMIT", 1}, {"DEGENERATE", 1}, {"SKIP", 1}}},
      {"aces", kAcesId},
      {"hue", "fixture/hue/hue_sweep"},
      {"golden_regression", "fixture/lut"},
      {"warned", 1},
      {"failing", "fixture/linear/dev8_gamut2_log_ramp"},
      {"warned_case", "fixture/linear/dev7_gamut1_log_ramp"},
      {"hostile", "<script>alert(1)</script>/log_ramp"},
      {"lut", "fixture/lut"},
      {"matrix",
       {{"rows", "r.HDR.Display.OutputDevice"},
        {"cols", "r.HDR.Display.ColorGamut"},
        {"fail_cell", {"8", "2"}},
        {"warn_cell", {"7", "1"}}}}};
  for (const auto& c : report.cases) {
    auto it = plants().find(c.spec.id);
    if (it == plants().end()) continue;
    const Plant& p = it->second;
    nlohmann::json px = {{"x", p.x}, {"y", p.y}, {"channel", p.channel}};
    for (const char* k : {"input", "reference", "candidate"}) {
      auto img = hdrc::read_image(out + "/cases/" + c.spec.id + "/" + k + ".exr");
      if (!img) continue;
      nlohmann::json v = nlohmann::json::array();
      for (int ch = 0; ch < 4; ++ch) v.push_back(img->px(p.x, p.y)[ch]);
      px[k] = v;
    }
    expect["planted"][c.spec.id] = px;
  }
  std::ofstream(out + "/expect.json") << expect.dump(2) << "\n";
  std::printf("report fixture: %zu cases in %s\n", report.cases.size(), out.c_str());
  return 0;
}
