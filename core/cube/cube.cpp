#include "core/cube/cube.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "core/utf8.h"

namespace hdrc::cube {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kWhitespace = " \t\r\f\v";
constexpr const char* kKeywordList =
    "TITLE, LUT_1D_SIZE, LUT_3D_SIZE, DOMAIN_MIN, DOMAIN_MAX, LUT_1D_INPUT_RANGE, "
    "LUT_3D_INPUT_RANGE";
constexpr const char* kNumberChoices = "finite decimal numbers such as 0.5, -2, 1.5e-3";
// The smallest double that rounds to float32 infinity: FLT_MAX plus half its ulp (ties go to the
// even neighbour, and FLT_MAX's significand is odd).
constexpr double kFloatOverflow = 0x1.ffffffp+127;

// The keywords, in the order the writer writes them.
enum Keyword { kTitle, k1DSize, k3DSize, kDomainMin, kDomainMax, k1DRange, k3DRange, kKeywords };
constexpr std::string_view kKeywordNames[kKeywords] = {
    "TITLE",      "LUT_1D_SIZE",        "LUT_3D_SIZE",       "DOMAIN_MIN",
    "DOMAIN_MAX", "LUT_1D_INPUT_RANGE", "LUT_3D_INPUT_RANGE"};

std::string_view trim(std::string_view s) {
  const size_t b = s.find_first_not_of(kWhitespace);
  if (b == std::string_view::npos) return {};
  return s.substr(b, s.find_last_not_of(kWhitespace) - b + 1);
}

// A token or line as messages show it: quoted, at most 40 bytes.
std::string shown(std::string_view t) {
  // Appended, not "'" + ...: GCC 12 -O3 -Wrestrict false positive (bug 105329).
  std::string s = "'";
  s += t.size() > 40 ? t.substr(0, 40) : t;
  s += t.size() > 40 ? "...'" : "'";
  return s;
}

// Whitespace-separated fields. Bounded by the line (kMaxCubeLineBytes).
std::vector<std::string_view> split_fields(std::string_view s) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < s.size()) {
    const size_t b = s.find_first_not_of(kWhitespace, i);
    if (b == std::string_view::npos) break;
    const size_t e = std::min(s.find_first_of(kWhitespace, b), s.size());
    out.push_back(s.substr(b, e - b));
    i = e;
  }
  return out;
}

enum class NumError { none, syntax, nonfinite, range };

// A C-locale decimal (std::from_chars, so no locale), with an optional leading '+' as strtod
// allows, rounded to the nearest float32. NaN/inf spellings parse and are refused as non-finite.
NumError parse_float(std::string_view t, float* out) {
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  if (t.empty() || t[0] == '+') return NumError::syntax;
  double d = 0;
  const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), d);
  if (ec == std::errc::invalid_argument || p != t.data() + t.size()) return NumError::syntax;
  if (ec == std::errc::result_out_of_range) return NumError::range;  // 1e999, 1e-999
  if (!std::isfinite(d)) return NumError::nonfinite;
  if (std::fabs(d) >= kFloatOverflow) return NumError::range;
  // A decimal written with %.9g lies within 5e-9 (relative) of its float, far from the midpoints
  // between floats (2^-25 relative away), so rounding through double gives that float back.
  *out = static_cast<float>(d);
  return NumError::none;
}

class Parser {
 public:
  Parser(std::string file, std::string_view text) : file_(std::move(file)), text_(text) {}

  Result<CubeLut> run();

 private:
  Error err(size_t line, std::string message, std::string choices) const {
    return Error{file_, "line " + std::to_string(line), valid_utf8(message), std::move(choices)};
  }
  // `what` names the value in messages ("DOMAIN_MIN", "3-D table row 5").
  std::optional<Error> number(size_t line, const std::string& what, std::string_view t,
                              float* out) const;
  std::optional<Error> keyword(size_t line, std::string_view text);
  std::optional<Error> size_value(size_t line, Keyword k, const std::vector<std::string_view>& f);
  std::optional<Error> end_of_header(size_t line);
  std::optional<Error> row(size_t line, std::string_view text);
  std::string size_text() const;

