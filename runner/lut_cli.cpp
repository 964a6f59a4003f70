#include "runner/lut_cli.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <istream>
#include <memory>
#include <ostream>
#include <vector>

#include "core/atomic_file.h"
#include "core/exr_header.h"
#include "core/image.h"
#include "core/utf8.h"
#include "runner/probe.h"

namespace hdrc::lut {

namespace {

namespace fs = std::filesystem;
using cube::CubeLut;
using cube::Rgb;

// runner/run.h: kExitBadInput (that header brings the whole executor; the value is pinned by the
// CLI tests, which run hdrconform itself).
constexpr int kExitBadInput = 2;

constexpr const char* kLutExitCodes =
    "Exit codes:\n"
    "  0  done\n"
    "  2  bad input: a usage error, an unreadable or invalid LUT, an --out that cannot be "
    "written,\n"
    "     or a bad \"R G B\" line (convert then writes nothing)\n";

constexpr const char* kChannel[3] = {"red", "green", "blue"};
constexpr const char* kLayoutChoices = "strip (N^2 x N), volume (N x N^2)";

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string extension(const std::string& path) {
  return lower(fs::path(path).extension());
}

std::string rgb_text(const Rgb& v) {
  return format_number(v[0]) + " " + format_number(v[1]) + " " + format_number(v[2]);
}

std::string lattice_text(int r, int g, int b) {
  return "lattice (" + std::to_string(r) + ", " + std::to_string(g) + ", " + std::to_string(b) +
         ")";
}

const char* layout_name(Layout l) {
  return l == Layout::strip ? "strip" : "volume";
}

const char* origin_name(Origin o) {
  return o == Origin::top ? "top" : "bottom";
}

// Pixel (x, y) of lattice point (r, g, b), y counted from the file's top row (lut_cli.h).
void pixel_of(Layout layout, Origin origin, int n, int r, int g, int b, int* x, int* y) {
  if (layout == Layout::strip) {
    *x = r + n * b;
    *y = g;
  } else {
    *x = r;
    *y = g + n * b;
  }
  if (origin == Origin::bottom) *y = (layout == Layout::strip ? n : n * n) - 1 - *y;
}

std::string layout_text(Layout layout, Origin origin, int n) {
  const std::string ns = std::to_string(n);
  const std::string row0 =
      origin == Origin::top ? ", row 0 at the top" : ", row 0 at the bottom (rows counted upward)";
  if (layout == Layout::strip)
    return "strip " + std::to_string(n * n) + " x " + ns + ": " + ns + " slices of " + ns + " x " +
           ns + " side by side, lattice (r, g, b) at pixel (r + " + ns + " b, g)" + row0;
  return "volume " + ns + " x " + std::to_string(n * n) + ": " + ns + " slices of " + ns + " x " +
         ns + " stacked, lattice (r, g, b) at pixel (r, g + " + ns + " b)" + row0;
}

// ---------------------------------------------------------------------------------------------
// Storage precision (`info`'s identity test).

// The spacing of float32 values around |x| (2^-149 below the normal range).
double ulp_f32(double x) {
  const double a = std::fabs(x);
  if (a < 0x1p-126) return 0x1p-149;
  return std::ldexp(1.0, std::ilogb(a) - 23);
}

// The same for IEEE half (2^-24 below the normal range, 2^-14).
double ulp_f16(double x) {
  const double a = std::fabs(x);
  if (a < 0x1p-14) return 0x1p-24;
  return std::ldexp(1.0, std::ilogb(a) - 10);
}

// How far a stored value of the exact coordinate x may be from it and still be x.
double tolerance(LoadedLut::Storage s, double x) {
  switch (s) {
    case LoadedLut::Storage::float32:
      return 0.5 * ulp_f32(x);
    case LoadedLut::Storage::cube_text:
      // Most writers (Resolve, the spec's own examples) print 6 decimal places: 5e-7.
      return std::max(0.5 * ulp_f32(x), 5e-7);
    case LoadedLut::Storage::half:
      return 0.5 * ulp_f16(x);
    case LoadedLut::Storage::uint16:  // k / 65535, then held as float32
      return 0.5 / 65535 + ulp_f32(x);
    case LoadedLut::Storage::uint8:
      return 0.5 / 255 + ulp_f32(x);
  }
  return 0;
}

// ---------------------------------------------------------------------------------------------
// Reading.

Result<LoadedLut> load_cube(const std::string& path) {
  auto lut = cube::read_cube_file(path);
  if (!lut) return lut.error();
  LoadedLut out;
  out.lut = std::move(*lut);
  out.format = ".cube text";
  out.storage = LoadedLut::Storage::cube_text;
  out.precision = "float32, or 6 decimal places (5e-07) as most .cube writers print";
  return out;
}

// Three finite numbers "r g b" (convert's domain metadata).
bool parse_rgb_attribute(const std::string& text, Rgb* out) {
  const char* p = text.data();
  const char* const end = p + text.size();
  for (int k = 0; k < 3; ++k) {
    while (p < end && *p == ' ') ++p;
    const auto r = std::from_chars(p, end, (*out)[k]);
    if (r.ec != std::errc() || !std::isfinite((*out)[k])) return false;
    p = r.ptr;
  }
  while (p < end && *p == ' ') ++p;
  return p == end;
}

Result<LoadedLut> load_image(const std::string& path, bool exr) {
  const std::string name = valid_utf8(path);
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int err = errno;
    return Error{name, "", std::string("cannot open LUT image: ") + std::strerror(err), ""};
  }
  if (!S_ISREG(st.st_mode))
    return Error{name, "", "the LUT image is not a regular file", "a regular image file"};
  if (static_cast<unsigned long long>(st.st_size) > kMaxImageFileBytes)
    return Error{name, "", "the image file is " + std::to_string(st.st_size) + " bytes",
                 "at most " + std::to_string(kMaxImageFileBytes) + " bytes"};
  if (exr) {
    // OpenEXR's magic number; then its headers are bounded before OpenEXR reads them
    // (core/exr_header.h).
    unsigned char magic[4] = {0, 0, 0, 0};
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    const ssize_t n = fd >= 0 ? ::read(fd, magic, sizeof magic) : -1;
    if (fd >= 0) ::close(fd);
    if (n != 4 || magic[0] != 0x76 || magic[1] != 0x2f || magic[2] != 0x31 || magic[3] != 0x01)
      return Error{name, "", "not an OpenEXR file (no EXR magic number)", "an OpenEXR image"};
    if (Status hs = check_exr_header(path); !hs) {
      Error e = hs.error();
      e.file = name;
      e.message = valid_utf8(e.message);
      return e;
    }
  }
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);  // a PNG's colours as stored, not times alpha
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in) return Error{name, "", "cannot open LUT image: " + valid_utf8(OIIO::geterror()), ""};
  const std::string format_name = in->format_name();
  if (format_name != (exr ? "openexr" : "png"))
    return Error{name, "", "a *" + extension(path) + " file read as " + format_name,
                 exr ? "an OpenEXR image" : "a PNG image"};
  const OIIO::ImageSpec& spec = in->spec();
  const std::string shape = std::to_string(spec.width) + " x " + std::to_string(spec.height) +
                            (spec.depth > 1 ? " x " + std::to_string(spec.depth) : "");
  if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1 ||
      static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height) > kMaxImagePixels)
    return Error{name, "", "the image is " + shape,
                 "a 2-D image of at most " + std::to_string(kMaxImagePixels) + " pixels"};
  int n = 0;
  const std::optional<Layout> layout = layout_from_shape(spec.width, spec.height, &n);
  if (!layout)
    return Error{name, "", "the image is " + shape + ": not a LUT layout",
                 std::string(kLayoutChoices) + ", N from " + std::to_string(cube::kMin3DSize) +
                     " to " + std::to_string(cube::kMax3DSize)};
  if (spec.nchannels < 3 || spec.channel_name(0) != "R" || spec.channel_name(1) != "G" ||
      spec.channel_name(2) != "B") {
    std::string names;
    for (int c = 0; c < spec.nchannels && c < 8; ++c)
      names += (c ? "," : "") + std::string(spec.channel_name(c));
    return Error{name, "", "the image's channels are " + valid_utf8(names),
                 "R,G,B first (R,G,B or R,G,B,A)"};
  }
  // The coarsest of the three channels' pixel types.
  LoadedLut out;
  int rank = -1;
  for (int c = 0; c < 3; ++c) {
    const OIIO::TypeDesc t = spec.channelformat(c);
    int r = -1;
    if (t == OIIO::TypeDesc::FLOAT) r = 0;
    if (t == OIIO::TypeDesc::HALF) r = 1;
    if (t == OIIO::TypeDesc::UINT16) r = 2;
    if (t == OIIO::TypeDesc::UINT8) r = 3;
    if (r < 0)
      return Error{name, "",
                   "channel " + valid_utf8(std::string(spec.channel_name(c))) + " is " + t.c_str(),
                   exr ? "float or half" : "uint8 or uint16"};
    rank = std::max(rank, r);
  }
  static const LoadedLut::Storage kStorage[4] = {
      LoadedLut::Storage::float32, LoadedLut::Storage::half, LoadedLut::Storage::uint16,
      LoadedLut::Storage::uint8};
  static const char* const kFormat[4] = {"float32", "half", "16-bit", "8-bit"};
  static const char* const kPrecision[4] = {"float32 (half an ulp)", "half (half an ulp)",
                                            "16-bit (0.5/65535)", "8-bit (0.5/255)"};
  out.storage = kStorage[rank];
  out.format = std::string(exr ? "OpenEXR " : "PNG ") + kFormat[rank];
  out.precision = kPrecision[rank];
  out.layout = layout;
  out.width = spec.width;
  out.height = spec.height;

  // convert's metadata: checked against the shape; the domain and title taken.
  CubeLut& lut = out.lut;
  const std::string meta_layout = spec.get_string_attribute(kMetaLayout);
  const std::string meta_origin = spec.get_string_attribute(kMetaOrigin);
  const std::string meta_size = spec.get_string_attribute(kMetaSize);
  const std::string meta_min = spec.get_string_attribute(kMetaDomainMin);
  const std::string meta_max = spec.get_string_attribute(kMetaDomainMax);
  out.metadata = !meta_layout.empty();
  if (!meta_layout.empty() && meta_layout != layout_name(*layout))
    return Error{name, kMetaLayout,
                 "'" + valid_utf8(meta_layout) + "' disagrees with the image's shape (" + shape +
                     ": " + layout_name(*layout) + ")",
                 kLayoutChoices};
  if (!meta_origin.empty() && meta_origin != "top" && meta_origin != "bottom")
    return Error{name, kMetaOrigin, "'" + valid_utf8(meta_origin) + "' is not an origin",
                 "top, bottom"};
  out.origin = meta_origin == "bottom" ? Origin::bottom : Origin::top;
  if (!meta_size.empty() && meta_size != std::to_string(n))
    return Error{name, kMetaSize,
                 "'" + valid_utf8(meta_size) + "' disagrees with the image's shape (" + shape +
                     ": N = " + std::to_string(n) + ")",
                 std::to_string(n)};
  if (!meta_min.empty() || !meta_max.empty()) {
    if (!parse_rgb_attribute(meta_min, &lut.domain_min_3d))
      return Error{name, kMetaDomainMin, "'" + valid_utf8(meta_min) + "' is not three numbers",
                   "\"r g b\", finite"};
    if (!parse_rgb_attribute(meta_max, &lut.domain_max_3d))
      return Error{name, kMetaDomainMax, "'" + valid_utf8(meta_max) + "' is not three numbers",
                   "\"r g b\", finite"};
    for (int k = 0; k < 3; ++k)
      if (!(lut.domain_min_3d[k] < lut.domain_max_3d[k]))
        return Error{name, kMetaDomainMin,
                     std::string(kChannel[k]) + " min " + format_number(lut.domain_min_3d[k]) +
                         " is not below max " + format_number(lut.domain_max_3d[k]),
                     "min < max"};
  }
  if (out.metadata) {
    const std::string title = spec.get_string_attribute(kMetaTitle);
    if (!title.empty() && title.find_first_of("\"\r\n") == std::string::npos)
      lut.title = valid_utf8(title);
  }

  // The pixels: exactly as stored (float and half widen exactly; integers as k / (2^bits - 1)).
  const size_t count = static_cast<size_t>(spec.width) * spec.height * 3;
  std::vector<float> px(count);
  bool read_ok = false;
  if (rank <= 1) {
    read_ok = in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, px.data());
  } else {
    std::vector<uint16_t> k(count);
    read_ok = in->read_image(0, 0, 0, 3, rank == 2 ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8,
                             k.data(), 3 * (rank == 2 ? 2 : 1));
    if (rank == 3) {  // bytes were packed into the first half of the buffer
      const auto* bytes = reinterpret_cast<const uint8_t*>(k.data());
      for (size_t i = 0; i < count; ++i) px[i] = static_cast<float>(bytes[i] / 255.0);
    } else {
      for (size_t i = 0; i < count; ++i) px[i] = static_cast<float>(k[i] / 65535.0);
    }
  }
  if (!read_ok) return Error{name, "", "cannot read pixels: " + valid_utf8(in->geterror()), ""};
  lut.size_3d = n;
  lut.table_3d.resize(static_cast<size_t>(n) * n * n);
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r) {
        int x = 0, y = 0;
        pixel_of(*layout, out.origin, n, r, g, b, &x, &y);
        const float* p = &px[(static_cast<size_t>(y) * spec.width + x) * 3];
        for (int k = 0; k < 3; ++k)
          if (!std::isfinite(p[k]))
            return Error{
                name, "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") " + kChannel[k],
                "the value is " + format_number(p[k]), "finite values"};
        lut.table_3d[static_cast<size_t>(r) +
                     static_cast<size_t>(n) * (g + static_cast<size_t>(n) * b)] = {p[0], p[1],
                                                                                   p[2]};
      }
  return out;
}

