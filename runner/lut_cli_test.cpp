// `hdrconform lut convert | info | apply` (runner/lut_cli.h): the image layouts checked pixel by
// pixel against the lattice (read back with OpenImageIO, not with our reader), the round trips
// (EXR float32 bit for bit, 16-bit PNG within 0.5/65535), every error pinned with its exit code
// and no file left behind, hostile "R G B" lines, `apply` against core/cube's evaluation and
// against OpenColorIO 2.1's FileTransform, a strip sampled as engines sample it, and the
// interpolation error figures docs/cube-workflow.md quotes.
#include "runner/lut_cli.h"

#include <OpenColorIO/OpenColorIO.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <set>
#include <sstream>

#ifndef HDRC_SOURCE_DIR
#error "HDRC_SOURCE_DIR must be defined"
#endif
#ifndef HDRC_BINARY
#error "HDRC_BINARY must be defined"
#endif

namespace OCIO = OCIO_NAMESPACE;
namespace fs = std::filesystem;
using hdrc::cube::CubeLut;
using hdrc::cube::Interp;
using hdrc::cube::Rgb;

namespace {

const std::string kCubeDir = std::string(HDRC_SOURCE_DIR) + "/cases/lut/cube/";

CubeLut load_cube(const std::string& name) {
  auto lut = hdrc::cube::read_cube_file(kCubeDir + name);
  EXPECT_TRUE(lut.ok()) << lut.error().to_string();
  return lut.ok() ? *lut : CubeLut{};
}

struct CliResult {
  int code = -1;
  std::string out, err;
};

// The lut command as hdrconform's main runs it: registered on an app, parsed, and the CLI11
// exception it ends with turned into an exit code as main does (0 stays 0, anything else is 2).
CliResult cli(const std::vector<std::string>& args, const std::string& input = "") {
  CLI::App app{"hdrconform"};
  std::istringstream in(input);
  std::ostringstream out, err;
  hdrc::lut::add_lut_command(app, in, out, err);
  std::vector<const char*> argv{"hdrconform"};
  for (const auto& a : args) argv.push_back(a.c_str());
  CliResult r;
  try {
    app.parse(static_cast<int>(argv.size()), argv.data());
    ADD_FAILURE() << "the lut command returned from parse without ending it";
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e, out, err);
    r.code = code == 0 ? 0 : 2;
  }
  r.out = out.str();
  r.err = err.str();
  return r;
}

// A fresh folder per test, removed afterwards.
class LutCli : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::replace(name.begin(), name.end(), '/', '_');  // parameterised tests: "Test/param"
    dir_ = fs::temp_directory_path() / ("lut_cli_test_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::set<std::string> files() const {
    std::set<std::string> s;
    for (const auto& e : fs::directory_iterator(dir_)) s.insert(e.path().filename().string());
    return s;
  }
  fs::path dir_;
};

// An image read with OpenImageIO directly (not through lut_cli): pixels as float, or as uint16.
struct Raw {
  int width = 0, height = 0, channels = 0;
  std::string format;
  std::vector<float> f;
  std::vector<uint16_t> u16;
  OIIO::ImageSpec spec;
};

Raw read_raw(const std::string& path) {
  Raw r;
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << OIIO::geterror();
  if (!in) return r;
  r.spec = in->spec();
  r.width = r.spec.width;
  r.height = r.spec.height;
  r.channels = r.spec.nchannels;
  r.format = r.spec.format.c_str();
  const size_t n = static_cast<size_t>(r.width) * r.height * r.channels;
  if (r.spec.format == OIIO::TypeDesc::UINT16) {
    r.u16.resize(n);
    EXPECT_TRUE(in->read_image(0, 0, 0, r.channels, OIIO::TypeDesc::UINT16, r.u16.data()));
  } else {
    r.f.resize(n);
    EXPECT_TRUE(in->read_image(0, 0, 0, r.channels, OIIO::TypeDesc::FLOAT, r.f.data()));
  }
  return r;
}

void write_raw(const std::string& path, int w, int h, int channels, OIIO::TypeDesc type,
               const std::vector<float>& px) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out);
  OIIO::ImageSpec spec(w, h, channels, type);
  ASSERT_TRUE(out->open(path, spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
  ASSERT_TRUE(out->close());
}

// The pixel of lattice point (r, g, b), as lut_cli.h documents the layouts; with `bottom`, row y
// of the layout is the file's row h - 1 - y.
size_t pixel_index(bool strip, int n, int r, int g, int b, bool bottom = false) {
  const int w = strip ? n * n : n, h = strip ? n : n * n;
  const int x = strip ? r + n * b : r;
  const int y = strip ? g : g + n * b;
  return static_cast<size_t>(bottom ? h - 1 - y : y) * w + x;
}

std::vector<std::array<double, 3>> parse_lines(const std::string& text) {
  std::vector<std::array<double, 3>> out;
  std::istringstream s(text);
  for (std::string line; std::getline(s, line);) {
    std::array<double, 3> v{};
    EXPECT_EQ(std::sscanf(line.c_str(), "%lf %lf %lf", &v[0], &v[1], &v[2]), 3) << line;
    out.push_back(v);
  }
  return out;
}

// The files with a 3-D table only (the ones convert takes) and those within [0, 1].
const char* const kThreeD[] = {"identity_2.cube",    "identity_17.cube", "contrast_17.cube",
                               "hue_rotate_17.cube", "domain_3d.cube",   "resolve_range_3d.cube"};
const char* const kUnitRange[] = {"identity_2.cube", "identity_17.cube", "contrast_17.cube",
                                  "hue_rotate_17.cube"};

// ---------------------------------------------------------------------------------------------
// convert

TEST_F(LutCli, LayoutsPlaceTheLatticeAsDocumented) {
  // identity_2: lattice point (r, g, b) holds (r, g, b); the strip is 4 x 2 with (r + 2 b, g),
  // the volume 2 x 4 with (r, g + 2 b). Every pixel written out by hand.
  ASSERT_EQ(cli({"lut", "convert", kCubeDir + "identity_2.cube", "--to", "strip", "--format", "exr",
                 "--out", path("s.exr")})
                .code,
            0);
  ASSERT_EQ(cli({"lut", "convert", kCubeDir + "identity_2.cube", "--to", "volume", "--format",
                 "exr", "--out", path("v.exr")})
                .code,
            0);
  const Raw s = read_raw(path("s.exr")), v = read_raw(path("v.exr"));
  ASSERT_EQ(s.width, 4);
  ASSERT_EQ(s.height, 2);
  ASSERT_EQ(s.channels, 3);
  EXPECT_EQ(s.format, "float");
  ASSERT_EQ(v.width, 2);
  ASSERT_EQ(v.height, 4);
  // Row 0 of the strip: (0,0,0) (1,0,0) | (0,0,1) (1,0,1); row 1: green 1.
  const std::vector<float> strip = {0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 1,
                                    0, 1, 0, 1, 1, 0, 0, 1, 1, 1, 1, 1};
  // The volume's rows are the .cube rows in order, two to an image row.
  const std::vector<float> volume = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0,
                                     0, 0, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1};
  EXPECT_EQ(s.f, strip);
  EXPECT_EQ(v.f, volume);
  EXPECT_EQ(s.spec.get_string_attribute("hdrconform:lut_layout"), "strip");
  EXPECT_EQ(v.spec.get_string_attribute("hdrconform:lut_layout"), "volume");
  EXPECT_EQ(s.spec.get_string_attribute("hdrconform:lut_size"), "2");
  EXPECT_EQ(s.spec.get_string_attribute("hdrconform:domain_min"), "0 0 0");
  EXPECT_EQ(s.spec.get_string_attribute("hdrconform:domain_max"), "1 1 1");
  EXPECT_EQ(s.spec.get_string_attribute("ImageDescription"), "identity 2");
  EXPECT_EQ(s.spec.get_string_attribute("hdrconform:lut_origin"), "top");

  // --origin bottom: the same rows, the file's last row first (green 0 at the bottom).
  ASSERT_EQ(cli({"lut", "convert", kCubeDir + "identity_2.cube", "--to", "strip", "--format", "exr",
                 "--out", path("sb.exr"), "--origin", "bottom"})
                .code,
            0);
  ASSERT_EQ(cli({"lut", "convert", kCubeDir + "identity_2.cube", "--to", "volume", "--format",
                 "exr", "--out", path("vb.exr"), "--origin", "bottom"})
                .code,
            0);
  const Raw sb = read_raw(path("sb.exr")), vb = read_raw(path("vb.exr"));
  EXPECT_EQ(sb.f, (std::vector<float>{0, 1, 0, 1, 1, 0, 0, 1, 1, 1, 1, 1,
                                      0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 1}));
  EXPECT_EQ(vb.f, (std::vector<float>{0, 1, 1, 1, 1, 1, 0, 0, 1, 1, 0, 1,
                                      0, 1, 0, 1, 1, 0, 0, 0, 0, 1, 0, 0}));
  EXPECT_EQ(sb.spec.get_string_attribute("hdrconform:lut_origin"), "bottom");
}