  std::string file_;
  std::string_view text_;
  CubeLut lut_;
  size_t seen_[kKeywords] = {};  // line of each keyword, 0 when absent
  size_t data_line_ = 0;         // line of the first row, 0 before it
  size_t expected_rows_ = 0;
  size_t rows_ = 0;
};

std::optional<Error> Parser::number(size_t line, const std::string& what, std::string_view t,
                                    float* out) const {
  switch (parse_float(t, out)) {
    case NumError::none:
      return std::nullopt;
    case NumError::syntax:
      return err(line, what + ": " + shown(t) + " is not a number", kNumberChoices);
    case NumError::nonfinite:
      return err(line, what + ": " + shown(t) + " is not finite (NaN and infinities are refused)",
                 kNumberChoices);
    case NumError::range:
      break;
  }
  return err(line, what + ": " + shown(t) + " is outside the float32 range",
             "finite numbers of magnitude at most 3.40282347e+38");
}

std::string Parser::size_text() const {
  std::string s;
  if (lut_.size_1d) s = "LUT_1D_SIZE " + std::to_string(lut_.size_1d);
  if (lut_.size_1d && lut_.size_3d) s += " + ";
  if (lut_.size_3d) s += "LUT_3D_SIZE " + std::to_string(lut_.size_3d) + "^3";
  return s;
}

std::optional<Error> Parser::size_value(size_t line, Keyword k,
                                        const std::vector<std::string_view>& f) {
  const bool is_1d = k == k1DSize;
  const int lo = is_1d ? kMin1DSize : kMin3DSize;
  const int hi = is_1d ? kMax1DSize : kMax3DSize;
  const std::string name(kKeywordNames[k]);
  const std::string range = std::to_string(lo) + " to " + std::to_string(hi);
  if (f.size() != 2)
    return err(line, name + " takes 1 value, found " + std::to_string(f.size() - 1),
               name + " N, N an integer " + range);
  long long n = 0;
  const auto [p, ec] = std::from_chars(f[1].data(), f[1].data() + f[1].size(), n);
  if (ec == std::errc::invalid_argument || p != f[1].data() + f[1].size())
    return err(line, name + ": " + shown(f[1]) + " is not an integer", "integers " + range);
  if (ec == std::errc::result_out_of_range || n < lo || n > hi)
    return err(line, name + " " + std::string(f[1]) + " is out of range", range);
  (is_1d ? lut_.size_1d : lut_.size_3d) = static_cast<int>(n);
  return std::nullopt;
}

