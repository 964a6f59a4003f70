// Text from outside the program (a candidate's output, a library's error message, a file name)
// can hold any bytes; JSON, XML and HTML hold only valid UTF-8 (nlohmann aborts a dump with
// type_error.316 on anything else). Such text is made valid here, where it enters.
#pragma once

#include <string>
#include <string_view>

namespace hdrc {

// True when `s` is well-formed UTF-8 (RFC 3629: no overlong forms, no surrogates, <= U+10FFFF).
inline bool is_valid_utf8(std::string_view s) {
  size_t i = 0;
  const size_t n = s.size();
  while (i < n) {
    const auto c = static_cast<unsigned char>(s[i]);
    size_t len = 0;
    unsigned lo = 0x80, hi = 0xBF;  // the allowed range of the second byte
    if (c < 0x80) {
      ++i;
      continue;
    } else if (c >= 0xC2 && c <= 0xDF) {
      len = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
      len = 3;
      if (c == 0xE0) lo = 0xA0;
      if (c == 0xED) hi = 0x9F;  // no UTF-16 surrogates
    } else if (c >= 0xF0 && c <= 0xF4) {
      len = 4;
      if (c == 0xF0) lo = 0x90;
      if (c == 0xF4) hi = 0x8F;
    } else {
      return false;
    }
    if (i + len > n) return false;
    for (size_t k = 1; k < len; ++k) {
      const auto b = static_cast<unsigned char>(s[i + k]);
      if (k == 1 ? (b < lo || b > hi) : (b < 0x80 || b > 0xBF)) return false;
    }
    i += len;
  }
  return true;
}

// `s` with every byte that is not part of a well-formed UTF-8 sequence replaced by U+FFFD, and
// NUL replaced by U+FFFD too (it ends C strings in messages). Valid text is returned unchanged.
inline std::string valid_utf8(std::string_view s) {
  if (is_valid_utf8(s) && s.find('\0') == std::string_view::npos) return std::string(s);
  static constexpr char kReplacement[] = "\xEF\xBF\xBD";
  std::string out;
  out.reserve(s.size() + 8);
  size_t i = 0;
  while (i < s.size()) {
    // The longest prefix (1 to 4 bytes) that is one valid sequence.
    size_t len = 0;
    for (size_t l = 1; l <= 4 && i + l <= s.size(); ++l)
      if (is_valid_utf8(s.substr(i, l))) {
        len = l;
        break;
      }
    if (len == 0 || (len == 1 && s[i] == '\0')) {
      out += kReplacement;
      ++i;
    } else {
      out.append(s.substr(i, len));
      i += len;
    }
  }
  return out;
}

// `text` made safe as XML or HTML character data and attribute values alike: valid UTF-8
// (valid_utf8), & < > " ' as entity references, a line feed as &#10; (kept inside attributes),
// and every other C0 control but tab and CR as a space (XML 1.0 allows none of them).
inline std::string escape_markup(std::string_view text) {
  const std::string s = valid_utf8(text);
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      case '\n':
        out += "&#10;";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\r')
          out += ' ';
        else
          out += c;
    }
  }
  return out;
}

}  // namespace hdrc