TEST_F(LutCli, ExrRoundTripIsBitExact) {
  for (const char* file : kThreeD)
    for (const bool strip : {true, false})
      for (const bool bottom : {false, true}) {
        SCOPED_TRACE(std::string(file) + (strip ? " strip" : " volume") +
                     (bottom ? " bottom" : ""));
        const CubeLut lut = load_cube(file);
        const std::string out = path(strip ? "s.exr" : "v.exr");
        const CliResult r =
            cli({"lut", "convert", kCubeDir + file, "--to", strip ? "strip" : "volume", "--format",
                 "exr", "--out", out, "--origin", bottom ? "bottom" : "top"});
        ASSERT_EQ(r.code, 0) << r.err;
        EXPECT_EQ(r.err, "");
        const int n = lut.size_3d;
        const Raw raw = read_raw(out);
        ASSERT_EQ(raw.width, strip ? n * n : n);
        ASSERT_EQ(raw.height, strip ? n : n * n);
        size_t mismatches = 0;
        for (int b = 0; b < n; ++b)
          for (int g = 0; g < n; ++g)
            for (int rr = 0; rr < n; ++rr)
              for (int k = 0; k < 3; ++k)
                mismatches += std::bit_cast<uint32_t>(
                                  raw.f[pixel_index(strip, n, rr, g, b, bottom) * 3 + k]) !=
                              std::bit_cast<uint32_t>(lut.at(rr, g, b)[k]);
        EXPECT_EQ(mismatches, 0u);
        // Read back through lut_cli: the same LUT, title and domain included.
        auto back = hdrc::lut::load_lut(out);
        ASSERT_TRUE(back.ok()) << back.error().to_string();
        EXPECT_TRUE(back->lut == lut);
        EXPECT_TRUE(back->metadata);
        EXPECT_EQ(back->format, "OpenEXR float32");
      }
}

TEST_F(LutCli, Png16RoundTripIsWithinHalfACode) {
  for (const char* file : kUnitRange)
    for (const bool strip : {true, false}) {
      SCOPED_TRACE(std::string(file) + (strip ? " strip" : " volume"));
      const CubeLut lut = load_cube(file);
      const std::string out = path("l.png");
      const CliResult r = cli({"lut", "convert", kCubeDir + file, "--to",
                               strip ? "strip" : "volume", "--format", "png16", "--out", out});
      ASSERT_EQ(r.code, 0) << r.err;
      const Raw raw = read_raw(out);
      ASSERT_EQ(raw.format, "uint16");
      ASSERT_EQ(raw.channels, 3);
      const int n = lut.size_3d;
      double worst = 0;
      for (int b = 0; b < n; ++b)
        for (int g = 0; g < n; ++g)
          for (int rr = 0; rr < n; ++rr)
            for (int k = 0; k < 3; ++k) {
              const double code = raw.u16[pixel_index(strip, n, rr, g, b) * 3 + k];
              worst = std::max(worst, std::fabs(code / 65535 - lut.at(rr, g, b)[k]));
            }
      EXPECT_LE(worst, 0.5 / 65535);
      auto back = hdrc::lut::load_lut(out);
      ASSERT_TRUE(back.ok()) << back.error().to_string();
      EXPECT_EQ(back->format, "PNG 16-bit");
      for (size_t i = 0; i < lut.table_3d.size(); ++i)
        for (int k = 0; k < 3; ++k)
          ASSERT_NEAR(back->lut.table_3d[i][k], lut.table_3d[i][k], 0.5 / 65535 + 6e-8);
      EXPECT_EQ(back->lut.title, lut.title);
    }
}

TEST_F(LutCli, Png16RefusesValuesOutsideTheUnitRangeUnlessClamped) {
  // resolve_range_3d: out = (r^2, g b, 0.5 + 0.5 sin(2 r + b)) on the grid -0.25 + 0.1875 i,
  // i = 0..8. Counted by hand: red r^2 > 1 for r = 1.0625, 1.25 (2 x 81 = 162); green g b < 0
  // when one of g, b is -0.25 or -0.0625 and the other positive (2 x 2 x 7 pairs x 9 = 252) and
  // g b > 1 for (1.0625, 1.0625), (1.0625, 1.25), (1.25, 0.875), (1.25, 1.0625), (1.25, 1.25)
  // and (0.875, 1.25) (6 x 9 = 54); blue stays within [0.159, 0.999]. 468 values, lowest
  // -0.25 x 1.25 = -0.3125, highest 1.25^2 = 1.5625; the first in file order is red at
  // r = 1.0625 (lattice (7, 0, 0)): 1.12890625.
  const std::string in = kCubeDir + "resolve_range_3d.cube";
  const CliResult r =
      cli({"lut", "convert", in, "--to", "strip", "--format", "png16", "--out", path("l.png")});
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err, "error: " + in +
                       ": lattice (7, 0, 0) red: 1.12890625 is outside [0, 1], which a 16-bit PNG "
                       "cannot hold (468 value(s) are: lowest -0.3125, highest 1.5625); valid "
                       "choices: --format exr (float32, any value), or --clamp to clamp them to "
                       "[0, 1]\n");
  EXPECT_TRUE(files().empty());

  const CliResult c = cli({"lut", "convert", in, "--to", "volume", "--format", "png16", "--out",
                           path("l.png"), "--clamp"});
  ASSERT_EQ(c.code, 0) << c.err;
  EXPECT_NE(c.out.find("clamped 468 value(s) outside [0, 1] to [0, 1] (lowest -0.3125, highest "
                       "1.5625)\n"),
            std::string::npos)
      << c.out;
  EXPECT_NE(c.out.find("note: the domain is [-0.25, 1.25] for red, green, blue, not [0, 1]"),
            std::string::npos)
      << c.out;
  const CubeLut lut = load_cube("resolve_range_3d.cube");
  auto back = hdrc::lut::load_lut(path("l.png"));
  ASSERT_TRUE(back.ok()) << back.error().to_string();
  EXPECT_EQ(back->lut.domain_min_3d, lut.domain_min_3d);
  EXPECT_EQ(back->lut.domain_max_3d, lut.domain_max_3d);
  for (size_t i = 0; i < lut.table_3d.size(); ++i)
    for (int k = 0; k < 3; ++k)
      ASSERT_NEAR(back->lut.table_3d[i][k], std::clamp(lut.table_3d[i][k], 0.f, 1.f),
                  0.5 / 65535 + 6e-8);
}

