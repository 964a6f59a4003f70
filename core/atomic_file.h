// Writes a whole file or nothing: the text goes to a temporary file beside the target, which is
// renamed over the target only when fully written.
#pragma once

#include <string>

#include "core/result.h"

namespace hdrc {
Status write_file_atomic(const std::string& path, const std::string& contents);
}
