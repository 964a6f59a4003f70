// The H200's VisualizeHDR FAILs of 2026-11-27 (NVIDIA H200, driver 580.159.04; device precision:
// subTexelPrecisionBits 8, float16 RTE; `hdrconform run --device nvidia`, tree 6e180a7): for each
// case, the worst value of the tight comparison and the worst against the device allowances then,
// as its reason named them (pixel, candidate RGB). The reference's device ranges for the
// visualize_hdr stage (reference/ue/visualize_device.h), asked for with the H200's precision, are
// checked against those candidate values (docs/precision.md, "VisualizeHDR").
#include <gtest/gtest.h>

#include <array>
#include <string>

#include "runner/case_loader.h"
#include "runner/h200_references.h"

namespace {

const std::string kCasesDir = std::string(HDRC_SOURCE_DIR) + "/cases";

struct H200Pixel {
  const char* id;
  int x, y;
  std::array<double, 3> candidate;
  // Inside the device ranges derived now. The pixels outside them all show the tonemapped scene
  // (meters, background): they miss the Tonemap pass's own device range there (1e-4 to 1e-3
  // relative in a dark channel; device 8 near black; 1.05 as float32 against the exact 1.05),
  // not a VisualizeHDR step.
  bool admitted;
};

// Whether every channel of `c` lies in the device range of pixel (x, y) (or equals the reference
// where the pixel has none).
bool admitted(const hdrc::Image& ref, int x, int y, const std::array<double, 3>& c,
              std::string* why) {
  const size_t i = static_cast<size_t>(y) * ref.width + x;
  const double* r = ref.px(x, y);
  const hdrc::AdmissibleRange* range = nullptr;
  for (const hdrc::AdmissibleRange& a : ref.device_admissible)
    if (a.pixel == i) range = &a;
  bool ok = true;
  for (int ch = 0; ch < 3; ++ch) {
    const double lo = range ? range->lo[ch] : r[ch], hi = range ? range->hi[ch] : r[ch];
    const bool in = c[ch] >= lo && c[ch] <= hi;
    ok = ok && in;
    *why += " " + std::string(1, "RGB"[ch]) + " [" + std::to_string(lo) + ", " +
            std::to_string(hi) + "] " + (in ? "has " : "misses ") + std::to_string(c[ch]);
  }
  return ok;
}

TEST(VisualizeDevice, H200CandidatesAgainstTheDeviceRanges) {
  const std::vector<H200Pixel> rows = {
      {"visualize/pre_exposure/dev0_preexposure0.5_exposure2_log_ramp",
       58,
       101,
       {4.80659182e-05, 0, 0},
       true},  // tight miss, R
      {"visualize/pre_exposure/dev0_preexposure0.5_exposure2_log_ramp",
       58,
       5,
       {0, 0, 0},
       true},  // allow miss, R
      {"visualize/pre_exposure/dev0_preexposure2.5_exposure1_log_ramp",
       83,
       149,
       {6.40898943e-05, 0, 0},
       true},  // tight miss, R
      {"visualize/pre_exposure/dev0_preexposure2.5_exposure1_log_ramp",
       83,
       149,
       {6.40898943e-05, 0, 0},
       true},  // allow miss, R
      {"visualize/pre_exposure/dev9_preexposure0.5_exposure2_log_ramp",
       134,
       49,
       {1.04748452, 0.0171755534, 0.0040856027},
       true},  // tight miss, B
      {"visualize/pre_exposure/dev9_preexposure0.5_exposure2_log_ramp",
       135,
       22,
       {0.0392377973, 0.923121929, 0.00604028394},
       false},  // allow miss, B
      {"visualize/pre_exposure/dev9_preexposure2.5_exposure1_log_ramp",
       159,
       45,
       {1.04999995, 0.017447928, 0.00410162471},
       false},  // tight miss, B
      {"visualize/pre_exposure/dev9_preexposure2.5_exposure1_log_ramp",
       160,
       150,
       {0.0387731791, 0.922128618, 0.0059601739},
       false},  // allow miss, B
      {"visualize/visualize_hdr/dev0_debug0_log_ramp",
       72,
       97,
       {4.80659182e-05, 0, 0},
       true},  // tight miss, R
      {"visualize/visualize_hdr/dev0_debug0_log_ramp",
       74,
       157,
       {6.40898943e-05, 0, 0},
       true},  // allow miss, R
      {"visualize/visualize_hdr/dev1_debug0_log_ramp",
       81,
       50,
       {0, 1.60219715e-05, 0},
       true},  // tight miss, G
      {"visualize/visualize_hdr/dev1_debug0_log_ramp",
       82,
       142,
       {0, 3.20672989e-05, 0},
       true},  // allow miss, G
      {"visualize/visualize_hdr/dev5_debug0_log_ramp",
       166,
       46,
       {0.00246264506, 7.11963177, 0.147900447},
       true},  // tight miss, R
      {"visualize/visualize_hdr/dev5_debug0_log_ramp",
       168,
       166,
       {0.00694543123, 7.12859488, 0.150283799},
       true},  // allow miss, R
      {"visualize/visualize_hdr/dev6_debug0_log_ramp",
       166,
       46,
       {0.00246264506, 7.11963177, 0.147900447},
       true},  // tight miss, R
      {"visualize/visualize_hdr/dev6_debug0_log_ramp",
       168,
       166,
       {0.00694543123, 7.12859488, 0.150283799},
       true},                                                                      // allow miss, R
      {"visualize/visualize_hdr/dev8_debug0_log_ramp", 59, 156, {0, 0, 0}, true},  // tight miss, R
      {"visualize/visualize_hdr/dev8_debug0_log_ramp", 59, 156, {0, 0, 0}, true},  // allow miss, R
      {"visualize/visualize_hdr/dev8_debug1_log_ramp",
       58,
       104,
       {4.80659182e-05, 3.20439431e-05, 4.80659182e-05},
       false},  // tight miss, G
      {"visualize/visualize_hdr/dev8_debug1_log_ramp",
       58,
       104,
       {4.80659182e-05, 3.20439431e-05, 4.80659182e-05},
       false},  // allow miss, G
      {"visualize/visualize_hdr/dev8_debug2_log_ramp",
       58,
       104,
       {4.80659182e-05, 3.20439431e-05, 4.80659182e-05},
       false},  // tight miss, G
      {"visualize/visualize_hdr/dev8_debug2_log_ramp",
       58,
       104,
       {4.80659182e-05, 3.20439431e-05, 4.80659182e-05},
       false},  // allow miss, G
      {"visualize/visualize_hdr/dev9_debug0_log_ramp",
       149,
       121,
       {1.04810941, 0.0172396433, 0.0040856027},
       false},  // tight miss, B
      {"visualize/visualize_hdr/dev9_debug0_log_ramp",
       144,
       163,
       {0, 0, 0.6589517},
       true},  // allow miss, G
      {"visualize/working_color_space/dev0_workingcolorspace1_log_ramp",
       72,
       97,
       {4.80659182e-05, 0, 0},
       true},  // tight miss, R
      {"visualize/working_color_space/dev0_workingcolorspace1_log_ramp",
       74,
       157,
       {6.40898943e-05, 0, 0},
       true},  // allow miss, R
      {"visualize/working_color_space/dev0_workingcolorspace3_log_ramp",
       72,
       70,
       {0, 4.80659182e-05, 0},
       true},  // tight miss, G
      {"visualize/working_color_space/dev0_workingcolorspace3_log_ramp",
       74,
       158,
       {0, 4.8071146e-05, 0},
       true},  // allow miss, G
      {"visualize/working_color_space/dev0_workingcolorspace5_log_ramp",
       158,
       90,
       {0, 1.04589832, 0},
       true},  // tight miss, B
      {"visualize/working_color_space/dev0_workingcolorspace5_log_ramp",
       88,
       147,
       {0, 0, 0.00410161912},
       false},  // allow miss, B
      {"visualize/working_color_space/dev0_workingcolorspace6_log_ramp",
       158,
       90,
       {0, 1.04999995, 0},
       false},  // tight miss, B
      {"visualize/working_color_space/dev0_workingcolorspace6_log_ramp",
       88,
       147,
       {0, 0, 0.00410161912},
       false},  // allow miss, B
      {"visualize/working_color_space/dev0_workingcolorspace7_log_ramp",
       72,
       97,
       {4.80659182e-05, 0, 0},
       true},  // tight miss, R
      {"visualize/working_color_space/dev0_workingcolorspace7_log_ramp",
       74,
       157,
       {6.40898943e-05, 0, 0},
       true},  // allow miss, R
  };
  hdrc::test::H200References refs(kCasesDir);
  int in = 0, out = 0;
  for (const H200Pixel& row : rows) {
    std::string error;
    const hdrc::Image* image = refs.get(row.id, &error);
    ASSERT_NE(image, nullptr) << error;
    std::string why;
    const bool ok = admitted(*image, row.x, row.y, row.candidate, &why);
    (ok ? in : out)++;
    if (row.admitted) {
      EXPECT_TRUE(ok) << row.id << " (" << row.x << ", " << row.y << "):" << why;
    }
    std::printf("%s (%d, %d): %s%s\n", row.id, row.x, row.y, ok ? "ADMITTED" : "OUTSIDE",
                why.c_str());
  }
  std::printf("admitted %d, outside %d\n", in, out);
}

}  // namespace
