// .cube LUT files: Adobe/Iridas "Cube LUT Specification 1.0" (2013) and DaVinci Resolve's variant
// (LUT_1D_INPUT_RANGE / LUT_3D_INPUT_RANGE, a 1-D shaper followed by a 3-D table). A parser that
// names the file, the line, the value found and what was expected for every problem; a writer
// whose output parses back bit for bit; and evaluation in double (trilinear or tetrahedral).
// Issue 16.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"

namespace hdrc::cube {

// 64 MiB, as the project's other inputs (runner/json_read.h): 128^3 rows of 9-digit text (up to
// 32 bytes a row) fit. A LUT_3D_SIZE near the spec's 256 does not: 256^3 rows take at least 100 MB
// ("0 0 0\n"), about 600 MB at 9 digits; such files are refused by size.
inline constexpr size_t kMaxCubeFileBytes = size_t{64} << 20;
inline constexpr size_t kMaxCubeLineBytes = 4096;  // a row or keyword line, without its newline
inline constexpr int kMin1DSize = 2;
inline constexpr int kMax1DSize = 65536;
inline constexpr int kMin3DSize = 2;
inline constexpr int kMax3DSize = 256;

using Rgb = std::array<float, 3>;

// One .cube file. Values are float32, as the spec's "floating point" tables are used everywhere
// (OpenColorIO, Resolve, GPU textures); parsing rounds each decimal to the nearest float.
//
// The input domain of each table, per channel: Iridas files give one DOMAIN_MIN/DOMAIN_MAX for
// their one table (spec 1.0 §"Domain"); Resolve files give LUT_1D_INPUT_RANGE and
// LUT_3D_INPUT_RANGE, one min/max for all three channels of each table. Default [0, 1].
struct CubeLut {
  std::optional<std::string> title;  // TITLE "text", without the quotes
  int size_1d = 0;                   // LUT_1D_SIZE; 0: no 1-D table
  int size_3d = 0;                   // LUT_3D_SIZE; 0: no 3-D table
  Rgb domain_min_1d{0.f, 0.f, 0.f};
  Rgb domain_max_1d{1.f, 1.f, 1.f};
  Rgb domain_min_3d{0.f, 0.f, 0.f};
  Rgb domain_max_3d{1.f, 1.f, 1.f};
  std::vector<Rgb> table_1d;  // size_1d rows
  std::vector<Rgb> table_3d;  // size_3d^3 rows; red varies fastest, then green, then blue

  // Row (r, g, b) of the 3-D table.
  const Rgb& at(int r, int g, int b) const {
    return table_3d[static_cast<size_t>(r) +
                    static_cast<size_t>(size_3d) *
                        (static_cast<size_t>(g) + static_cast<size_t>(size_3d) * b)];
  }
  bool operator==(const CubeLut&) const = default;
};

// Parses .cube text read from `file` (named in errors). Accepted, per spec 1.0 and Resolve:
//  - keywords TITLE "text", LUT_1D_SIZE N (2..65536), LUT_3D_SIZE N (2..256), DOMAIN_MIN r g b,
//    DOMAIN_MAX r g b, LUT_1D_INPUT_RANGE min max, LUT_3D_INPUT_RANGE min max, each at most once,
//    all before the first row; keywords are upper case, as the spec spells them;
//  - `#` comments (whole-line and trailing; a `#` inside TITLE's quotes is text), blank lines, LF
//    or CRLF, spaces and tabs around and between fields;
//  - numbers in C-locale decimal syntax (std::from_chars: no locale), with an optional leading
//    '+', scientific notation included; NaN, infinities and values outside float32's range
//    (1e39, 1e999) are errors;
//  - rows of three numbers: the 1-D table's size_1d rows first, then the 3-D table's size_3d^3.
// DOMAIN_* applies to the file's one table; with both tables it is ambiguous and an error (use
// the INPUT_RANGE keywords). DOMAIN_* and *_INPUT_RANGE together are an error.
// Errors: Error{file, "line N", what was found, what is valid}.
Result<CubeLut> parse_cube(const std::string& file, std::string_view text);

// Reads and parses a .cube file: a regular file of at most kMaxCubeFileBytes (checked before
// reading).
Result<CubeLut> read_cube_file(const std::string& path);

// .cube text: TITLE (when present), the sizes, the domain when not [0, 1] (DOMAIN_MIN/DOMAIN_MAX
// for a file with one table; LUT_1D_INPUT_RANGE/LUT_3D_INPUT_RANGE for a 1-D shaper + 3-D file),
// then the rows, each value with 9 significant digits (%.9g), enough for every float32 to parse
// back to itself: parse_cube(write_cube(x)) == x bit for bit. Errors (a LUT parse_cube would not
// produce): table lengths that disagree with the sizes, sizes out of range, a non-finite value,
// min >= max, a title holding '"' or a line break, or a shaper + 3-D file whose domain differs
// between channels (INPUT_RANGE has one min/max per table).
Result<std::string> write_cube(const CubeLut& lut);

enum class Interp { trilinear, tetrahedral };

// Evaluates the LUT at `rgb`, in double: the 1-D table first when present (each channel on its
// own, linear interpolation between rows), then the 3-D table when present (the standard
// trilinear, or tetrahedral: the cube split into 6 tetrahedra by the order of the fractional
// parts, all of which share the cube's main diagonal).
// Each table maps its domain [min, max] linearly onto [0, N-1]; inputs are clamped to the domain
// first, so a value below min gives the first row's output and one above max the last row's (as
// OpenColorIO and Resolve do; there is no extrapolation). +Inf clamps to max, -Inf to min and NaN
// is taken as the domain's min (OpenColorIO's CPU Lut3D does the same: max(0, min(NaN, N-1)) = 0).
// The LUT must be valid (as parse_cube returns it).
std::array<double, 3> apply(const CubeLut& lut, const std::array<double, 3>& rgb, Interp interp);

}  // namespace hdrc::cube