TEST_F(LutCli, ConvertSummary) {
  const CliResult r = cli({"lut", "convert", kCubeDir + "contrast_17.cube", "--to", "strip",
                           "--format", "exr", "--out", path("c.exr")});
  ASSERT_EQ(r.code, 0);
  const std::string size = std::to_string(fs::file_size(path("c.exr")));
  EXPECT_EQ(r.out, "wrote " + path("c.exr") +
                       ": strip 289 x 17: 17 slices of 17 x 17 side by side, lattice (r, g, b) at "
                       "pixel (r + 17 b, g), row 0 at the top, OpenEXR float32 RGB, " +
                       size + " bytes, from " + kCubeDir + "contrast_17.cube (LUT_3D_SIZE 17)\n");
  EXPECT_EQ(files(), std::set<std::string>{"c.exr"});
  // Converting is deterministic: the same input gives the same bytes (no time stamp).
  EXPECT_EQ(read_raw(path("c.exr")).spec.find_attribute("DateTime"), nullptr);
  ASSERT_EQ(cli({"lut", "convert", kCubeDir + "contrast_17.cube", "--to", "strip", "--format",
                 "exr", "--out", path("d.exr")})
                .code,
            0);
  std::ifstream a(path("c.exr"), std::ios::binary), b(path("d.exr"), std::ios::binary);
  EXPECT_TRUE(
      std::equal(std::istreambuf_iterator<char>(a), {}, std::istreambuf_iterator<char>(b), {}));
}

TEST_F(LutCli, ConvertImageToImage) {
  // An image convert wrote converts again (strip EXR -> volume PNG -> strip EXR), the values
  // kept within the 16-bit step.
  const CubeLut lut = load_cube("hue_rotate_17.cube");
  ASSERT_EQ(cli({"lut", "convert", kCubeDir + "hue_rotate_17.cube", "--to", "strip", "--format",
                 "exr", "--out", path("a.exr")})
                .code,
            0);
  ASSERT_EQ(cli({"lut", "convert", path("a.exr"), "--to", "volume", "--format", "png16", "--out",
                 path("b.png")})
                .code,
            0);
  ASSERT_EQ(cli({"lut", "convert", path("b.png"), "--to", "strip", "--format", "exr", "--out",
                 path("c.exr")})
                .code,
            0);
  auto back = hdrc::lut::load_lut(path("c.exr"));
  ASSERT_TRUE(back.ok()) << back.error().to_string();
  EXPECT_EQ(back->lut.title, lut.title);
  for (size_t i = 0; i < lut.table_3d.size(); ++i)
    for (int k = 0; k < 3; ++k)
      ASSERT_NEAR(back->lut.table_3d[i][k], lut.table_3d[i][k], 0.5 / 65535 + 6e-8);
}

struct BadConvert {
  std::string name;
  std::vector<std::string> args;  // {OUT} is the test folder
  std::string err;                // {CUBE} the sample folder, {OUT} the test folder
};

void PrintTo(const BadConvert& b, std::ostream* os) {
  *os << b.name;
}

std::string subst(std::string s, const std::string& out) {
  for (const auto& [key, value] :
       {std::pair<std::string, std::string>{"{CUBE}", kCubeDir}, {"{OUT}", out}})
    for (size_t at; (at = s.find(key)) != std::string::npos;) s.replace(at, key.size(), value);
  return s;
}

class LutCliBad : public LutCli, public ::testing::WithParamInterface<BadConvert> {};

TEST_P(LutCliBad, ExitsTwoNamingTheProblemAndWritesNothing) {
  const BadConvert& bc = GetParam();
  // Files some cases read.
  {
    std::ofstream(path("garbage.cube")) << "LUT_3D_SIZE 2\n0 0 0\n1 0 zero\n";
    std::ofstream(path("garbage.exr")) << "this is not an EXR file";
    std::ofstream(path("garbage.png")) << "\x89PNG\r\n\x1a\n truncated";
    std::ofstream(path("lut.txt")) << "LUT_3D_SIZE 2\n";
    fs::create_directories(path("folder.exr"));
    std::vector<float> px(5 * 3 * 3, 0.5f);
    write_raw(path("shape.exr"), 5, 3, 3, OIIO::TypeDesc::FLOAT, px);
    std::vector<float> nan(4 * 2 * 3, 0.25f);
    nan[3 * 5 + 1] = std::numeric_limits<float>::quiet_NaN();  // pixel (1, 1) green
    write_raw(path("nan.exr"), 4, 2, 3, OIIO::TypeDesc::FLOAT, nan);
    std::vector<float> gray(4 * 2, 0.5f);
    write_raw(path("gray.exr"), 4, 2, 1, OIIO::TypeDesc::FLOAT, gray);
  }
  const std::set<std::string> before = files();
  std::vector<std::string> args;
  for (const auto& a : bc.args) args.push_back(subst(a, dir_.string()));
  const CliResult r = cli(args);
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.out, "");
  // An expected message that does not end its line is a prefix (the rest is a library's words).
  const std::string want = subst(bc.err, dir_.string());
  if (!want.empty() && want.back() == '\n')
    EXPECT_EQ(r.err, want);
  else
    EXPECT_EQ(r.err.substr(0, want.size()), want) << r.err;
  EXPECT_EQ(files(), before);
}

