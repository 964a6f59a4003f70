// Unit tests of the report builder: escaping, file names, the documented SDR preview mapping,
// the heatmap colours (UE's Colorize ramp), the float data encoding, the error maps, and
// write_report on hand-written results directories. The browser test (report/browser_test)
// checks the pages themselves.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "report/html_report.h"
#include "report/images.h"
#include "runner/diff.h"
#include "runner/tolerance.h"

namespace {

using hdrc::Image;
using namespace hdrc::report;

std::string read_file(const std::filesystem::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

TEST(ReportEscaping, HtmlEscapesEveryMarkupCharacter) {
  EXPECT_EQ(hdrc::html_escape("<script>alert('x')</script> & \"q\""),
            "&lt;script&gt;alert(&#39;x&#39;)&lt;/script&gt; &amp; &quot;q&quot;");
}

TEST(ReportEscaping, UrlPathKeepsSlashesAndEncodesTheRest) {
  EXPECT_EQ(url_path_escape("a/<b> c%#?"), "a/%3Cb%3E%20c%25%23%3F");
  EXPECT_EQ(url_path_escape("tonemap/dev7_gamut2-x.y~z"), "tonemap/dev7_gamut2-x.y~z");
}

TEST(ReportEscaping, ScriptSafeJsonCannotCloseTheScriptElement) {
  EXPECT_EQ(script_safe_json(R"({"id":"</script><b>&"})"),
            R"({"id":"\u003c/script\u003e\u003cb\u003e\u0026"})");
  EXPECT_EQ(script_safe_json("\"a\xE2\x80\xA8"
                             "b\xE2\x80\xA9\""),
            "\"a\\u2028b\\u2029\"");
}

TEST(ReportFiles, SlugsAreSafeFileNames) {
  const std::string s = case_slug("<script>alert(1)</script>/log_ramp");
  EXPECT_EQ(s, "_script_alert_1____script___log_ramp");
  EXPECT_EQ(case_slug("tonemap/linear_dev7/dev7_gamut2"), "tonemap__linear_dev7__dev7_gamut2");
  EXPECT_EQ(case_slug("../x"), "_..__x");  // never starts with '.', never a path
  EXPECT_EQ(case_slug("").front(), '_');
}

TEST(ReportPreview, SrgbOetfPublishedValues) {
  // IEC 61966-2-1: 12.92·L below 0.0031308, 1.055·L^(1/2.4) − 0.055 above.
  EXPECT_NEAR(srgb_oetf(0.0031308), 0.040449936, 1e-9);
  EXPECT_NEAR(srgb_oetf(0.5), 0.735356983, 1e-9);
  EXPECT_EQ(srgb_oetf(-1), 0.0);
  EXPECT_EQ(srgb_oetf(2), 1.0);
  EXPECT_EQ(srgb_oetf(std::nan("")), 0.0);
}

TEST(ReportPreview, HundredNitsIsSdrWhiteAtZeroEv) {
  EXPECT_EQ(preview_code(100, 0), 255);
  EXPECT_EQ(preview_code(50, 1), 255);    // +1 EV doubles
  EXPECT_EQ(preview_code(400, -2), 255);  // −2 EV quarters
  EXPECT_EQ(preview_code(18, 0), 118);    // round(sRGB(0.18) · 255), by hand: 117.65
  EXPECT_EQ(preview_code(-5, 0), 0);
  EXPECT_EQ(preview_code(1e4, 0), 255);  // clipped
}

// The preview's byte comes from a table of the 255 code boundaries (no pow per channel); it must
// be the formula's byte for every value: at and beside each boundary (a few ulps either side),
// across [0, 1] on a fine grid, and for the values outside it.
TEST(ReportImages, PreviewCodeTableAgreesWithTheFormula) {
  int checked = 0;
  for (int k = 1; k <= 255; ++k) {
    const double v = (k - 0.5) / 255.0;
    double x = v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
    for (int i = 0; i < 8; ++i) x = std::nextafter(x, -1.0);
    for (int i = 0; i < 16; ++i, x = std::nextafter(x, 2.0)) {
      ASSERT_EQ(preview_code_linear(x), preview_code_exact(x)) << k << " " << x;
      ++checked;
    }
  }
  for (int i = -1000; i <= 1001000; ++i) {
    const double x = i / 1e6;
    ASSERT_EQ(preview_code_linear(x), preview_code_exact(x)) << x;
    ++checked;
  }
  for (double x :
       {-1e300, -0.0, 0.0, 1.0, 1.0000001, 1e300, std::numeric_limits<double>::infinity(),
        -std::numeric_limits<double>::infinity(), std::nan("")}) {
    EXPECT_EQ(preview_code_linear(x), preview_code_exact(x)) << x;
    ++checked;
  }
  EXPECT_GT(checked, 1000000);
  // A boundary by hand: code 1 starts at (0.5 / 255) / 12.92 = 1.51770e-4 (linear segment).
  EXPECT_EQ(preview_code_linear(1.517e-4), 0);
  EXPECT_EQ(preview_code_linear(1.518e-4), 1);
}

TEST(ReportPreview, NonFinitePixelsAreFlagged) {
  Image img(3, 1);
  const double v[3][4] = {{std::nan(""), 0, 0, 1}, {INFINITY, 0, 0, 1}, {1, 1, 1, 1}};
  for (int x = 0; x < 3; ++x)
    for (int c = 0; c < 4; ++c) img.px(x, 0)[c] = v[x][c];
  hdrc::OutputEncoding scene;  // shaper: scene-linear × 100 nits
  const Rgb8 p = preview(img, scene, false);
  EXPECT_EQ(p.data[0], 255);  // magenta
  EXPECT_EQ(p.data[1], 0);
  EXPECT_EQ(p.data[2], 255);
  EXPECT_EQ(p.data[3], 0);  // cyan
  EXPECT_EQ(p.data[4], 255);
  EXPECT_EQ(p.data[5], 255);
  EXPECT_EQ(p.data[6], 255);  // 1.0 scene-linear = 100 nits = white
}

TEST(ReportHeatmap, ColorizeIsBlueGreenRed) {
  // PostProcessVisualizeHDR.usf Colorize: 0 blue, 0.5 green, 1 red; NaN saturates to 0.
  EXPECT_EQ(colorize8(0), (std::array<uint8_t, 3>{0, 0, 255}));
  EXPECT_EQ(colorize8(0.5), (std::array<uint8_t, 3>{0, 255, 0}));
  EXPECT_EQ(colorize8(1), (std::array<uint8_t, 3>{255, 0, 0}));
  EXPECT_EQ(colorize8(std::nan("")), (std::array<uint8_t, 3>{0, 0, 255}));
  // x = 0.75: t = 0.5, lerp(green, lerp(blue, red, 0.75), 0.5) = (0.375, 0.5, 0.125).
  EXPECT_EQ(colorize8(0.75), (std::array<uint8_t, 3>{96, 128, 32}));
}

TEST(ReportHeatmap, ScaleEndsAndSpecialValues) {
  EXPECT_EQ(heat_colour(0, kHeatPq10), (std::array<uint8_t, 3>{0, 0, 0}));
  EXPECT_EQ(heat_colour(std::nan(""), kHeatPq10), kMismatchColour);
  EXPECT_EQ(heat_colour(1e-4, kHeatPq10), (std::array<uint8_t, 3>{0, 0, 255}));
  EXPECT_EQ(heat_colour(1e-6, kHeatPq10), (std::array<uint8_t, 3>{0, 0, 255}));  // clamped
  EXPECT_EQ(heat_colour(std::pow(10.0, -1.5), kHeatPq10), (std::array<uint8_t, 3>{0, 255, 0}));
  EXPECT_EQ(heat_colour(10, kHeatPq10), (std::array<uint8_t, 3>{255, 0, 0}));
  EXPECT_EQ(heat_colour(100, kHeatItp), (std::array<uint8_t, 3>{255, 0, 0}));
}

TEST(ReportData, Float32Base64IsLittleEndian) {
  Image img(1, 1);
  img.px(0, 0)[0] = 1.0;
  img.px(0, 0)[1] = -2.0;
  img.px(0, 0)[2] = 0.5;
  // 00 00 80 3F | 00 00 00 C0 | 00 00 00 3F
  EXPECT_EQ(float32_base64(img, 3), "AACAPwAAAMAAAAA/");
  double a = -1;
  EXPECT_TRUE(constant_alpha(img, &a));
  EXPECT_EQ(a, 0.0);
}

TEST(ReportErrorMaps, MaskMarksValuesOverTheirMetricAndMismatches) {
  Image ref(3, 1), cand(3, 1);
  for (int x = 0; x < 3; ++x)
    for (int c = 0; c < 4; ++c) ref.px(x, 0)[c] = cand.px(x, 0)[c] = 0.5;
  cand.px(1, 0)[0] = 0.5 * 1.01;    // rel 1e-2 > 1e-3
  cand.px(2, 0)[1] = std::nan("");  // non-finite mismatch
  hdrc::Tolerance tol;
  tol.linear_rel = 1e-3;
  tol.rel_floor = 1e-4;
  hdrc::OutputEncoding scene;
  const Rgb8 prev = preview(ref, scene, false);
  const ErrorMaps m = error_maps(ref, cand, scene, tol, prev);
  EXPECT_EQ(m.over, 1u);
  EXPECT_EQ(m.mismatch, 1u);
  EXPECT_EQ(m.heat.data[0], 0);    // exact: black
  EXPECT_EQ(m.mask.data[3], 255);  // over: red
  EXPECT_EQ(m.mask.data[4], 0);
  EXPECT_EQ(m.mask.data[6], 255);  // mismatch: magenta
  EXPECT_EQ(m.mask.data[7], 0);
  EXPECT_EQ(m.heat.data[6], 255);  // mismatch: white
  EXPECT_EQ(m.heat.data[7], 255);
  // Pixel 1's heat: (PQ(50.5 nits) − PQ(50 nits)) · 1023 = 0.968089 codes (ST 2084 eq. 5.2 by
  // hand), on the documented scale.
  const double pq10 = pq10_error(scene, 0.5, 0.505);
  EXPECT_NEAR(pq10, 0.968089, 1e-6);
  const auto want = heat_colour(pq10, kHeatPq10);
  EXPECT_EQ(m.heat.data[3], want[0]);
  EXPECT_EQ(m.heat.data[4], want[1]);
}

// The report decodes each image once and skips the curves where the candidate's value is the
// reference's, bit for bit: its maps and counts are those of the full evaluation, value by value.
TEST(ReportErrorMaps, EqualValuesShortcutMatchesTheFullEvaluation) {
  hdrc::OutputEncoding pq;
  pq.transfer = hdrc::OutputEncoding::Transfer::kPq;
  pq.nits_scale = 1.0;
  const int w = 64, h = 16;
  Image ref(w, h), cand(w, h);
  uint32_t seed = 12345;
  auto rnd = [&] {
    seed = seed * 1664525u + 1013904223u;
    return (seed >> 8) / 16777216.0;
  };
  for (size_t i = 0; i < ref.pixel_count(); ++i)
    for (int c = 0; c < 4; ++c) {
      const double v = c == 3 ? 1.0 : rnd();
      ref.data[i * 4 + c] = v;
      const double r = rnd();  // a third equal, a third a few ulps off, a third further off
      cand.data[i * 4 + c] = r < 0.33 ? v : r < 0.66 ? v * (1 + 1e-7) : v + (r - 0.8) * 1e-3;
    }
  ref.data[5 * 4 + 1] = cand.data[5 * 4 + 1] = std::nan("");  // consistent non-finite
  hdrc::Tolerance tol;
  tol.pq_code10 = 0.05;
  tol.delta_e_itp = 0.5;
  const Rgb8 prev = preview(ref, pq, false);
  const Image rn = nits_image(ref, pq);
  const Image cn = nits_image(cand, pq, &ref, &rn);
  EXPECT_EQ(std::memcmp(cn.data.data(), nits_image(cand, pq).data.data(),
                        cn.data.size() * sizeof(double)),
            0);
  EXPECT_EQ(preview_of_nits(ref, rn).data, prev.data);
  const ErrorMaps m = error_maps(ref, cand, rn, cn, pq, tol, prev);
  size_t over = 0;
  for (size_t i = 0; i < ref.pixel_count(); ++i) {
    const double* r = &ref.data[i * 4];
    const double* c = &cand.data[i * 4];
    double worst = 0;
    bool finite = true;
    hdrc::ref::Vec3 a, b;
    for (int ch = 0; ch < 3; ++ch) {
      finite &= std::isfinite(r[ch]) && std::isfinite(c[ch]);
      if (!std::isfinite(r[ch]) || !std::isfinite(c[ch])) continue;
      worst = std::fmax(worst, pq10_error(pq, r[ch], c[ch]));
      a[ch] = pq.to_nits(r[ch]);
      b[ch] = pq.to_nits(c[ch]);
    }
    const double itp = finite ? hdrc::delta_e_itp(hdrc::ictcp_from_rec2020_nits(b),
                                                  hdrc::ictcp_from_rec2020_nits(a))
                              : 0.0;
    over += worst > tol.pq_code10 || itp > tol.delta_e_itp;
    const auto want = heat_colour(worst, kHeatPq10), want_itp = heat_colour(itp, kHeatItp);
    ASSERT_EQ(std::memcmp(&m.heat.data[i * 3], want.data(), 3), 0) << i;
    ASSERT_EQ(std::memcmp(&m.heat_itp.data[i * 3], want_itp.data(), 3), 0) << i;
  }
  EXPECT_GT(over, 0u);
  EXPECT_LT(over, ref.pixel_count());
  EXPECT_EQ(m.over, over);
  EXPECT_EQ(m.mismatch, 0u);
}

class WriteReport : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        std::filesystem::temp_directory_path() /
        ("hdrc_report_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

TEST_F(WriteReport, MissingResultsNamesTheFile) {
  auto r = hdrc::write_report(dir_.string());
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().to_string().find("results.json"), std::string::npos);
}

TEST_F(WriteReport, InvalidJsonIsAnError) {
  std::ofstream(dir_ / "results.json") << "{\"cases\": [";
  auto r = hdrc::write_report(dir_.string());
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().to_string().find("malformed JSON"), std::string::npos);
}

TEST_F(WriteReport, SparseResultsAndHostileTextAreShownEscaped) {
  // A case with almost nothing: no stats, no images, no tolerance; a hostile id and reason.
  std::ofstream(dir_ / "results.json")
      << R"({"cases": [{"id": "<img src=x onerror=alert(1)>/x", "verdict": "FAIL",
                        "stage": "shaper", "reason": "<b>bold</b>"},
                       {"id": "ok/case", "verdict": "PASS", "stage": "shaper"}]})";
  auto r = hdrc::write_report(dir_.string());
  ASSERT_TRUE(r) << r.error().to_string();
  EXPECT_EQ(r->cases, 2u);
  const std::string index = read_file(dir_ / "report" / "index.html");
  const std::string list = read_file(dir_ / "report" / "cases.html");
  const std::string data = read_file(dir_ / "report" / "data.js");
  for (const std::string* page : {&index, &list}) {
    EXPECT_EQ(page->find("<img src=x"), std::string::npos);
    EXPECT_EQ(page->find("<b>bold"), std::string::npos);
  }
  EXPECT_NE(list.find("&lt;img src=x onerror=alert(1)&gt;/x"), std::string::npos);
  EXPECT_EQ(data.find('<'), std::string::npos);  // every '<' in script data is \u003c
  EXPECT_NE(index.find("id=\"count-FAIL\">1<"), std::string::npos);
  EXPECT_NE(index.find("id=\"count-PASS\">1<"), std::string::npos);
  const std::string page = read_file(dir_ / "report" / "c" / "ok__case.html");
  EXPECT_NE(page.find("No images were written"), std::string::npos);
  EXPECT_NE(page.find("—"), std::string::npos);
  // Rebuilding replaces the folder (no stale files survive).
  std::ofstream(dir_ / "report" / "stale.html") << "x";
  ASSERT_TRUE(hdrc::write_report(dir_.string()));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "report" / "stale.html"));
}