// ---------------------------------------------------------------------------------------------
// `info`.

struct Deviation {
  double max = 0;  // the largest |value - input|
  bool identity = true;
  std::string where;
};

void measure(const Rgb& v, const std::array<double, 3>& x, LoadedLut::Storage s,
             const std::string& where, Deviation* d) {
  for (int k = 0; k < 3; ++k) {
    const double dev = std::fabs(static_cast<double>(v[k]) - x[k]);
    if (!(dev <= tolerance(s, x[k]))) d->identity = false;
    if (dev > d->max) {
      d->max = dev;
      d->where = where + " " + kChannel[k];
    }
  }
}

std::string deviation_text(const Deviation& d, const LoadedLut& l) {
  std::string s = d.identity ? "yes" : "no";
  s += " (largest |value - input| " + format_number(d.max);
  if (d.max > 0) s += " at " + d.where;
  return s + "; storage precision " + l.precision + ")";
}

std::string domain_text(const Rgb& lo, const Rgb& hi) {
  if (lo[0] == lo[1] && lo[1] == lo[2] && hi[0] == hi[1] && hi[1] == hi[2])
    return "[" + format_number(lo[0]) + ", " + format_number(hi[0]) + "] for red, green, blue";
  return "min " + rgb_text(lo) + ", max " + rgb_text(hi);
}

