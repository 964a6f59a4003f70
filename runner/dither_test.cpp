// The dither criterion (runner/dither.h): unit tests on synthetic noise with numbers derived by
// hand, the tolerance's "dither" object, and planted dither defects in a copy of the suite's
// shaders run on lavapipe (as runner/pipelines_test.cpp's planted shaders).
#include "runner/dither.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "runner/test_support.h"
#include "runner/tolerance.h"

namespace {

using hdrc::DitherCriterion;
using hdrc::DitherStats;
using hdrc::Image;

// The triangular quantile: the inverse of (1 + t)²/2 below 1/2, of 1 − (1 − t)²/2 above.
double triangular_quantile(double u) {
  return u < 0.5 ? std::sqrt(2.0 * u) - 1.0 : 1.0 - std::sqrt(2.0 * (1.0 - u));
}

// A w x h image of constant `level` and the same plus `scale` x amount x a stratified triangular
// sample (quantile (k + 0.5) / n at pixel i, k = 389 i mod n: every block gets quantiles from the
// whole range), `bias` x amount added; green and blue get the same noise as red, as UE's grain.
struct Pair {
  Image undithered, candidate;
};
Pair noisy(int w, int h, double level, double amount, double scale, double bias = 0.0) {
  Pair p{Image(w, h), Image(w, h)};
  const size_t n = p.undithered.pixel_count();
  for (size_t i = 0; i < n; ++i) {
    const size_t k = (389 * i) % n;
    const double t = triangular_quantile((static_cast<double>(k) + 0.5) / static_cast<double>(n));
    for (int c = 0; c < 4; ++c) {
      p.undithered.data[i * 4 + c] = c < 3 ? level : 1.0;
      p.candidate.data[i * 4 + c] = c < 3 ? level + (scale * t + bias) * amount : 1.0;
    }
  }
  return p;
}

DitherStats stats(const Pair& p, double amount) {
  return hdrc::dither_stats(p.undithered, p.candidate, amount, DitherCriterion{});
}

TEST(Dither, TriangularCdfByHand) {
  EXPECT_DOUBLE_EQ(hdrc::triangular_cdf(-2.0), 0.0);
  EXPECT_DOUBLE_EQ(hdrc::triangular_cdf(-1.0), 0.0);
  EXPECT_DOUBLE_EQ(hdrc::triangular_cdf(-0.5), 0.125);  // 0.5² / 2
  EXPECT_DOUBLE_EQ(hdrc::triangular_cdf(0.0), 0.5);
  EXPECT_DOUBLE_EQ(hdrc::triangular_cdf(0.5), 0.875);
  EXPECT_DOUBLE_EQ(hdrc::triangular_cdf(1.0), 1.0);
  EXPECT_DOUBLE_EQ(triangular_quantile(0.125), -0.5);
}

// A stratified triangular sample: std exactly that of the distribution up to O(1/n), KS distance
// 0.5 / n (each quantile sits mid-step), block means near 0; every bound holds.
TEST(Dither, StratifiedTriangularNoisePasses) {
  const double amount = 1.0 / 1023.0;
  const DitherStats s = stats(noisy(64, 16, 0.5, amount, 1.0), amount);
  EXPECT_EQ(s.values, 3u * 1024);
  EXPECT_EQ(s.over_amplitude, 0u);
  EXPECT_EQ(s.resolved, 3u * 1024);
  ASSERT_TRUE(s.statistics);
  for (const auto& ch : s.channel) {
    EXPECT_EQ(ch.n, 1024u);
    EXPECT_EQ(ch.blocks, 4u);
    EXPECT_TRUE(ch.judged);
    EXPECT_FALSE(ch.mean_over);
    EXPECT_NEAR(ch.std_ratio, 1.0, 2e-3);
    EXPECT_NEAR(ch.ks, 0.5 / 1024, 1e-6);
    // 5 sqrt(1.4 / 4096) + sqrt(6) / 256 and 3.75 / 32 + 1 / 256: the bounds as derived.
    EXPECT_NEAR(ch.std_bound, 5 * std::sqrt(1.4 / 4096) + std::sqrt(6.0) / 256, 1e-12);
    EXPECT_NEAR(ch.ks_bound, 3.75 / 32 + 1.0 / 256, 1e-12);
  }
  hdrc::Tolerance tol;
  tol.dither.judged = true;
  const hdrc::DiffStats diff;
  hdrc::DiffStats some = diff;
  some.values = s.values;
  some.pixels = 1024;
  const hdrc::Verdict v = hdrc::judge_dither(some, s, tol, false, false);
  EXPECT_TRUE(v.pass) << v.reason;
  EXPECT_NE(v.reason.find("exact pattern reported, not judged"), std::string::npos) << v.reason;
}

hdrc::Verdict verdict(const Pair& p, double amount) {
  hdrc::Tolerance tol;
  tol.dither.judged = true;
  hdrc::DiffStats d;
  d.pixels = p.undithered.pixel_count();
  d.values = 3 * d.pixels;
  return hdrc::judge_dither(d, stats(p, amount), tol, false, false);
}

// 1.5 x the amplitude: |t| > 2/3 exceeds the amount, (1/3)² of the values.
TEST(Dither, AmplitudeTimesOneAndAHalfFails) {
  const double amount = 1.0 / 1023.0;
  const DitherStats s = stats(noisy(64, 16, 0.5, amount, 1.5), amount);
  EXPECT_NEAR(static_cast<double>(s.over_amplitude) / (3 * 1024), 1.0 / 9.0, 2e-3);
  // The largest quantile (1023.5 / 1024) is t = 1 − sqrt(1 / 1024) = 31/32: 1.5 x that.
  EXPECT_NEAR(s.max_amplitude, 1.5 * 31.0 / 32.0, 1e-9);
  const hdrc::Verdict v = verdict(noisy(64, 16, 0.5, amount, 1.5), amount);
  EXPECT_FALSE(v.pass);
  EXPECT_EQ(v.reason.rfind("dither amplitude: ", 0), 0u) << v.reason;
}

// Half the amplitude stays within it, but its std is half the triangular one's.
TEST(Dither, AmplitudeTimesOneHalfFailsTheStd) {
  const double amount = 1.0 / 255.0;
  const DitherStats s = stats(noisy(64, 16, 0.5, amount, 0.5), amount);
  EXPECT_EQ(s.over_amplitude, 0u);
  EXPECT_NEAR(s.channel[0].std_ratio, 0.5, 1e-3);
  const hdrc::Verdict v = verdict(noisy(64, 16, 0.5, amount, 0.5), amount);
  EXPECT_FALSE(v.pass);
  EXPECT_EQ(v.reason.rfind("dither std: R's noise has 0.5 x", 0), 0u) << v.reason;
}

// A bias of 0.1 amount: each block's mean is 0.1 (plus the block's own sample mean, a few
// hundredths of a standard error here), sqrt(6 · 256) · 0.1 = 3.9 standard errors — under 5.5;
// 0.2 (7.8) is over.
TEST(Dither, BiasedGrainFailsTheBlockMean) {
  const double amount = 1.0 / 1023.0;
  const DitherStats small = stats(noisy(64, 16, 0.25, amount, 0.8, 0.1), amount);
  EXPECT_EQ(small.over_amplitude, 0u);
  EXPECT_FALSE(small.channel[1].mean_over);
  EXPECT_NEAR(small.channel[1].mean_z, 0.1 * std::sqrt(6.0 * 256), 0.2);
  const hdrc::Verdict v = verdict(noisy(64, 16, 0.25, amount, 0.8, 0.2), amount);
  EXPECT_FALSE(v.pass);
  EXPECT_EQ(v.reason.rfind("dither mean: block ", 0), 0u) << v.reason;
}

// A uniform grain of the triangular variance (half-width 1/sqrt(2)) has the right amplitude and
// std; only the histogram tells them apart: KS distance 0.0429 (at t = -0.30: uniform 0.288,
// triangular 0.245), over 3.75 / sqrt(n) + 1/256 from n = 9 200 values. 128 x 128 shows it.
TEST(Dither, UniformGrainOfTheSameVarianceFailsTheHistogram) {
  const double amount = 1.0 / 1023.0;
  Pair p = noisy(128, 128, 0.5, amount, 1.0);
  const size_t n = p.undithered.pixel_count();
  for (size_t i = 0; i < n; ++i) {
    const double u = (static_cast<double>((389 * i) % n) + 0.5) / static_cast<double>(n);
    for (int c = 0; c < 3; ++c)
      p.candidate.data[i * 4 + c] = 0.5 + (2.0 * u - 1.0) / std::sqrt(2.0) * amount;
  }
  const DitherStats s = stats(p, amount);
  EXPECT_EQ(s.over_amplitude, 0u);
  EXPECT_NEAR(s.channel[0].std_ratio, 1.0, 1e-3);
  EXPECT_NEAR(s.channel[0].ks, 0.0429, 5e-4);
  const hdrc::Verdict v = verdict(p, amount);
  EXPECT_FALSE(v.pass);
  EXPECT_EQ(v.reason.rfind("dither histogram: R's noise is 0.0429", 0), 0u) << v.reason;
}

// Amount 0 (devices 8/9): the output must be the input, within float32 noise of it.
TEST(Dither, NoAmountMeansNoNoise) {
  Pair p = noisy(16, 4, 0.5, 0.0, 1.0);
  EXPECT_TRUE(verdict(p, 0.0).pass);
  p.candidate.data[0] += 0.5 * 0x1p-20;  // float32 noise of 0.5: within
  EXPECT_TRUE(verdict(p, 0.0).pass);
  p.candidate.data[0] += 1e-6;
  const hdrc::Verdict v = verdict(p, 0.0);
  EXPECT_FALSE(v.pass);
  EXPECT_NE(v.reason.find("1 of 192 values differ"), std::string::npos) << v.reason;
}

// Values whose float32 spacing is coarse against the amount (16-bit amount at 100) leave the
// statistics; the amplitude still judges them.
TEST(Dither, CoarseValuesLeaveTheStatistics) {
  const double amount = 1.0 / 65535.0;
  const DitherStats s = stats(noisy(64, 16, 100.0, amount, 1.0), amount);
  EXPECT_EQ(s.resolved, 0u);
  EXPECT_FALSE(s.statistics);
  EXPECT_EQ(s.over_amplitude, 0u);
}

// The exact pattern: judged where the device is float32-exact, reported elsewhere.
TEST(Dither, ExactPatternOnlyOnFloat32ExactDevices) {
  hdrc::DeviceInfo lavapipe{"vulkan", "llvmpipe (LLVM 15.0.6, 256 bits)", "", "", {}};
  hdrc::DeviceInfo worst = lavapipe;
  worst.precision.model = "worst";
  hdrc::DeviceInfo nvidia{"vulkan", "NVIDIA H200", "", "", {}};
  hdrc::DeviceInfo reference{"reference", "cpu (IEEE double)", "", "", {}};
  hdrc::DeviceInfo port{"candidate-dir", "a port", "", "", {}};
  EXPECT_TRUE(hdrc::float32_exact_device(lavapipe));
  EXPECT_TRUE(hdrc::float32_exact_device(reference));
  EXPECT_FALSE(hdrc::float32_exact_device(worst));
  EXPECT_FALSE(hdrc::float32_exact_device(nvidia));
  EXPECT_FALSE(hdrc::float32_exact_device(port));
  nvidia.precision.float32_exact = true;  // a device that says so
  EXPECT_TRUE(hdrc::float32_exact_device(nvidia));
  DitherCriterion c;
  EXPECT_TRUE(hdrc::exact_pattern_judged(c, lavapipe));
  EXPECT_FALSE(hdrc::exact_pattern_judged(c, port));
  c.exact_pattern = "always";
  EXPECT_TRUE(hdrc::exact_pattern_judged(c, port));
  c.exact_pattern = "never";
  EXPECT_FALSE(hdrc::exact_pattern_judged(c, lavapipe));
}

TEST(Dither, ToleranceObjectParsesAndNamesItsErrors) {
  using nlohmann::ordered_json;
  auto parse = [](const std::string& text) {
    return hdrc::parse_tolerance(ordered_json::parse(text), "t.json", "/tolerance");
  };
  auto t = parse(R"({"dither": {"mean_sigmas": 4, "ks_c": 3, "exact_pattern": "always",
                    "reason": "why"}, "reason": "r"})");
  ASSERT_TRUE(t) << t.error().to_string();
  EXPECT_TRUE(t->dither.judged);
  EXPECT_EQ(t->dither.mean_sigmas, 4);
  EXPECT_EQ(t->dither.std_sigmas, 5);  // not named: the default
  EXPECT_EQ(t->dither.ks_c, 3);
  EXPECT_EQ(t->dither.exact_pattern, "always");
  EXPECT_EQ(hdrc::tolerance_json(*t)["dither"]["block_pixels"], 256);
  // An overlay's null clears it.
  auto cleared = hdrc::parse_tolerance(ordered_json::parse(R"({"dither": null, "reason": "r"})"),
                                       "o.json", "/o", *t);
  ASSERT_TRUE(cleared);
  EXPECT_FALSE(cleared->dither.judged);
  EXPECT_TRUE(hdrc::tolerance_json(*cleared)["dither"].is_null());
  auto no_reason = parse(R"({"dither": {"mean_sigmas": 4}, "reason": "r"})");
  ASSERT_FALSE(no_reason);
  EXPECT_EQ(no_reason.error().pointer, "/tolerance/dither/reason");
  auto bad_key = parse(R"({"dither": {"sigmas": 4, "reason": "x"}, "reason": "r"})");
  ASSERT_FALSE(bad_key);
  EXPECT_NE(bad_key.error().to_string().find("unknown key 'sigmas'"), std::string::npos);
  auto bad_choice = parse(R"({"dither": {"exact_pattern": "sometimes", "reason": "x"},
                              "reason": "r"})");
  ASSERT_FALSE(bad_choice);
  EXPECT_EQ(bad_choice.error().pointer, "/tolerance/dither/exact_pattern");
  EXPECT_FALSE(parse(R"({"dither": {"ks_c": 0, "reason": "x"}, "reason": "r"})"));
  EXPECT_FALSE(parse(R"({"dither": {"block_pixels": 2.5, "reason": "x"}, "reason": "r"})"));
}