// One keyword line (trimmed, comment still attached). Spec 1.0 and Resolve: keywords precede the
// table data.
std::optional<Error> Parser::keyword(size_t line, std::string_view text) {
  const std::string_view head = text.substr(0, text.find_first_of(kWhitespace));
  int k = 0;
  while (k < kKeywords && kKeywordNames[k] != head) ++k;
  if (k == kKeywords) {
    std::string upper(head.substr(0, 40));
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    std::string hint;
    for (const std::string_view name : kKeywordNames)
      if (name == upper) hint = " (keywords are upper case: " + upper + ")";
    if (data_line_)
      return err(line, "row " + shown(text) + " is not three numbers" + hint,
                 "rows of three numbers: red green blue");
    return err(line, "unknown keyword " + shown(head) + hint, kKeywordList);
  }
  const std::string name(kKeywordNames[k]);
  if (data_line_)
    return err(line,
               "keyword " + name + " after the table data (rows began on line " +
                   std::to_string(data_line_) + ")",
               "keywords before the first row");
  if (seen_[k])
    return err(line, "duplicate " + name + " (first on line " + std::to_string(seen_[k]) + ")",
               "each keyword at most once");
  seen_[k] = line;

  // DOMAIN_* (Iridas) and *_INPUT_RANGE (Resolve) both set the input domain.
  const bool is_domain = k == kDomainMin || k == kDomainMax;
  const bool is_range = k == k1DRange || k == k3DRange;
  for (const int other : {kDomainMin, kDomainMax, k1DRange, k3DRange}) {
    const bool other_domain = other == kDomainMin || other == kDomainMax;
    if (seen_[other] && ((is_domain && !other_domain) || (is_range && other_domain)))
      return err(line,
                 name + " and " + std::string(kKeywordNames[other]) + " (line " +
                     std::to_string(seen_[other]) + ") both set the input domain",
                 "DOMAIN_MIN/DOMAIN_MAX (Iridas) or LUT_1D_INPUT_RANGE/LUT_3D_INPUT_RANGE "
                 "(Resolve), not both");
  }

  if (k == kTitle) {
    // TITLE "text": the text is everything between the quotes, '#' included (spec 1.0).
    const std::string_view rest = trim(text.substr(head.size()));
    if (rest.empty() || rest[0] != '"')
      return err(line, "TITLE expects its text in double quotes, found " + shown(rest),
                 "TITLE \"text\"");
    const size_t close = rest.find('"', 1);
    if (close == std::string_view::npos)
      return err(line, "TITLE's quote is not closed: " + shown(rest), "TITLE \"text\"");
    const std::string_view after = trim(rest.substr(close + 1));
    if (!after.empty() && after[0] != '#')
      return err(line, "text after TITLE's closing quote: " + shown(after),
                 "TITLE \"text\", then nothing or a # comment");
    lut_.title = std::string(rest.substr(1, close - 1));
    return std::nullopt;
  }

  const std::vector<std::string_view> f = split_fields(trim(text.substr(0, text.find('#'))));
  if (k == k1DSize || k == k3DSize) return size_value(line, static_cast<Keyword>(k), f);
  const size_t want = is_domain ? 3 : 2;
  if (f.size() != want + 1)
    return err(
        line,
        name + " takes " + std::to_string(want) + " values, found " + std::to_string(f.size() - 1),
        name + (is_domain ? " r g b" : " min max"));
  float v[3] = {};
  for (size_t i = 0; i < want; ++i)
    if (auto e = number(line, name, f[i + 1], &v[i])) return e;
  if (is_domain) {
    Rgb& d = k == kDomainMin ? lut_.domain_min_1d : lut_.domain_max_1d;
    d = {v[0], v[1], v[2]};
    return std::nullopt;
  }
  if (!(v[0] < v[1]))
    return err(line,
               name + " min " + format_number(v[0]) + " is not below max " + format_number(v[1]),
               "min < max");
  const bool one_d = k == k1DRange;
  (one_d ? lut_.domain_min_1d : lut_.domain_min_3d) = {v[0], v[0], v[0]};
  (one_d ? lut_.domain_max_1d : lut_.domain_max_3d) = {v[1], v[1], v[1]};
  return std::nullopt;
}