void min_max(const std::vector<Rgb>& t, Rgb* lo, Rgb* hi) {
  *lo = t.front();
  *hi = t.front();
  for (const Rgb& v : t)
    for (int k = 0; k < 3; ++k) {
      (*lo)[k] = std::min((*lo)[k], v[k]);
      (*hi)[k] = std::max((*hi)[k], v[k]);
    }
}

// Lattice coordinate i of n over [lo, hi] (scripts/gen_cube_samples.py: lo + (hi - lo) i / (n-1)).
double coordinate(float lo, float hi, int i, int n) {
  return lo + (static_cast<double>(hi) - lo) * i / (n - 1);
}

// ---------------------------------------------------------------------------------------------
// `apply`.

constexpr size_t kMaxApplyLine = kMaxInputLine;

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

// The three numbers of a line; on failure `why` says what is wrong (empty: the count).
bool parse_rgb(std::string_view line, double v[3], std::string* why) {
  size_t i = 0;
  int n = 0;
  while (true) {
    while (i < line.size() && is_space(line[i])) ++i;
    if (i == line.size()) break;
    size_t j = i;
    while (j < line.size() && !is_space(line[j])) ++j;
    std::string_view t = line.substr(i, j - i);
    i = j;
    if (n == 3) return false;
    if (t.size() > 1 && t[0] == '+' && t[1] != '+' && t[1] != '-') t.remove_prefix(1);
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v[n]);
    const std::string shown = t.size() > 40 ? std::string(t.substr(0, 40)) + "..." : std::string(t);
    if (r.ec == std::errc::result_out_of_range) {
      *why = "'" + shown + "' is outside a double's range";
      return false;
    }
    if (r.ec != std::errc() || r.ptr != t.data() + t.size()) {
      *why = "'" + shown + "' is not a number";
      return false;
    }
    ++n;
  }
  return n == 3;
}

