// The one way every loader reads a JSON file (cases, defaults, overlays, known limits, coverage,
// params.json, results.json, golden sidecars): a regular file of bounded size, nesting bounded
// before nlohmann sees it, and every nlohmann exception (malformed text, a number that overflows
// a double such as 1e999, ill-formed UTF-8) turned into an Error naming the file.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "core/result.h"

namespace hdrc {

inline constexpr size_t kMaxJsonFileBytes = size_t{64} << 20;  // 64 MiB
// results.json, which a run writes itself at about 10 KB per case: the exhaustive tier's 7,090
// cases write 73 MB. 256 MiB holds 3.5 times that; parsing it takes about 10 bytes of memory per
// byte of text.
inline constexpr size_t kMaxResultsFileBytes = size_t{256} << 20;  // 256 MiB
inline constexpr int kMaxJsonDepth = 100;  // nested arrays/objects; our formats need under 10

// Reads a whole input file: it must be a regular file (not a FIFO, device or folder) of at most
// `max_bytes`. `what` names it in errors ("case file", "candidate image"). Errors carry the OS
// reason.
Result<std::string> read_bounded_file(const std::string& path, size_t max_bytes,
                                      const std::string& what);

// Rejects text nested deeper than kMaxJsonDepth (found without recursion), naming the line.
Status check_json_nesting(const std::string& file, const std::string& text);

// Parses `text` (read from `file`) into J (nlohmann::json or nlohmann::ordered_json).
template <class J>
Result<J> parse_json_text(const std::string& file, const std::string& text) {
  if (Status st = check_json_nesting(file, text); !st) return st.error();
  try {
    return J::parse(text);
  } catch (const nlohmann::json::exception& e) {
    std::string why = e.what();
    if (e.id == 406) why += " (numbers must fit a double: at most about 1.8e308)";
    return Error{file, "", "malformed JSON: " + why, ""};
  }
}

// read_bounded_file + parse_json_text.
template <class J>
Result<J> read_json_file(const std::string& path, const std::string& what = "JSON file",
                         size_t max_bytes = kMaxJsonFileBytes) {
  auto text = read_bounded_file(path, max_bytes, what);
  if (!text) return text.error();
  return parse_json_text<J>(path, *text);
}

// JSON text for writing: any ill-formed UTF-8 left in a string is replaced by U+FFFD instead of
// aborting (nlohmann's type_error.316). `indent` as for nlohmann's dump.
template <class J>
std::string dump_json(const J& j, int indent = -1) {
  return j.dump(indent, ' ', false, J::error_handler_t::replace);
}

}  // namespace hdrc
