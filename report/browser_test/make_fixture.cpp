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
//   fixture/lut64                          a 64³ CombineLUTs LUT (4096 × 64), passing, every value
//                                          off by up to 2 float32 ulps (a GPU's rounding): the
//                                          heaviest case page of the default suite
//   fixture/ue58                           a UE 5.8 CombineLUTs LUT (16³, inner 17³, ACES 2.0 on
//                                          device 3), passing: a ue58 case page, its resolved
//                                          parameters with the ACES 2.0 tables
//   fixture/long-ids/<long family>/...     failing cases with ids and reasons longer than a list
//                                          row's line, from two pipelines (ue55 shaper,
//                                          operators tone_curve): every value × 1.002
// and a golden check with one regression (fixture/lut), recorded as the runner records it.
//
// Usage: report_fixture OUT_DIR. Also writes OUT_DIR/expect.json: what the fixture planted, for
// the browser test to check the report against (independently of results.json).
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <vector>

#include "core/pipeline.h"
#include "reference/reference_engine.h"
#include "report/images.h"
#include "runner/case_loader.h"
#include "runner/goldens.h"
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
const std::string kLongIds = "fixture/long-ids/";
const std::string kLut64 = "fixture/lut64";
const std::string kUe58 = "fixture/ue58";

// Writes the first `channels` channels of `img` (R, G, B[, A]) as an EXR with `compression`
// (OpenImageIO's name) in `type`.
bool write_exr_as(const std::string& path, const Image& img, int channels,
                  const std::string& compression, OIIO::TypeDesc type) {
  OIIO::ImageSpec spec(img.width, img.height, channels, type);
  spec.attribute("compression", compression);
  std::vector<float> px(img.pixel_count() * channels);
  for (size_t i = 0; i < img.pixel_count(); ++i)
    for (int c = 0; c < channels; ++c)
      px[i * channels + c] = static_cast<float>(img.data[i * 4 + c]);
  auto o = OIIO::ImageOutput::create(path);
  return o && o->open(path, spec) && o->write_image(OIIO::TypeDesc::FLOAT, px.data()) && o->close();
}

// The EXR forms' values: smooth ramps with NaN, ±Inf, −0, negatives, values under half's
// normal range and over its largest, and alpha varying per pixel.
double form_value(size_t i, int c) {
  switch ((i * 4 + c) % 97) {
    case 5:
      return std::nan("");
    case 11:
      return HUGE_VAL;
    case 23:
      return -HUGE_VAL;
    case 31:
      return -0.0;
    case 43:
      return 3e-6;  // a half subnormal
    case 59:
      return 70000.0;  // over half's largest (65504): +Inf in half
    default:
      return (c == 3 ? 0.25 : 1.0) * std::pow(1.37, static_cast<double>(i % 41) - 20.0) *
             ((i + c) % 7 == 0 ? -1.0 : 1.0);
  }
}

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
    return {
        "planted", "reference rounded to float32, defects planted (report fixture)", "—", "—", {}};
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
    if (c.spec.id.rfind(kLongIds, 0) == 0)
      for (double& v : img->data) v = static_cast<float>(v * 1.002);
    if (c.spec.id == kLut64)
      for (size_t i = 0; i < img->data.size(); ++i)
        img->data[i] = static_cast<float>(
            img->data[i] * (1.0 + std::ldexp(static_cast<double>(i % 5) - 2.0, -23)));
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

const char* kLut64Case = R"({
  "stage": "combine_luts",
  "cvars": {"r.HDR.EnableHDROutput": 1, "r.HDR.Display.OutputDevice": 3, "r.LUT.Size": 64},
  "settings": {"LUTFormat": 2, "LUTLayout": 1},
  "tolerance": {"linear_rel": 1e-5, "rel_floor": 1e-4, "pq_code10": 0.05,
                "reason": "report fixture: every value off by up to 2 float32 ulps"}
})";