// An image over 4 Mpixel gets no float data in its page: its pictures (previews, heatmaps, mask)
// are made in C++ from a nearest-neighbour sample of at most 1 Mpixel (issue 29: full-size
// pictures of a 4096x4096 case were 1.9 GB and 70 s), stacked in one PNG the page carries (a
// data: URL), with the mask's counts of every pixel (the one pixel over is not among the
// sampled ones: the count must come from the whole image).
TEST_F(WriteReport, ImagesOverFourMegapixelsArePicturedHereWithoutFloatData) {
  const int w = 2049, h = 2048;  // 4 196 352 pixels > 2^22
  Image ref(w, h);
  for (size_t i = 0; i < ref.pixel_count(); ++i)
    for (int c = 0; c < 4; ++c) ref.data[i * 4 + c] = c == 3 ? 1.0 : 0.5;
  Image cand = ref;
  cand.px(8, 4)[1] = 0.75;  // one pixel over the tolerance, in no sampled row or column
  const auto cdir = dir_ / "cases" / "big" / "x";
  std::filesystem::create_directories(cdir);
  ASSERT_TRUE(hdrc::write_exr((cdir / "reference.exr").string(), ref, 1));
  ASSERT_TRUE(hdrc::write_exr((cdir / "candidate.exr").string(), cand, 1));
  std::ofstream(dir_ / "results.json") << R"({"cases": [{"id": "big/x", "verdict": "FAIL",
      "stage": "shaper", "tolerance": {"linear_abs": {"max": 1e-06}}}]})";
  auto r = hdrc::write_report(dir_.string());
  ASSERT_TRUE(r) << r.error().to_string();
  const std::string page = read_file(dir_ / "report" / "c" / "big__x.html");
  EXPECT_EQ(page.find("id=\"case-px\""), std::string::npos);  // no float data
  EXPECT_NE(page.find("<style id=\"case-sprite\">#images .sprite { background-image: "
                      "url(\"data:image/png;base64,iVBORw0KGgo"),
            std::string::npos);  // the PNG signature, base64
  // Reference, candidate, heatmaps and mask stacked: the mask is the fifth picture down. Each is
  // sampled to sqrt(2^20 / (2049 · 2048)) = 0.499878 of the image's size: 1024 x 1023.
  EXPECT_NE(page.find("\"mask\":[0,4092,1024,1023]"), std::string::npos);
  EXPECT_NE(page.find("id=\"mask-over\">1<"), std::string::npos);
  EXPECT_NE(page.find("id=\"mask-mismatch\">0<"), std::string::npos);
}

