#include "core/image.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <mutex>
#include <unordered_map>

#include "core/exr_header.h"
#include "core/utf8.h"

namespace hdrc {

namespace {

std::string oiio_error(std::string text) {
  // OpenEXR quotes corrupt channel and attribute names byte for byte.
  return valid_utf8(text);
}

}  // namespace

Result<Image> read_image(const std::string& path) {
  const std::string name = valid_utf8(path);
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int err = errno;
    return Error{name, "", std::string("cannot open image: ") + std::strerror(err), ""};
  }
  if (!S_ISREG(st.st_mode))
    return Error{name, "", "the image is not a regular file", "a regular image file"};
  if (static_cast<unsigned long long>(st.st_size) > kMaxImageFileBytes)
    return Error{name, "", "the image file is " + std::to_string(st.st_size) + " bytes",
                 "at most " + std::to_string(kMaxImageFileBytes) + " bytes"};
  const bool exr_name = std::filesystem::path(path).extension() == ".exr";
  if (exr_name) {
    // OpenEXR's magic number (OpenEXR file layout: 0x76, 0x2f, 0x31, 0x01).
    unsigned char magic[4] = {0, 0, 0, 0};
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    const ssize_t n = fd >= 0 ? ::read(fd, magic, sizeof magic) : -1;
    if (fd >= 0) ::close(fd);
    if (n != 4 || magic[0] != 0x76 || magic[1] != 0x2f || magic[2] != 0x31 || magic[3] != 0x01)
      return Error{name, "", "not an OpenEXR file (no EXR magic number)", "an OpenEXR image"};
  }
  // OpenEXR allocates what a header declares before reading it (core/exr_header.h).
  if (exr_name)
    if (Status hs = check_exr_header(path); !hs) {
      Error e = hs.error();
      e.file = name;
      e.message = valid_utf8(e.message);
      return e;
    }
  auto in = OIIO::ImageInput::open(path);
  if (!in) return Error{name, "", "cannot open image: " + oiio_error(OIIO::geterror()), ""};
  const OIIO::ImageSpec& spec = in->spec();
  if (exr_name && std::string(in->format_name()) != "openexr")
    return Error{name, "", std::string("a *.exr file read as ") + in->format_name(),
                 "an OpenEXR image"};
  if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1 ||
      static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height) > kMaxImagePixels)
    return Error{name, "",
                 "the image is " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                     (spec.depth > 1 ? "x" + std::to_string(spec.depth) : ""),
                 "at most " + std::to_string(kMaxImagePixels) + " pixels (4096x4096), 2D"};
  if (spec.nchannels < 3) {
    return Error{name, "", "image has " + std::to_string(spec.nchannels) + " channel(s)",
                 "3 (RGB) or 4 (RGBA) channels"};
  }
  std::string names;
  for (int c = 0; c < spec.nchannels && c < 8; ++c)
    names += (c ? "," : "") + std::string(spec.channel_name(c));
  if (spec.nchannels > 8) names += ",...";
  if (spec.channel_name(0) != "R" || spec.channel_name(1) != "G" || spec.channel_name(2) != "B")
    return Error{name, "", "the image's channels are " + oiio_error(names),
                 "R,G,B or R,G,B,A (first, in that order)"};
  const int nch = spec.nchannels >= 4 && spec.channel_name(3) == "A" ? 4 : 3;
  std::vector<float> pixels(static_cast<size_t>(spec.width) * spec.height * nch);
  if (!in->read_image(0, 0, 0, nch, OIIO::TypeDesc::FLOAT, pixels.data())) {
    return Error{name, "", "cannot read pixels: " + oiio_error(in->geterror()), ""};
  }
  Image img(spec.width, spec.height);
  for (size_t i = 0; i < img.pixel_count(); ++i) {
    for (int c = 0; c < 4; ++c) {
      img.data[i * 4 + c] = c < nch ? pixels[i * nch + c] : 1.0;
    }
  }
  return img;
}

Status write_exr(const std::string& path, const Image& image, int zip_level) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  std::error_code ec;
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  const std::string tmp = path + ".tmp" + std::to_string(::getpid()) + ".exr";
  OIIO::ImageSpec spec(image.width, image.height, Image::kChannels, OIIO::TypeDesc::FLOAT);
  spec.attribute("compression", zip_level < 0
                                    ? std::string("zip")
                                    : "zip:" + std::to_string(std::clamp(zip_level, 1, 9)));
  // No time in the header (OpenImageIO's EXR writer stamps DateTime, capDate, with the time of
  // writing unless the spec sets it): the file is a function of the pixels, so an image written
  // again with the same pixels has the same bytes (goldens: git shows no change).
  spec.attribute("DateTime", "");
  std::vector<float> pixels(image.data.begin(), image.data.end());
  auto out = OIIO::ImageOutput::create(tmp);
  if (!out || !out->open(tmp, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) ||
      !out->close()) {
    std::string why = out ? out->geterror() : OIIO::geterror();
    fs::remove(tmp, ec);
    return Error{valid_utf8(path), "", "cannot write EXR: " + valid_utf8(why), ""};
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    fs::remove(tmp, ec);
    return Error{path, "", "cannot move the written EXR into place: " + ec.message(), ""};
  }
  return {};
}

namespace written_images {
namespace {

struct Kept {
  int width = 0, height = 0;
  std::vector<float> rgba;
};

struct Store {
  std::mutex m;
  std::unordered_map<std::string, Kept> images;
  size_t bytes = 0, capacity = 0;
};

Store& store() {
  static Store s;
  return s;
}

std::string key_of(const std::string& path) {
  return std::filesystem::path(path).lexically_normal().string();
}

}  // namespace

void set_capacity(size_t bytes) {
  std::lock_guard lock(store().m);
  store().capacity = bytes;
}

void keep(const std::string& path, const Image& image) {
  const size_t bytes = image.data.size() * sizeof(float);
  const std::string key = key_of(path);
  Store& s = store();
  std::lock_guard lock(s.m);
  if (auto it = s.images.find(key); it != s.images.end()) {  // written again: the newer values
    s.bytes -= it->second.rgba.size() * sizeof(float);
    s.images.erase(it);
  }
  if (bytes > s.capacity - std::min(s.capacity, s.bytes)) return;
  s.images.emplace(key, Kept{image.width, image.height,
                             std::vector<float>(image.data.begin(), image.data.end())});
  s.bytes += bytes;
}

std::optional<Image> take(const std::string& path) {
  Kept k;
  {
    Store& s = store();
    std::lock_guard lock(s.m);
    auto it = s.images.find(key_of(path));
    if (it == s.images.end()) return std::nullopt;
    k = std::move(it->second);
    s.images.erase(it);
    s.bytes -= k.rgba.size() * sizeof(float);
  }
  Image img(k.width, k.height);
  std::copy(k.rgba.begin(), k.rgba.end(), img.data.begin());
  return img;
}

void forget(const std::string& path) {
  Store& s = store();
  std::lock_guard lock(s.m);
  if (auto it = s.images.find(key_of(path)); it != s.images.end()) {
    s.bytes -= it->second.rgba.size() * sizeof(float);
    s.images.erase(it);
  }
}

void clear() {
  Store& s = store();
  std::lock_guard lock(s.m);
  s.images.clear();
  s.bytes = 0;
}

size_t bytes_kept() {
  std::lock_guard lock(store().m);
  return store().bytes;
}

}  // namespace written_images

}  // namespace hdrc