// A ue58 case as the default suite's cases/ue58/devices.json has them (16³ outer LUT, 17³ inner
// LUT), ACES 2.0 on the 1000-nit PQ device.
const char* kUe58Case = R"({
  "pipeline": "ue58",
  "stage": "ue58_combine_luts",
  "cvars": {"r.LUT.Size": 16, "r.HDR.Display.OutputDevice": 3, "r.HDR.Display.ColorGamut": 2},
  "settings": {"r.LUT.Inner.Size": 17, "TonemappingMethod": "StandardACES",
               "r.HDR.Aces.Version": 2},
  "tolerance": {"linear_rel": 1e-5, "rel_floor": 1e-4, "pq_code10": 0.05,
                "reason": "report fixture: the reference rounded to float32"}
})";

// Failing cases whose ids and reasons are longer than a list row (issue 27: at 1400 px a row of
// the failing-case list was ~842 px tall): every value × 1.002, over a tolerance with an
// allowed fraction (the longest form of the judge's reason).
const char* kLongUe = R"({
  "stage": "shaper",
  "input": {"stimulus": "log_ramp", "width": 64, "height": 4},
  "tolerance": {"linear_rel": {"max": 1e-4, "allowed_fraction": 0.001, "hard": 0.1},
                "rel_floor": 1e-4, "pq_code10": null,
                "reason": "report fixture: a long failing case of the ue55 pipeline"}
})";
const char* kLongOps = R"({
  "pipeline": "operators",
  "stage": "tone_curve",
  "settings": {"Operator": "Hable", "AdaptedLuminance": 0.72, "Key": 0.09},
  "input": {"stimulus": "log_ramp", "width": 64, "height": 4},
  "tolerance": {"linear_rel": {"max": 1e-4, "allowed_fraction": 0.001, "hard": 0.1},
                "rel_floor": 1e-3, "pq_code10": null,
                "reason": "report fixture: a long failing case of the operators pipeline"}
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

  const std::string cases_dir = std::string(HDRC_SOURCE_DIR) + "/cases";
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
  add(&main_cases, kLut64Case, kLut64);
  add(&main_cases, kUe58Case, kUe58);
  add(&main_cases, kLongUe,
      kLongIds + "ue55_shaper_of_the_log_ramp_with_a_case_family_name_far_longer_than_a_line");
  add(&main_cases, kLongOps,
      kLongIds + "operators_hable_tone_curve_adapted_luminance_and_key_off_default_too_long");
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
      {"verdicts", {{"PASS", 10}, {"FAIL", 4}, {"KNOWN_LIMIT", 1}, {"DEGENERATE", 1}, {"SKIP", 1}}},
      {"aces", kAcesId},
      {"hue", "fixture/hue/hue_sweep"},
      {"golden_regression", "fixture/lut"},
      {"warned", 1},
      {"failing", "fixture/linear/dev8_gamut2_log_ramp"},
      {"warned_case", "fixture/linear/dev7_gamut1_log_ramp"},
      {"hostile", "<script>alert(1)</script>/log_ramp"},
      {"lut", "fixture/lut"},
      {"lut64", kLut64},
      {"ue58", kUe58},
      {"long_ids", kLongIds},
      {"matrix",
       {{"rows", "r.HDR.Display.OutputDevice"},
        {"cols", "r.HDR.Display.ColorGamut"},
        {"fail_cell", {"8", "2"}},
        {"warn_cell", {"7", "1"}}}}};
  // The class of each failure, by design (the summary groups its worst cases by class): the
  // planted pixel's linear_rel 0.01 and the long cases' 0.002 are over linear_rel's max (the
  // first metric judged), the ACES case judges pq_code10 alone.
  expect["classes"]["linear_rel over tolerance"] = {expect["failing"]};
  for (const auto& c : report.cases)
    if (c.spec.id.rfind(kLongIds, 0) == 0)
      expect["classes"]["linear_rel over tolerance"].push_back(c.spec.id);
  expect["classes"]["pq_code10 over tolerance"] = {kAcesId};
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
  // The heatmaps and mask report/images.cpp error_maps makes of the compared cases (C++, from the
  // EXRs, the case's resolved encoding and tolerance): the case page's script draws its own from
  // the float data, and the browser test compares the two (report.js mirrors error_maps).
  for (const auto& c : report.cases) {
    if (!c.has_params || !c.spec.stage) continue;
    const std::string dir = out + "/cases/" + c.spec.id + "/";
    auto ref = hdrc::read_image(dir + "reference.exr");
    auto cand = hdrc::read_image(dir + "candidate.exr");
    if (!ref || !cand) continue;
    const hdrc::OutputEncoding enc = hdrc::output_encoding(*c.spec.stage, c.params);
    const Image rn = hdrc::report::nits_image(*ref, enc);
    const Image cn = hdrc::report::nits_image(*cand, enc);
    const hdrc::ref::Mat3 to_display = hdrc::report::output_to_display(enc);
    const auto prev = hdrc::report::preview_of_nits(*ref, rn, 0, &to_display);
    const auto maps = hdrc::report::error_maps(*ref, *cand, rn, cn, enc, c.tolerance, prev);
    auto bytes = [](const hdrc::report::Rgb8& m) {
      return hdrc::report::base64_of(m.data.data(), m.data.size());
    };
    expect["maps"][c.spec.id] = {{"w", ref->width},           {"h", ref->height},
                                 {"heat", bytes(maps.heat)},  {"heat_itp", bytes(maps.heat_itp)},
                                 {"mask", bytes(maps.mask)},  {"over", maps.over},
                                 {"mismatch", maps.mismatch}, {"encoding", enc.describe()}};
  }
  // OutputEncoding::to_nits of every transfer on sample values, for the script's toNits (the
  // suites' SDR outputs decode through sRGB, Rec.709 and gamma; the fixture's cases do not).
  {
    using T = hdrc::OutputEncoding::Transfer;
    const char* names[] = {"linear", "pq", "srgb", "rec709", "gamma"};
    const T kinds[] = {T::kLinear, T::kPq, T::kSrgb, T::kRec709, T::kGamma};
    for (int k = 0; k < 5; ++k)
      for (double pre : {1.0, 1.05}) {
        hdrc::OutputEncoding e;
        e.transfer = kinds[k];
        e.pre_scale = pre;
        e.nits_scale = kinds[k] == T::kPq ? 1.0 : 100.0;
        e.gamma = 2.4;
        nlohmann::json v = nlohmann::json::array(), n = nlohmann::json::array();
        for (double x : {-0.5, 0.0, 1e-6, 3e-5, 0.003, 0.0385, 0.04045, 0.05, 0.077, 0.081, 0.09,
                         0.25, 0.5, 0.75, 0.95, 1.0, 1.3}) {
          v.push_back(x);
          const double nits = e.to_nits(x);
          n.push_back(std::isnan(nits) ? nlohmann::json("NaN") : nlohmann::json(nits));
        }
        expect["to_nits"].push_back({{"enc",
                                      {{"transfer", names[k]},
                                       {"pre_scale", pre},
                                       {"nits_scale", e.nits_scale},
                                       {"gamma", e.gamma}}},
                                     {"v", v},
                                     {"nits", n}});
      }
  }
  // The failing case's input rewritten with PIZ compression (same float32 values): an EXR the
  // case page's script does not decode itself, so the report packs its values (the fallback path
  // of report/html_report.cpp; the probe must show the same numbers either way).
  {
    const std::string p = out + "/cases/" + expect["failing"].get<std::string>() + "/input.exr";
    auto img = hdrc::read_image(p);
    if (!img || !write_exr_as(p, *img, 4, "piz", OIIO::TypeDesc::FLOAT)) {
      std::fprintf(stderr, "error: cannot rewrite %s\n", p.c_str());
      return 1;
    }
    expect["piz_input"] = expect["failing"];
  }
  // EXR files in every form report.js decodeExr reads, with the values OpenImageIO reads back
  // (what the report's C++ shows): HALF and FLOAT, compression NONE, ZIPS and ZIP, RGB and RGBA,
  // 37 x 19 (a last ZIP chunk of 3 lines), special values included.
  fs::create_directories(out + "/exr-forms", ec);
  for (const char* comp : {"none", "zips", "zip"})
    for (const bool half : {false, true})
      for (const int ch : {3, 4}) {
        Image img(37, 19);
        for (size_t i = 0; i < img.pixel_count(); ++i)
          for (int c = 0; c < 4; ++c) img.data[i * 4 + c] = form_value(i, c);
        const std::string name = std::string(comp) + (half ? "-half" : "-float") + "-" +
                                 (ch == 3 ? "rgb" : "rgba") + ".exr";
        const std::string p = out + "/exr-forms/" + name;
        if (!write_exr_as(p, img, ch, comp, half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT)) {
          std::fprintf(stderr, "error: cannot write %s\n", p.c_str());
          return 1;
        }
        auto back = hdrc::read_image(p);
        if (!back) return 1;
        nlohmann::json v = nlohmann::json::array();
        for (double x : back->data)  // non-finite values as strings (JSON has no NaN)
          v.push_back(std::isnan(x)   ? nlohmann::json("NaN")
                      : std::isinf(x) ? nlohmann::json(x > 0 ? "Infinity" : "-Infinity")
                                      : nlohmann::json(x));
        expect["exr_forms"].push_back(
            {{"file", "exr-forms/" + name}, {"w", 37}, {"h", 19}, {"rgba", v}});
      }
  // The golden review (`hdrconform goldens diff`, runner/goldens_diff.h): a planted change of
  // one reference constant. goldens-review/cases holds the ACES case, old/ its golden as
  // `goldens update` writes it, new/ the golden the reference makes with one coefficient of the
  // working colour space -> AP0 matrix changed in its 4th significant digit (the change
  // GoldenCompare.ARealChangeOfAConstantFailsAgainstTheRepositorysGolden makes in the 5th).
  // run.sh runs `goldens diff --old old --goldens new`; expect.json's "review" has the largest
  // move in 10-bit PQ codes computed here from the two EXRs: the output is a PQ signal (device
  // 3), so the PQ move of a value is |new − old| · 1023 (ST 2084: PQ(nits(v)) = v).
  {
    const std::string rv = out + "/goldens-review";
    fs::create_directories(rv + "/cases/review", ec);
    std::ofstream(rv + "/cases/review/aces.json") << kAces;
    hdrc::LoadedCases loaded = hdrc::load_cases(rv + "/cases");
    if (!loaded.errors.empty() || loaded.cases.size() != 1) {
      std::fprintf(stderr, "error: the review case did not load\n");
      return 1;
    }
    const Case& c = loaded.cases[0];
    const hdrc::GoldenUpdateReport up = hdrc::update_goldens(loaded.cases, rv + "/old", false, 1);
    if (!up.errors.empty() || up.written != 1) {
      std::fprintf(stderr, "error: the review's old golden was not written\n");
      return 1;
    }
    auto rc = hdrc::resolve_case(c);
    if (!rc) return 1;
    rc->params.wcs_to_ap0(0, 0) *= 1 + 1e-3;
    hdrc::ref::ReferenceEngine engine;
    auto changed = engine.run(*rc);
    fs::create_directories(rv + "/new", ec);
    fs::copy(rv + "/old", rv + "/new", fs::copy_options::recursive, ec);
    const hdrc::GoldenPaths paths = hdrc::golden_paths(rv + "/new", c.id);
    if (!changed || !hdrc::write_exr(paths.exr, *changed)) {
      std::fprintf(stderr, "error: the review's new golden was not written\n");
      return 1;
    }
    auto a = hdrc::read_image(hdrc::golden_paths(rv + "/old", c.id).exr);
    auto b = hdrc::read_image(paths.exr);
    if (!a || !b) return 1;
    double largest = 0;
    for (size_t i = 0; i < a->pixel_count(); ++i)
      for (int ch = 0; ch < 3; ++ch)
        largest = std::max(largest, std::abs(b->data[i * 4 + ch] - a->data[i * 4 + ch]) * 1023);
    expect["review"] = {{"id", c.id}, {"pq10_max", largest}};
  }
  std::ofstream(out + "/expect.json") << expect.dump(2) << "\n";
  std::printf("report fixture: %zu cases in %s\n", report.cases.size(), out.c_str());
  return 0;
}