// ---- Planted dither defects on lavapipe
// ----------------------------------------------------------

namespace fs = std::filesystem;
using hdrc::test::read;
using hdrc::test::write;

const char* kDitherCases = "tonemap/dither/*,tonemap/working_color_space_dither/*";

// Runs the default suite's dither cases with `from` replaced by `to` in a copy of
// gpu/shaders/lib/dither.glsl (none when `from` is empty); with `properties_only`, a copy of
// cases/ whose overlay judges the properties alone (exact_pattern "never", as a device whose hash
// differs). The verdict of each case, and its amount.
struct Outcome {
  std::map<std::string, std::string> verdict;
  std::map<std::string, double> amount;
  std::map<std::string, int> frame;
  std::string out;
};
Outcome run_dither(const std::string& from, const std::string& to, bool properties_only) {
  const fs::path shaders = hdrc::test::temp_dir("dither_shaders");
  const fs::path cases = hdrc::test::temp_dir("dither_cases");
  const fs::path results = hdrc::test::temp_dir("dither_out");
  fs::copy(fs::path(HDRC_SOURCE_DIR) / "gpu/shaders", shaders, fs::copy_options::recursive);
  if (!from.empty()) {
    std::string text = read(shaders / "lib/dither.glsl");
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    write(shaders / "lib/dither.glsl", text);
  }
  fs::copy(fs::path(HDRC_SOURCE_DIR) / "cases", cases, fs::copy_options::recursive);
  if (properties_only) {
    auto overlays = nlohmann::ordered_json::parse(read(cases / "tolerance_overlays.json"));
    overlays["overlays"].push_back(
        {{"stage", "dither"},
         {"tolerance",
          {{"dither", {{"exact_pattern", "never"}, {"reason", "test: the properties alone"}}},
           {"reason", "test: judged as on a device whose hash differs"}}}});
    write(cases / "tolerance_overlays.json", overlays.dump(2));
  }
  const hdrc::test::Ran r = hdrc::test::run("run --cases " + cases.string() + " --filter '" +
                                            kDitherCases + "' --no-goldens --shader-dir " +
                                            shaders.string() + " --out " + results.string());
  Outcome o;
  o.out = r.out;
  const auto j = nlohmann::json::parse(read(results / "results.json"));
  for (const auto& c : j["cases"]) {
    const std::string id = c["id"];
    o.verdict[id] = c["verdict"];
    o.amount[id] = c["params"]["dither_amount"];
    o.frame[id] = c["params"]["frame_index"];
  }
  fs::remove_all(shaders);
  fs::remove_all(cases);
  fs::remove_all(results);
  return o;
}

