// `hdrconform lut convert | info | apply` (issue 16): a .cube LUT (core/cube/cube.h) turned into
// the texture an engine samples, described, and evaluated from the command line.
//
// The two image layouts of a 3-D table of size N (lattice point (r, g, b), red fastest as in the
// .cube file), pixel (x, y) counted from the image's top-left corner (core/image.h):
//   strip   N^2 wide, N high: pixel (r + N b, g). N slices of N x N side by side, blue choosing
//           the slice: UE's unwrapped colour-grading LUT (UnwrappedTexture3DSample) and Unity's
//           lookup strip (Color.hlsl: ApplyLut2D) use this texel order.
//   volume  N wide, N^2 high: pixel (r, g + N b). The same slices stacked top to bottom, so the
//           image's rows, read in order, are the .cube rows in order: the pixels upload unchanged
//           to an N x N x N 3-D texture (x = r, y = g, z = b).
// Origin: pixel row y = 0 is the file's top row (UE, Direct3D: texture v = 0 at the image's top)
// or, with Origin::bottom, its bottom row (Unity, OpenGL: an imported texture's v = 0 is the
// image's bottom row), so that the engine's texel row y still holds green y.
// Files: OpenEXR float32 RGB (ZIP, lossless: every value is stored exactly) or 16-bit RGB PNG
// (round(65535 v): within 0.5/65535 of v; v must lie in [0, 1], or --clamp clamps and reports).
// A converted image carries its layout, size, domain and title as metadata (kMeta*), so `lut
// info` and `lut apply` read it back as the .cube it came from. docs/cube-workflow.md.
#pragma once

#include <cstddef>
#include <iosfwd>
#include <optional>
#include <string>

#include "core/cube/cube.h"
#include "core/result.h"

namespace CLI {
class App;
}

namespace hdrc::lut {

enum class Layout { strip, volume };
enum class Origin { top, bottom };
enum class Format { exr, png16 };

// Image metadata written by convert (string attributes, in the EXR header and PNG tEXt chunks).
inline constexpr const char* kMetaLayout = "hdrconform:lut_layout";     // "strip" | "volume"
inline constexpr const char* kMetaOrigin = "hdrconform:lut_origin";     // "top" | "bottom"
inline constexpr const char* kMetaSize = "hdrconform:lut_size";         // N, decimal
inline constexpr const char* kMetaDomainMin = "hdrconform:domain_min";  // "r g b", %.9g
inline constexpr const char* kMetaDomainMax = "hdrconform:domain_max";  // "r g b", %.9g
inline constexpr const char* kMetaTitle = "ImageDescription";           // the .cube's TITLE

// A LUT as read from a file, with how it was stored.
struct LoadedLut {
  cube::CubeLut lut;
  std::string format;  // ".cube text", "OpenEXR float32", "OpenEXR half", "PNG 16-bit", ...
  std::optional<Layout> layout;  // images only
  Origin origin = Origin::top;   // images only: from the metadata, else top
  int width = 0, height = 0;     // images only
  bool metadata = false;         // images only: convert's metadata was present
  // The storage precision, for `info`'s identity test: a stored value v of the exact lattice
  // coordinate x is an identity when |v - x| <= tolerance(x). Described in `precision`.
  enum class Storage { cube_text, float32, half, uint16, uint8 } storage = Storage::cube_text;
  std::string precision;
};

// The layout of an image of width x height, as convert writes them: a strip when width = N^2 and
// height = N, a volume when width = N and height = N^2, N in 2..256; otherwise nullopt.
std::optional<Layout> layout_from_shape(int width, int height, int* n);

// Reads a LUT file, chosen by extension: .cube (core/cube: bounded, every problem located), .exr
// or .png (an image in either layout; metadata when convert wrote it, else a [0, 1] domain and a
// top origin). The
// image's size, channels (R, G, B first) and pixel type are checked before its pixels are read;
// non-finite texels are refused. Errors name the file and what is valid.
Result<LoadedLut> load_lut(const std::string& path);

// What png16 had to clamp (values outside [0, 1]).
struct ClampReport {
  size_t count = 0;         // values (channels) outside [0, 1]
  double min = 0, max = 0;  // the lowest and highest of them
};

// The image file bytes (EXR float32 RGB, ZIP; or 16-bit RGB PNG) of `lut`'s 3-D table in
// `layout`, with kMeta* metadata. Errors (naming `file`): no 3-D table, a 1-D table (a shaper
// or 1-D LUT has no place in a 3-D texture), and for png16 a value outside [0, 1] unless `clamp`
// (the first such value is named by lattice point and channel). `clamped`, when not null, gets
// what was clamped.
Result<std::string> encode_lut_image(const cube::CubeLut& lut, const std::string& file,
                                     Layout layout, Origin origin, Format format, bool clamp,
                                     ClampReport* clamped = nullptr);

struct ConvertOptions {
  Layout layout = Layout::strip;
  Origin origin = Origin::top;
  Format format = Format::exr;
  std::string out;  // .exr for exr, .png for png16; its folder must exist
  bool clamp = false;
};

// `lut convert`: reads `in` (.cube, or an image convert wrote), checks --out (extension matches
// the format, the folder exists, not a folder itself) before any work, encodes, and writes --out
// atomically (core/atomic_file.h): nothing else is written, nothing is left half-written. Prints
// one summary line (and a clamp report) to `out`.
Status convert_lut(const std::string& in, const ConvertOptions& options, std::ostream& out);

// `lut info`: "key: value" lines: file, format (and layout), title, each table's size, domain,
// min and max per channel, and whether the table is an identity within storage precision (with
// the largest deviation and where).
Result<std::string> lut_info(const std::string& path);

// `lut apply`: reads "R G B" lines from `in` (blank lines and lines starting with '#' skipped;
// decimal numbers as std::from_chars reads them, an optional leading '+', nan and inf accepted:
// cube::apply takes NaN as the domain's min and clamps infinities) and writes the looked-up colour
// of each, "R G B" with 9 significant digits, as `hdrconform probe` prints them. A line longer
// than 4096 characters, without exactly three numbers, or with a number outside a double's range
// is an error naming "<stdin>", the line and the text; lines before it have been answered.
Status apply_lut_stream(const cube::CubeLut& lut, cube::Interp interp, std::istream& in,
                        std::ostream& out);

// Registers `lut` and its three subcommands on `app`. Each runs from its CLI11 callback during
// app.parse() and ends the parse by throwing: CLI::Success when it succeeded, CLI::RuntimeError(2)
// after printing "error: ..." to `err` when it did not (exit code 2, bad input, as the rest of
// the CLI: README "Exit codes"); app.exit(e) turns either into the process's exit code without
// printing more. Streams must outlive the parse.
void add_lut_command(CLI::App& app, std::istream& in, std::ostream& out, std::ostream& err);
// The same on std::cin, std::cout and std::cerr (apply unsynchronises them from stdio first).
void add_lut_command(CLI::App& app);

}  // namespace hdrc::lut
