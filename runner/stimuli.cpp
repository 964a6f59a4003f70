#include "runner/stimuli.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>

#include "color/st2084.h"
#include "core/nearest.h"
#include "reference/color/ue_matrices.h"

namespace hdrc {

namespace {
using PK = ParamKind;
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

const std::vector<StimulusInfo>& stimulus_table() {
  static const std::vector<StimulusInfo> table = {
      {"log_ramp",
       1024,
       4,
       "log-luminance ramp from min_nits to max_nits, evenly in log10 along x; rows cycle grey, "
       "red, green, blue",
       {{"min_nits", PK::kNumber, {1e-4}, 1e-9, 1e9, {}, "nits at x = 0"},
        {"max_nits", PK::kNumber, {1e4}, 1e-9, 1e9, {}, "nits at the last column"}}},
      {"special_ramp",
       256,
       4,
       "linear ramp over [min, max] with NaN, +Inf, -Inf, -0 and a float32 denormal every 8th "
       "pixel; rows cycle grey, red, green, blue",
       {{"min", PK::kNumber, {-1.0}, -1e6, 1e6, {}, "linear value at x = 0"},
        {"max", PK::kNumber, {2.0}, -1e6, 1e6, {}, "linear value at the last column"}}},
      {"pq_codes",
       1024,
       4,
       "every 10-bit PQ code value c / 1023, in raster order: pixel i holds code i mod 1024; each "
       "block of 1024 pixels is grey, red, green, blue in turn (back-buffer signals, not "
       "scene-linear); needs at least 1024 pixels",
       {}},
      {"hue_sweep",
       360,
       4,
       "fully saturated hues (HSV, hue 0-360 along x, saturation `saturation`) scaled so their "
       "Rec.709 luminance is each of `luminances` nits; the rows are split evenly among the "
       "luminances",
       {{"luminances", PK::kNumberList, {1.0, 18.0, 100.0, 1000.0}, 1e-6, 1e6, {}, "nits"},
        {"saturation", PK::kNumber, {1.0}, 0.0, 1.0, {}, "HSV saturation"}}},
      {"colorchecker",
       96,
       20,
       "the 24 ColorChecker patches (BabelColor 2006 sRGB values, decoded to linear) across x, "
       "one row band per exposure in `exposures` (stops: linear x 2^EV)",
       {{"exposures", PK::kNumberList, {-4.0, -2.0, 0.0, 2.0, 4.0}, -20.0, 20.0, {}, "EV stops"}}},
      {"primaries",
       48,
       10,
       "saturated primaries and secondaries R, G, B, C, M, Y of `gamut` along x, one row band per "
       "scale in `scales`, converted to the working colour space (AP1 and Rec.2020 colours fall "
       "outside sRGB: negative components)",
       {{"gamut", PK::kChoice, {0}, 0, 2, {"srgb", "ap1", "rec2020"}, "source gamut"},
        {"scales",
         PK::kNumberList,
         {0.01, 0.18, 1.0, 10.0, 100.0},
         -1e6,
         1e6,
         {},
         "linear multipliers k (1 = 100 nits)"}}},
      {"near_black",
       256,
       4,
       "linear ramp from 0 to max_nits (the log shaper's black offset and PQ's steep toe); rows "
       "cycle grey, red, green, blue",
       {{"max_nits", PK::kNumber, {0.01}, 0.0, 1e6, {}, "nits at the last column"}}},
      {"above_peak",
       256,
       4,
       "log ramp from min_nits to max_nits, above the display peak and PQ's 10 000 nits; rows "
       "cycle grey, red, green, blue",
       {{"min_nits", PK::kNumber, {1000.0}, 1e-9, 1e12, {}, "nits at x = 0"},
        {"max_nits", PK::kNumber, {1e6}, 1e-9, 1e12, {}, "nits at the last column"}}},
      {"pq_lattice",
       0,
       0,
       "an n^3 lattice uniform in PQ: channel value ST2084ToLinear(k / (n - 1)) / 100 for k = 0 "
       "... n-1; lattice point (r, g, b) at raster index r + n b + n^2 g (the LUT's layout at "
       "the default size n^2 x n); needs at least n^3 pixels",
       {{"n", PK::kInteger, {9}, 2, 65, {}, "lattice points per axis"}}},
      {"random",
       64,
       16,
       "seeded random colours, log-uniform per channel between min_nits and max_nits "
       "(splitmix64, so every platform draws the same numbers)",
       {{"seed", PK::kInteger, {1}, 0, 4294967295.0, {}, "generator seed"},
        {"min_nits", PK::kNumber, {1e-3}, 1e-9, 1e9, {}, "smallest value"},
        {"max_nits", PK::kNumber, {1e4}, 1e-9, 1e9, {}, "largest value"}}},
      {"ui_overlay",
       256,
       8,
       "premultiplied sRGB-encoded UI: alpha ramps 0..1 along x, rows white, red, green, blue, "
       "grey, a hard-edged opaque/transparent checker, and alpha 0 and 1 rows",
       {{"transparent_rgb",
         PK::kNumber,
         {0.0},
         0.0,
         1.0,
         {},
         "colour of the alpha-0 row, x (1, 0.5, 0.25): 0 premultiplied black; > 0 a colour "
         "a premultiplied texel cannot hold (UE 5.8's composite zeroes it)"}}},
      {"ui_srgb_codes",
       256,
       4,
       "every 8-bit sRGB code c / 255 from min_code to max_code as an opaque grey UI (alpha 1, so "
       "the premultiplied texel is the code itself), in raster order: pixel i holds code min_code "
       "+ i mod (max_code - min_code + 1) (the UI EOTF's decode at every code Slate's 8-bit UI "
       "can hold: its linear segment, codes 0-10, and the darkest codes above 0.04045, where a "
       "rounded sRGB offset moves the decode most); needs a pixel per code",
       {{"min_code", PK::kInteger, {0.0}, 0.0, 255.0, {}, "the first 8-bit code"},
        {"max_code", PK::kInteger, {255.0}, 0.0, 255.0, {}, "the last 8-bit code"}}},
      {"bloom",
       64,
       16,
       "a smooth bloom texture: three coloured Gaussian glows (warm, cool, white) at fixed "
       "fractions of the image, peak `intensity` x (2, 1, 4)",
       {{"intensity", PK::kNumber, {1.0}, 0.0, 1e6, {}, "linear scale of the glows"}}},
  };
  return table;
}

const StimulusInfo* find_stimulus(std::string_view name) {
  for (const auto& s : stimulus_table())
    if (s.name == name) return &s;
  return nullptr;
}

const StimulusParam* find_stimulus_param(const StimulusInfo& info, std::string_view name) {
  for (const auto& p : info.params)
    if (p.name == name) return &p;
  return nullptr;
}

std::string stimulus_names() {
  std::string out;
  for (const auto& s : stimulus_table()) out += (out.empty() ? "" : ", ") + std::string(s.name);
  return out;
}

std::string stimulus_param_names(const StimulusInfo& info) {
  std::string out;
  for (const auto& p : info.params) out += (out.empty() ? "" : ", ") + std::string(p.name);
  return out.empty() ? "none" : out;
}

std::vector<double> stimulus_param(const StimulusInfo& info, const StimulusParams& params,
                                   std::string_view name) {
  auto it = params.find(std::string(name));
  if (it != params.end()) return it->second;
  const StimulusParam* p = find_stimulus_param(info, name);
  return p ? p->default_value : std::vector<double>{};
}

void stimulus_default_size(const StimulusInfo& info, const StimulusParams& params, int* width,
                           int* height) {
  if (info.name == "pq_lattice") {
    const int n = static_cast<int>(stimulus_param(info, params, "n")[0]);
    *width = n * n;
    *height = n;
    return;
  }
  *width = info.default_width;
  *height = info.default_height;
}

Status check_stimulus(const StimulusInfo& info, const StimulusParams& params, int width,
                      int height) {
  for (const auto& [name, values] : params) {
    const StimulusParam* p = find_stimulus_param(info, name);
    if (!p) {
      std::vector<std::string> names;
      for (const auto& q : info.params) names.emplace_back(q.name);
      const auto near = nearest_names(name, names, 1);
      return Error{"", "",
                   "unknown parameter '" + name + "' of stimulus " + std::string(info.name) +
                       (near.empty() ? "" : ", did you mean '" + near[0] + "'?"),
                   stimulus_param_names(info)};
    }
    const std::string range = format_number(p->min_value) + " to " + format_number(p->max_value);
    if (values.empty() || (p->kind != PK::kNumberList && values.size() != 1))
      return Error{"", "", "parameter " + name + " takes one value", ""};
    for (double v : values) {
      if (p->kind == PK::kChoice) {
        if (!(v >= 0 && v < static_cast<double>(p->choices.size()) && v == std::floor(v)))
          return Error{"", "", "parameter " + name + " has no choice " + format_number(v), ""};
        continue;
      }
      if (p->kind == PK::kInteger && v != std::floor(v))
        return Error{"", "", "parameter " + name + " is an integer, got " + format_number(v),
                     "integers " + range};
      if (!(v >= p->min_value && v <= p->max_value))
        return Error{"", "", "parameter " + name + " = " + format_number(v) + " is out of range",
                     range};
    }
  }
  for (const char* lo_hi : {"nits", ""}) {
    const std::string lo = std::string("min") + (*lo_hi ? "_nits" : "");
    const std::string hi = std::string("max") + (*lo_hi ? "_nits" : "");
    if (find_stimulus_param(info, lo) && find_stimulus_param(info, hi) &&
        !(stimulus_param(info, params, lo)[0] < stimulus_param(info, params, hi)[0]))
      return Error{"", "", lo + " must be below " + hi, ""};
  }
  const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
  if (info.name == "pq_codes" && pixels < 1024)
    return Error{"", "",
                 "pq_codes needs at least 1024 pixels to hold every 10-bit code, got " +
                     std::to_string(width) + "x" + std::to_string(height),
                 "width x height >= 1024"};
  if (info.name == "ui_srgb_codes") {
    const double lo = stimulus_param(info, params, "min_code")[0],
                 hi = stimulus_param(info, params, "max_code")[0];
    if (!(lo <= hi)) return Error{"", "", "min_code must not be above max_code", ""};
    const size_t n = static_cast<size_t>(hi - lo) + 1;
    if (pixels < n)
      return Error{"", "",
                   "ui_srgb_codes with codes " + format_number(lo) + " to " + format_number(hi) +
                       " needs at least " + std::to_string(n) + " pixels, got " +
                       std::to_string(width) + "x" + std::to_string(height),
                   "width x height >= max_code - min_code + 1"};
  }
  if (info.name == "pq_lattice") {
    const size_t n = static_cast<size_t>(stimulus_param(info, params, "n")[0]);
    if (pixels < n * n * n)
      return Error{"", "",
                   "pq_lattice with n = " + std::to_string(n) + " needs " +
                       std::to_string(n * n * n) + " pixels, got " + std::to_string(width) + "x" +
                       std::to_string(height),
                   "width x height >= n^3 (default size n^2 x n)"};
  }
  return {};
}

namespace stimulus_data {

const std::vector<ColorCheckerPatch>& colorchecker24() {
  // Pascale 2006 (BabelColor), Table 3, sRGB 8-bit column.
  static const std::vector<ColorCheckerPatch> patches = {
      {"dark skin", 115, 82, 68},   {"light skin", 194, 150, 130},  {"blue sky", 98, 122, 157},
      {"foliage", 87, 108, 67},     {"blue flower", 133, 128, 177}, {"bluish green", 103, 189, 170},
      {"orange", 214, 126, 44},     {"purplish blue", 80, 91, 166}, {"moderate red", 193, 90, 99},
      {"purple", 94, 60, 108},      {"yellow green", 157, 188, 64}, {"orange yellow", 224, 163, 46},
      {"blue", 56, 61, 150},        {"green", 70, 148, 73},         {"red", 175, 54, 60},
      {"yellow", 231, 199, 31},     {"magenta", 187, 86, 149},      {"cyan", 8, 133, 161},
      {"white 9.5", 243, 243, 242}, {"neutral 8", 200, 200, 200},   {"neutral 6.5", 160, 160, 160},
      {"neutral 5", 122, 122, 121}, {"neutral 3.5", 85, 85, 85},    {"black 2", 52, 52, 52},
  };
  return patches;
}

double srgb_decode(double v) {
  // IEC 61966-2-1:1999 §5.2 (the inverse of the encoding), exact constants.
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

double rec709_luminance(double r, double g, double b) {
  return 0.2126 * r + 0.7152 * g + 0.0722 * b;
}

}  // namespace stimulus_data

namespace {

// Rows of the ramps cycle through (v, v, v), (v, 0, 0), (0, v, 0), (0, 0, v).
void coloured(double v, int y, double* p) {
  const int kind = y % 4;
  for (int c = 0; c < 3; ++c) p[c] = (kind == 0 || kind == c + 1) ? v : 0.0;
  p[3] = 1.0;
}

double along(int x, int width) {
  return width > 1 ? static_cast<double>(x) / (width - 1) : 0.0;
}

double log_interp(double lo, double hi, double t) {
  return std::pow(10.0, std::log10(lo) + (std::log10(hi) - std::log10(lo)) * t);
}

double special_ramp_value(int x, int width, double lo, double hi) {
  if (x % 8 == 7) {
    constexpr double kSpecials[] = {std::numeric_limits<double>::quiet_NaN(), kInf, -kInf, -0.0,
                                    // the smallest positive float32 normal / 4: a float denormal
                                    1.1754943508222875e-38 / 4.0};
    return kSpecials[(x / 8) % 5];
  }
  return lo + (hi - lo) * along(x, width);
}

// UI overlay rows (premultiplied alpha, sRGB-encoded colour as Slate renders it).
void ui_overlay_pixel(int x, int y, int width, double transparent_rgb, double* p) {
  const double ramp = along(x, width);
  static const double colours[5][3] = {{1, 1, 1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.5, 0.5, 0.5}};
  const int row = y % 8;
  double a = ramp;
  const double* c = colours[row < 5 ? row : 0];
  if (row == 5) a = ((x / 8) % 2) ? 1.0 : 0.0;  // hard premultiplied edges
  if (row == 6) a = 0.0;
  if (row == 7) a = 1.0;
  for (int k = 0; k < 3; ++k) p[k] = c[k] * a;
  p[3] = a;
  if (row == 6 && transparent_rgb != 0.0) {
    static const double kTint[3] = {1.0, 0.5, 0.25};
    for (int k = 0; k < 3; ++k) p[k] = transparent_rgb * kTint[k];
  }
}

// HSV (value 1) to RGB, hue in degrees [0, 360).
void hue_rgb(double hue, double saturation, double* rgb) {
  const double h = std::fmod(hue, 360.0) / 60.0;
  const int sector = static_cast<int>(std::floor(h));
  const double f = h - sector;
  const double p = 1.0 - saturation, q = 1.0 - saturation * f, t = 1.0 - saturation * (1.0 - f);
  const double table[6][3] = {{1, t, p}, {q, 1, p}, {p, 1, t}, {p, q, 1}, {t, p, 1}, {1, p, q}};
  for (int c = 0; c < 3; ++c) rgb[c] = table[sector % 6][c];
}

// splitmix64 (Steele, Lea, Flood, "Fast splittable pseudorandom number generators", OOPSLA 2014):
// fully specified, so the random stimulus is the same on every platform (unlike <random>'s
// distributions).
struct SplitMix64 {
  uint64_t state;
  uint64_t next() {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
};

ref::Mat3 gamut_to_working(int gamut) {
  using namespace ref;
  switch (gamut) {
    case 1:
      // AP1 → working: the FromAP1 matrix UE's working colour space holds (float-cast), so the
      // pipeline's ToAP1 maps the stimulus back onto the AP1 primary.
      return make_working_color_space(standard::kSrgb).from_ap1;
    case 2:
      return standard::rgb_to_rgb(standard::kRec2020, standard::kSrgb);
    default:
      return Mat3::identity();
  }
}

}  // namespace

Result<Image> make_stimulus(std::string_view name, int width, int height,
                            const StimulusParams& params) {
  const StimulusInfo* info = find_stimulus(name);
  if (!info) return Error{"", "", "unknown stimulus '" + std::string(name) + "'", stimulus_names()};
  int dw = 0, dh = 0;
  stimulus_default_size(*info, params, &dw, &dh);
  if (width <= 0) width = dw;
  if (height <= 0) height = dh;
  if (Status st = check_stimulus(*info, params, width, height); !st) return st.error();
  auto param = [&](const char* p) { return stimulus_param(*info, params, p); };
  Image img(width, height);

  if (name == "log_ramp" || name == "above_peak") {
    const double lo = param("min_nits")[0], hi = param("max_nits")[0];
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        coloured(log_interp(lo, hi, along(x, width)) / 100.0, y, img.px(x, y));
  } else if (name == "special_ramp") {
    const double lo = param("min")[0], hi = param("max")[0];
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        coloured(special_ramp_value(x, width, lo, hi), y, img.px(x, y));
  } else if (name == "near_black") {
    const double hi = param("max_nits")[0] / 100.0;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) coloured(hi * along(x, width), y, img.px(x, y));
  } else if (name == "pq_codes") {
    for (size_t i = 0; i < img.pixel_count(); ++i) {
      double* p = &img.data[i * 4];
      const double v = static_cast<double>(i % 1024) / 1023.0;
      const int kind = static_cast<int>((i / 1024) % 4);
      for (int c = 0; c < 3; ++c) p[c] = (kind == 0 || kind == c + 1) ? v : 0.0;
      p[3] = 1.0;
    }
  } else if (name == "hue_sweep") {
    const auto lums = param("luminances");
    const double sat = param("saturation")[0];
    for (int y = 0; y < height; ++y) {
      const double nits = lums[static_cast<size_t>(y) * lums.size() / height];
      for (int x = 0; x < width; ++x) {
        double* p = img.px(x, y);
        hue_rgb(360.0 * x / width, sat, p);
        const double scale = (nits / 100.0) / stimulus_data::rec709_luminance(p[0], p[1], p[2]);
        for (int c = 0; c < 3; ++c) p[c] *= scale;
        p[3] = 1.0;
      }
    }
  } else if (name == "colorchecker") {
    const auto ev = param("exposures");
    const auto& patches = stimulus_data::colorchecker24();
    for (int y = 0; y < height; ++y) {
      const double gain = std::exp2(ev[static_cast<size_t>(y) * ev.size() / height]);
      for (int x = 0; x < width; ++x) {
        const auto& patch = patches[static_cast<size_t>(x) * patches.size() / width];
        double* p = img.px(x, y);
        p[0] = stimulus_data::srgb_decode(patch.r / 255.0) * gain;
        p[1] = stimulus_data::srgb_decode(patch.g / 255.0) * gain;
        p[2] = stimulus_data::srgb_decode(patch.b / 255.0) * gain;
        p[3] = 1.0;
      }
    }
  } else if (name == "primaries") {
    const ref::Mat3 to_working = gamut_to_working(static_cast<int>(param("gamut")[0]));
    const auto scales = param("scales");
    static const ref::Vec3 kColours[6] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1},
                                          {0, 1, 1}, {1, 0, 1}, {1, 1, 0}};
    for (int y = 0; y < height; ++y) {
      const double k = scales[static_cast<size_t>(y) * scales.size() / height];
      for (int x = 0; x < width; ++x) {
        const ref::Vec3& c = kColours[static_cast<size_t>(x) * 6 / width];
        const ref::Vec3 w = to_working * ref::Vec3{c[0] * k, c[1] * k, c[2] * k};
        double* p = img.px(x, y);
        for (int ch = 0; ch < 3; ++ch) p[ch] = w[ch];
        p[3] = 1.0;
      }
    }
  } else if (name == "pq_lattice") {
    const size_t n = static_cast<size_t>(param("n")[0]);
    for (size_t i = 0; i < img.pixel_count(); ++i) {
      const size_t li = i % (n * n * n);
      const size_t idx[3] = {li % n, li / (n * n), (li / n) % n};  // r, g, b
      double* p = &img.data[i * 4];
      for (int c = 0; c < 3; ++c)
        p[c] = ref::st2084::nits_from_pq(static_cast<double>(idx[c]) / (n - 1)) / 100.0;
      p[3] = 1.0;
    }
  } else if (name == "random") {
    SplitMix64 rng{static_cast<uint64_t>(param("seed")[0])};
    const double lo = std::log(param("min_nits")[0]), hi = std::log(param("max_nits")[0]);
    for (size_t i = 0; i < img.pixel_count(); ++i) {
      double* p = &img.data[i * 4];
      for (int c = 0; c < 3; ++c) p[c] = std::exp(lo + (hi - lo) * rng.uniform()) / 100.0;
      p[3] = 1.0;
    }
  } else if (name == "ui_overlay") {
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        ui_overlay_pixel(x, y, width, param("transparent_rgb")[0], img.px(x, y));
  } else if (name == "ui_srgb_codes") {
    const size_t lo = static_cast<size_t>(param("min_code")[0]);
    const size_t n = static_cast<size_t>(param("max_code")[0]) - lo + 1;
    for (size_t i = 0; i < img.pixel_count(); ++i) {
      double* p = &img.data[i * 4];
      for (int c = 0; c < 3; ++c) p[c] = static_cast<double>(lo + i % n) / 255.0;
      p[3] = 1.0;
    }
  } else if (name == "bloom") {
    struct Glow {
      double cx, cy, sigma, r, g, b, peak;
    };
    static const Glow kGlows[3] = {{0.25, 0.35, 0.12, 1.0, 0.6, 0.3, 2.0},
                                   {0.70, 0.60, 0.20, 0.3, 0.5, 1.0, 1.0},
                                   {0.50, 0.80, 0.08, 1.0, 1.0, 1.0, 4.0}};
    const double intensity = param("intensity")[0];
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        double* p = img.px(x, y);
        const double u = (x + 0.5) / width, v = (y + 0.5) / height;
        for (const Glow& g : kGlows) {
          const double d2 = (u - g.cx) * (u - g.cx) + (v - g.cy) * (v - g.cy);
          const double a = intensity * g.peak * std::exp(-d2 / (2.0 * g.sigma * g.sigma));
          p[0] += a * g.r;
          p[1] += a * g.g;
          p[2] += a * g.b;
        }
        p[3] = 1.0;
      }
  }
  return img;
}

}  // namespace hdrc