// Every case with a dither (amount > 0) fails, every one without passes.
void expect_fails_where_dithered(const Outcome& o, const std::string& what) {
  ASSERT_EQ(o.verdict.size(), 75u) << o.out;
  for (const auto& [id, v] : o.verdict) {
    if (o.amount.at(id) > 0)
      EXPECT_EQ(v, "FAIL") << what << ": " << id;
    else
      EXPECT_EQ(v, "PASS") << what << ": " << id;
  }
}

// The shaders as they are: every case passes with the properties alone, as with the exact pattern.
TEST(DitherPlanted, TheShadersAsTheyArePassTheProperties) {
  const Outcome o = run_dither("", "", true);
  ASSERT_EQ(o.verdict.size(), 75u) << o.out;
  for (const auto& [id, v] : o.verdict) EXPECT_EQ(v, "PASS") << id;
}

TEST(DitherPlanted, AmplitudeTimesOneAndAHalfFails) {
  expect_fails_where_dithered(
      run_dither("return rgb + grain * amount;", "return rgb + grain * (amount * 1.5);", true),
      "amount x 1.5");
}

TEST(DitherPlanted, AmplitudeTimesOneHalfFails) {
  expect_fails_where_dithered(
      run_dither("return rgb + grain * amount;", "return rgb + grain * (amount * 0.5);", true),
      "amount x 0.5");
}