// "a b c\n" with 9 significant digits: std::to_chars with a precision prints as printf's %.9g
// in the "C" locale ([charconv.to.chars]), the format `hdrconform probe` prints.
void append_rgb(std::string& buf, const std::array<double, 3>& v) {
  char tmp[96];
  char* p = tmp;
  for (int k = 0; k < 3; ++k) {
    if (k) *p++ = ' ';
    p = std::to_chars(p, tmp + sizeof tmp, v[k], std::chars_format::general, 9).ptr;
  }
  *p++ = '\n';
  buf.append(tmp, p);
}

// ---------------------------------------------------------------------------------------------
// The command line.

struct CliOptions {
  std::string in, to, format, out, origin = "top", interp = "trilinear";
  bool clamp = false;
};

[[noreturn]] void finish(const Status& st, std::ostream& err) {
  if (!st) {
    err << "error: " << st.error().to_string() << '\n';
    err.flush();
    throw CLI::RuntimeError(kExitBadInput);
  }
  throw CLI::Success();
}

void add_commands(CLI::App& app, std::istream& in, std::ostream& out, std::ostream& err,
                  bool std_streams) {
  auto o = std::make_shared<CliOptions>();
  CLI::App* lut = app.add_subcommand(
      "lut",
      ".cube LUTs (Iridas/Adobe 1.0 and Resolve): convert to the strip or volume image an "
      "engine\nsamples, describe, evaluate (docs/cube-workflow.md)");
  lut->require_subcommand(1);
  lut->footer(kLutExitCodes);

  CLI::App* convert = lut->add_subcommand(
      "convert",
      "write a .cube's 3-D table as an image: strip (N^2 x N, lattice (r, g, b) at pixel\n"
      "(r + N b, g): UE's unwrapped LUT, Unity's strip) or volume (N x N^2, pixel (r, g + N b):\n"
      "the rows in .cube order, for a 3-D texture); OpenEXR float32 or 16-bit PNG, written\n"
      "atomically, with the layout, size, domain and title as metadata");
  convert->footer(kLutExitCodes);
  convert->add_option("IN", o->in, "a .cube file (or an image `lut convert` wrote)")->required();
  convert->add_option("--to", o->to, "layout: strip or volume")
      ->required()
      ->check(CLI::IsMember({"strip", "volume"}));
  convert
      ->add_option("--format", o->format,
                   "exr (float32, exact) or png16 (16-bit, values in [0, 1] only)")
      ->required()
      ->check(CLI::IsMember({"exr", "png16"}));
  convert->add_option("--out", o->out, "the image to write (.exr or .png, as --format)")
      ->required();
  convert
      ->add_option("--origin", o->origin,
                   "the file row holding texel row 0: top (UE, Direct3D) or bottom (Unity, "
                   "OpenGL:\nan imported texture's v = 0 is the image's bottom row)")
      ->check(CLI::IsMember({"top", "bottom"}))
      ->capture_default_str();
  convert->add_flag("--clamp", o->clamp,
                    "png16: clamp values outside [0, 1] (and report them) instead of refusing");
  convert->callback([o, &out, &err] {
    ConvertOptions c;
    c.layout = o->to == "volume" ? Layout::volume : Layout::strip;
    c.origin = o->origin == "bottom" ? Origin::bottom : Origin::top;
    c.format = o->format == "png16" ? Format::png16 : Format::exr;
    c.out = o->out;
    c.clamp = o->clamp;
    finish(convert_lut(o->in, c, out), err);
  });

  CLI::App* info = lut->add_subcommand(
      "info",
      "describe a .cube or a converted image: format, layout, title, sizes, domain (input\n"
      "range, shaper), min and max per channel, and whether it is an identity within storage\n"
      "precision");
  info->footer(kLutExitCodes);
  info->add_option("FILE", o->in, "a .cube, .exr or .png LUT")->required();
  info->callback([o, &out, &err] {
    auto text = lut_info(o->in);
    if (text) {
      out << *text;
      out.flush();
      finish({}, err);
    }
    finish(text.error(), err);
  });

  CLI::App* apply = lut->add_subcommand(
      "apply",
      "read \"R G B\" lines on standard input and print the LUT's output for each, 9 significant\n"
      "digits (as `hdrconform probe`); NaN takes the domain's min, values beyond it clamp");
  apply->footer(kLutExitCodes);
  apply->add_option("FILE", o->in, "a .cube, .exr or .png LUT")->required();
  apply->add_option("--interp", o->interp, "3-D interpolation: trilinear or tetrahedral")
      ->check(CLI::IsMember({"trilinear", "tetrahedral"}))
      ->capture_default_str();
  apply->callback([o, &in, &out, &err, std_streams] {
    auto lut = load_lut(o->in);
    if (!lut) finish(lut.error(), err);
    // Buffered std::cin/std::cout, as `probe` runs (1e6 lines in about a second).
    if (std_streams) std::ios::sync_with_stdio(false);
    const Status st = apply_lut_stream(
        lut->lut, o->interp == "tetrahedral" ? cube::Interp::tetrahedral : cube::Interp::trilinear,
        in, out);
    out.flush();
    finish(st, err);
  });
}

}  // namespace

