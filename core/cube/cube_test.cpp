// .cube LUTs: the parser's errors pinned, parse(write(x)) == x bit for bit, and apply() against
// OpenColorIO 2.1 (a test-only oracle: its Iridas and Resolve .cube readers and its CPU Lut1D/Lut3D
// evaluation) on the sample files under cases/lut/cube/, which scripts/gen_cube_samples.py writes
// from the formulas it documents.
#include "core/cube/cube.h"

#include <OpenColorIO/OpenColorIO.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>

#include "core/cube/ocio_oracle.h"

#ifndef HDRC_SOURCE_DIR
#error "HDRC_SOURCE_DIR must be defined"
#endif

namespace OCIO = OCIO_NAMESPACE;
namespace fs = std::filesystem;
using hdrc::cube::apply;
using hdrc::cube::CubeLut;
using hdrc::cube::Interp;
using hdrc::cube::parse_cube;
using hdrc::cube::Rgb;
using hdrc::cube::write_cube;

namespace {

const std::string kCubeDir = std::string(HDRC_SOURCE_DIR) + "/cases/lut/cube/";

CubeLut load(const std::string& name) {
  auto lut = hdrc::cube::read_cube_file(kCubeDir + name);
  EXPECT_TRUE(lut.ok()) << lut.error().to_string();
  return lut.ok() ? *lut : CubeLut{};
}

// ---------------------------------------------------------------------------------------------
// Errors: each names the file, the line, what was found and what is valid.

struct BadCase {
  std::string name;
  std::string text;
  std::string expected;  // Error::to_string()
};

void PrintTo(const BadCase& bc, std::ostream* os) {
  *os << bc.name;
}

std::vector<BadCase> bad_cases() {
  const std::string rows8 = "0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n";
  return {
      {"empty_file", "",
       "t.cube: line 1: empty .cube file: no keywords and no rows; valid "
       "choices: LUT_1D_SIZE N and/or LUT_3D_SIZE N, then the rows"},
      {"only_comments", "# a comment\n\n   \n# another\n",
       "t.cube: line 4: empty .cube file: no keywords and no rows; valid choices: LUT_1D_SIZE N "
       "and/or LUT_3D_SIZE N, then the rows"},
      {"rows_without_size", "TITLE \"x\"\n0 0 0\n",
       "t.cube: line 2: no LUT_1D_SIZE or LUT_3D_SIZE before the table data; valid choices: "
       "LUT_1D_SIZE N and/or LUT_3D_SIZE N before the rows"},
      {"keywords_without_size", "TITLE \"x\"\nDOMAIN_MIN 0 0 0\n",
       "t.cube: line 2: no LUT_1D_SIZE or LUT_3D_SIZE before the table data; valid choices: "
       "LUT_1D_SIZE N and/or LUT_3D_SIZE N before the rows"},
      {"size_1d_too_small", "LUT_1D_SIZE 1\n0 0 0\n",
       "t.cube: line 1: LUT_1D_SIZE 1 is out of range; valid choices: 2 to 65536"},
      {"size_1d_too_large", "LUT_1D_SIZE 65537\n",
       "t.cube: line 1: LUT_1D_SIZE 65537 is out of range; valid choices: 2 to 65536"},
      {"size_3d_too_large", "LUT_3D_SIZE 257\n",
       "t.cube: line 1: LUT_3D_SIZE 257 is out of range; valid choices: 2 to 256"},
      {"size_3d_negative", "LUT_3D_SIZE -2\n",
       "t.cube: line 1: LUT_3D_SIZE -2 is out of range; valid choices: 2 to 256"},
      {"size_overflows", "LUT_1D_SIZE 99999999999999999999\n",
       "t.cube: line 1: LUT_1D_SIZE 99999999999999999999 is out of range; valid choices: 2 to "
       "65536"},
      {"size_not_integer", "LUT_3D_SIZE 2.5\n",
       "t.cube: line 1: LUT_3D_SIZE: '2.5' is not an integer; valid choices: integers 2 to 256"},
      {"size_two_values", "LUT_3D_SIZE 2 2\n",
       "t.cube: line 1: LUT_3D_SIZE takes 1 value, found 2; valid choices: LUT_3D_SIZE N, N an "
       "integer 2 to 256"},
      {"size_no_value", "LUT_3D_SIZE # none\n",
       "t.cube: line 1: LUT_3D_SIZE takes 1 value, found 0; valid choices: LUT_3D_SIZE N, N an "
       "integer 2 to 256"},
      {"duplicate_size", "LUT_3D_SIZE 2\n\nLUT_3D_SIZE 3\n",
       "t.cube: line 3: duplicate LUT_3D_SIZE (first on line 1); valid choices: each keyword at "
       "most once"},
      {"duplicate_title", "TITLE \"a\"\nTITLE \"b\"\n",
       "t.cube: line 2: duplicate TITLE (first on line 1); valid choices: each keyword at most "
       "once"},
      {"unknown_keyword", "LUT_3D_SIZ 2\n",
       "t.cube: line 1: unknown keyword 'LUT_3D_SIZ'; valid choices: TITLE, LUT_1D_SIZE, "
       "LUT_3D_SIZE, DOMAIN_MIN, DOMAIN_MAX, LUT_1D_INPUT_RANGE, LUT_3D_INPUT_RANGE"},
      {"lower_case_keyword", "lut_3d_size 2\n",
       "t.cube: line 1: unknown keyword 'lut_3d_size' (keywords are upper case: LUT_3D_SIZE); "
       "valid choices: TITLE, LUT_1D_SIZE, LUT_3D_SIZE, DOMAIN_MIN, DOMAIN_MAX, "
       "LUT_1D_INPUT_RANGE, LUT_3D_INPUT_RANGE"},
      {"crlf_line_numbers", "LUT_3D_SIZE 2\r\n\r\nLUT_2D_SIZE 2\r\n",
       "t.cube: line 3: unknown keyword 'LUT_2D_SIZE'; valid choices: TITLE, LUT_1D_SIZE, "
       "LUT_3D_SIZE, DOMAIN_MIN, DOMAIN_MAX, LUT_1D_INPUT_RANGE, LUT_3D_INPUT_RANGE"},
      {"keyword_after_data", "LUT_1D_SIZE 2\n0 0 0\nTITLE \"late\"\n1 1 1\n",
       "t.cube: line 3: keyword TITLE after the table data (rows began on line 2); valid "
       "choices: keywords before the first row"},
      {"word_among_rows", "LUT_1D_SIZE 2\n0 0 0\nabc 1 1\n",
       "t.cube: line 3: row 'abc 1 1' is not three numbers; valid choices: rows of three "
       "numbers: red green blue"},
      {"row_two_values", "LUT_1D_SIZE 2\n0 0 0\n1 1\n",
       "t.cube: line 3: 1-D table row 2 has 2 values: '1 1'; valid choices: three numbers: red "
       "green blue"},
      {"row_four_values", "LUT_3D_SIZE 2\n0 0 0 0\n",
       "t.cube: line 2: 3-D table row 1 has 4 values: '0 0 0 0'; valid choices: three numbers: "
       "red green blue"},
      {"non_numeric", "LUT_1D_SIZE 2\n0 0x 0\n1 1 1\n",
       "t.cube: line 2: 1-D table row 1: '0x' is not a number; valid choices: finite decimal "
       "numbers such as 0.5, -2, 1.5e-3"},
      {"comma_decimal", "LUT_1D_SIZE 2\n0,5 0 0\n1 1 1\n",
       "t.cube: line 2: 1-D table row 1: '0,5' is not a number; valid choices: finite decimal "
       "numbers such as 0.5, -2, 1.5e-3"},
      {"hex_float", "LUT_1D_SIZE 2\n0x1p-2 0 0\n1 1 1\n",
       "t.cube: line 2: 1-D table row 1: '0x1p-2' is not a number; valid choices: finite "
       "decimal numbers such as 0.5, -2, 1.5e-3"},
      {"double_plus", "LUT_1D_SIZE 2\n++1 0 0\n1 1 1\n",
       "t.cube: line 2: 1-D table row 1: '++1' is not a number; valid choices: finite decimal "
       "numbers such as 0.5, -2, 1.5e-3"},
      {"nan_value", "LUT_1D_SIZE 2\nnan 0 0\n1 1 1\n",
       "t.cube: line 2: 1-D table row 1: 'nan' is not finite (NaN and infinities are refused); "
       "valid choices: finite decimal numbers such as 0.5, -2, 1.5e-3"},
      {"inf_value", "LUT_1D_SIZE 2\n0 0 0\n1 inf 1\n",
       "t.cube: line 3: 1-D table row 2: 'inf' is not finite (NaN and infinities are refused); "
       "valid choices: finite decimal numbers such as 0.5, -2, 1.5e-3"},
      {"minus_infinity", "LUT_3D_SIZE 2\n0 0 -Infinity\n",
       "t.cube: line 2: 3-D table row 1: '-Infinity' is not finite (NaN and infinities are "
       "refused); valid choices: finite decimal numbers such as 0.5, -2, 1.5e-3"},
      {"overflow_double", "LUT_3D_SIZE 2\n1e999 0 0\n",
       "t.cube: line 2: 3-D table row 1: '1e999' is outside the float32 range; valid choices: "
       "finite numbers of magnitude at most 3.40282347e+38"},
      {"overflow_float", "LUT_3D_SIZE 2\n0 -1e39 0\n",
       "t.cube: line 2: 3-D table row 1: '-1e39' is outside the float32 range; valid choices: "
       "finite numbers of magnitude at most 3.40282347e+38"},
      {"truncated_3d", "LUT_3D_SIZE 2\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n",
       "t.cube: line 6: truncated: 8 rows expected (LUT_3D_SIZE 2^3), 5 found; valid choices: 8 "
       "rows"},
      {"truncated_shaper", "LUT_1D_SIZE 2\nLUT_3D_SIZE 2\n0 0 0\n1 1 1\n" + rows8.substr(0, 42),
       "t.cube: line 11: truncated: 10 rows expected (LUT_1D_SIZE 2 + LUT_3D_SIZE 2^3), 9 found; "
       "valid choices: 10 rows"},
      {"keywords_only", "LUT_3D_SIZE 2\n",
       "t.cube: line 1: truncated: 8 rows expected (LUT_3D_SIZE 2^3), 0 found; valid choices: 8 "
       "rows"},
      {"too_many_rows", "LUT_3D_SIZE 2\n" + rows8 + "1 1 1\n",
       "t.cube: line 10: more rows than declared: 8 expected (LUT_3D_SIZE 2^3); valid choices: 8 "
       "rows"},
      {"domain_min_not_below_max", "LUT_3D_SIZE 2\nDOMAIN_MIN 0 1 0\nDOMAIN_MAX 1 1 1\n" + rows8,
       "t.cube: line 3: DOMAIN_MIN 1 is not below DOMAIN_MAX 1 in the green channel; valid "
       "choices: DOMAIN_MIN < DOMAIN_MAX in every channel"},
      {"domain_min_above_default_max", "LUT_1D_SIZE 2\nDOMAIN_MIN 0 0 2\n0 0 0\n1 1 1\n",
       "t.cube: line 2: DOMAIN_MIN 2 is not below DOMAIN_MAX 1 in the blue channel; valid "
       "choices: DOMAIN_MIN < DOMAIN_MAX in every channel"},
      {"domain_two_values", "LUT_3D_SIZE 2\nDOMAIN_MAX 1 1\n",
       "t.cube: line 2: DOMAIN_MAX takes 3 values, found 2; valid choices: DOMAIN_MAX r g b"},
      {"domain_nan", "LUT_3D_SIZE 2\nDOMAIN_MIN 0 NaN 0\n",
       "t.cube: line 2: DOMAIN_MIN: 'NaN' is not finite (NaN and infinities are refused); valid "
       "choices: finite decimal numbers such as 0.5, -2, 1.5e-3"},
      {"input_range_min_above_max", "LUT_3D_SIZE 2\nLUT_3D_INPUT_RANGE 1 0\n",
       "t.cube: line 2: LUT_3D_INPUT_RANGE min 1 is not below max 0; valid choices: min < max"},
      {"input_range_empty", "LUT_1D_SIZE 2\nLUT_1D_INPUT_RANGE 0.5 0.5\n",
       "t.cube: line 2: LUT_1D_INPUT_RANGE min 0.5 is not below max 0.5; valid choices: min < "
       "max"},
      {"input_range_three_values", "LUT_1D_SIZE 2\nLUT_1D_INPUT_RANGE 0 1 2\n",
       "t.cube: line 2: LUT_1D_INPUT_RANGE takes 2 values, found 3; valid choices: "
       "LUT_1D_INPUT_RANGE min max"},
      {"input_range_without_its_table", "LUT_3D_SIZE 2\nLUT_1D_INPUT_RANGE 0 2\n" + rows8,
       "t.cube: line 2: LUT_1D_INPUT_RANGE without LUT_1D_SIZE; valid choices: an INPUT_RANGE "
       "for a table the file declares"},
      {"domain_and_input_range", "LUT_3D_SIZE 2\nLUT_3D_INPUT_RANGE 0 2\nDOMAIN_MAX 2 2 2\n",
       "t.cube: line 3: DOMAIN_MAX and LUT_3D_INPUT_RANGE (line 2) both set the input domain; "
       "valid choices: DOMAIN_MIN/DOMAIN_MAX (Iridas) or LUT_1D_INPUT_RANGE/LUT_3D_INPUT_RANGE "
       "(Resolve), not both"},
      {"domain_with_both_tables", "LUT_1D_SIZE 2\nLUT_3D_SIZE 2\nDOMAIN_MAX 2 2 2\n0 0 0\n",
       "t.cube: line 3: DOMAIN_MIN/DOMAIN_MAX in a file with both a 1-D and a 3-D table; valid "
       "choices: LUT_1D_INPUT_RANGE and LUT_3D_INPUT_RANGE (Resolve) for a 1-D shaper + 3-D "
       "file"},
      {"unterminated_title", "TITLE \"no end\nLUT_3D_SIZE 2\n",
       "t.cube: line 1: TITLE's quote is not closed: '\"no end'; valid choices: TITLE \"text\""},
      {"title_without_quotes", "TITLE plain\n",
       "t.cube: line 1: TITLE expects its text in double quotes, found 'plain'; valid choices: "
       "TITLE \"text\""},
      {"text_after_title", "TITLE \"a\" b\n",
       "t.cube: line 1: text after TITLE's closing quote: 'b'; valid choices: TITLE \"text\", "
       "then nothing or a # comment"},
      {"line_too_long", "LUT_1D_SIZE 2\n0 0 " + std::string(4093, '0') + "\n1 1 1\n",
       "t.cube: line 2: line is 4097 bytes long; valid choices: lines of at most 4096 bytes"},
  };
}

class CubeErrors : public ::testing::TestWithParam<BadCase> {};

TEST_P(CubeErrors, PinnedMessage) {
  const BadCase& bc = GetParam();
  auto lut = parse_cube("t.cube", bc.text);
  ASSERT_FALSE(lut.ok());
  EXPECT_EQ(lut.error().file, "t.cube");
  EXPECT_EQ(lut.error().pointer.rfind("line ", 0), 0u) << lut.error().pointer;
  EXPECT_EQ(lut.error().to_string(), bc.expected);
}

INSTANTIATE_TEST_SUITE_P(Table, CubeErrors, ::testing::ValuesIn(bad_cases()),
                         [](const auto& info) { return info.param.name; });

TEST(CubeParse, LineOfExactlyTheBoundIsAccepted) {
  // 4096 bytes of row + "\r": the CR is not counted.
  const std::string row = "0 0 " + std::string(4091, '0') + "1";
  ASSERT_EQ(row.size(), hdrc::cube::kMaxCubeLineBytes);
  auto lut = parse_cube("t.cube", "LUT_1D_SIZE 2\n" + row + "\r\n1 1 1");
  ASSERT_TRUE(lut.ok()) << lut.error().to_string();
  EXPECT_EQ(lut->table_1d[0][2], 1.f);
}

TEST(CubeParse, TextOverTheSizeBound) {
  const std::string text(hdrc::cube::kMaxCubeFileBytes + 1, '\n');
  auto lut = parse_cube("big.cube", text);
  ASSERT_FALSE(lut.ok());
  EXPECT_EQ(lut.error().to_string(),
            "big.cube: .cube text is 67108865 bytes, over the limit; valid choices: at most "
            "67108864 bytes");
}

class TempDir {
 public:
  TempDir() : path_(fs::temp_directory_path() / ("cube_test_" + std::to_string(::getpid()))) {
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

TEST(CubeRead, FileErrorsNameTheFile) {
  TempDir dir;
  auto missing = hdrc::cube::read_cube_file(dir / "missing.cube");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().to_string(),
            dir / "missing.cube" + ": cannot open .cube file: No such file or directory");

  auto folder = hdrc::cube::read_cube_file(dir / "");
  ASSERT_FALSE(folder.ok());
  EXPECT_NE(folder.error().message.find("not a regular file"), std::string::npos);

  ASSERT_EQ(::mkfifo((dir / "fifo.cube").c_str(), 0600), 0);
  auto fifo = hdrc::cube::read_cube_file(dir / "fifo.cube");  // must not block
  ASSERT_FALSE(fifo.ok());
  EXPECT_EQ(fifo.error().to_string(), dir / "fifo.cube" +
                                          ": .cube file is not a regular file; valid choices: a "
                                          "regular file");

  // A sparse file one byte over the bound: refused from its size, before reading.
  { std::ofstream(dir / "big.cube") << "LUT_3D_SIZE 2\n"; }
  fs::resize_file(dir / "big.cube", hdrc::cube::kMaxCubeFileBytes + 1);
  auto big = hdrc::cube::read_cube_file(dir / "big.cube");
  ASSERT_FALSE(big.ok());
  EXPECT_EQ(big.error().to_string(), dir / "big.cube" +
                                         ": .cube file is 67108865 bytes, over the limit; valid "
                                         "choices: at most 67108864 bytes");

  // Parse errors name the path.
  { std::ofstream(dir / "bad.cube") << "LUT_3D_SIZE 2\n0 0 0\n"; }
  auto bad = hdrc::cube::read_cube_file(dir / "bad.cube");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().file, dir / "bad.cube");
  EXPECT_EQ(bad.error().pointer, "line 2");
}

// ---------------------------------------------------------------------------------------------
// Syntax accepted.

TEST(CubeParse, SyntaxVariants) {
  const std::string text =
      "# leading comment\r\n"
      "  TITLE \"a # is text inside quotes\"   # trailing comment\r\n"
      "\tLUT_1D_SIZE\t3  # three rows\r\n"
      "\r\n"
      "DOMAIN_MIN -1 0 +0.5\r\n"
      "DOMAIN_MAX 1e1 2.5E+0 .75\r\n"
      "# comment between rows\r\n"
      " 0 0 0 \r\n"
      "5. -1.25e-3 +3\t# row comment\r\n"
      "1e-40 -0 3.4028234663852886e38";  // no final newline
  auto lut = parse_cube("t.cube", text);
  ASSERT_TRUE(lut.ok()) << lut.error().to_string();
  EXPECT_EQ(lut->title, "a # is text inside quotes");
  EXPECT_EQ(lut->size_1d, 3);
  EXPECT_EQ(lut->size_3d, 0);
  EXPECT_EQ(lut->domain_min_1d, (Rgb{-1.f, 0.f, 0.5f}));
  EXPECT_EQ(lut->domain_max_1d, (Rgb{10.f, 2.5f, 0.75f}));
  ASSERT_EQ(lut->table_1d.size(), 3u);
  EXPECT_EQ(lut->table_1d[1], (Rgb{5.f, -1.25e-3f, 3.f}));
  EXPECT_EQ(lut->table_1d[2][0], 1e-40f);  // a float32 subnormal
  EXPECT_TRUE(std::signbit(lut->table_1d[2][1]));
  EXPECT_EQ(lut->table_1d[2][2], std::numeric_limits<float>::max());
  // Unused 3-D domain stays at its default.
  EXPECT_EQ(lut->domain_min_3d, (Rgb{0.f, 0.f, 0.f}));
}

TEST(CubeParse, ShaperAndThreeDRowsInFileOrder) {
  auto lut = parse_cube("t.cube",
                        "LUT_3D_SIZE 2\nLUT_1D_SIZE 2\nLUT_3D_INPUT_RANGE -1 2\n"
                        "LUT_1D_INPUT_RANGE 0 4\n"
                        "10 10 10\n11 11 11\n"
                        "0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n");
  ASSERT_TRUE(lut.ok()) << lut.error().to_string();
  EXPECT_EQ(lut->table_1d, (std::vector<Rgb>{{10, 10, 10}, {11, 11, 11}}));
  EXPECT_EQ(lut->at(1, 0, 0), (Rgb{1, 0, 0}));
  EXPECT_EQ(lut->at(0, 1, 1), (Rgb{0, 1, 1}));
  EXPECT_EQ(lut->domain_min_1d, (Rgb{0, 0, 0}));
  EXPECT_EQ(lut->domain_max_1d, (Rgb{4, 4, 4}));
  EXPECT_EQ(lut->domain_min_3d, (Rgb{-1, -1, -1}));
  EXPECT_EQ(lut->domain_max_3d, (Rgb{2, 2, 2}));
}

// ---------------------------------------------------------------------------------------------
// Round trip: parse(write(x)) == x, bit for bit.

bool same_bits(const CubeLut& a, const CubeLut& b) {
  auto bits = [](const std::vector<Rgb>& t) {
    std::vector<uint32_t> out;
    for (const Rgb& v : t)
      for (float x : v) out.push_back(std::bit_cast<uint32_t>(x));
    return out;
  };
  auto rgb_bits = [](const Rgb& v) {
    return std::array<uint32_t, 3>{std::bit_cast<uint32_t>(v[0]), std::bit_cast<uint32_t>(v[1]),
                                   std::bit_cast<uint32_t>(v[2])};
  };
  return a.title == b.title && a.size_1d == b.size_1d && a.size_3d == b.size_3d &&
         rgb_bits(a.domain_min_1d) == rgb_bits(b.domain_min_1d) &&
         rgb_bits(a.domain_max_1d) == rgb_bits(b.domain_max_1d) &&
         rgb_bits(a.domain_min_3d) == rgb_bits(b.domain_min_3d) &&
         rgb_bits(a.domain_max_3d) == rgb_bits(b.domain_max_3d) &&
         bits(a.table_1d) == bits(b.table_1d) && bits(a.table_3d) == bits(b.table_3d);
}

// Any finite float32: uniform over bit patterns (subnormals, -0, huge and tiny magnitudes).
float random_float(std::mt19937& rng) {
  for (;;) {
    const float f = std::bit_cast<float>(static_cast<uint32_t>(rng()));
    if (std::isfinite(f)) return f;
  }
}

TEST(CubeRoundTrip, RandomTablesBitForBit) {
  std::mt19937 rng(16);
  for (int trial = 0; trial < 40; ++trial) {
    CubeLut lut;
    const int kind = trial % 4;  // 1-D, 3-D, shaper + 3-D, 3-D with title and domain
    if (kind == 0 || kind == 2) lut.size_1d = 2 + static_cast<int>(rng() % 300);
    if (kind != 0) lut.size_3d = 2 + static_cast<int>(rng() % 9);
    if (kind == 3) lut.title = "trial " + std::to_string(trial) + " # with a hash";
    for (int i = 0; i < lut.size_1d; ++i)
      lut.table_1d.push_back({random_float(rng), random_float(rng), random_float(rng)});
    for (int i = 0; i < lut.size_3d * lut.size_3d * lut.size_3d; ++i)
      lut.table_3d.push_back({random_float(rng), random_float(rng), random_float(rng)});
    std::uniform_real_distribution<float> u(-4.f, 0.f);
    if (kind == 2) {  // Resolve ranges: one min/max per table
      const float lo1 = u(rng), lo3 = u(rng);
      lut.domain_min_1d = {lo1, lo1, lo1};
      lut.domain_max_1d = {lo1 + 5.3f, lo1 + 5.3f, lo1 + 5.3f};
      lut.domain_min_3d = {lo3, lo3, lo3};
      lut.domain_max_3d = {0.1f, 0.1f, 0.1f};
    } else if (kind == 3) {  // Iridas domain, per channel
      lut.domain_min_3d = {u(rng), u(rng), u(rng)};
      lut.domain_max_3d = {1e-7f, 3.3f, 1e30f};
    } else if (kind == 0 && trial % 8 == 0) {
      lut.domain_min_1d = {-1e-30f, 0.f, 0.25f};
    }
    auto text = write_cube(lut);
    ASSERT_TRUE(text.ok()) << text.error().to_string();
    auto back = parse_cube("w.cube", *text);
    ASSERT_TRUE(back.ok()) << back.error().to_string();
    EXPECT_TRUE(same_bits(*back, lut)) << "trial " << trial;
    EXPECT_TRUE(*back == lut);
  }
}

TEST(CubeRoundTrip, SampleFiles) {
  for (const auto& entry : fs::directory_iterator(kCubeDir)) {
    const CubeLut lut = load(entry.path().filename().string());
    auto text = write_cube(lut);
    ASSERT_TRUE(text.ok()) << text.error().to_string();
    auto back = parse_cube("w.cube", *text);
    ASSERT_TRUE(back.ok()) << back.error().to_string();
    EXPECT_TRUE(same_bits(*back, lut)) << entry.path();
  }
}

TEST(CubeWrite, Layout) {
  CubeLut lut;
  lut.title = "t";
  lut.size_1d = 2;
  lut.size_3d = 2;
  lut.domain_min_1d = {-0.5f, -0.5f, -0.5f};
  lut.table_1d = {{0.f, 0.f, 0.f}, {1.f / 3, 1.f, 1.f}};
  for (int i = 0; i < 8; ++i)
    lut.table_3d.push_back(
        {static_cast<float>(i & 1), static_cast<float>(i >> 1 & 1), static_cast<float>(i >> 2)});
  auto text = write_cube(lut);
  ASSERT_TRUE(text.ok()) << text.error().to_string();
  EXPECT_EQ(*text,
            "TITLE \"t\"\nLUT_1D_SIZE 2\nLUT_3D_SIZE 2\nLUT_1D_INPUT_RANGE -0.5 1\n"
            "0 0 0\n0.333333343 1 1\n"
            "0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n");
}

TEST(CubeWrite, RefusesWhatNoFileCanSay) {
  CubeLut lut;
  lut.size_1d = 2;
  lut.table_1d = {{0, 0, 0}, {1, 1, 1}};
  ASSERT_TRUE(write_cube(lut).ok());
  auto with = [&](auto change) {
    CubeLut l = lut;
    change(l);
    auto r = write_cube(l);
    return r.ok() ? std::string("ok") : r.error().to_string();
  };
  EXPECT_EQ(with([](CubeLut& l) { l.size_1d = 3; }),
            "table: tables of 2 and 0 rows for sizes 3 and 0; valid choices: size_1d rows and "
            "size_3d^3 rows");
  EXPECT_EQ(with([](CubeLut& l) { l.title = "say \"hi\""; }),
            "title: title holds a double quote or a line break; valid choices: one line without "
            "'\"'");
  EXPECT_EQ(with([](CubeLut& l) { l.table_1d[1][1] = std::nanf(""); }),
            "table: non-finite value nan; valid choices: finite values");
  EXPECT_EQ(with([](CubeLut& l) { l.domain_max_1d[2] = 0.f; }),
            "domain: domain min 0 is not below max 0; valid choices: finite min < max in every "
            "channel");
  EXPECT_EQ(with([](CubeLut& l) {
              l.size_3d = 2;
              l.table_3d.assign(8, Rgb{});
              l.domain_max_3d[0] = 2.f;
            }),
            "domain: a 1-D shaper + 3-D file has one input range per table; valid choices: the "
            "same domain min and max in all three channels of each table");
  EXPECT_EQ(with([](CubeLut& l) { l.domain_max_3d[0] = 2.f; }),
            "domain: a domain for a table the LUT does not have; valid choices: the default [0, "
            "1]");
}

// ---------------------------------------------------------------------------------------------
// Evaluation against values known without our code.

TEST(CubeApply, IdentityIsExactInsideAndClampsOutside) {
  const CubeLut lut = load("identity_17.cube");
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 1000; ++i) {
    const std::array<double, 3> x{u(rng), u(rng), u(rng)};
    for (const Interp interp : {Interp::trilinear, Interp::tetrahedral}) {
      const auto y = apply(lut, x, interp);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(y[c], x[c], 1e-15);
    }
  }
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto y = apply(lut, {-0.5, 1.5, inf}, Interp::tetrahedral);
  EXPECT_EQ(y, (std::array<double, 3>{0.0, 1.0, 1.0}));
  const auto n = apply(lut, {nan, -inf, 0.5}, Interp::trilinear);
  EXPECT_EQ(n, (std::array<double, 3>{0.0, 0.0, 0.5}));  // NaN: the domain's min
}