// The 8-bit step where a 10-bit one applies (and 1/255 for every override): the cases whose
// amount is 1/255 pass, every other dithered case fails.
TEST(DitherPlanted, WrongQuantisationStepFails) {
  const Outcome o = run_dither("return rgb + grain * amount;",
                               "return rgb + grain * (amount > 0.0 ? 1.0 / 255.0 : 0.0);", true);
  ASSERT_EQ(o.verdict.size(), 75u) << o.out;
  size_t failed = 0;
  for (const auto& [id, v] : o.verdict) {
    const double a = o.amount.at(id);
    const bool right = a == 0 || std::fabs(a - 1.0 / 255.0) < 1e-12;
    EXPECT_EQ(v, right ? "PASS" : "FAIL") << id << " amount " << a;
    failed += v == "FAIL";
  }
  EXPECT_GE(failed, 40u);
}

// The 10-bit step where the 8-bit one applies: a third of the noise, caught by its std.
TEST(DitherPlanted, TenBitStepOnAnEightBitBackBufferFails) {
  const Outcome o = run_dither("return rgb + grain * amount;",
                               "return rgb + grain * (amount > 1.0 / 256.0 && amount < 1.0 / 254.0"
                               " ? 1.0 / 1023.0 : amount);",
                               true);
  ASSERT_EQ(o.verdict.size(), 75u) << o.out;
  size_t eight_bit = 0;
  for (const auto& [id, v] : o.verdict) {
    const bool is8 = std::fabs(o.amount.at(id) - 1.0 / 255.0) < 1e-12;
    eight_bit += is8;
    EXPECT_EQ(v, is8 ? "FAIL" : "PASS") << id;
  }
  EXPECT_GE(eight_bit, 5u);
}