// ---------------------------------------------------------------------------------------------

std::optional<Layout> layout_from_shape(int width, int height, int* n) {
  for (int k = cube::kMin3DSize; k <= cube::kMax3DSize; ++k) {
    if (width == k * k && height == k) {
      *n = k;
      return Layout::strip;
    }
    if (width == k && height == k * k) {
      *n = k;
      return Layout::volume;
    }
  }
  return std::nullopt;
}

Result<LoadedLut> load_lut(const std::string& path) {
  const std::string ext = extension(path);
  if (ext == ".cube") return load_cube(path);
  if (ext == ".exr" || ext == ".png") return load_image(path, ext == ".exr");
  return Error{valid_utf8(path), "",
               "unknown LUT file type '" + valid_utf8(fs::path(path).extension().string()) + "'",
               ".cube, .exr, .png"};
}

Result<std::string> encode_lut_image(const CubeLut& lut, const std::string& file, Layout layout,
                                     Origin origin, Format format, bool clamp,
                                     ClampReport* clamped) {
  const std::string name = valid_utf8(file);
  if (!lut.size_3d)
    return Error{name, "LUT_1D_SIZE " + std::to_string(lut.size_1d),
                 "a 1-D LUT has no 3-D table to write as a strip or volume",
                 "a .cube with LUT_3D_SIZE"};
  if (lut.size_1d)
    return Error{name, "LUT_1D_SIZE " + std::to_string(lut.size_1d),
                 "a 1-D shaper before the 3-D table has no place in a strip or volume texture "
                 "(the engine would sample the 3-D table without it)",
                 "a .cube with only a 3-D table (export it without a shaper, or apply the "
                 "shaper in the engine before the lookup)"};
  const int n = lut.size_3d;
  const int width = layout == Layout::strip ? n * n : n;
  const int height = layout == Layout::strip ? n : n * n;
  const size_t count = static_cast<size_t>(width) * height * 3;
  std::vector<float> fpx;
  std::vector<uint16_t> ipx;
  if (format == Format::exr)
    fpx.resize(count);
  else
    ipx.resize(count);
  ClampReport report;
  std::string first;  // the first value outside [0, 1] and where it is, for the error
  double first_value = 0;
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r) {
        int x = 0, y = 0;
        pixel_of(layout, origin, n, r, g, b, &x, &y);
        const size_t at = (static_cast<size_t>(y) * width + x) * 3;
        const Rgb& v = lut.at(r, g, b);
        for (int k = 0; k < 3; ++k) {
          if (format == Format::exr) {
            fpx[at + k] = v[k];
            continue;
          }
          const double d = v[k];
          if (d < 0 || d > 1) {
            if (report.count == 0) {
              report.min = report.max = d;
              first = lattice_text(r, g, b) + " " + kChannel[k];
              first_value = d;
            }
            report.min = std::min(report.min, d);
            report.max = std::max(report.max, d);
            ++report.count;
          }
          // Nearest of k / 65535: within 0.5 / 65535 of the clamped value.
          ipx[at + k] = static_cast<uint16_t>(std::lround(std::clamp(d, 0.0, 1.0) * 65535.0));
        }
      }
  if (report.count && !clamp) {
    return Error{name, first,
                 format_number(first_value) +
                     " is outside [0, 1], which a 16-bit PNG cannot hold (" +
                     std::to_string(report.count) + " value(s) are: lowest " +
                     format_number(report.min) + ", highest " + format_number(report.max) + ")",
                 "--format exr (float32, any value), or --clamp to clamp them to [0, 1]"};
  }
  if (clamped) *clamped = report;

  OIIO::ImageSpec spec(width, height, 3,
                       format == Format::exr ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT16);
  if (format == Format::exr) spec.attribute("compression", "zip");
  spec.attribute(kMetaLayout, layout_name(layout));
  spec.attribute(kMetaOrigin, origin_name(origin));
  spec.attribute(kMetaSize, std::to_string(n));
  spec.attribute(kMetaDomainMin, rgb_text(lut.domain_min_3d));
  spec.attribute(kMetaDomainMax, rgb_text(lut.domain_max_3d));
  if (lut.title) spec.attribute(kMetaTitle, *lut.title);
  spec.attribute("Software", "hdrconform lut convert");
  // OpenImageIO's EXR writer adds the time as DateTime unless the attribute is set; empty, it
  // writes none: the same LUT always gives the same bytes.
  spec.attribute("DateTime", "");
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput proxy(bytes);
  void* proxy_ptr = &proxy;
  spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy_ptr);
  const char* const oiio_format = format == Format::exr ? "openexr" : "png";
  auto out = OIIO::ImageOutput::create(oiio_format);
  const bool ok = out && out->open(format == Format::exr ? "lut.exr" : "lut.png", spec) &&
                  (format == Format::exr ? out->write_image(OIIO::TypeDesc::FLOAT, fpx.data())
                                         : out->write_image(OIIO::TypeDesc::UINT16, ipx.data())) &&
                  out->close();
  if (!ok)
    return Error{name, "",
                 std::string("cannot encode the ") + (format == Format::exr ? "EXR" : "PNG") +
                     ": " + valid_utf8(out ? out->geterror() : OIIO::geterror()),
                 ""};
  return std::string(bytes.begin(), bytes.end());
}