// The checks that need the whole header, at the first row (or the end of a file without rows).
std::optional<Error> Parser::end_of_header(size_t line) {
  if (!lut_.size_1d && !lut_.size_3d)
    return err(line, "no LUT_1D_SIZE or LUT_3D_SIZE before the table data",
               "LUT_1D_SIZE N and/or LUT_3D_SIZE N before the rows");
  for (const auto& [k, size] :
       {std::pair{k1DRange, lut_.size_1d}, std::pair{k3DRange, lut_.size_3d}})
    if (seen_[k] && !size)
      return err(seen_[k],
                 std::string(kKeywordNames[k]) + " without " +
                     (k == k1DRange ? "LUT_1D_SIZE" : "LUT_3D_SIZE"),
                 "an INPUT_RANGE for a table the file declares");
  if (seen_[kDomainMin] || seen_[kDomainMax]) {
    const size_t at = std::max(seen_[kDomainMin], seen_[kDomainMax]);
    if (lut_.size_1d && lut_.size_3d)
      return err(at, "DOMAIN_MIN/DOMAIN_MAX in a file with both a 1-D and a 3-D table",
                 "LUT_1D_INPUT_RANGE and LUT_3D_INPUT_RANGE (Resolve) for a 1-D shaper + 3-D "
                 "file");
    static constexpr const char* kChannel[3] = {"red", "green", "blue"};
    for (int c = 0; c < 3; ++c)
      if (!(lut_.domain_min_1d[c] < lut_.domain_max_1d[c]))
        return err(at,
                   "DOMAIN_MIN " + format_number(lut_.domain_min_1d[c]) +
                       " is not below DOMAIN_MAX " + format_number(lut_.domain_max_1d[c]) +
                       " in the " + kChannel[c] + " channel",
                   "DOMAIN_MIN < DOMAIN_MAX in every channel");
    // The parser collected DOMAIN_* in the 1-D fields; it belongs to the file's one table.
    if (lut_.size_3d) {
      lut_.domain_min_3d = lut_.domain_min_1d;
      lut_.domain_max_3d = lut_.domain_max_1d;
      lut_.domain_min_1d = {0.f, 0.f, 0.f};
      lut_.domain_max_1d = {1.f, 1.f, 1.f};
    }
  }
  const size_t n3 = static_cast<size_t>(lut_.size_3d);
  expected_rows_ = static_cast<size_t>(lut_.size_1d) + n3 * n3 * n3;
  // Never more than the text can hold (a row is at least 6 bytes: "0 0 0\n").
  const size_t fit = text_.size() / 6 + 1;
  lut_.table_1d.reserve(std::min(static_cast<size_t>(lut_.size_1d), fit));
  lut_.table_3d.reserve(std::min(n3 * n3 * n3, fit));
  return std::nullopt;
}

std::optional<Error> Parser::row(size_t line, std::string_view text) {
  const bool in_1d = rows_ < static_cast<size_t>(lut_.size_1d);
  if (rows_ >= expected_rows_)
    return err(line,
               "more rows than declared: " + std::to_string(expected_rows_) + " expected (" +
                   size_text() + ")",
               std::to_string(expected_rows_) + " rows");
  const size_t index = in_1d ? rows_ : rows_ - static_cast<size_t>(lut_.size_1d);
  const std::string what =
      std::string(in_1d ? "1-D" : "3-D") + " table row " + std::to_string(index + 1);
  const std::vector<std::string_view> f = split_fields(trim(text.substr(0, text.find('#'))));
  if (f.size() != 3)
    return err(line, what + " has " + std::to_string(f.size()) + " values: " + shown(text),
               "three numbers: red green blue");
  Rgb v{};
  for (int c = 0; c < 3; ++c)
    if (auto e = number(line, what, f[c], &v[c])) return e;
  (in_1d ? lut_.table_1d : lut_.table_3d).push_back(v);
  ++rows_;
  return std::nullopt;
}