// A correct dither whose hash differs (the sine's argument moved by 1e-3, far more than a driver's
// sin differs): the properties pass every case; the exact pattern (lavapipe's default judgement)
// fails every dithered one.
TEST(DitherPlanted, AnotherHashPassesThePropertiesAndFailsTheExactPattern) {
  const std::string from = "precise float g = sin(a) * DITHER_GRAIN_SIN_SCALE;";
  const std::string to = "precise float g = sin(a + 1e-3) * DITHER_GRAIN_SIN_SCALE;";
  const Outcome props = run_dither(from, to, true);
  ASSERT_EQ(props.verdict.size(), 75u) << props.out;
  for (const auto& [id, v] : props.verdict) EXPECT_EQ(v, "PASS") << id;
  expect_fails_where_dithered(run_dither(from, to, false), "sin(a + 1e-3), exact pattern");
  // The hash constant's last digit: the same.
  const Outcome digit = run_dither(from, "precise float g = sin(a) * 493017.0;", true);
  for (const auto& [id, v] : digit.verdict) EXPECT_EQ(v, "PASS") << id;
}

// Frame 0's grain offset for every frame: one frame of it is a correct triangular grain, so the
// properties cannot tell (every case passes them); the exact pattern catches it on every dithered
// case whose frame index is not 0.
TEST(DitherPlanted, MissingFrameIndexFailsOnlyWhereTheExactPatternIsJudged) {
  const std::string from = "precise vec2 grain_uv = uv + grain_random;";
  const std::string to = "precise vec2 grain_uv = uv + 0.0 * grain_random;";
  const Outcome props = run_dither(from, to, true);
  ASSERT_EQ(props.verdict.size(), 75u) << props.out;
  for (const auto& [id, v] : props.verdict) EXPECT_EQ(v, "PASS") << id;
  const Outcome exact = run_dither(from, to, false);
  ASSERT_EQ(exact.verdict.size(), 75u) << exact.out;
  size_t judged = 0;
  for (const auto& [id, v] : exact.verdict) {
    const bool shows = exact.amount.at(id) > 0 && exact.frame.at(id) != 0;
    judged += shows;
    EXPECT_EQ(v, shows ? "FAIL" : "PASS") << id;
  }
  EXPECT_GE(judged, 20u);
}

}  // namespace