Status convert_lut(const std::string& in, const ConvertOptions& o, std::ostream& out) {
  // --out first: nothing is read or computed for an output that cannot be written.
  const std::string want = o.format == Format::exr ? ".exr" : ".png";
  const std::string out_name = valid_utf8(o.out);
  if (o.out.empty()) return Error{"--out", "", "no output file given", "a " + want + " file"};
  if (extension(o.out) != want)
    return Error{"--out", out_name,
                 "the extension '" + valid_utf8(fs::path(o.out).extension().string()) +
                     "' does not match --format " + (o.format == Format::exr ? "exr" : "png16"),
                 want};
  std::error_code ec;
  if (fs::is_directory(o.out, ec))
    return Error{"--out", out_name, "is a folder", "a " + want + " file"};
  const fs::path parent = fs::path(o.out).parent_path();
  if (!parent.empty() && !fs::is_directory(parent, ec))
    return Error{"--out", out_name,
                 "the folder '" + valid_utf8(parent.string()) + "' does not exist",
                 "a file in an existing folder"};

  auto loaded = load_lut(in);
  if (!loaded) return loaded.error();
  ClampReport clamped;
  auto bytes = encode_lut_image(loaded->lut, in, o.layout, o.origin, o.format, o.clamp, &clamped);
  if (!bytes) return bytes.error();
  if (Status st = write_file_atomic(o.out, *bytes); !st) return st;

  const CubeLut& lut = loaded->lut;
  const int n = lut.size_3d;
  out << "wrote " << out_name << ": " << layout_text(o.layout, o.origin, n) << ", "
      << (o.format == Format::exr ? "OpenEXR float32" : "PNG 16-bit") << " RGB, " << bytes->size()
      << " bytes, from " << valid_utf8(in) << " (LUT_3D_SIZE " << n << ")\n";
  if (clamped.count)
    out << "clamped " << clamped.count << " value(s) outside [0, 1] to [0, 1] (lowest "
        << format_number(clamped.min) << ", highest " << format_number(clamped.max) << ")\n";
  const Rgb zero{0.f, 0.f, 0.f}, one{1.f, 1.f, 1.f};
  if (lut.domain_min_3d != zero || lut.domain_max_3d != one)
    out << "note: the domain is " << domain_text(lut.domain_min_3d, lut.domain_max_3d)
        << ", not [0, 1]: the engine must map its input onto it before the lookup (kept in the "
           "image's "
        << kMetaDomainMin << " and " << kMetaDomainMax << ")\n";
  return {};
}