double smoothstep(double x) {
  return x * x * (3.0 - 2.0 * x);
}

TEST(CubeApply, GridPointsGiveTheFormula) {
  // contrast_17: out_c = smoothstep(in_c) at the 17^3 grid points, to float32 rounding.
  const CubeLut lut = load("contrast_17.cube");
  for (int b = 0; b < 17; ++b)
    for (int g = 0; g < 17; ++g)
      for (int r = 0; r < 17; ++r) {
        const std::array<double, 3> x{r / 16.0, g / 16.0, b / 16.0};
        for (const Interp interp : {Interp::trilinear, Interp::tetrahedral}) {
          const auto y = apply(lut, x, interp);
          for (int c = 0; c < 3; ++c) EXPECT_NEAR(y[c], smoothstep(x[c]), 6e-8);
        }
      }
  // gamma_1d: red = x^2.2 at the 1024 rows.
  const CubeLut gamma = load("gamma_1d.cube");
  for (int i = 0; i < 1024; ++i) {
    const double x = i / 1023.0;
    EXPECT_NEAR(apply(gamma, {x, x, x}, Interp::trilinear)[0], std::pow(x, 2.2), 6e-8);
  }
}

TEST(CubeApply, TetrahedralIsExactForAPlaneAndDiffersFromTrilinearForAProduct) {
  // A 2-point LUT of out = r * g * b: trilinear reproduces the product; tetrahedral gives the
  // piecewise-linear interpolant, f3 = min(r, g, b) (weight of (1,1,1), the only non-zero corner).
  CubeLut lut;
  lut.size_3d = 2;
  for (int i = 0; i < 8; ++i) {
    const float v = (i == 7) ? 1.f : 0.f;
    lut.table_3d.push_back({v, v, v});
  }
  const std::array<double, 3> x{0.3, 0.8, 0.5};
  EXPECT_NEAR(apply(lut, x, Interp::trilinear)[0], 0.3 * 0.8 * 0.5, 1e-15);
  EXPECT_NEAR(apply(lut, x, Interp::tetrahedral)[0], 0.3, 1e-15);
}

