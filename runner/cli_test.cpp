// The hdrconform binary end to end: help and exit codes, bad input, and a planted defect.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#ifndef HDRC_BINARY
#error "HDRC_BINARY must be defined"
#endif

namespace fs = std::filesystem;

namespace {

struct Ran {
  int code;
  std::string out;  // stdout and stderr
};

Ran run(const std::string& args, const std::string& env = "") {
  const std::string cmd = env + std::string(HDRC_BINARY) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf;
  while (size_t n = fread(buf.data(), 1, buf.size(), p)) out.append(buf.data(), n);
  const int status = pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

fs::path temp_dir(const std::string& name) {
  fs::path p = fs::temp_directory_path() / ("hdrc_cli_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

std::string read(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

TEST(Cli, HelpExplainsOptionsAndExitCodes) {
  for (const char* sub : {"", "run ", "list ", "devices ", "probe ", "cvars "}) {
    const Ran r = run(std::string(sub) + "--help");
    EXPECT_EQ(r.code, 0) << sub;
    EXPECT_NE(r.out.find("Exit codes:"), std::string::npos) << sub;
    EXPECT_NE(r.out.find("3  engine unavailable"), std::string::npos) << sub;
  }
  EXPECT_NE(run("run --help").out.find("--shader-dir"), std::string::npos);
}

// The cvar table lists every cvar with its default and range (spec §10 defaults).
TEST(Cli, CvarTableListsDefaultsAndRanges) {
  const Ran r = run("cvars");
  EXPECT_EQ(r.code, 0);
  for (const char* want :
       {"r.HDR.Display.OutputDevice", "r.HDR.UI.Luminance", "300",
        "r.HDR.Aces.SceneColorMultiplier", "1.5", "FilmSlope", "0.88", "ColorGammaHighlights"})
    EXPECT_NE(r.out.find(want), std::string::npos) << want;
}

TEST(Cli, UsageErrorIsExitCode2) {
  EXPECT_EQ(run("").code, 2);
  EXPECT_EQ(run("frobnicate").code, 2);
  EXPECT_EQ(run("run --engine metal").code, 2);
}

// A bad case file: one clear error, exit 2, and the previous results are left as they were.
TEST(Cli, BadCaseFileRunsNothingAndOverwritesNothing) {
  const fs::path cases = temp_dir("badcases");
  const fs::path out = temp_dir("badout");
  {
    std::ofstream f(cases / "a.json");
    f << R"({"stage": "shaper", "cvars": {"r.HDR.Display.OutputDevice": 12}, "input": {"stimulus": "log_ramp"}})";
  }
  std::ofstream(out / "results.json") << "previous results";
  const Ran r = run("run --cases " + cases.string() + " --out " + out.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find((cases / "a.json").string() +
                       ": /cvars/r.HDR.Display.OutputDevice: cvar r.HDR.Display.OutputDevice = 12 "
                       "is out of range; valid choices: 0 to 9"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(read(out / "results.json"), "previous results");
  EXPECT_FALSE(fs::exists(out / "junit.xml"));
  fs::remove_all(cases);
  fs::remove_all(out);
}

TEST(Cli, UnavailableDeviceSkipsAndExits3) {
  const fs::path out = temp_dir("nodevice");
  const Ran r =
      run("run --filter 'tonemap/shaper_pq/dev3_*' --device no-such-gpu --out " + out.string());
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("SKIP"), std::string::npos);
  EXPECT_NE(r.out.find("0 passed"), std::string::npos);
  EXPECT_NE(read(out / "junit.xml").find("<skipped"), std::string::npos);
  fs::remove_all(out);
}

// No Vulkan driver at all (an ICD list naming no file): unavailable with the reason, exit 3.
TEST(Cli, NoVulkanDriverSkipsAndExits3) {
  const fs::path out = temp_dir("noicd");
  const Ran r = run("run --filter 'tonemap/linear_dev8/*' --out " + out.string(),
                    "VK_ICD_FILENAMES=/nonexistent/icd.json ");
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("candidate unavailable: vulkan engine unavailable"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("10 skipped"), std::string::npos) << r.out;
  fs::remove_all(out);
}

// probe: the README example; lines out match lines in; errors name the line.
TEST(Cli, ProbePrintsNineDigitsPerLine) {
  const fs::path in = temp_dir("probe") / "in.txt";
  std::ofstream(in) << "# scene grey and white\n0.18 0.18 0.18\n\n1 1 1\n";
  const Ran p =
      run("probe --set r.HDR.EnableHDROutput=1 --set r.HDR.Display.OutputDevice=3 "
          "--set r.HDR.Display.ColorGamut=4 --stage device < " +
          in.string());
  EXPECT_EQ(p.code, 0) << p.out;
  // Spec §13: PQ 0.378296436 for grey 0.18 and 0.552035909 for 1.0 (AP1 output: no gamut drift).
  std::istringstream lines(p.out);
  double a, b, c;
  ASSERT_TRUE(lines >> a >> b >> c);
  EXPECT_NEAR(b, 0.378296436, 2e-6);
  ASSERT_TRUE(lines >> a >> b >> c);
  EXPECT_NEAR(b, 0.552035909, 2e-6);
  EXPECT_FALSE(lines >> a);
  EXPECT_NE(p.out.find("0.378296"), std::string::npos);
  const Ran j =
      run("probe --json --stage aces_nits --set r.HDR.EnableHDROutput=1 --set "
          "r.HDR.Display.OutputDevice=3 < " +
          in.string());
  EXPECT_EQ(j.code, 0);
  EXPECT_NE(j.out.find("\"aces_nits\""), std::string::npos) << j.out;
  std::ofstream(in) << "0.18 x 0.18\n";
  const Ran bad = run("probe < " + in.string());
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.out.find("<stdin>: line 1: expected three numbers"), std::string::npos) << bad.out;
  const Ran bad_stage = run("probe --stage foo < " + in.string());
  EXPECT_EQ(bad_stage.code, 2);
  EXPECT_NE(bad_stage.out.find("valid choices: lattice, decoded"), std::string::npos);
  const Ran bad_cvar = run("probe --set r.HDR.Display.OutputDevice=12 < " + in.string());
  EXPECT_EQ(bad_cvar.code, 2);
  EXPECT_NE(bad_cvar.out.find("out of range; valid choices: 0 to 9"), std::string::npos);
  fs::remove_all(in.parent_path());
}

// probe's UI composite and VisualizeHDR false colour, against hand-derived values: an opaque white
// UI at r.HDR.UI.Luminance 300 is PQ(300 nits) = 0.6218628 up to the sRGB→Rec.2020 literal
// product's row sums (8.6e-6); Colorize(0) is pure blue for a luminance below the histogram.
TEST(Cli, ProbeUiCompositeAndFalseColour) {
  const fs::path dir = temp_dir("probe_ui");
  std::ofstream(dir / "in.txt") << "0.5 0.5 0.5\n";
  const Ran ui =
      run("probe --set r.HDR.EnableHDROutput=1 --set r.HDR.Display.OutputDevice=3 "
          "--stage ui_composite --ui 1,1,1,1 < " +
          (dir / "in.txt").string());
  EXPECT_EQ(ui.code, 0) << ui.out;
  std::istringstream l(ui.out);
  double r, g, b;
  ASSERT_TRUE(l >> r >> g >> b);
  for (double v : {r, g, b}) EXPECT_NEAR(v, 0.621862837, 1e-5);
  const Ran sdr = run("probe --stage ui_composite < " + (dir / "in.txt").string());
  EXPECT_EQ(sdr.code, 2);
  EXPECT_NE(sdr.out.find("HDR back buffers only"), std::string::npos) << sdr.out;
  std::ofstream(dir / "in.txt") << "1e-6 1e-6 1e-6\n";
  const Ran fc = run("probe --stage visualize_false_colour < " + (dir / "in.txt").string());
  EXPECT_EQ(fc.code, 0);
  EXPECT_EQ(fc.out, "0 0 1\n");
  fs::remove_all(dir);
}

// Planted defect: one output pixel of the shaper stage altered by 0.1 %. The suite must fail,
// naming the case and locating the pixel and channel exactly. (A one-ULP change of PQ's m2 is
// below lavapipe's own float32 error here, see docs/precision.md.)
TEST(Cli, PlantedDefectOnePixelFailsAndIsLocated) {
  const fs::path shaders = temp_dir("defect_shaders");
  const fs::path out = temp_dir("defect_out");
  fs::copy(fs::path(HDRC_SOURCE_DIR) / "gpu/shaders", shaders, fs::copy_options::recursive);
  std::string text = read(shaders / "stages/shaper.comp");
  const std::string from = "  out_px[i] = vec4(rgb, px.a);";
  const size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, from.size(), "  if (i == 517u) rgb.g *= 1.001;\n" + from);
  std::ofstream(shaders / "stages/shaper.comp") << text;

  const Ran r = run("run --filter 'tonemap/shaper_pq/dev3_log_ramp' --shader-dir " +
                    shaders.string() + " --out " + out.string());
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("FAIL  tonemap/shaper_pq/dev3_log_ramp  linear rel error"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("(1 values over) at (517, 0) G: input"), std::string::npos) << r.out;
  const std::string results = read(out / "results.json");
  EXPECT_NE(results.find("\"verdict\": \"FAIL\""), std::string::npos);
  EXPECT_NE(read(out / "junit.xml").find("<failure message=\"linear rel error"), std::string::npos);
  fs::remove_all(shaders);
  fs::remove_all(out);
}

}  // namespace