std::vector<BadConvert> bad_converts() {
  const std::vector<std::string> ok = {"--to", "strip", "--format", "exr", "--out", "{OUT}/o.exr"};
  auto with = [&](std::string in, std::vector<std::string> rest) {
    std::vector<std::string> a = {"lut", "convert", std::move(in)};
    a.insert(a.end(), rest.begin(), rest.end());
    return a;
  };
  return {
      {"missing_file", with("{OUT}/none.cube", ok),
       "error: {OUT}/none.cube: cannot open .cube file: No such file or directory\n"},
      {"garbage_cube", with("{OUT}/garbage.cube", ok),
       "error: {OUT}/garbage.cube: line 3: 3-D table row 2: 'zero' is not a number; valid "
       "choices: finite decimal numbers such as 0.5, -2, 1.5e-3\n"},
      {"garbage_exr", with("{OUT}/garbage.exr", ok),
       "error: {OUT}/garbage.exr: not an OpenEXR file (no EXR magic number); valid choices: an "
       "OpenEXR image\n"},
      {"unknown_extension", with("{OUT}/lut.txt", ok),
       "error: {OUT}/lut.txt: unknown LUT file type '.txt'; valid choices: .cube, .exr, .png\n"},
      {"image_not_a_layout", with("{OUT}/shape.exr", ok),
       "error: {OUT}/shape.exr: the image is 5 x 3: not a LUT layout; valid choices: strip (N^2 "
       "x N), volume (N x N^2), N from 2 to 256\n"},
      {"image_nan", with("{OUT}/nan.exr", ok),
       "error: {OUT}/nan.exr: pixel (1, 1) green: the value is nan; valid choices: finite "
       "values\n"},
      {"image_one_channel", with("{OUT}/gray.exr", ok),
       "error: {OUT}/gray.exr: the image's channels are Y; valid choices: R,G,B first (R,G,B or "
       "R,G,B,A)\n"},
      {"shaper", with("{CUBE}resolve_shaper.cube", ok),
       "error: {CUBE}resolve_shaper.cube: LUT_1D_SIZE 256: a 1-D shaper before the 3-D table has "
       "no place in a strip or volume texture (the engine would sample the 3-D table without "
       "it); valid choices: a .cube with only a 3-D table (export it without a shaper, or apply "
       "the shaper in the engine before the lookup)\n"},
      {"one_d", with("{CUBE}gamma_1d.cube", ok),
       "error: {CUBE}gamma_1d.cube: LUT_1D_SIZE 1024: a 1-D LUT has no 3-D table to write as a "
       "strip or volume; valid choices: a .cube with LUT_3D_SIZE\n"},
      {"out_extension",
       with("{CUBE}contrast_17.cube", {"--to", "strip", "--format", "exr", "--out", "{OUT}/o.png"}),
       "error: --out: {OUT}/o.png: the extension '.png' does not match --format exr; valid "
       "choices: .exr\n"},
      {"out_extension_png16",
       with("{CUBE}contrast_17.cube",
            {"--to", "strip", "--format", "png16", "--out", "{OUT}/o.exr"}),
       "error: --out: {OUT}/o.exr: the extension '.exr' does not match --format png16; valid "
       "choices: .png\n"},
      {"out_folder_missing",
       with("{CUBE}contrast_17.cube",
            {"--to", "strip", "--format", "exr", "--out", "{OUT}/no/o.exr"}),
       "error: --out: {OUT}/no/o.exr: the folder '{OUT}/no' does not exist; valid choices: a "
       "file in an existing folder\n"},
      {"out_is_a_folder",
       with("{CUBE}contrast_17.cube",
            {"--to", "strip", "--format", "exr", "--out", "{OUT}/folder.exr"}),
       "error: --out: {OUT}/folder.exr: is a folder; valid choices: a .exr file\n"},
      {"bad_layout",
       with("{CUBE}contrast_17.cube", {"--to", "cube", "--format", "exr", "--out", "{OUT}/o.exr"}),
       "--to: cube not in {strip,volume}\nRun with --help for more information.\n"},
      {"bad_format",
       with("{CUBE}contrast_17.cube",
            {"--to", "strip", "--format", "png8", "--out", "{OUT}/o.png"}),
       "--format: png8 not in {exr,png16}\nRun with --help for more information.\n"},
      {"bad_origin",
       with("{CUBE}contrast_17.cube",
            {"--to", "strip", "--format", "exr", "--out", "{OUT}/o.exr", "--origin", "left"}),
       "--origin: left not in {top,bottom}\nRun with --help for more information.\n"},
      {"no_out", with("{CUBE}contrast_17.cube", {"--to", "strip", "--format", "exr"}),
       "--out is required\nRun with --help for more information.\n"},
      {"no_layout", with("{CUBE}contrast_17.cube", {"--format", "exr", "--out", "{OUT}/o.exr"}),
       "--to is required\nRun with --help for more information.\n"},
      {"unknown_flag",
       with("{CUBE}contrast_17.cube",
            {"--to", "strip", "--format", "exr", "--out", "{OUT}/o.exr", "--half"}),
       "The following argument was not expected: --half\nRun with --help for more "
       "information.\n"},
      {"no_subcommand",
       {"lut"},
       "A subcommand is required\nRun with --help for more information.\n"},
      {"unknown_subcommand",
       {"lut", "bake", "x.cube"},
       "A subcommand is required\nRun with --help for more information.\n"},
      {"apply_bad_interp",
       {"lut", "apply", "{CUBE}contrast_17.cube", "--interp", "cubic"},
       "--interp: cubic not in {trilinear,tetrahedral}\nRun with --help for more "
       "information.\n"},
      {"info_missing",
       {"lut", "info", "{OUT}/none.exr"},
       "error: {OUT}/none.exr: cannot open LUT image: No such file or directory\n"},
      {"info_garbage_png",
       {"lut", "info", "{OUT}/garbage.png"},
       "error: {OUT}/garbage.png: cannot open LUT image: "},
      {"apply_missing",
       {"lut", "apply", "{OUT}/none.cube"},
       "error: {OUT}/none.cube: cannot open .cube file: No such file or directory\n"},
  };
}

INSTANTIATE_TEST_SUITE_P(Errors, LutCliBad, ::testing::ValuesIn(bad_converts()),
                         [](const auto& info) { return info.param.name; });

// ---------------------------------------------------------------------------------------------
// info