// ---------------------------------------------------------------------------------------------
// OpenColorIO oracle.

using hdrc::cube::testing::ocio_processor;  // core/cube/ocio_oracle.h

struct Sample {
  const char* file;
  const char* flavour;  // the OCIO reader that accepts it
  double lo, hi;        // the input domain the colours are drawn from (all channels)
};

// The Resolve files carry LUT_*_INPUT_RANGE (OCIO's Iridas reader stops at it, "Invalid color
// triples") or both tables; OCIO then tries its Resolve reader. The Iridas files carry TITLE,
// which the Resolve reader refuses ("Unsupported tag: 'TITLE'"), so each file is read by exactly
// one of the two.
const Sample kSamples[] = {
    {"identity_2.cube", "iridas", 0.0, 1.0},
    {"identity_17.cube", "iridas", 0.0, 1.0},
    {"contrast_17.cube", "iridas", 0.0, 1.0},
    {"hue_rotate_17.cube", "iridas", 0.0, 1.0},
    {"gamma_1d.cube", "iridas", 0.0, 1.0},
    {"domain_1d.cube", "iridas", -1.0, 8.0},
    {"domain_3d.cube", "iridas", -0.5, 4.0},
    {"resolve_shaper.cube", "resolve", 0.0, 4.0},
    {"resolve_range_3d.cube", "resolve", -0.25, 1.25},
};