// Issue 14: the budget is the runner's figure (results.json budget_used), never recomputed from
// max/limit: a passing dither case with an allowed fraction has max 1.91 over a 1e-6 limit but
// uses 1.99 % of its budget, and the report must say 1.99 %, not 1.91e+08 %.
TEST_F(WriteReport, BudgetIsDisplayedAsTheRunnerComputedIt) {
  std::ofstream(dir_ / "results.json") << R"({"cases": [
      {"id": "dither/a", "verdict": "PASS", "stage": "dither", "budget_used": 0.0199,
       "tolerance": {"linear_abs": {"max": 1e-6, "allowed_fraction": 0.02, "hard": 2}},
       "stats": {"overall": {"linear_abs": {"max": 1.91}}}},
      {"id": "dither/b", "verdict": "FAIL", "stage": "dither", "budget_used": 3.5,
       "tolerance": {"linear_abs": {"max": 1e-6}}},
      {"id": "dither/c", "verdict": "PASS", "stage": "dither", "budget_used": 0.5}]})";
  auto r = hdrc::write_report(dir_.string());
  ASSERT_TRUE(r) << r.error().to_string();
  const std::string page = read_file(dir_ / "report" / "c" / "dither__a.html");
  EXPECT_NE(page.find("id=\"budget\">1.99 %"), std::string::npos);
  EXPECT_EQ(page.find("e+08"), std::string::npos);
  const std::string index = read_file(dir_ / "report" / "index.html");
  // The worst cases: the failure first, then by budget (50 % before 1.99 %).
  const size_t b = index.find("dither/b"), c = index.find("dither/c"), a = index.find("dither/a");
  ASSERT_NE(b, std::string::npos);
  EXPECT_LT(b, c);
  EXPECT_LT(c, a);
  EXPECT_NE(index.find("350 %"), std::string::npos);
  const std::string data = read_file(dir_ / "report" / "data.js");
  EXPECT_NE(data.find("\"budget\":0.0199"), std::string::npos);
}