Result<CubeLut> Parser::run() {
  if (text_.size() > kMaxCubeFileBytes)
    return Error{file_, "",
                 ".cube text is " + std::to_string(text_.size()) + " bytes, over the limit",
                 "at most " + std::to_string(kMaxCubeFileBytes) + " bytes"};
  size_t line = 0;
  bool any = false;  // a keyword or row seen
  // Bounded by the text: `pos` moves past at least one byte per line.
  for (size_t pos = 0; pos < text_.size();) {
    const size_t nl = std::min(text_.find('\n', pos), text_.size());
    std::string_view raw = text_.substr(pos, nl - pos);
    pos = nl + 1;
    ++line;
    if (!raw.empty() && raw.back() == '\r') raw.remove_suffix(1);
    if (raw.size() > kMaxCubeLineBytes)
      return err(line, "line is " + std::to_string(raw.size()) + " bytes long",
                 "lines of at most " + std::to_string(kMaxCubeLineBytes) + " bytes");
    const std::string_view text = trim(raw);
    if (text.empty() || text[0] == '#') continue;
    any = true;
    // A row starts with a number; NaN/inf spellings are rows, refused there as non-finite.
    const std::string_view head = text.substr(0, text.find_first_of(kWhitespace));
    float ignored = 0;
    const bool word = (std::isalpha(static_cast<unsigned char>(head[0])) || head[0] == '_') &&
                      parse_float(head, &ignored) != NumError::nonfinite;
    if (word) {
      if (auto e = keyword(line, text)) return *e;
      continue;
    }
    if (!data_line_) {
      if (auto e = end_of_header(line)) return *e;
      data_line_ = line;
    }
    if (auto e = row(line, text)) return *e;
  }
  const size_t last = std::max<size_t>(line, 1);
  if (!any)
    return err(last, "empty .cube file: no keywords and no rows",
               "LUT_1D_SIZE N and/or LUT_3D_SIZE N, then the rows");
  if (!data_line_)
    if (auto e = end_of_header(last)) return *e;
  if (rows_ < expected_rows_)
    return err(last,
               "truncated: " + std::to_string(expected_rows_) + " rows expected (" + size_text() +
                   "), " + std::to_string(rows_) + " found",
               std::to_string(expected_rows_) + " rows");
  return std::move(lut_);
}

std::string number_text(float v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(v));
  return buf;
}

bool is_default(const Rgb& lo, const Rgb& hi) {
  return lo == Rgb{0.f, 0.f, 0.f} && hi == Rgb{1.f, 1.f, 1.f};
}
bool uniform(const Rgb& v) {
  return v[0] == v[1] && v[1] == v[2];
}

// Index space of one channel of a table: `x` mapped from [lo, hi] onto [0, n-1] and clamped there;
// NaN gives 0 (see apply()).
double to_index(double x, double lo, double hi, int n) {
  if (std::isnan(x)) return 0.0;
  const double t = (x - lo) / (hi - lo) * (n - 1);
  return std::clamp(t, 0.0, static_cast<double>(n - 1));
}

}  // namespace

Result<CubeLut> parse_cube(const std::string& file, std::string_view text) {
  return Parser(valid_utf8(file), text).run();
}