Result<std::string> lut_info(const std::string& path) {
  auto loaded = load_lut(path);
  if (!loaded) return loaded.error();
  const LoadedLut& l = *loaded;
  const CubeLut& lut = l.lut;
  std::string s = "file: " + valid_utf8(path) + "\n";
  s += "format: " + l.format;
  if (l.layout) s += ", " + layout_text(*l.layout, l.origin, lut.size_3d);
  s += "\n";
  if (l.layout)
    s += std::string("metadata: ") +
         (l.metadata ? "hdrconform lut convert (layout, origin, size, domain, title)"
                     : "none (the layout is taken from the shape, the origin as top, the "
                       "domain as [0, 1])") +
         "\n";
  s += "title: " + (lut.title ? "\"" + *lut.title + "\"" : std::string("(none)")) + "\n";
  bool identity = true;
  if (lut.size_1d) {
    const int n = lut.size_1d;
    s += std::string("1-D table: ") + std::to_string(n) + " points" +
         (lut.size_3d ? " (a shaper: applied first, per channel)" : "") + "\n";
    s += std::string(lut.size_3d ? "1-D input range: " : "1-D domain: ") +
         domain_text(lut.domain_min_1d, lut.domain_max_1d) + "\n";
    Rgb lo, hi;
    min_max(lut.table_1d, &lo, &hi);
    s += "1-D min: " + rgb_text(lo) + "\n1-D max: " + rgb_text(hi) + "\n";
    Deviation d;
    for (int i = 0; i < n; ++i) {
      std::array<double, 3> x;
      for (int k = 0; k < 3; ++k)
        x[k] = coordinate(lut.domain_min_1d[k], lut.domain_max_1d[k], i, n);
      measure(lut.table_1d[i], x, l.storage, "row " + std::to_string(i), &d);
    }
    identity = identity && d.identity;
    s += "1-D identity: " + deviation_text(d, l) + "\n";
  }
  if (lut.size_3d) {
    const int n = lut.size_3d;
    s += "3-D table: " + std::to_string(n) + " x " + std::to_string(n) + " x " + std::to_string(n) +
         " (" + std::to_string(lut.table_3d.size()) + " points, red fastest)\n";
    s += std::string(lut.size_1d ? "3-D input range: " : "3-D domain: ") +
         domain_text(lut.domain_min_3d, lut.domain_max_3d) + "\n";
    Rgb lo, hi;
    min_max(lut.table_3d, &lo, &hi);
    s += "3-D min: " + rgb_text(lo) + "\n3-D max: " + rgb_text(hi) + "\n";
    Deviation d;
    for (int b = 0; b < n; ++b)
      for (int g = 0; g < n; ++g)
        for (int r = 0; r < n; ++r) {
          const std::array<double, 3> x{
              coordinate(lut.domain_min_3d[0], lut.domain_max_3d[0], r, n),
              coordinate(lut.domain_min_3d[1], lut.domain_max_3d[1], g, n),
              coordinate(lut.domain_min_3d[2], lut.domain_max_3d[2], b, n)};
          measure(lut.at(r, g, b), x, l.storage, lattice_text(r, g, b), &d);
        }
    identity = identity && d.identity;
    s += "3-D identity: " + deviation_text(d, l) + "\n";
  }
  s += std::string("identity: ") + (identity ? "yes" : "no") + "\n";
  return s;
}