TEST_F(LutCli, InfoOnCubeFiles) {
  // contrast_17: smoothstep per channel on i/16. Its largest distance from the identity, by hand:
  // s(x) - x is extreme at x = (3 -+ sqrt 3)/6 = 0.211, 0.789; on the grid at i = 3 and 13:
  // s(3/16) = 27/256 - 54/4096 = 378/4096, minus 768/4096 = -390/4096 = -0.0952148438 (first
  // met at lattice (3, 0, 0), red).
  CliResult r = cli({"lut", "info", kCubeDir + "contrast_17.cube"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "file: " + kCubeDir +
                       "contrast_17.cube\n"
                       "format: .cube text\n"
                       "title: \"contrast: smoothstep per channel\"\n"
                       "3-D table: 17 x 17 x 17 (4913 points, red fastest)\n"
                       "3-D domain: [0, 1] for red, green, blue\n"
                       "3-D min: 0 0 0\n"
                       "3-D max: 1 1 1\n"
                       "3-D identity: no (largest |value - input| 0.0952148438 at lattice (3, 0, "
                       "0) red; storage precision float32, or 6 decimal places (5e-07) as most "
                       ".cube writers print)\n"
                       "identity: no\n");

  r = cli({"lut", "info", kCubeDir + "identity_17.cube"});
  ASSERT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("3-D identity: yes (largest |value - input| 0; storage"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("\nidentity: yes\n"), std::string::npos);

  // resolve_shaper: log2(1 + x)/log2(5) over [0, 4] (0 to 1), then a 3-D table whose outputs
  // run from 0 (black) to 0.9 + 0.1 = 1, 1, 0.8 + 0.2 = 1 (white).
  r = cli({"lut", "info", kCubeDir + "resolve_shaper.cube"});
  ASSERT_EQ(r.code, 0);
  for (const char* line :
       {"title: (none)\n", "1-D table: 256 points (a shaper: applied first, per channel)\n",
        "1-D input range: [0, 4] for red, green, blue\n", "1-D min: 0 0 0\n", "1-D max: 1 1 1\n",
        "3-D input range: [0, 1] for red, green, blue\n", "3-D min: 0 0 0\n", "3-D max: 1 1 1\n",
        "\nidentity: no\n"})
    EXPECT_NE(r.out.find(line), std::string::npos) << line << " in\n" << r.out;

  // domain_3d: DOMAIN_MIN -0.5 0 0.25, DOMAIN_MAX 2 4 1.5.
  r = cli({"lut", "info", kCubeDir + "domain_3d.cube"});
  EXPECT_NE(r.out.find("3-D domain: min -0.5 0 0.25, max 2 4 1.5\n"), std::string::npos) << r.out;

  // resolve_range_3d: min and max per channel by hand on the grid -0.25 + 0.1875 i: red r^2
  // from 0.0625^2 = 0.00390625 to 1.5625; green g b from -0.3125 to 1.5625; blue
  // 0.5 + 0.5 sin(2 r + b), 2 r + b = -0.75 + 0.1875 k: lowest at k = 0, sin(-0.75), highest at
  // k = 12 (1.5, nearest pi/2).
  r = cli({"lut", "info", kCubeDir + "resolve_range_3d.cube"});
  EXPECT_NE(r.out.find("3-D min: 0.00390625 -0.3125 " +
                       hdrc::format_number(static_cast<float>(0.5 + 0.5 * std::sin(-0.75))) +
                       "\n3-D max: 1.5625 1.5625 " +
                       hdrc::format_number(static_cast<float>(0.5 + 0.5 * std::sin(1.5))) + "\n"),
            std::string::npos)
      << r.out;

  // gamma_1d: r^2.2, g^(1/2.2), b^1.8 on [0, 1]: 0 at 0 and 1 at 1.
  r = cli({"lut", "info", kCubeDir + "gamma_1d.cube"});
  for (const char* line : {"1-D table: 1024 points\n", "1-D domain: [0, 1] for red, green, blue\n",
                           "1-D min: 0 0 0\n", "1-D max: 1 1 1\n", "\nidentity: no\n"})
    EXPECT_NE(r.out.find(line), std::string::npos) << line << " in\n" << r.out;
}

TEST_F(LutCli, InfoOnImages) {
  ASSERT_EQ(cli({"lut", "convert", kCubeDir + "identity_17.cube", "--to", "volume", "--format",
                 "png16", "--out", path("i.png")})
                .code,
            0);
  CliResult r = cli({"lut", "info", path("i.png")});
  ASSERT_EQ(r.code, 0) << r.err;
  // i/16 in 16 bits: round(65535 i / 16) / 65535 is off by at most 0.5/65535 (1/16 -> 4096 codes
  // instead of 4095.9375: 0.0625/65535 = 9.5e-07 off). An identity within the 16-bit step.
  EXPECT_EQ(r.out.substr(0, r.out.find("3-D min")),
            "file: " + path("i.png") +
                "\n"
                "format: PNG 16-bit, volume 17 x 289: 17 slices of 17 x 17 stacked, lattice (r, "
                "g, b) at pixel (r, g + 17 b), row 0 at the top\n"
                "metadata: hdrconform lut convert (layout, origin, size, domain, title)\n"
                "title: \"identity 17\"\n"
                "3-D table: 17 x 17 x 17 (4913 points, red fastest)\n"
                "3-D domain: [0, 1] for red, green, blue\n");
  EXPECT_NE(r.out.find("3-D identity: yes (largest |value - input| "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("storage precision 16-bit (0.5/65535))\nidentity: yes\n"), std::string::npos)
      << r.out;

  // An image without convert's metadata (as an engine's neutral LUT): the shape gives the layout,
  // the domain is [0, 1]. A half EXR of the 2-point identity strip is an identity; one texel off
  // by 1/64 is not, and info names it.
  std::vector<float> strip = {0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 1,
                              0, 1, 0, 1, 1, 0, 0, 1, 1, 1, 1, 1};
  write_raw(path("h.exr"), 4, 2, 3, OIIO::TypeDesc::HALF, strip);
  r = cli({"lut", "info", path("h.exr")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "file: " + path("h.exr") +
                       "\n"
                       "format: OpenEXR half, strip 4 x 2: 2 slices of 2 x 2 side by side, "
                       "lattice (r, g, b) at pixel (r + 2 b, g), row 0 at the top\n"
                       "metadata: none (the layout is taken from the shape, the origin as top, "
                       "the domain as [0, 1])\n"
                       "title: (none)\n"
                       "3-D table: 2 x 2 x 2 (8 points, red fastest)\n"
                       "3-D domain: [0, 1] for red, green, blue\n"
                       "3-D min: 0 0 0\n"
                       "3-D max: 1 1 1\n"
                       "3-D identity: yes (largest |value - input| 0; storage precision half "
                       "(half an ulp))\n"
                       "identity: yes\n");
  // UE's neutral LUT is an 8-bit 256 x 16 strip: (r, g, b)/15 at pixel (r + 16 b, g), 17 (r, g,
  // b) in 8 bits, exactly.
  std::vector<float> neutral(256 * 16 * 3);
  for (int b = 0; b < 16; ++b)
    for (int g = 0; g < 16; ++g)
      for (int rr = 0; rr < 16; ++rr)
        for (int k = 0; k < 3; ++k)
          neutral[(static_cast<size_t>(g) * 256 + rr + 16 * b) * 3 + k] = (k == 0   ? rr
                                                                           : k == 1 ? g
                                                                                    : b) *
                                                                          17 / 255.f;
  write_raw(path("neutral.png"), 256, 16, 3, OIIO::TypeDesc::UINT8, neutral);
  r = cli({"lut", "info", path("neutral.png")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("format: PNG 8-bit, strip 256 x 16"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("3-D identity: yes"), std::string::npos) << r.out;
  auto n8 = hdrc::lut::load_lut(path("neutral.png"));
  ASSERT_TRUE(n8.ok());
  EXPECT_EQ(n8->lut.at(15, 3, 7),
            (Rgb{1.f, static_cast<float>(51 / 255.0), static_cast<float>(119 / 255.0)}));

  strip[3 * 6 + 2] = 1.f - 1.f / 64;  // pixel (2, 1) = lattice (0, 1, 1), blue
  write_raw(path("h.exr"), 4, 2, 3, OIIO::TypeDesc::HALF, strip);
  r = cli({"lut", "info", path("h.exr")});
  EXPECT_NE(r.out.find("3-D identity: no (largest |value - input| 0.015625 at lattice (0, 1, 1) "
                       "blue; storage precision half (half an ulp))\n"),
            std::string::npos)
      << r.out;
}

// ---------------------------------------------------------------------------------------------
// apply

TEST_F(LutCli, ApplyKnownValues) {
  // Lattice points give the formula exactly: smoothstep(0.25) = 0.0625 x 2.5 = 0.15625,
  // smoothstep(0.75) = 0.5625 x 1.5 = 0.84375. The identity gives its input back. Blank lines,
  // comments, CRLF, tabs and a leading '+' are taken as probe takes them.
  CliResult r = cli({"lut", "apply", kCubeDir + "contrast_17.cube"},
                    "# a comment\n\n0.25 0.5 0.75\r\n\t+0.25  0.5\t0.75  \n");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "0.15625 0.5 0.84375\n0.15625 0.5 0.84375\n");
  EXPECT_EQ(r.err, "");
  r = cli({"lut", "apply", kCubeDir + "identity_17.cube", "--interp", "tetrahedral"},
          "0.3 0.5 0.7\n0.1 0.2 0.3");  // the last line has no newline
  EXPECT_EQ(r.out, "0.3 0.5 0.7\n0.1 0.2 0.3\n");
  // Nothing on standard input: nothing printed, exit 0.
  r = cli({"lut", "apply", kCubeDir + "identity_17.cube"}, "");
  EXPECT_EQ(r.code, 0);
  EXPECT_EQ(r.out, "");
}

TEST_F(LutCli, ApplyNonFiniteInputs) {
  // cube::apply: NaN is the domain's min, +-Inf clamp to its ends (as OpenColorIO). contrast_17:
  // s(0) = 0, s(1) = 1. domain_3d's min is (-0.5, 0, 0.25): NaN there gives row (0, 0, 0).
  CliResult r = cli({"lut", "apply", kCubeDir + "contrast_17.cube"},
                    "nan 0.5 0.5\ninf -inf 0.5\n-nan NaN INF\n1e308 -1e308 0\n");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "0 0.5 0.5\n1 0 0.5\n0 0 1\n1 0 0\n");
  const CubeLut d = load_cube("domain_3d.cube");
  r = cli({"lut", "apply", kCubeDir + "domain_3d.cube"}, "nan nan nan\n");
  EXPECT_EQ(r.out, hdrc::format_number(d.at(0, 0, 0)[0]) + " " +
                       hdrc::format_number(d.at(0, 0, 0)[1]) + " " +
                       hdrc::format_number(d.at(0, 0, 0)[2]) + "\n");
}

struct BadLine {
  std::string name, input, out, err;
};

void PrintTo(const BadLine& b, std::ostream* os) {
  *os << b.name;
}

class LutApplyBad : public ::testing::TestWithParam<BadLine> {};

TEST_P(LutApplyBad, StopsAtTheLineAndNamesIt) {
  const BadLine& b = GetParam();
  const CliResult r = cli({"lut", "apply", kCubeDir + "identity_17.cube"}, b.input);
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.out, b.out);  // the lines before the bad one are answered
  EXPECT_EQ(r.err, b.err);
}

std::vector<BadLine> bad_lines() {
  const std::string choices = "; valid choices: three decimal numbers, nan and inf accepted\n";
  return {
      {"too_few", "0.5 0.5 0.5\n1 2\n", "0.5 0.5 0.5\n",
       "error: <stdin>: line 2: expected three numbers \"R G B\", got \"1 2\"" + choices},
      {"too_many", "1 2 3 4\n", "",
       "error: <stdin>: line 1: expected three numbers \"R G B\", got \"1 2 3 4\"" + choices},
      {"word", "# c\nred 0 0\n", "",
       "error: <stdin>: line 2: expected three numbers \"R G B\", got \"red 0 0\" ('red' is not "
       "a number)" +
           choices},
      {"comma_separated", "0.1,0.2,0.3\n", "",
       "error: <stdin>: line 1: expected three numbers \"R G B\", got \"0.1,0.2,0.3\" "
       "('0.1,0.2,0.3' is not a number)" +
           choices},
      {"decimal_comma", "0,5 0 0\n", "",
       "error: <stdin>: line 1: expected three numbers \"R G B\", got \"0,5 0 0\" ('0,5' is not "
       "a number)" +
           choices},
      {"double_sign", "++1 0 0\n", "",
       "error: <stdin>: line 1: expected three numbers \"R G B\", got \"++1 0 0\" ('++1' is not "
       "a number)" +
           choices},
      {"out_of_range", "1e999 0 0\n", "",
       "error: <stdin>: line 1: expected three numbers \"R G B\", got \"1e999 0 0\" ('1e999' is "
       "outside a double's range)" +
           choices},
      {"long_line", "0 0 0\n" + std::string(5000, '1') + "\n", "0 0 0\n",
       "error: <stdin>: line 2: longer than 4096 characters; valid choices: \"R G B\" lines\n"},
      // Standard input that never ends a line (e.g. /dev/zero): stops after 4097 characters.
      {"no_newline", std::string(size_t{20} << 20, '0'), "",
       "error: <stdin>: line 1: longer than 4096 characters; valid choices: \"R G B\" lines\n"},
      // Error::to_string makes messages valid UTF-8: the NUL is shown as U+FFFD.
      {"nul_bytes", std::string("0 0\0 0\n", 7), "",
       "error: <stdin>: line 1: expected three numbers \"R G B\", got \"0 0\xEF\xBF\xBD 0\" "
       "('0\xEF\xBF\xBD' is not a number)" +
           choices},
  };
}

INSTANTIATE_TEST_SUITE_P(Lines, LutApplyBad, ::testing::ValuesIn(bad_lines()),
                         [](const auto& info) { return info.param.name; });

// Colours over each sample's domain widened by a quarter each side (clamping), and a few
// non-finite ones.
std::string random_lines(double lo, double hi, int count, unsigned seed) {
  std::mt19937 rng(seed);
  const double w = hi - lo;
  std::uniform_real_distribution<double> u(lo - 0.25 * w, hi + 0.25 * w);
  std::string s;
  char buf[128];
  for (int i = 0; i < count; ++i) {
    std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g\n", u(rng), u(rng), u(rng));
    s += buf;
  }
  return s + "nan 0.5 0.5\ninf -inf nan\n";
}

struct Sample {
  const char* file;
  double lo, hi;
};
const Sample kSamples[] = {
    {"identity_2.cube", 0, 1},
    {"identity_17.cube", 0, 1},
    {"contrast_17.cube", 0, 1},
    {"hue_rotate_17.cube", 0, 1},
    {"gamma_1d.cube", 0, 1},
    {"domain_1d.cube", -1, 8},
    {"domain_3d.cube", -0.5, 4},
    {"resolve_shaper.cube", 0, 4},
    {"resolve_range_3d.cube", -0.25, 1.25},
};

TEST_F(LutCli, ApplyMatchesCubeEvaluation) {
  // Each printed number is cube::apply's double rounded to 9 significant digits (%.9g: within
  // half a unit of the 9th digit, 5e-9 relative).
  for (const Sample& s : kSamples)
    for (const Interp interp : {Interp::trilinear, Interp::tetrahedral}) {
      SCOPED_TRACE(std::string(s.file) + (interp == Interp::trilinear ? " tri" : " tet"));
      const CubeLut lut = load_cube(s.file);
      const std::string input = random_lines(s.lo, s.hi, 2000, 16);
      const CliResult r = cli({"lut", "apply", kCubeDir + s.file, "--interp",
                               interp == Interp::trilinear ? "trilinear" : "tetrahedral"},
                              input);
      ASSERT_EQ(r.code, 0) << r.err;
      const auto in = parse_lines(input), out = parse_lines(r.out);
      ASSERT_EQ(out.size(), in.size());
      for (size_t i = 0; i < in.size(); ++i) {
        const auto want = hdrc::cube::apply(lut, in[i], interp);
        for (int k = 0; k < 3; ++k)
          ASSERT_NEAR(out[i][k], want[k], 5.000001e-9 * std::fabs(want[k]) + 1e-300)
              << "line " << i + 1;
      }
    }
}

TEST_F(LutCli, ApplyOnConvertedImagesEqualsTheCube) {
  // An EXR holds the table exactly, and its metadata the domain: the converted image answers
  // every line as the .cube does, character for character.
  for (const char* file : kThreeD)
    for (const char* layout : {"strip", "volume"}) {
      SCOPED_TRACE(std::string(file) + " " + layout);
      const std::string out = path("l.exr");
      ASSERT_EQ(
          cli({"lut", "convert", kCubeDir + file, "--to", layout, "--format", "exr", "--out", out})
              .code,
          0);
      const CubeLut lut = load_cube(file);
      const std::string input = random_lines(lut.domain_min_3d[0], lut.domain_max_3d[2], 500, 7);
      for (const char* interp : {"trilinear", "tetrahedral"}) {
        const CliResult a = cli({"lut", "apply", kCubeDir + file, "--interp", interp}, input);
        const CliResult b = cli({"lut", "apply", out, "--interp", interp}, input);
        ASSERT_EQ(a.code, 0);
        ASSERT_EQ(b.code, 0) << b.err;
        EXPECT_EQ(a.out, b.out);
      }
    }
}

TEST_F(LutCli, ApplyAgreesWithOpenColorIO) {
  // OpenColorIO 2.1's FileTransform on the .cube (as core/cube/cube_test.cpp uses it), against
  // `lut apply` on the .cube and on its strip EXR. OCIO evaluates in float32: 2e-6 relative +
  // 1e-6 (cube_test.cpp's measured bound), plus the 9-digit printing (5e-9 relative).
  OCIO::ConfigRcPtr cfg = OCIO::Config::CreateRaw()->createEditableCopy();
  cfg->setProcessorCacheFlags(OCIO::PROCESSOR_CACHE_OFF);
  ASSERT_EQ(cli({"lut", "convert", kCubeDir + "hue_rotate_17.cube", "--to", "strip", "--format",
                 "exr", "--out", path("h.exr")})
                .code,
            0);
  std::mt19937 rng(2024);
  std::uniform_real_distribution<float> u(-0.25f, 1.25f);
  std::string input;
  std::vector<std::array<float, 3>> colours;
  char buf[128];
  for (int i = 0; i < 3000; ++i) {
    const std::array<float, 3> c{u(rng), u(rng), u(rng)};
    std::snprintf(buf, sizeof buf, "%.9g %.9g %.9g\n", c[0], c[1], c[2]);  // exact for floats
    input += buf;
    colours.push_back(c);
  }
  for (const auto& [interp, name] : {std::pair{OCIO::INTERP_LINEAR, "trilinear"},
                                     std::pair{OCIO::INTERP_TETRAHEDRAL, "tetrahedral"}}) {
    auto t = OCIO::FileTransform::Create();
    t->setSrc((kCubeDir + "hue_rotate_17.cube").c_str());
    t->setInterpolation(interp);
    t->setDirection(OCIO::TRANSFORM_DIR_FORWARD);
    auto proc = cfg->getProcessor(t)->getOptimizedCPUProcessor(OCIO::OPTIMIZATION_NONE);
    for (const std::string& file : {kCubeDir + "hue_rotate_17.cube", path("h.exr")}) {
      const CliResult r = cli({"lut", "apply", file, "--interp", name}, input);
      ASSERT_EQ(r.code, 0) << r.err;
      const auto out = parse_lines(r.out);
      ASSERT_EQ(out.size(), colours.size());
      double worst = 0;
      for (size_t i = 0; i < colours.size(); ++i) {
        float px[3] = {colours[i][0], colours[i][1], colours[i][2]};
        proc->applyRGB(px);
        for (int k = 0; k < 3; ++k) {
          const double d = std::fabs(out[i][k] - px[k]);
          worst = std::max(worst, d);
          ASSERT_LE(d, 2e-6 * std::fabs(px[k]) + 1e-6 + 5e-9 * std::fabs(px[k]))
              << file << " " << name << " line " << i + 1 << " channel " << k;
        }
      }
      std::printf("hue_rotate_17 %-11s %s vs OCIO: max abs %.3g over %zu colours\n", name,
                  fs::path(file).extension().c_str(), worst, colours.size());
    }
  }
}

// ---------------------------------------------------------------------------------------------
// The strip as engines sample it, and interpolation error against the generating formulas.

// UE's UnwrappedTexture3DSample / Unity's ApplyLut2D on the strip (docs/spec/unity_urp.md §5.3):
// slice s = floor(b (N-1)), a bilinear tap in slice s and one in slice s+1 (clamped to the
// strip), blended by the fraction. Hardware bilinear on texel centres: (r (N-1), g (N-1)) within
// the slice, clamp-to-edge. Written from the pixel layout alone, on the image OpenImageIO reads.
std::array<double, 3> engine_strip_sample(const Raw& img, int n, std::array<double, 3> c) {
  for (double& v : c) v = std::clamp(v, 0.0, 1.0);
  auto texel = [&](int x, int y, int k) {
    x = std::clamp(x, 0, img.width - 1);
    y = std::clamp(y, 0, img.height - 1);
    return static_cast<double>(img.f[(static_cast<size_t>(y) * img.width + x) * 3 + k]);
  };
  auto bilinear = [&](double x, double y, int k) {  // x, y in texels, at texel centres
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const double fx = x - x0, fy = y - y0;
    return (1 - fy) * ((1 - fx) * texel(x0, y0, k) + fx * texel(x0 + 1, y0, k)) +
           fy * ((1 - fx) * texel(x0, y0 + 1, k) + fx * texel(x0 + 1, y0 + 1, k));
  };
  const double z = c[2] * (n - 1);
  const int s = static_cast<int>(std::floor(z));
  const double phi = z - s;
  std::array<double, 3> out{};
  for (int k = 0; k < 3; ++k) {
    const double x = c[0] * (n - 1) + s * n, y = c[1] * (n - 1);
    // The second tap is one slice (n texels) to the right; at b = 1 it is off the strip (clamped
    // to the last column) but weighted 0.
    const double a = bilinear(x, y, k);
    const double b = s + 1 < n ? bilinear(x + n, y, k) : a;
    out[k] = (1 - phi) * a + phi * b;
  }
  return out;
}

TEST_F(LutCli, StripSampledAsEnginesDoIsTrilinear) {
  for (const char* file : {"contrast_17.cube", "hue_rotate_17.cube", "identity_17.cube"}) {
    const CubeLut lut = load_cube(file);
    ASSERT_EQ(cli({"lut", "convert", kCubeDir + file, "--to", "strip", "--format", "exr", "--out",
                   path("s.exr")})
                  .code,
              0);
    const Raw img = read_raw(path("s.exr"));
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-0.1, 1.1);
    double worst = 0;
    for (int i = 0; i < 20000; ++i) {
      const std::array<double, 3> c{u(rng), u(rng), u(rng)};
      const auto e = engine_strip_sample(img, lut.size_3d, c);
      const auto t = hdrc::cube::apply(lut, c, Interp::trilinear);
      for (int k = 0; k < 3; ++k) worst = std::max(worst, std::fabs(e[k] - t[k]));
    }
    // The same weights reached another way: double rounding only, of texel coordinates up to
    // N^2 = 289 (half an ulp there is 2.8e-14) times values that change by at most 1 a texel.
    EXPECT_LE(worst, 3e-14) << file;
  }
}

// scripts/gen_cube_samples.py's formulas, in double.
double smoothstep(double x) {
  return x * x * (3.0 - 2.0 * x);
}
std::array<double, 3> hue_rotate(const std::array<double, 3>& v) {
  // Rodrigues' rotation by 30 degrees about the grey axis k = (1, 1, 1)/sqrt 3, clamped.
  const double t = 30.0 * std::numbers::pi / 180.0, k = 1.0 / std::sqrt(3.0);
  const double c = std::cos(t), s = std::sin(t), dot = k * (v[0] + v[1] + v[2]);
  const std::array<double, 3> cross{k * (v[2] - v[1]), k * (v[0] - v[2]), k * (v[1] - v[0])};
  std::array<double, 3> out{};
  for (int i = 0; i < 3; ++i)
    out[i] = std::clamp(v[i] * c + cross[i] * s + k * dot * (1.0 - c), 0.0, 1.0);
  return out;
}

struct ErrorFigures {
  double max = 0, sum2 = 0;
  int count = 0;
  double rms() const { return std::sqrt(sum2 / std::max(count, 1)); }
};

ErrorFigures measure(const CubeLut& lut, Interp interp,
                     const std::function<std::array<double, 3>(const std::array<double, 3>&)>& f) {
  std::mt19937 rng(33);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  ErrorFigures e;
  for (int i = 0; i < 200000; ++i) {
    const std::array<double, 3> c{u(rng), u(rng), u(rng)};
    const auto got = hdrc::cube::apply(lut, c, interp);
    const auto want = f(c);
    for (int k = 0; k < 3; ++k) {
      const double d = std::fabs(got[k] - want[k]);
      e.max = std::max(e.max, d);
      e.sum2 += d * d;
      ++e.count;
    }
  }
  return e;
}

CubeLut contrast_lut(int n) {
  CubeLut lut;
  lut.size_3d = n;
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r)
        lut.table_3d.push_back({static_cast<float>(smoothstep(r / (n - 1.0))),
                                static_cast<float>(smoothstep(g / (n - 1.0))),
                                static_cast<float>(smoothstep(b / (n - 1.0)))});
  return lut;
}