Result<CubeLut> read_cube_file(const std::string& path) {
  const std::string name = valid_utf8(path);
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st))
    return Error{name, "", "cannot open .cube file: " + (ec ? ec.message() : "it does not exist"),
                 ""};
  if (!fs::is_regular_file(st))
    return Error{name, "", ".cube file is not a regular file", "a regular file"};
  // The size bound is checked before reading; at most that many bytes are read even if the file
  // grows meanwhile.
  const uintmax_t size = fs::file_size(path, ec);
  if (ec) return Error{name, "", "cannot read .cube file: " + ec.message(), ""};
  if (size > kMaxCubeFileBytes)
    return Error{name, "", ".cube file is " + std::to_string(size) + " bytes, over the limit",
                 "at most " + std::to_string(kMaxCubeFileBytes) + " bytes"};
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{name, "", "cannot open .cube file", ""};
  std::string text(static_cast<size_t>(size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  text.resize(static_cast<size_t>(in.gcount()));
  if (in.bad()) return Error{name, "", "cannot read .cube file", ""};
  return parse_cube(path, text);
}

Result<std::string> write_cube(const CubeLut& lut) {
  auto fail = [](const std::string& where, std::string message, std::string choices) {
    return Error{"", where, std::move(message), std::move(choices)};
  };
  if (!lut.size_1d && !lut.size_3d)
    return fail("size", "a .cube LUT needs a 1-D or a 3-D table", "size_1d and/or size_3d set");
  if (lut.size_1d && (lut.size_1d < kMin1DSize || lut.size_1d > kMax1DSize))
    return fail("size_1d", "size_1d " + std::to_string(lut.size_1d) + " is out of range",
                std::to_string(kMin1DSize) + " to " + std::to_string(kMax1DSize));
  if (lut.size_3d && (lut.size_3d < kMin3DSize || lut.size_3d > kMax3DSize))
    return fail("size_3d", "size_3d " + std::to_string(lut.size_3d) + " is out of range",
                std::to_string(kMin3DSize) + " to " + std::to_string(kMax3DSize));
  const size_t n3 = static_cast<size_t>(lut.size_3d);
  if (lut.table_1d.size() != static_cast<size_t>(lut.size_1d) ||
      lut.table_3d.size() != n3 * n3 * n3)
    return fail("table",
                "tables of " + std::to_string(lut.table_1d.size()) + " and " +
                    std::to_string(lut.table_3d.size()) + " rows for sizes " +
                    std::to_string(lut.size_1d) + " and " + std::to_string(lut.size_3d),
                "size_1d rows and size_3d^3 rows");
  if (lut.title && lut.title->find_first_of("\"\r\n") != std::string::npos)
    return fail("title", "title holds a double quote or a line break", "one line without '\"'");
  for (const auto* t : {&lut.table_1d, &lut.table_3d})
    for (const Rgb& v : *t)
      for (const float x : v)
        if (!std::isfinite(x))
          return fail("table", "non-finite value " + format_number(x), "finite values");
  for (const auto& [lo, hi] : {std::pair{&lut.domain_min_1d, &lut.domain_max_1d},
                               std::pair{&lut.domain_min_3d, &lut.domain_max_3d}})
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite((*lo)[c]) || !std::isfinite((*hi)[c]) || !((*lo)[c] < (*hi)[c]))
        return fail("domain",
                    "domain min " + format_number((*lo)[c]) + " is not below max " +
                        format_number((*hi)[c]),
                    "finite min < max in every channel");
  const bool both = lut.size_1d && lut.size_3d;
  if (both && (!uniform(lut.domain_min_1d) || !uniform(lut.domain_max_1d) ||
               !uniform(lut.domain_min_3d) || !uniform(lut.domain_max_3d)))
    return fail("domain", "a 1-D shaper + 3-D file has one input range per table",
                "the same domain min and max in all three channels of each table");
  // A table a file does not have keeps the default domain (the parser gives it that).
  if ((!lut.size_1d && !is_default(lut.domain_min_1d, lut.domain_max_1d)) ||
      (!lut.size_3d && !is_default(lut.domain_min_3d, lut.domain_max_3d)))
    return fail("domain", "a domain for a table the LUT does not have", "the default [0, 1]");

  std::string out;
  out.reserve(40 * (lut.table_1d.size() + lut.table_3d.size()) + 256);
  if (lut.title) out += "TITLE \"" + *lut.title + "\"\n";
  if (lut.size_1d) out += "LUT_1D_SIZE " + std::to_string(lut.size_1d) + "\n";
  if (lut.size_3d) out += "LUT_3D_SIZE " + std::to_string(lut.size_3d) + "\n";
  if (both) {
    // Resolve: one min/max per table.
    if (!is_default(lut.domain_min_1d, lut.domain_max_1d))
      out += "LUT_1D_INPUT_RANGE " + number_text(lut.domain_min_1d[0]) + " " +
             number_text(lut.domain_max_1d[0]) + "\n";
    if (!is_default(lut.domain_min_3d, lut.domain_max_3d))
      out += "LUT_3D_INPUT_RANGE " + number_text(lut.domain_min_3d[0]) + " " +
             number_text(lut.domain_max_3d[0]) + "\n";
  } else {
    // Iridas spec 1.0: DOMAIN_MIN/DOMAIN_MAX, per channel, for the file's one table.
    const Rgb& lo = lut.size_1d ? lut.domain_min_1d : lut.domain_min_3d;
    const Rgb& hi = lut.size_1d ? lut.domain_max_1d : lut.domain_max_3d;
    if (!is_default(lo, hi))
      for (const auto& [name, v] : {std::pair{"DOMAIN_MIN", &lo}, std::pair{"DOMAIN_MAX", &hi}})
        out += std::string(name) + " " + number_text((*v)[0]) + " " + number_text((*v)[1]) + " " +
               number_text((*v)[2]) + "\n";
  }
  for (const auto* t : {&lut.table_1d, &lut.table_3d})
    for (const Rgb& v : *t)
      out += number_text(v[0]) + " " + number_text(v[1]) + " " + number_text(v[2]) + "\n";
  return out;
}