struct Agreement {
  double max_abs = 0, max_rel = 0;
  int points = 0, failures = 0;
};

// Colours: a 13^3 lattice over the domain widened by 25% on each side (points outside test the
// clamping) and 3000 pseudo-random colours inside.
std::vector<std::array<float, 3>> colours(double lo, double hi) {
  std::vector<std::array<float, 3>> out;
  const double w = hi - lo;
  for (int b = 0; b < 13; ++b)
    for (int g = 0; g < 13; ++g)
      for (int r = 0; r < 13; ++r) {
        auto at = [&](int i) { return static_cast<float>(lo - 0.25 * w + 1.5 * w * i / 12.0); };
        out.push_back({at(r), at(g), at(b)});
      }
  std::mt19937 rng(1616);
  std::uniform_real_distribution<double> u(lo, hi);
  for (int i = 0; i < 3000; ++i)
    out.push_back(
        {static_cast<float>(u(rng)), static_cast<float>(u(rng)), static_cast<float>(u(rng))});
  return out;
}

Agreement compare(const Sample& s, Interp interp) {
  const std::string path = kCubeDir + s.file;
  const CubeLut lut = load(s.file);
  auto proc = ocio_processor(
      path, interp == Interp::trilinear ? OCIO::INTERP_LINEAR : OCIO::INTERP_TETRAHEDRAL);
  Agreement a;
  for (const auto& c : colours(s.lo, s.hi)) {
    float px[3] = {c[0], c[1], c[2]};
    proc->applyRGB(px);
    const auto ours = apply(lut, {c[0], c[1], c[2]}, interp);
    for (int k = 0; k < 3; ++k) {
      const double d = std::fabs(ours[k] - px[k]);
      a.max_abs = std::max(a.max_abs, d);
      a.max_rel = std::max(a.max_rel, d / std::max(std::fabs(ours[k]), 1e-3));
      // OCIO evaluates in float32 (input scaling, index and blend): 2e-6 relative + 1e-6.
      if (d > 2e-6 * std::fabs(ours[k]) + 1e-6 && a.failures++ < 5)
        ADD_FAILURE() << s.file << " at (" << c[0] << ", " << c[1] << ", " << c[2] << ") channel "
                      << k << ": ours " << ours[k] << ", OCIO " << px[k];
    }
    ++a.points;
  }
  return a;
}

