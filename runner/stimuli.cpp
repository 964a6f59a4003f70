#include "runner/stimuli.h"

#include <cmath>
#include <limits>

namespace hdrc {

const std::vector<StimulusInfo>& stimulus_table() {
  static const std::vector<StimulusInfo> table = {
      {"log_ramp", 1024, 4,
       "log-luminance ramp, 1e-4 to 1e4 nits (linear 1e-6 to 100) evenly in log10"},
      {"special_ramp", 256, 4,
       "linear ramp over [-1, 2] with NaN, +Inf, -Inf, -0 and a denormal every 8th pixel"},
      {"pq_codes", 1024, 4,
       "every 10-bit PQ code value once per row: x / 1023 (back-buffer signals, not scene-linear)"},
      {"ui_overlay", 256, 8,
       "premultiplied sRGB-encoded UI: alpha ramps 0..1 along x, rows white, red, green, blue, "
       "grey, a hard-edged opaque/transparent checker, and alpha 0 and 1 rows"},
  };
  return table;
}

const StimulusInfo* find_stimulus(std::string_view name) {
  for (const auto& s : stimulus_table())
    if (s.name == name) return &s;
  return nullptr;
}

std::string stimulus_names() {
  std::string out;
  for (const auto& s : stimulus_table()) out += (out.empty() ? "" : ", ") + std::string(s.name);
  return out;
}

namespace {
double log_ramp_value(int x, int width) {
  const double t = width > 1 ? static_cast<double>(x) / (width - 1) : 0.0;
  const double nits = std::pow(10.0, -4.0 + 8.0 * t);
  return nits / 100.0;
}

double special_ramp_value(int x, int width) {
  if (x % 8 == 7) {
    constexpr double kSpecials[] = {std::numeric_limits<double>::quiet_NaN(),
                                    std::numeric_limits<double>::infinity(),
                                    -std::numeric_limits<double>::infinity(), -0.0,
                                    // the smallest positive float32 normal / 4: a float denormal
                                    1.1754943508222875e-38 / 4.0};
    return kSpecials[(x / 8) % 5];
  }
  const double t = width > 1 ? static_cast<double>(x) / (width - 1) : 0.0;
  return -1.0 + 3.0 * t;
}
// UI overlay rows (premultiplied alpha, sRGB-encoded colour as Slate renders it).
void ui_overlay_pixel(int x, int y, int width, double* p) {
  const double ramp = width > 1 ? static_cast<double>(x) / (width - 1) : 0.0;
  static const double colours[5][3] = {{1, 1, 1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.5, 0.5, 0.5}};
  const int row = y % 8;
  double a = ramp;
  const double* c = colours[row < 5 ? row : 0];
  if (row == 5) a = ((x / 8) % 2) ? 1.0 : 0.0;  // hard premultiplied edges
  if (row == 6) a = 0.0;
  if (row == 7) a = 1.0;
  for (int k = 0; k < 3; ++k) p[k] = c[k] * a;
  p[3] = a;
}

}  // namespace

Result<Image> make_stimulus(std::string_view name, int width, int height) {
  const StimulusInfo* info = find_stimulus(name);
  if (!info) return Error{"", "", "unknown stimulus '" + std::string(name) + "'", stimulus_names()};
  if (width <= 0) width = info->default_width;
  if (height <= 0) height = info->default_height;
  Image img(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      double* p = img.px(x, y);
      if (name == "ui_overlay") {
        ui_overlay_pixel(x, y, width, p);
        continue;
      }
      const double v = name == "log_ramp"   ? log_ramp_value(x, width)
                       : name == "pq_codes" ? (width > 1 ? x * 1023.0 / (width - 1) : 0.0) / 1023.0
                                            : special_ramp_value(x, width);
      const int row_kind = y % 4;
      for (int c = 0; c < 3; ++c) p[c] = (row_kind == 0 || row_kind == c + 1) ? v : 0.0;
      p[3] = 1.0;
    }
  }
  return img;
}

}  // namespace hdrc
