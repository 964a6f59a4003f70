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
}  // namespace

Result<Image> make_stimulus(std::string_view name, int width, int height) {
  const StimulusInfo* info = find_stimulus(name);
  if (!info) return Error{"", "", "unknown stimulus '" + std::string(name) + "'", stimulus_names()};
  if (width <= 0) width = info->default_width;
  if (height <= 0) height = info->default_height;
  Image img(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double v = name == "log_ramp" ? log_ramp_value(x, width) : special_ramp_value(x, width);
      double* p = img.px(x, y);
      const int row_kind = y % 4;
      for (int c = 0; c < 3; ++c) p[c] = (row_kind == 0 || row_kind == c + 1) ? v : 0.0;
      p[3] = 1.0;
    }
  }
  return img;
}

}  // namespace hdrc
