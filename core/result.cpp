#include "core/result.h"

namespace hdrc {

std::string Error::to_string() const {
  std::string s;
  if (!file.empty()) s += file + ": ";
  if (!pointer.empty()) s += pointer + ": ";
  s += message;
  if (!choices.empty()) s += "; valid choices: " + choices;
  return s;
}

}  // namespace hdrc