TEST(LutInterpolation, ErrorAgainstTheGeneratingFormulas) {
  // contrast: out_c = s(in_c) per channel. Linear interpolation of s on spacing h errs by at most
  // h^2/8 max|s''| = h^2/8 x 6 (s'' = 6 - 12 x), 0.0029296875 at N = 17; a per-channel function
  // is interpolated identically by the trilinear and the tetrahedral scheme (every tetrahedron's
  // weights sum, per axis, to the 1-D linear weights). The largest error is in the first and last
  // cells, near their middle: L(h/2) - s(h/2) = (3h - 2h^2) h/2 - 3h^2/4 + h^3/4 = 0.75 h^2 (1 -
  // h), 0.94 of the bound at N = 17 (the exact maximum, at x = 0.0309, is 1e-4 relatively higher).
  const auto contrast = [](const std::array<double, 3>& c) {
    return std::array<double, 3>{smoothstep(c[0]), smoothstep(c[1]), smoothstep(c[2])};
  };
  std::printf("%-22s %-11s %12s %12s\n", "LUT", "interp", "max |err|", "rms");
  for (const int n : {17, 33, 65}) {
    const CubeLut lut = n == 17 ? load_cube("contrast_17.cube") : contrast_lut(n);
    const double h = 1.0 / (n - 1), bound = h * h / 8 * 6;
    const ErrorFigures tri = measure(lut, Interp::trilinear, contrast);
    const ErrorFigures tet = measure(lut, Interp::tetrahedral, contrast);
    std::printf("contrast N=%-11d %-11s %12.3g %12.3g\ncontrast N=%-11d %-11s %12.3g %12.3g\n", n,
                "trilinear", tri.max, tri.rms(), n, "tetrahedral", tet.max, tet.rms());
    EXPECT_LE(tri.max, bound + 1e-7) << n;
    EXPECT_GE(tri.max, 0.99 * 0.75 * h * h * (1 - h)) << n;
    EXPECT_NEAR(tet.max, tri.max, 1e-12) << n;
    EXPECT_NEAR(tet.rms(), tri.rms(), 1e-12) << n;
  }
  // UE's user LUT has 16 points (a 256 x 16 strip); Resolve writes 17, 33 or 65. contrast_17
  // resampled to 16 points (docs/cube-workflow.md's recipe: `lut apply --interp tetrahedral` at
  // the 16-point lattice) errs by at most the 17-point error at the new nodes plus the 16-point
  // interpolation error: 0.75/16^2 + 0.75/15^2 = 6.26e-3.
  {
    const CubeLut c17 = load_cube("contrast_17.cube");
    CubeLut c16;
    c16.size_3d = 16;
    for (int b = 0; b < 16; ++b)
      for (int g = 0; g < 16; ++g)
        for (int r = 0; r < 16; ++r) {
          const auto v =
              hdrc::cube::apply(c17, {r / 15.0, g / 15.0, b / 15.0}, Interp::tetrahedral);
          c16.table_3d.push_back(
              {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])});
        }
    const ErrorFigures e = measure(c16, Interp::trilinear, contrast);
    const ErrorFigures direct = measure(contrast_lut(16), Interp::trilinear, contrast);
    std::printf("%-22s %-11s %12.3g %12.3g\n%-22s %-11s %12.3g %12.3g\n", "contrast 17->16",
                "trilinear", e.max, e.rms(), "contrast N=16", "trilinear", direct.max,
                direct.rms());
    EXPECT_LE(e.max, 0.75 / 256 + 0.75 / 225);
    EXPECT_LE(direct.max, 0.75 / 225 + 1e-7);
  }
  // hue_rotate: linear where nothing clamps, so both schemes reproduce it up to the float32
  // table (6e-8); all the error is in cells the [0, 1] clamp cuts through, where the two
  // schemes differ.
  const CubeLut hue = load_cube("hue_rotate_17.cube");
  const ErrorFigures tri = measure(hue, Interp::trilinear, hue_rotate);
  const ErrorFigures tet = measure(hue, Interp::tetrahedral, hue_rotate);
  std::printf("%-22s %-11s %12.3g %12.3g\n%-22s %-11s %12.3g %12.3g\n", "hue_rotate N=17",
              "trilinear", tri.max, tri.rms(), "hue_rotate N=17", "tetrahedral", tet.max,
              tet.rms());
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double inside = 0;
  int checked = 0;
  for (int i = 0; i < 100000; ++i) {
    const std::array<double, 3> c{u(rng), u(rng), u(rng)};
    // The cell's 8 corners unclamped: the rotation of each stays within [0, 1] before clamping.
    bool clean = true;
    for (int corner = 0; corner < 8 && clean; ++corner) {
      std::array<double, 3> p{};
      for (int k = 0; k < 3; ++k) p[k] = (std::floor(c[k] * 16) + ((corner >> k) & 1)) / 16;
      const double t = 30.0 * std::numbers::pi / 180.0, kk = 1.0 / std::sqrt(3.0);
      const double cs = std::cos(t), sn = std::sin(t), dot = kk * (p[0] + p[1] + p[2]);
      const std::array<double, 3> cross{kk * (p[2] - p[1]), kk * (p[0] - p[2]), kk * (p[1] - p[0])};
      for (int k = 0; k < 3; ++k) {
        const double v = p[k] * cs + cross[k] * sn + kk * dot * (1.0 - cs);
        clean = clean && v >= 0 && v <= 1;
      }
    }
    if (!clean) continue;
    ++checked;
    for (const Interp interp : {Interp::trilinear, Interp::tetrahedral}) {
      const auto got = hdrc::cube::apply(hue, c, interp);
      const auto want = hue_rotate(c);
      for (int k = 0; k < 3; ++k) inside = std::max(inside, std::fabs(got[k] - want[k]));
    }
  }
  std::printf("hue_rotate N=17 in unclamped cells (%d colours): max |err| %.3g\n", checked, inside);
  EXPECT_GT(checked, 10000);
  EXPECT_LE(inside, 1.2e-7);  // float32 table values (6e-8 each) and 9-digit decimals
  EXPECT_GT(tri.max, 1e-3);   // the clamp's kink is not linear
  EXPECT_NE(tri.max, tet.max);
}

