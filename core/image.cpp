#include "core/image.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <memory>

#include "core/exr_header.h"

namespace hdrc {

Result<Image> read_image(const std::string& path) {
  // OpenEXR allocates what a header declares before reading it (core/exr_header.h).
  if (Status st = check_exr_header(path); !st) return st.error();
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    return Error{path, "", "cannot open image: " + OIIO::geterror(), ""};
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.nchannels < 3) {
    return Error{path, "", "image has " + std::to_string(spec.nchannels) + " channel(s)",
                 "3 (RGB) or 4 (RGBA) channels"};
  }
  std::vector<float> pixels(static_cast<size_t>(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data())) {
    return Error{path, "", "cannot read pixels: " + in->geterror(), ""};
  }
  Image img(spec.width, spec.height);
  for (size_t i = 0; i < img.pixel_count(); ++i) {
    for (int c = 0; c < 4; ++c) {
      img.data[i * 4 + c] = c < spec.nchannels ? pixels[i * spec.nchannels + c] : 1.0;
    }
  }
  return img;
}

Status write_exr(const std::string& path, const Image& image) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  std::error_code ec;
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  const std::string tmp = path + ".tmp" + std::to_string(::getpid()) + ".exr";
  OIIO::ImageSpec spec(image.width, image.height, Image::kChannels, OIIO::TypeDesc::FLOAT);
  spec.attribute("compression", "zip");
  std::vector<float> pixels(image.data.begin(), image.data.end());
  auto out = OIIO::ImageOutput::create(tmp);
  if (!out || !out->open(tmp, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) ||
      !out->close()) {
    std::string why = out ? out->geterror() : OIIO::geterror();
    fs::remove(tmp, ec);
    return Error{path, "", "cannot write EXR: " + why, ""};
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    fs::remove(tmp, ec);
    return Error{path, "", "cannot move the written EXR into place: " + ec.message(), ""};
  }
  return {};
}

}  // namespace hdrc
