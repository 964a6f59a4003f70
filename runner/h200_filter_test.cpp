// The H200's FAILs of 2026-11-27 in the Tonemap pass, Unity's grading and pq_grading (NVIDIA H200,
// driver 580.159.04; device precision: subTexelPrecisionBits 8, float16 RTE; `hdrconform run
// --device nvidia`, tree 6e180a7; its results.json): per case the worst value of every metric that
// failed, as the results named it (pixel, channel, the H200's value, the reference's), against the
// reference's device ranges asked for with the H200's precision. Those ranges hold the filter's
// arithmetic in the texture format's precision (reference/color/device_allowance.h filter_taps:
// VK-GL-CTS's filtering precision), so this is the count of docs/precision.md, "Filter arithmetic":
// which of the H200's lookups a device filtering at the CTS's precision, each tap's weight on the
// sub-texel grid, can produce: all of them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "core/image.h"
#include "runner/diff.h"
#include "runner/h200_references.h"
#include "runner/tolerance.h"

namespace {

const std::string kCasesDir = std::string(HDRC_SOURCE_DIR) + "/cases";

struct H200Value {
  const char* id;
  int x, y, channel;
  double candidate, reference;
  // Inside the reference's device ranges: every value since each tap's weight snaps to the
  // sub-texel grid too (device_allowance.h filter_taps, weight_bits; docs/precision.md, "Filter
  // arithmetic"). Before that, the 10 values of Unity's RGBA16F lookups marked "snapped weight"
  // lay outside.
  bool admitted;
};

// From the H200's results.json (cases[].stats.overall.<metric>.worst of every metric with values
// over its bound), one row per distinct pixel and channel; VisualizeHDR's cases are
// runner/visualize_device_test.cpp's (their references take minutes here).
const std::vector<H200Value>& h200_values() {
  static const std::vector<H200Value> rows = {
      {"pq_grading/amplify/amplify10_display1_backbuffer1_peaknits4000_lutpq_hue_33_log_ramp", 453,
       2, 0, 0.56161052, 0.552157942, true},  // linear_rel
      {"pq_grading/amplify/amplify10_display1_backbuffer1_peaknits4000_lutpq_hue_33_log_ramp", 451,
       2, 0, 0.182729423, 0.188698796, true},  // pq_code10
      {"pq_grading/amplify/amplify10_display1_backbuffer1_peaknits4000_lutpq_hue_33_log_ramp", 165,
       0, 1, 0.00117669278, 0.00122172208, true},  // delta_e_itp
      {"tonemap/cvars/"
       "dev2_gamut0_hdr1_max5000_minlog0_mid1_scm0_gc1_cmin-10_cmid0_cmax10_gamma0_sharpen-1_"
       "colorchecker",
       13, 2, 1, 0.168166623, 0.171523944, true},  // pq_code10
      {"tonemap/display/hdr0_dev9_gamut1_lut16_fmt0_layout0_log_ramp", 41, 1, 2, 0.00105745019,
       0.00206616199, true},  // pq_code10
      {"tonemap/display/hdr0_dev9_gamut2_lut16_fmt0_layout0_log_ramp", 34, 1, 1, 0, 0.000875865321,
       true},  // pq_code10
      {"unity_urp/graded_look/gradingmode1_mode0_postexposure-2_colorchecker", 44, 16, 2,
       0.0858362913, 0.0870662801, true},  // linear_rel
      {"unity_urp/graded_look/gradingmode1_mode0_postexposure-2_colorchecker", 24, 16, 1,
       0.00111789256, 0.00164685032, true},  // pq_code10
      {"unity_urp/graded_look/gradingmode1_mode0_postexposure-2_hue_sweep", 13, 3, 1, 0.109558105,
       0.107996821, true},  // linear_rel
      {"unity_urp/graded_look/gradingmode1_mode0_postexposure0_colorchecker", 44, 16, 1,
       0.563015461, 0.554145666, true},  // linear_rel
      {"unity_urp/graded_look/gradingmode1_mode0_postexposure0_colorchecker", 24, 12, 1,
       0.00111789256, 0.00164685032, true},  // pq_code10
      {"unity_urp/graded_look/gradingmode1_mode0_postexposure0_hue_sweep", 18, 3, 2, 0.193969727,
       0.176768041, true},  // linear_rel
      {"unity_urp/graded_look/gradingmode1_mode0_postexposure1.5_colorchecker", 60, 16, 1,
       7.67578125, 7.61706251, true},  // linear_rel
      {"unity_urp/graded_look/gradingmode1_mode0_postexposure1.5_hue_sweep", 28, 3, 2, 0.0312194824,
       0.019502168, true},  // linear_rel
      {"unity_urp/graded_look/gradingmode1_mode1_postexposure-2_colorchecker", 44, 16, 2,
       0.0760378465, 0.0767448293, true},  // linear_rel
      {"unity_urp/graded_look/gradingmode1_mode1_postexposure-2_colorchecker", 24, 16, 1,
       0.00106070179, 0.00156259825, true},  // pq_code10
      {"unity_urp/graded_look/gradingmode1_mode1_postexposure0_colorchecker", 44, 16, 1, 0.164003,
       0.162504972, true},  // linear_rel
      {"unity_urp/graded_look/gradingmode1_mode1_postexposure0_colorchecker", 24, 12, 1,
       0.00106070179, 0.00156259825, true},  // pq_code10
      {"unity_urp/graded_look/gradingmode1_mode1_postexposure0_hue_sweep", 18, 3, 2, 0.033416748,
       0.0304532733, true},  // linear_rel
      {"unity_urp/graded_look/gradingmode1_mode1_postexposure1.5_hue_sweep", 28, 3, 2,
       0.00430297852, 0.0026879821, true},  // linear_rel
      {"unity_urp/grading_modes/gradingmode1_mode2_lutsize32_random", 25, 11, 0, 0.000807234494,
       0.000812091955, true},  // delta_e_itp
      {"unity_urp/grading_modes/gradingmode1_mode2_lutsize64_log_ramp", 246, 1, 0, 0,
       2.09028646e-06, true},  // delta_e_itp
      // The H200 run of main 5466e1a (2026-11-27, second session): the values the cases still
      // failed on with the allowances of that tree (results.json reasons, "outside the device
      // allowances too").
      {"pq_grading/amplify/amplify10_display1_backbuffer1_peaknits4000_lutpq_hue_33_log_ramp", 76,
       0, 0, 3.52538264e-05, 3.22788907e-05, true},  // delta_e_itp
      {"unity_urp/graded_look/gradingmode1_mode0_postexposure1.5_colorchecker", 44, 8, 2,
       0.0495279878, 0.0484141683, true},  // linear_rel
      {"unity_urp/grading_modes/gradingmode1_mode2_lutsize32_random", 25, 11, 1, -0.00015404851,
       -0.000155594883, true},  // delta_e_itp
  };
  return rows;
}

TEST(H200Filter, ValuesAgainstTheDeviceRangesAtTheCtsFilterPrecision) {
  hdrc::test::H200References refs(kCasesDir);
  std::map<std::string, std::pair<int, int>> per_case;  // admitted, outside
  int in = 0, out = 0;
  for (const H200Value& row : h200_values()) {
    std::string error;
    const hdrc::Image* image = refs.get(row.id, &error);
    ASSERT_NE(image, nullptr) << error;
    const hdrc::Image& ref = *image;
    const double r = ref.px(row.x, row.y)[row.channel];
    // The same case and pixel as the H200's run: the tight reference it was compared with.
    EXPECT_NEAR(r, row.reference, 1e-6 * std::fmax(1.0, std::fabs(r))) << row.id;
    const size_t i = static_cast<size_t>(row.y) * ref.width + row.x;
    double lo = r, hi = r;
    for (const hdrc::AdmissibleRange& a : ref.device_admissible)
      if (a.pixel == i) {
        lo = a.lo[row.channel];
        hi = a.hi[row.channel];
      }
    const bool ok = row.candidate >= lo && row.candidate <= hi;
    EXPECT_EQ(ok, row.admitted) << row.id << " (" << row.x << ", " << row.y << ")";
    (ok ? in : out)++;
    (ok ? per_case[row.id].first : per_case[row.id].second)++;
    std::printf("%s (%d, %d) %c: %s [%.9g, %.9g] %.9g (reference %.9g)\n", row.id, row.x, row.y,
                "RGB"[row.channel], ok ? "ADMITTED" : "OUTSIDE", lo, hi, row.candidate, r);
  }
  int cases_in = 0;
  for (const auto& [id, n] : per_case) cases_in += n.second == 0;
  std::printf("values admitted %d, outside %d; cases with every value admitted %d of %zu\n", in,
              out, cases_in, per_case.size());
}

// The H200's six ue58 FAILs of 2026-11-27 (tree 5466e1a, `hdrconform run --device nvidia`; its
// results.json, the worst value of each case's failing metric): Filmic with ACES 2.0, where the
// inner LUT's texel is the SDR inverse then the forward 1000- or 4000-nit transform. One channel
// of one inner texel moved (G and B of the outer texel identical to 9 digits): a channel near
// black of a saturated colour at the SDR peak, where the device's decode of the lattice
// coordinate (ST2084ToLinear at the precision table's bounds) goes through the inverse gamut
// compressor near its asymptote (docs/ue58-decisions.md E9, docs/precision.md). Each must lie in
// the reference's device range with the H200's precision; before E9 none did.
TEST(H200Filter, Ue58FilmicAces2ValuesInsideTheInnerLutInputRanges) {
  struct Row {
    const char* id;
    int x, y, channel;
    double candidate, reference;
  };
  const Row rows[] = {
      {"ue58/devices/dev3_gamut0_tonemappingmethod0_version2", 198, 8, 0, 0.0850439883,
       0.0664711632},  // linear_abs
      {"ue58/devices/dev4_gamut0_tonemappingmethod0_version2", 198, 8, 0, 0.0850439883,
       0.0664711632},  // linear_abs
      {"ue58/devices/dev5_gamut0_tonemappingmethod0_version2", 199, 8, 0, 0.0942382812,
       0.0784912109},  // linear_rel
      {"ue58/devices/dev6_gamut0_tonemappingmethod0_version2", 199, 8, 0, 0.0942382812,
       0.0784912109},  // linear_rel
      {"ue58/hdr_display/dev4_max4000_gamut1_tonemappingmethod0_limitinggamut2_paperwhite100", 11,
       11, 2, 0.1485826, 0.127077224},  // linear_abs
      {"ue58/hdr_display/dev6_max1000_gamut0_tonemappingmethod0_limitinggamut4_paperwhite203", 211,
       12, 0, 1.91308594, 1.86035156},  // linear_rel
  };
  hdrc::test::H200References refs(kCasesDir);
  for (const Row& row : rows) {
    std::string error;
    const hdrc::Image* image = refs.get(row.id, &error);
    ASSERT_NE(image, nullptr) << error;
    const double r = image->px(row.x, row.y)[row.channel];
    EXPECT_NEAR(r, row.reference, 1e-6 * std::fmax(1.0, std::fabs(r))) << row.id;
    const size_t i = static_cast<size_t>(row.y) * image->width + row.x;
    double lo = r, hi = r;
    for (const hdrc::AdmissibleRange& a : image->device_admissible)
      if (a.pixel == i) {
        lo = a.lo[row.channel];
        hi = a.hi[row.channel];
      }
    EXPECT_TRUE(row.candidate >= lo && row.candidate <= hi)
        << row.id << " (" << row.x << ", " << row.y << ") "
        << "RGB"[row.channel] << ": " << row.candidate << " outside [" << lo << ", " << hi << "]";
    std::printf("%s (%d, %d) %c: [%.9g, %.9g] %.9g (reference %.9g)\n", row.id, row.x, row.y,
                "RGB"[row.channel], lo, hi, row.candidate, r);
  }
}

// The same six cases, the H200's whole images (its candidate.exr of that run, in
// runner/h200_candidates/<case id>.exr: a `verify --candidate-dir` folder) judged as `run` judges
// a case that misses its tight bounds (run.cpp judge_with_device_allowances): the reference's
// device ranges with the H200's precision, the case's tolerance with the overlays for "vulkan" on
// an NVIDIA device. The H200's run judged each of them FAIL "outside the device allowances too"
// (585 values over in dev5's).
TEST(H200Filter, Ue58FilmicAces2WholeImagesPassWithTheH200Precision) {
  const char* ids[] = {
      "ue58/devices/dev3_gamut0_tonemappingmethod0_version2",
      "ue58/devices/dev4_gamut0_tonemappingmethod0_version2",
      "ue58/devices/dev5_gamut0_tonemappingmethod0_version2",
      "ue58/devices/dev6_gamut0_tonemappingmethod0_version2",
      "ue58/hdr_display/dev4_max4000_gamut1_tonemappingmethod0_limitinggamut2_paperwhite100",
      "ue58/hdr_display/dev6_max1000_gamut0_tonemappingmethod0_limitinggamut4_paperwhite203",
  };
  const hdrc::LoadedCases loaded = hdrc::load_cases(kCasesDir);
  std::vector<hdrc::Error> errors;
  const auto overlays = hdrc::load_tolerance_overlays(kCasesDir, &errors);
  ASSERT_TRUE(errors.empty()) << errors.front().to_string();
  for (const char* id : ids) {
    const hdrc::Case* found = nullptr;
    for (const hdrc::Case& c : loaded.cases)
      if (c.id == id) found = &c;
    ASSERT_NE(found, nullptr) << id;
    auto rc = hdrc::resolve_case(*found);
    ASSERT_TRUE(rc.ok()) << rc.error().to_string();
    hdrc::test::set_h200_precision(*rc);
    auto ref = hdrc::pipeline_of(*found->stage).reference(*rc, false);
    ASSERT_TRUE(ref.ok()) << ref.error().to_string();
    auto candidate =
        hdrc::read_image(std::string(HDRC_SOURCE_DIR) + "/runner/h200_candidates/" + id + ".exr");
    ASSERT_TRUE(candidate.ok()) << candidate.error().to_string();
    auto tol = hdrc::apply_overlays(*found, "vulkan", "NVIDIA H200", overlays);
    ASSERT_TRUE(tol.ok()) << tol.error().to_string();
    ref->admissible = std::move(ref->device_admissible);
    const hdrc::DiffStats s = hdrc::diff_images(
        rc->input, *ref, *candidate, hdrc::output_encoding(*found->stage, rc->params), *tol);
    const hdrc::Verdict v = hdrc::judge(s, *tol, !found->pins_nonfinite.empty());
    EXPECT_TRUE(v.pass) << id << ": " << v.reason;
  }
}

}  // namespace