// Golden regressions are part of the report; nothing links outside report/.
TEST_F(WriteReport, GoldenFailuresAreListedAndNoLinkLeavesTheReport) {
  std::ofstream(dir_ / "results.json") << R"({"cases": [{"id": "shaper/x", "verdict": "PASS",
      "stage": "shaper"}], "goldens": {"dir": "goldens", "checked": 1, "match": 0, "missing": 0,
      "stale": 0, "regression": 1, "failed": 1, "cases": [{"id": "shaper/x",
      "outcome": "regression", "message": "golden regression: 3 value(s) differ"}]}})";
  ASSERT_TRUE(hdrc::write_report(dir_.string()));
  const std::string index = read_file(dir_ / "report" / "index.html");
  EXPECT_NE(index.find("id=\"golden-failures\""), std::string::npos);
  EXPECT_NE(index.find("GOLDEN regression"), std::string::npos);
  EXPECT_NE(index.find("3 value(s) differ"), std::string::npos);
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir_ / "report")) {
    if (!e.is_regular_file() || e.path().extension() != ".html") continue;
    const std::string html = read_file(e.path());
    const bool in_c = e.path().parent_path().filename() == "c";
    // href/src: from report/ no "../", from report/c/ one "../" at most.
    for (const char* attr : {"href=\"", "src=\""})
      for (size_t at = html.find(attr); at != std::string::npos; at = html.find(attr, at + 1)) {
        const std::string v = html.substr(at + std::strlen(attr), 6);
        EXPECT_NE(v.rfind(in_c ? "../../" : "../", 0), 0u) << e.path() << ": " << v;
      }
  }
}

