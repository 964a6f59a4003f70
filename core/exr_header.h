// A bounds check of an OpenEXR file's headers before OpenEXR reads them. OpenEXR 3.1 (Debian 12)
// allocates what a header declares before it reads it: an attribute declaring 2 GB in a 500-byte
// file makes it allocate and clear 2 GB (found by fuzz/image_fuzzer: 11 s and 1.2 GB for one
// file), and a huge data window makes it allocate its offset table. This walks the headers
// (OpenEXR file layout: magic, version, then per part attributes `name\0 type\0 int32 size,
// value`, ended by an empty name) without allocating from declared sizes, and refuses a file whose
// attribute runs past its end or whose data window is larger than `max_pixels`.
#pragma once

#include <cstddef>
#include <string>

#include "core/result.h"

namespace hdrc {

// The largest data window the check lets OpenEXR see (4096 x 4096).
inline constexpr size_t kMaxExrHeaderPixels = size_t{4096} * 4096;
// The widest or tallest data window it lets through: a 256-edge LUT's strip (256² × 256), the
// widest image of the suite. OpenEXR's line compressors allocate a chunk of lines of that width.
inline constexpr long long kMaxExrDimension = 65536;

// Ok when `path` is not an OpenEXR file (no EXR magic number) or its headers are within bounds;
// otherwise an error naming the file, the part and the attribute.
Status check_exr_header(const std::string& path, size_t max_pixels = kMaxExrHeaderPixels);

}  // namespace hdrc
