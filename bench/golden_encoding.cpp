// Which lossless EXR encoding keeps the goldens smallest (docs/goldens.md, "Size"): every golden
// under GOLDENS is written again with each candidate encoding through OpenImageIO, read back, and
// kept as a candidate only where every value reads back bit for bit as the golden's float32 value
// (lossless for that file). Prints the total bytes of each encoding over the files it is lossless
// for, and of the best lossless encoding per file.
//
//   golden_encoding GOLDENS [TMPDIR]
//
// Candidates: 32-bit float with ZIP (OpenEXR's default level, and 9), ZIPS, PIZ, RLE, none;
// 16-bit half with ZIP and PIZ (lossless only for goldens whose every value is a half, e.g. the
// LUTs of a half storage format); RGB without the alpha channel (float ZIP and PIZ) where alpha
// is 1 everywhere (core/image.cpp read_image gives an RGB file alpha 1).
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/image.h"

namespace fs = std::filesystem;

namespace {

struct Encoding {
  const char* name;
  OIIO::TypeDesc type;
  const char* compression;
  bool rgb;  // alpha dropped
};

// Writes `rgba` (width x height x 4 float32) with `e` to `path`; its size, or 0 on failure.
uintmax_t write_with(const std::string& path, const std::vector<float>& rgba, int w, int h,
                     const Encoding& e) {
  const int nch = e.rgb ? 3 : 4;
  OIIO::ImageSpec spec(w, h, nch, e.type);
  spec.attribute("compression", e.compression);
  spec.attribute("DateTime", "");
  std::vector<float> px;
  if (e.rgb) {
    px.reserve(static_cast<size_t>(w) * h * 3);
    for (size_t i = 0; i < rgba.size(); i += 4) px.insert(px.end(), &rgba[i], &rgba[i + 3]);
  }
  auto out = OIIO::ImageOutput::create(path);
  if (!out || !out->open(path, spec) ||
      !out->write_image(OIIO::TypeDesc::FLOAT, e.rgb ? px.data() : rgba.data()) || !out->close())
    return 0;
  std::error_code ec;
  return fs::file_size(path, ec);
}

bool same_bits(const std::vector<float>& a, const hdrc::Image& b) {
  if (a.size() != b.data.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    const float y = static_cast<float>(b.data[i]);
    if (std::memcmp(&a[i], &y, 4) != 0) return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: golden_encoding GOLDENS [TMPDIR]\n");
    return 2;
  }
  const std::string dir = argv[1];
  const std::string tmp =
      (argc > 2 ? fs::path(argv[2]) : fs::temp_directory_path()) / "golden_encoding.exr";
  const std::vector<Encoding> encodings = {
      {"float zip (default level)", OIIO::TypeDesc::FLOAT, "zip", false},
      {"float zip:9", OIIO::TypeDesc::FLOAT, "zip:9", false},
      {"float zips", OIIO::TypeDesc::FLOAT, "zips", false},
      {"float piz", OIIO::TypeDesc::FLOAT, "piz", false},
      {"float rle", OIIO::TypeDesc::FLOAT, "rle", false},
      {"float none", OIIO::TypeDesc::FLOAT, "none", false},
      {"half zip (lossless files only)", OIIO::TypeDesc::HALF, "zip", false},
      {"half piz (lossless files only)", OIIO::TypeDesc::HALF, "piz", false},
      {"float RGB zip (alpha 1 only)", OIIO::TypeDesc::FLOAT, "zip", true},
      {"float RGB piz (alpha 1 only)", OIIO::TypeDesc::FLOAT, "piz", true},
  };
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file() && e.path().extension() == ".exr") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  uintmax_t current = 0, best = 0, sidecars = 0;
  std::vector<uintmax_t> total(encodings.size(), 0), same_files(encodings.size(), 0);
  std::vector<size_t> lossless(encodings.size(), 0);
  std::map<std::string, size_t> best_count;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file() && e.path().extension() != ".exr") sidecars += e.file_size();
  for (const fs::path& f : files) {
    auto img = hdrc::read_image(f.string());
    if (!img) {
      std::fprintf(stderr, "%s\n", img.error().to_string().c_str());
      return 1;
    }
    const uintmax_t now = fs::file_size(f);
    current += now;
    std::vector<float> rgba(img->data.begin(), img->data.end());
    uintmax_t file_best = now;
    std::string best_name = "as committed";
    for (size_t k = 0; k < encodings.size(); ++k) {
      const uintmax_t size = write_with(tmp, rgba, img->width, img->height, encodings[k]);
      auto back = size ? hdrc::read_image(tmp) : hdrc::Result<hdrc::Image>(hdrc::Error{});
      const bool ok = size && back && same_bits(rgba, *back);
      if (ok) {
        ++lossless[k];
        total[k] += size;
        same_files[k] += now;
        if (size < file_best) {
          file_best = size;
          best_name = encodings[k].name;
        }
      }
    }
    best += file_best;
    ++best_count[best_name];
  }
  std::error_code ec;
  fs::remove(tmp, ec);
  std::printf("%zu goldens under %s: EXR %ju bytes as committed, sidecars and others %ju bytes\n",
              files.size(), dir.c_str(), current, sidecars);
  std::printf("%-34s %8s %14s %14s %8s\n", "encoding", "lossless", "bytes", "committed", "ratio");
  for (size_t k = 0; k < encodings.size(); ++k)
    std::printf("%-34s %8zu %14ju %14ju %8.3f\n", encodings[k].name, lossless[k], total[k],
                same_files[k], same_files[k] ? double(total[k]) / same_files[k] : 0.0);
  std::printf("best lossless encoding per file: %ju bytes (%.3f of the committed EXRs)\n", best,
              current ? double(best) / current : 0.0);
  for (const auto& [name, n] : best_count) std::printf("  %5zu files: %s\n", n, name.c_str());
  return 0;
}