// The packed float data: byte planes of float32 (little-endian), zlib-deflated, base64.
TEST(ReportData, PackedFloatDataIsDeflatedBytePlanes) {
  Image img(2, 1);
  img.px(0, 0)[0] = 1.0;   // 00 00 80 3F
  img.px(1, 0)[0] = -2.0;  // 00 00 00 C0
  const std::string b64 = float32_packed_base64(img, 1);
  // Decode base64 by the RFC 4648 alphabet, then inflate.
  const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string z;
  uint32_t acc = 0;
  int bits = 0;
  for (char ch : b64) {
    if (ch == '=') break;
    acc = (acc << 6) | static_cast<uint32_t>(alphabet.find(ch));
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      z += static_cast<char>((acc >> bits) & 0xFF);
    }
  }
  unsigned char out[64];
  uLongf n = sizeof out;
  ASSERT_EQ(uncompress(out, &n, reinterpret_cast<const Bytef*>(z.data()), z.size()), Z_OK);
  ASSERT_EQ(n, 8u);
  const unsigned char want[8] = {0x00, 0x00, 0x00, 0x00, 0x80, 0x00, 0x3F, 0xC0};
  for (int i = 0; i < 8; ++i) EXPECT_EQ(out[i], want[i]) << i;
}

}  // namespace