std::array<double, 3> apply(const CubeLut& lut, const std::array<double, 3>& rgb, Interp interp) {
  std::array<double, 3> x = rgb;
  if (lut.size_1d) {
    // Per channel: linear interpolation between the two rows around the input.
    const int n = lut.size_1d;
    for (int c = 0; c < 3; ++c) {
      const double t = to_index(x[c], lut.domain_min_1d[c], lut.domain_max_1d[c], n);
      const int i = std::min(static_cast<int>(t), n - 2);
      const double f = t - i;
      const double a = lut.table_1d[static_cast<size_t>(i)][c];
      const double b = lut.table_1d[static_cast<size_t>(i) + 1][c];
      x[c] = a + f * (b - a);
    }
  }
  if (!lut.size_3d) return x;
  const int n = lut.size_3d;
  std::array<int, 3> i0{};
  std::array<double, 3> f{};
  for (int c = 0; c < 3; ++c) {
    const double t = to_index(x[c], lut.domain_min_3d[c], lut.domain_max_3d[c], n);
    i0[c] = std::min(static_cast<int>(t), n - 2);
    f[c] = t - i0[c];
  }
  auto corner = [&](const std::array<int, 3>& i) -> const Rgb& { return lut.at(i[0], i[1], i[2]); };
  std::array<double, 3> out{};
  if (interp == Interp::trilinear) {
    // Weights of the 8 corners: the product over channels of f or 1 - f.
    for (int k = 0; k < 8; ++k) {
      const std::array<int, 3> d{k & 1, (k >> 1) & 1, (k >> 2) & 1};
      double w = 1.0;
      for (int c = 0; c < 3; ++c) w *= d[c] ? f[c] : 1.0 - f[c];
      const Rgb& v = corner({i0[0] + d[0], i0[1] + d[1], i0[2] + d[2]});
      for (int c = 0; c < 3; ++c) out[c] += w * v[c];
    }
    return out;
  }
  // Tetrahedral: walk from the cube's (0,0,0) corner to (1,1,1) stepping along the axes in the
  // order of decreasing fractional part; the 4 corners visited span the tetrahedron holding the
  // point, with weights 1-f1, f1-f2, f2-f3, f3 (f1 >= f2 >= f3). Ties pick either tetrahedron;
  // both give the same value on their shared face.
  std::array<int, 3> axis{0, 1, 2};
  std::stable_sort(axis.begin(), axis.end(), [&](int a, int b) { return f[a] > f[b]; });
  const double w[4] = {1.0 - f[axis[0]], f[axis[0]] - f[axis[1]], f[axis[1]] - f[axis[2]],
                       f[axis[2]]};
  std::array<int, 3> at = i0;
  for (int step = 0; step < 4; ++step) {
    if (step > 0) ++at[axis[step - 1]];
    const Rgb& v = corner(at);
    for (int c = 0; c < 3; ++c) out[c] += w[step] * v[c];
  }
  return out;
}

}  // namespace hdrc::cube