Status apply_lut_stream(const CubeLut& lut, cube::Interp interp, std::istream& in,
                        std::ostream& out) {
  // Output goes out in blocks, and whenever the input has nothing more buffered (a line typed at
  // a terminal is answered at once).
  std::string pending;
  auto flush = [&](bool force) {
    if (!pending.empty() && (force || pending.size() > (1u << 16) || in.rdbuf()->in_avail() <= 0)) {
      out.write(pending.data(), static_cast<std::streamsize>(pending.size()));
      out.flush();
      pending.clear();
    }
  };
  std::string line;
  for (size_t number = 1; read_bounded_line(in, &line, kMaxApplyLine); ++number) {
    if (line.size() > kMaxApplyLine) {
      flush(true);
      return Error{"<stdin>", "line " + std::to_string(number),
                   "longer than " + std::to_string(kMaxApplyLine) + " characters",
                   "\"R G B\" lines"};
    }
    size_t first = 0;
    while (first < line.size() && is_space(line[first])) ++first;
    if (first == line.size() || line[first] == '#') continue;
    double v[3];
    std::string why;
    if (!parse_rgb(line, v, &why)) {
      flush(true);
      std::string shown = line.size() > 80 ? line.substr(0, 80) + "..." : line;
      while (!shown.empty() && shown.back() == '\r') shown.pop_back();
      return Error{"<stdin>", "line " + std::to_string(number),
                   "expected three numbers \"R G B\", got \"" + valid_utf8(shown) + "\"" +
                       (why.empty() ? "" : " (" + why + ")"),
                   "three decimal numbers, nan and inf accepted"};
    }
    append_rgb(pending, cube::apply(lut, {v[0], v[1], v[2]}, interp));
    flush(false);
  }
  flush(true);
  return {};
}

void add_lut_command(CLI::App& app, std::istream& in, std::ostream& out, std::ostream& err) {
  add_commands(app, in, out, err, false);
}

void add_lut_command(CLI::App& app) {
  add_commands(app, std::cin, std::cout, std::cerr, true);
}

}  // namespace hdrc::lut
