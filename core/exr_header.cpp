#include "core/exr_header.h"

#include <cstdint>
#include <cstring>
#include <fstream>

namespace hdrc {

namespace {

// Reads a NUL-terminated name of at most `max_len` characters; false at EOF or when longer.
bool read_name(std::istream& in, size_t max_len, std::string* out) {
  out->clear();
  for (char c; in.get(c);) {
    if (c == '\0') return true;
    if (out->size() >= max_len) return false;
    out->push_back(c);
  }
  return false;
}

int32_t le32(const unsigned char* p) {
  return static_cast<int32_t>(uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 |
                              uint32_t(p[3]) << 24);
}

}  // namespace

Status check_exr_header(const std::string& path, size_t max_pixels) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};  // the reader reports why it cannot open the file
  in.seekg(0, std::ios::end);
  const long long file_size = static_cast<long long>(in.tellg());
  in.seekg(0);
  unsigned char head[8];
  if (!in.read(reinterpret_cast<char*>(head), 8) || head[0] != 0x76 || head[1] != 0x2f ||
      head[2] != 0x31 || head[3] != 0x01)
    return {};  // not OpenEXR: another reader's business
  const uint32_t flags = uint32_t(le32(head + 4));
  const size_t max_name = flags & 0x400 ? 255 : 31;  // "long names" bit
  const bool multipart = flags & 0x1000;
  auto fail = [&](const std::string& what) {
    return Error{path, "", "corrupt OpenEXR header: " + what, "a valid OpenEXR image"};
  };
  constexpr int kMaxParts = 64, kMaxAttributes = 1024;
  for (int part = 0;; ++part) {
    if (part >= kMaxParts) return fail("more than " + std::to_string(kMaxParts) + " parts");
    const std::string where = multipart ? " (part " + std::to_string(part) + ")" : "";
    std::string name, type;
    for (int n = 0;; ++n) {
      if (n >= kMaxAttributes)
        return fail("more than " + std::to_string(kMaxAttributes) + " attributes" + where);
      if (!read_name(in, max_name, &name))
        return fail("an attribute name is unterminated or too long" + where);
      if (name.empty()) break;  // end of this header
      if (!read_name(in, max_name, &type))
        return fail("the type of attribute '" + name + "' is unterminated or too long" + where);
      unsigned char sz[4];
      if (!in.read(reinterpret_cast<char*>(sz), 4))
        return fail("attribute '" + name + "' has no size" + where);
      const long long size = le32(sz), left = file_size - static_cast<long long>(in.tellg());
      if (size < 0 || size > left)
        return fail("attribute '" + name + "' declares " + std::to_string(size) + " bytes, " +
                    std::to_string(left) + " remain in the file" + where);
      if ((name == "dataWindow" || name == "displayWindow") && type == "box2i" && size == 16) {
        unsigned char box[16];
        in.read(reinterpret_cast<char*>(box), 16);
        const long long w = static_cast<long long>(le32(box + 8)) - le32(box) + 1;
        const long long h = static_cast<long long>(le32(box + 12)) - le32(box + 4) + 1;
        if (name == "dataWindow" &&
            (w <= 0 || h <= 0 || static_cast<unsigned long long>(w) * h > max_pixels))
          return fail("the data window is " + std::to_string(w) + "x" + std::to_string(h) +
                      ", at most " + std::to_string(max_pixels) + " pixels are read" + where);
        // OpenEXR's line compressors allocate a chunk's lines (up to 32, PIZ/B44; 16 ZIP) of the
        // window's width before any pixel is read: a 16M × 1 window passes the pixel limit and
        // asks ZIP for 2 GB (found by fuzz/image_fuzzer). No image of the suite is wider or taller
        // than a 256-edge LUT's strip (65 536 × 256).
        if (name == "dataWindow" && (w > kMaxExrDimension || h > kMaxExrDimension))
          return fail("the data window is " + std::to_string(w) + "x" + std::to_string(h) +
                      ", at most " + std::to_string(kMaxExrDimension) + " pixels wide and high" +
                      where);
      } else if (type == "chlist") {
        // OpenEXR reads a channel list by its structure (entries `name\0` + 16 bytes up to an
        // empty name), not by the declared size, and reads the next attribute from where the list
        // ends: walk it the same way, or a list declaring more bytes than it holds hides the
        // attributes after it (a 16M-wide data window, found by fuzz/image_fuzzer) from this check.
        const long long end = static_cast<long long>(in.tellg()) + size;
        std::string channel;
        for (int c = 0;; ++c) {
          if (c > kMaxAttributes)
            return fail("attribute '" + name + "' lists more than " +
                        std::to_string(kMaxAttributes) + " channels" + where);
          if (!read_name(in, max_name, &channel) || static_cast<long long>(in.tellg()) > end)
            return fail("attribute '" + name + "' holds an unterminated channel name" + where);
          if (channel.empty()) break;
          unsigned char entry[16];
          if (!in.read(reinterpret_cast<char*>(entry), 16) ||
              static_cast<long long>(in.tellg()) > end)
            return fail("attribute '" + name + "' ends inside channel '" + channel + "'" + where);
        }
      } else if (name == "chunkCount" && type == "int" && size == 4) {
        // The offset table holds 8 bytes per chunk, and OpenEXR allocates it first.
        unsigned char v[4];
        in.read(reinterpret_cast<char*>(v), 4);
        if (le32(v) < 0 || static_cast<long long>(le32(v)) * 8 > file_size)
          return fail("chunkCount is " + std::to_string(le32(v)) + ", the file has " +
                      std::to_string(file_size) + " bytes" + where);
      } else {
        in.seekg(size, std::ios::cur);
      }
    }
    if (!multipart) return {};
    // Multi-part: the list of headers ends with an empty header (a lone NUL).
    const int next = in.peek();
    if (next == std::char_traits<char>::eof()) return fail("the list of parts is unterminated");
    if (next == 0) return {};
  }
}

}  // namespace hdrc
