#include "core/result.h"

#include <cstdio>

#include "core/utf8.h"

namespace hdrc {

std::string format_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

std::string Error::to_string() const {
  std::string s;
  if (!file.empty()) s += file + ": ";
  if (!pointer.empty()) s += pointer + ": ";
  s += message;
  if (!choices.empty()) s += "; valid choices: " + choices;
  // Messages quote file names, library errors and a candidate's output: any bytes at all.
  return valid_utf8(s);
}

}  // namespace hdrc