class CubeVsOcio : public ::testing::TestWithParam<Sample> {};

// Measured (OCIO 2.1.2, glibc 2.36, 5197 colours each; rel = abs / max(|ours|, 1e-3)):
//   file                   trilinear abs / rel    tetrahedral abs / rel
//   identity_2             1.1e-16 / 2.9e-16      6.0e-8 / 1.1e-7
//   identity_17            2.2e-16 / 3.9e-16      6.0e-8 / 1.1e-7
//   contrast_17            3.4e-8  / 8.6e-8       1.0e-7 / 1.6e-7
//   hue_rotate_17          8.1e-8  / 4.3e-7       1.1e-7 / 1.5e-7
//   gamma_1d (1-D)         8.6e-8  / 1.7e-6       -
//   domain_1d (1-D)        3.0e-7  / 1.1e-5       -
//   domain_3d              3.6e-7  / 4.6e-5       4.1e-7 / 4.8e-5
//   resolve_shaper         9.8e-8  / 2.1e-7       1.4e-7 / 2.3e-7
//   resolve_range_3d       2.8e-7  / 9.8e-6       3.6e-7 / 1.7e-5
// All within 2e-6 relative + 1e-6 absolute; the largest relative ones are near 0 outputs, the
// absolute ones come from OCIO's float32 domain scaling (x * scale + offset) ahead of the index.
TEST_P(CubeVsOcio, Agrees) {
  const Sample& s = GetParam();
  const CubeLut lut = load(s.file);
  std::vector<Interp> interps{Interp::trilinear};
  if (lut.size_3d) interps.push_back(Interp::tetrahedral);  // 1-D tables interpolate linearly
  for (const Interp interp : interps) {
    const Agreement a = compare(s, interp);
    std::printf("%-22s %-7s %-11s %5d colours: max abs %.3g, max rel %.3g\n", s.file, s.flavour,
                interp == Interp::trilinear ? "trilinear" : "tetrahedral", a.points, a.max_abs,
                a.max_rel);
    EXPECT_EQ(a.failures, 0);
  }
}