// ---------------------------------------------------------------------------------------------
// hdrconform itself: main registers the command, exit codes and streams as documented.

struct Shell {
  int code = -1;
  std::string out, err;
};

Shell run_binary(const fs::path& dir, const std::string& args, const std::string& input) {
  std::ofstream(dir / "stdin.txt") << input;
  const std::string cmd = "cd '" + dir.string() + "' && '" + HDRC_BINARY + "' " + args +
                          " < stdin.txt > stdout.txt 2> stderr.txt";
  const int status = std::system(cmd.c_str());
  Shell s;
  s.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream o(dir / "stdout.txt"), e(dir / "stderr.txt");
  s.out.assign(std::istreambuf_iterator<char>(o), {});
  s.err.assign(std::istreambuf_iterator<char>(e), {});
  fs::remove(dir / "stdin.txt");
  fs::remove(dir / "stdout.txt");
  fs::remove(dir / "stderr.txt");
  return s;
}

TEST_F(LutCli, TheBinary) {
  Shell s = run_binary(dir_, "lut apply " + kCubeDir + "contrast_17.cube", "0.25 0.5 0.75\n");
  EXPECT_EQ(s.code, 0) << s.err;
  EXPECT_EQ(s.out, "0.15625 0.5 0.84375\n");
  s = run_binary(dir_, "lut apply " + kCubeDir + "contrast_17.cube", "0.25 0.5\n");
  EXPECT_EQ(s.code, 2);
  EXPECT_EQ(s.err,
            "error: <stdin>: line 1: expected three numbers \"R G B\", got \"0.25 0.5\"; valid "
            "choices: three decimal numbers, nan and inf accepted\n");
  s = run_binary(
      dir_,
      "lut convert " + kCubeDir + "identity_17.cube --to volume --format exr " + "--out v.exr", "");
  EXPECT_EQ(s.code, 0) << s.err;
  EXPECT_EQ(s.out.rfind("wrote v.exr: volume 17 x 289", 0), 0u) << s.out;
  s = run_binary(dir_, "lut info v.exr", "");
  EXPECT_EQ(s.code, 0) << s.err;
  EXPECT_NE(s.out.find("\nidentity: yes\n"), std::string::npos) << s.out;
  s = run_binary(dir_, "lut convert missing.cube --to strip --format exr --out o.exr", "");
  EXPECT_EQ(s.code, 2);
  EXPECT_EQ(s.err, "error: missing.cube: cannot open .cube file: No such file or directory\n");
  s = run_binary(dir_, "lut convert x.cube --to cube --format exr --out o.exr", "");
  EXPECT_EQ(s.code, 2);
  EXPECT_NE(s.err.find("--to: cube not in {strip,volume}"), std::string::npos) << s.err;
  s = run_binary(dir_, "lut", "");
  EXPECT_EQ(s.code, 2);
  s = run_binary(dir_, "lut --help", "");
  EXPECT_EQ(s.code, 0);
  EXPECT_NE(s.out.find("convert"), std::string::npos);
  EXPECT_EQ(files(), std::set<std::string>{"v.exr"});
}

}  // namespace
