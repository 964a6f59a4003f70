// golden_deviation GOLDENS_DIR OUT_DIR...: how far the reference images of runs (OUT/cases/<id>/
// reference.exr, written by `hdrconform run --engine reference --out OUT`) are from the goldens,
// in the measures docs/goldens.md weighs for the golden comparison's bound. A measurement, not a
// test: docs/goldens.md records its output for builds of several compilers and optimisation
// levels.
//
// Per value (float32 golden g, reference r):
//   ulps         distance in float32 units in the last place (what `float_close` counts);
//   abs          |g - r|;
//   of_image     |g - r| / (2^-24 * S), S = the image's largest finite |colour value|;
//   of_pixel     |g - r| / (2^-24 * P), P = the pixel's largest finite |colour value| (R, G, B).
// Prints, per run folder: the number of values over 2 ulps, the largest of each measure, and the
// worst values by `ulps`.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "core/image.h"
#include "runner/golden_compare.h"

namespace fs = std::filesystem;

namespace {

long long ulps(float a, float b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b) ? 0 : INT32_MAX;
  if (a == b) return 0;
  if (std::isinf(a) || std::isinf(b)) return INT32_MAX;
  return hdrc::ulp_distance(a, b);
}

struct Worst {
  long long ulps = 0;
  std::string id;
  size_t index = 0;
  float g = 0, r = 0;
  double of_image = 0, of_pixel = 0;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: golden_deviation GOLDENS_DIR OUT_DIR...\n");
    return 2;
  }
  const fs::path goldens = argv[1];
  for (int a = 2; a < argc; ++a) {
    const fs::path cases = fs::path(argv[a]) / "cases";
    size_t images = 0, values = 0, over2 = 0, nonfinite_mismatch = 0;
    double max_abs = 0, max_of_image = 0, max_of_pixel = 0;
    long long max_ulps = 0;
    std::vector<Worst> worst;
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(cases, ec);
         it != fs::recursive_directory_iterator(); ++it) {
      if (it->path().filename() != "reference.exr") continue;
      const std::string id = fs::relative(it->path().parent_path(), cases).generic_string();
      const fs::path gpath = goldens / (id + ".exr");
      if (!fs::exists(gpath)) continue;
      auto ref = hdrc::read_image(it->path().string());
      auto gold = hdrc::read_image(gpath.string());
      if (!ref || !gold || ref->data.size() != gold->data.size()) {
        std::printf("  %s: unreadable or sizes differ\n", id.c_str());
        continue;
      }
      ++images;
      double scale = 0;
      for (size_t i = 0; i < gold->data.size(); ++i)
        if (i % 4 != 3 && std::isfinite(gold->data[i]))
          scale = std::max(scale, std::fabs(gold->data[i]));
      for (size_t i = 0; i < gold->data.size(); ++i) {
        const float g = static_cast<float>(gold->data[i]), r = static_cast<float>(ref->data[i]);
        ++values;
        const long long u = ulps(g, r);
        if (u == INT32_MAX) {
          ++nonfinite_mismatch;
          continue;
        }
        if (u == 0) continue;
        const size_t px = i / 4 * 4;
        double pixel = 0;
        for (int c = 0; c < 3; ++c)
          if (std::isfinite(gold->data[px + c]))
            pixel = std::max(pixel, std::fabs(gold->data[px + c]));
        const double d = std::fabs(static_cast<double>(g) - r);
        const double unit = std::ldexp(1.0, -24);
        const double of_image = scale > 0 ? d / (unit * scale) : INFINITY;
        const double of_pixel = pixel > 0 ? d / (unit * pixel) : INFINITY;
        max_abs = std::max(max_abs, d);
        max_ulps = std::max(max_ulps, u);
        max_of_image = std::max(max_of_image, of_image);
        if (i % 4 != 3) max_of_pixel = std::max(max_of_pixel, of_pixel);
        if (u > 2) {
          ++over2;
          worst.push_back({u, id, i, g, r, of_image, of_pixel});
        }
      }
    }
    std::sort(worst.begin(), worst.end(),
              [](const Worst& x, const Worst& y) { return x.ulps > y.ulps; });
    std::printf(
        "%s: %zu images, %zu values; max %lld ulps, max abs %.3g, max %.3g of image scale, "
        "max %.3g of pixel scale (units of 2^-24); %zu values over 2 ulps; %zu non-finite "
        "mismatches\n",
        argv[a], images, values, max_ulps, max_abs, max_of_image, max_of_pixel, over2,
        nonfinite_mismatch);
    for (size_t k = 0; k < worst.size() && k < 12; ++k) {
      const Worst& w = worst[k];
      std::printf(
          "  %s [%zu %c]: golden %.9g reference %.9g, %lld ulps, %.3g of image, %.3g "
          "of pixel\n",
          w.id.c_str(), w.index / 4, "RGBA"[w.index % 4], w.g, w.r, w.ulps, w.of_image, w.of_pixel);
    }
  }
  return 0;
}