INSTANTIATE_TEST_SUITE_P(Samples, CubeVsOcio, ::testing::ValuesIn(kSamples), [](const auto& info) {
  std::string n = info.param.file;
  n = n.substr(0, n.find('.'));
  return n;
});

// NaN and infinities: OCIO 2.1.2's CPU Lut1D/Lut3D clamp the index with max(0, min(x, N-1)), so
// NaN lands on the domain's min and +-Inf on its ends, also through a DOMAIN/INPUT_RANGE scaling
// (NaN * scale + offset is NaN). apply() documents the same; checked here on every sample.
TEST(CubeVsOcio, NonFiniteInputsAgree) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (const Sample& s : kSamples) {
    const CubeLut lut = load(s.file);
    for (const Interp interp : {Interp::trilinear, Interp::tetrahedral}) {
      auto proc =
          ocio_processor(kCubeDir + s.file, interp == Interp::trilinear ? OCIO::INTERP_LINEAR
                                                                        : OCIO::INTERP_TETRAHEDRAL);
      for (const std::array<float, 3> c : {std::array<float, 3>{nan, 0.5f, 0.5f},
                                           {inf, -inf, 0.5f},
                                           {0.5f, nan, -inf},
                                           {nan, nan, inf}}) {
        float px[3] = {c[0], c[1], c[2]};
        proc->applyRGB(px);
        const auto ours = apply(lut, {c[0], c[1], c[2]}, interp);
        for (int k = 0; k < 3; ++k) {
          ASSERT_TRUE(std::isfinite(ours[k]));
          EXPECT_NEAR(ours[k], px[k], 2e-6 * std::fabs(ours[k]) + 1e-6)
              << s.file << " channel " << k << " of (" << c[0] << ", " << c[1] << ", " << c[2]
              << ")";
        }
      }
    }
  }
}

}  // namespace