// exr_embeddable: the EXR forms report.js decodeExr reads are accepted (the browser test checks
// its values for each), anything else refused, and no prefix of a valid file passes.
namespace {

std::string exr_bytes(const std::filesystem::path& p, int w, int h, int channels,
                      const std::string& compression, OIIO::TypeDesc type, int tile = 0,
                      const char* fifth = "Z") {
  OIIO::ImageSpec spec(w, h, channels, type);
  if (channels > 4) spec.channelnames = {"R", "G", "B", "A", fifth};
  if (channels == 1) spec.channelnames = {"Y"};
  spec.attribute("compression", compression);
  if (tile) spec.tile_width = spec.tile_height = tile;
  std::vector<float> px(static_cast<size_t>(w) * h * channels);
  for (size_t i = 0; i < px.size(); ++i) px[i] = static_cast<float>(std::sin(0.1 * i) * 10);
  auto o = OIIO::ImageOutput::create(p.string());
  EXPECT_TRUE(o && o->open(p.string(), spec) && o->write_image(OIIO::TypeDesc::FLOAT, px.data()) &&
              o->close());
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

}  // namespace

TEST(ReportData, ExrEmbeddableAcceptsTheFormsTheScriptDecodesAndRefusesTheRest) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("hdrc_exr_embed_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto p = dir / "x.exr";
  for (const char* comp : {"none", "zips", "zip"})
    for (auto type : {OIIO::TypeDesc::HALF, OIIO::TypeDesc::FLOAT})
      for (int ch : {3, 4})
        EXPECT_TRUE(exr_embeddable(exr_bytes(p, 37, 19, ch, comp, type), 37, 19))
            << comp << " " << OIIO::TypeDesc(type).c_str() << " " << ch;
  // The run's own writer (core/image.h write_exr: FLOAT RGBA, ZIP at a level).
  Image img(33, 17);
  ASSERT_TRUE(hdrc::write_exr(p.string(), img, 1));
  {
    std::ifstream f(p, std::ios::binary);
    EXPECT_TRUE(exr_embeddable(std::string(std::istreambuf_iterator<char>(f), {}), 33, 17));
  }
  const std::string good = exr_bytes(p, 37, 19, 4, "zip", OIIO::TypeDesc::FLOAT);
  EXPECT_FALSE(exr_embeddable(good, 36, 19));  // not the case's size
  EXPECT_FALSE(exr_embeddable(good, 37, 20));
  EXPECT_FALSE(exr_embeddable(good, 0, 0));
  EXPECT_FALSE(exr_embeddable(exr_bytes(p, 37, 19, 4, "piz", OIIO::TypeDesc::FLOAT), 37, 19));
  EXPECT_FALSE(exr_embeddable(exr_bytes(p, 37, 19, 4, "rle", OIIO::TypeDesc::FLOAT), 37, 19));
  EXPECT_FALSE(exr_embeddable(exr_bytes(p, 37, 19, 4, "zip", OIIO::TypeDesc::UINT), 37, 19));
  EXPECT_FALSE(exr_embeddable(exr_bytes(p, 37, 19, 4, "zip", OIIO::TypeDesc::FLOAT, 16), 37, 19));
  EXPECT_FALSE(exr_embeddable(exr_bytes(p, 37, 19, 5, "zip", OIIO::TypeDesc::FLOAT), 37, 19));
  EXPECT_FALSE(exr_embeddable(exr_bytes(p, 37, 19, 1, "zip", OIIO::TypeDesc::FLOAT), 37, 19));
  EXPECT_FALSE(exr_embeddable("", 37, 19));
  EXPECT_FALSE(exr_embeddable("not an EXR file at all, but long enough to have a header", 37, 19));
  // Every proper prefix is refused (the offset table or a chunk runs past the end), and no read
  // goes past the end (ASan in the sanitizer stage).
  for (size_t n = 0; n < good.size(); ++n)
    ASSERT_FALSE(exr_embeddable(std::string_view(good).substr(0, n), 37, 19)) << n;
  // A corrupted offset table entry (the last 8-byte entry before the first chunk) is refused.
  {
    std::string bad = good;
    const size_t chunks = (19 + 15) / 16;
    // The table ends where the first chunk begins: its entry 0 names that position.
    size_t table = 0;
    for (size_t at = 8; at + 8 * chunks < bad.size(); ++at) {
      uint64_t first = 0;
      std::memcpy(&first, bad.data() + at, 8);
      if (first == at + 8 * chunks) {
        table = at;
        break;
      }
    }
    ASSERT_NE(table, 0u);
    bad[table + 8] = static_cast<char>(bad[table + 8] ^ 0x40);
    EXPECT_FALSE(exr_embeddable(bad, 37, 19));
  }
  std::filesystem::remove_all(dir);
}

// ---------------------------------------------------------------------------------------------
// The list pages' short ids, the metrics a case is judged on, the class of a failure (issue 27).

TEST(ReportLists, ShortIdsKeepTheSuiteAndTheEnd) {
  EXPECT_EQ(short_case_id("tonemap/dev3_gamut2", 64), "tonemap/dev3_gamut2");  // fits: as is
  const std::string id =
      "tonemap/aces_devices/a_family_name_that_goes_on/dev3_gamut2_hdr1_log_ramp_maxlum1000";
  const std::string s = short_case_id(id, 48);
  EXPECT_EQ(s, "tonemap/…/dev3_gamut2_hdr1_log_ramp_maxlum1000");
  // No segment start within the room: the id's last characters after the suite.
  EXPECT_EQ(short_case_id("ue/" + std::string(60, 'x') + "yz", 20),
            "ue/…" + std::string(14, 'x') + "yz");
  // Code points, not bytes: a multi-byte character is never cut.
  EXPECT_EQ(short_case_id("s/" + std::string(30, 'a') + "ΔE_ITP", 16), "s/…aaaaaaaΔE_ITP");
}

// The judged metrics are the tolerance the runner recorded (runner/tolerance.cpp tolerance_json,
// what results.json holds): a metric with a max, a hard cap or a warn level, and the dither
// criterion when it is set; nothing named per stage.
TEST(ReportLists, JudgedMetricsAreTheRecordedTolerancesJudgedEntries) {
  hdrc::Tolerance t;
  t.linear_rel = 1e-5;
  t.hard[static_cast<int>(hdrc::Metric::kPqCode12)] = 2;  // judged by its hard cap alone
  t.dither.judged = true;
  const nlohmann::json c = {{"tolerance", nlohmann::json::parse(hdrc::tolerance_json(t).dump())}};
  EXPECT_EQ(judged_metrics(c), (std::vector<std::string>{"linear_rel", "pq_code12", "dither"}));
  hdrc::Tolerance itp;
  itp.delta_e_itp = 0.5;
  itp.pq_code10 = 0.05;
  const nlohmann::json d = {{"tolerance", nlohmann::json::parse(hdrc::tolerance_json(itp).dump())}};
  EXPECT_EQ(judged_metrics(d), (std::vector<std::string>{"pq_code10", "delta_e_itp"}));
  EXPECT_TRUE(judged_metrics(nlohmann::json::object()).empty());
}

// Each kind of failure the runner's judge reports (runner/diff.cpp judge, runner/dither.cpp),
// written as results.json records it.
TEST(ReportLists, FailureClassIsTheMetricAndTheKind) {
  auto fail = [](nlohmann::json tol, nlohmann::json overall, std::string reason = "") {
    return nlohmann::json{{"verdict", "FAIL"},
                          {"reason", reason},
                          {"tolerance", tol},
                          {"stats", {{"overall", overall}}},
                          {"nonfinite", {{"mismatch", 0}}}};
  };
  const nlohmann::json rel = {{"max", 1e-4}, {"allowed_fraction", 0}, {"hard", 0.1}};
  const nlohmann::json pq = {{"max", 0.05}, {"allowed_fraction", 0}, {"hard", nullptr}};
  // Over its max.
  auto c = fail({{"linear_rel", rel}, {"pq_code10", pq}},
                {{"linear_rel", {{"max", 5e-5}}}, {"pq_code10", {{"max", 0.3}}}});
  EXPECT_EQ(failure_class(c).label(), "pq_code10 over tolerance");
  // Over its hard cap (decides before any max, metric by metric in the runner's order).
  c = fail({{"linear_rel", rel}, {"pq_code10", pq}},
           {{"linear_rel", {{"max", 0.5}}}, {"pq_code10", {{"max", 0.3}}}});
  EXPECT_EQ(failure_class(c).metric, "linear_rel");
  EXPECT_EQ(failure_class(c).kind, "over hard cap");
  // With an allowed fraction: the share over decides, not the max.
  nlohmann::json frac = rel;
  frac["allowed_fraction"] = 0.01;
  c = fail({{"linear_rel", frac}}, {{"linear_rel", {{"max", 0.05}, {"fraction_over", 0.005}}}});
  EXPECT_EQ(failure_class(c).kind, "fail");  // within its fraction: no metric explains it
  c = fail({{"linear_rel", frac}}, {{"linear_rel", {{"max", 0.05}, {"fraction_over", 0.02}}}});
  EXPECT_EQ(failure_class(c).label(), "linear_rel over tolerance");
  // A metric the tolerance does not judge never explains a failure.
  c = fail({{"linear_rel", rel}, {"delta_e_itp", nullptr}},
           {{"linear_rel", {{"max", 2e-4}}}, {"delta_e_itp", {{"max", 700}}}});
  EXPECT_EQ(failure_class(c).label(), "linear_rel over tolerance");
  // A non-finite mismatch decides first.
  c["nonfinite"]["mismatch"] = 3;
  EXPECT_EQ(failure_class(c).label(), "non-finite mismatch");
  // The dither criterion the reason names.
  c = fail({{"dither", {{"mean_sigmas", 4}}}}, nlohmann::json::object(),
           "dither mean: block 3 (256 pixels) of G has a mean noise of 5 standard errors");
  c["dither"] = {{"amount", 1}};
  EXPECT_EQ(failure_class(c).label(), "dither mean over tolerance");
  EXPECT_EQ(failure_class({{"verdict", "ERROR"}}).label(), "error");
}

// The summary's worst cases: one group per class, the class holding most failures first (not
// the case with the largest number), each case under its class.
TEST_F(WriteReport, WorstCasesAreGroupedByClassMostFailuresFirst) {
  const std::string tol =
      R"("tolerance": {"linear_rel": {"max": 1e-4, "allowed_fraction": 0, "hard": 0.1},
                       "pq_code10": {"max": 0.05, "allowed_fraction": 0, "hard": null},
                       "delta_e_itp": null, "rel_floor": 1e-4})";
  auto fail = [&](const std::string& id, double rel, double pq, double budget) {
    return R"({"id": ")" + id + R"(", "verdict": "FAIL", "stage": "linear_device", )" + tol +
           R"(, "budget_used": )" + std::to_string(budget) +
           R"(, "nonfinite": {"mismatch": 0}, "stats": {"overall": {"linear_rel": {"max": )" +
           std::to_string(rel) + R"(}, "pq_code10": {"max": )" + std::to_string(pq) +
           R"(}, "delta_e_itp": {"max": 720}}}})";
  };
  std::ofstream(dir_ / "results.json")
      << R"({"cases": [)" << fail("hard/a", 0.5, 0.01, 5000) << ","  // the largest budget
      << fail("pq/a", 1e-5, 0.2, 4) << "," << fail("pq/b", 1e-5, 0.9, 18) << ","
      << fail("pq/c", 1e-5, 0.1, 2) << ","
      << R"({"id": "err/a", "verdict": "ERROR", "stage": "linear_device", "reason": "x"},
            {"id": "ok/a", "verdict": "PASS", "stage": "linear_device", "budget_used": 0.7}]})";
  auto r = hdrc::write_report(dir_.string());
  ASSERT_TRUE(r) << r.error().to_string();
  const std::string index = read_file(dir_ / "report" / "index.html");
  auto at = [&](const std::string& s) { return index.find(s); };
  const size_t pq = at("data-class=\"pq_code10 over tolerance\""),
               hard = at("data-class=\"linear_rel over hard cap\""),
               err = at("data-class=\"error\""),
               passed = at("data-class=\"passed, most budget used\"");
  ASSERT_NE(pq, std::string::npos);
  ASSERT_NE(hard, std::string::npos);
  ASSERT_NE(err, std::string::npos);
  ASSERT_NE(passed, std::string::npos);
  EXPECT_LT(pq, hard);  // 3 failures before 1, although hard/a used most budget
  EXPECT_LT(hard, passed);
  EXPECT_LT(err, passed);
  // In the pq class, by budget used: b (18), a (4), c (2).
  EXPECT_LT(at("data-id=\"pq/b\""), at("data-id=\"pq/a\""));
  EXPECT_LT(at("data-id=\"pq/a\""), at("data-id=\"pq/c\""));
  EXPECT_GT(at("data-id=\"pq/b\""), pq);
  EXPECT_LT(at("data-id=\"pq/c\""), hard);
  // data.js carries each case's judged metrics (the matrix shows a metric only for these):
  // ΔE_ITP has statistics here but is not judged.
  const std::string data = read_file(dir_ / "report" / "data.js");
  EXPECT_NE(data.find(R"("judged":["linear_rel","pq_code10"])"), std::string::npos);
  EXPECT_EQ(data.find(R"("judged":["linear_rel","pq_code10","delta_e_itp"])"), std::string::npos);
}
