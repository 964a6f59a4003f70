// Measurements of the reference (not tests): the LUT bake's error against the analytic pipeline
// per LUT size and storage format (written to docs/precision.md), and throughput figures.
//   reference_bench precision   — markdown table: baked vs analytic error
//   reference_bench speed       — bake 32³ for devices 0 and 3; probe 1 million pixels
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>

#include "color/st2084.h"
#include "reference/ue/combine_luts.h"
#include "reference/ue/cpp/resolve.h"
#include "reference/ue/tonemap.h"

namespace {

using hdrc::ref::Vec3;

hdrc::ParamBlock params(int device, int size, int format, int layout) {
  hdrc::Case c;
  c.stage = hdrc::find_stage("tonemap");
  c.cvars.set("r.HDR.EnableHDROutput", 1);
  c.cvars.set("r.HDR.Display.OutputDevice", device);
  c.cvars.set("r.HDR.Display.ColorGamut", device == 0 ? 0 : 2);
  c.cvars.set("r.LUT.Size", size);
  c.settings.set("LUTFormat", {static_cast<double>(format), 0, 0, 0}, 1);
  c.settings.set("LUTLayout", {static_cast<double>(layout), 0, 0, 0}, 1);
  return *hdrc::ref::resolve_params(c, 1, 1);
}

// Probe colours: a grey ramp over 1e-4 … 1e4 nits and seeded random colours in log space.
std::vector<Vec3> probe_colours() {
  std::vector<Vec3> v;
  for (int i = 0; i <= 400; ++i) {
    const double x = std::pow(10.0, -6.0 + 8.0 * i / 400.0);
    v.push_back({x, x, x});
  }
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<double> u(-5.0, 1.5);
  for (int i = 0; i < 4000; ++i)
    v.push_back({std::pow(10.0, u(rng)), std::pow(10.0, u(rng)), std::pow(10.0, u(rng))});
  return v;
}

// Error in displayed code values: both sides clamped to [0, 1] as the back buffer stores them,
// then 10-bit PQ codes for device 3, 8-bit sRGB codes for device 0. NaN pairs are counted apart.
double code_error(int device, double a, double b) {
  auto shown = [](double v) { return v < 0.0 ? 0.0 : (v > 1.0 ? 1.0 : v); };
  return std::fabs(shown(a) - shown(b)) * (device == 0 ? 255.0 : 1023.0);
}

void precision() {
  std::printf(
      "| device | LUT size | format | layout | max error | p99.9 | mean | NaN pairs |\n"
      "|---|---|---|---|---|---|---|---|\n");
  const auto colours = probe_colours();
  const char* formats[] = {"A2B10G10R10", "RGBA16F", "RGBA32F"};
  for (int device : {0, 3}) {
    for (int size : {16, 32, 33, 64}) {
      for (int format = 0; format < 3; ++format) {
        for (int layout : {0, 1}) {
          if (layout == 1 && size != 32) continue;
          const auto p = params(device, size, format, layout);
          const auto lut = hdrc::ref::bake_lut(p);
          std::vector<double> errs;
          int nan_pairs = 0;
          for (const Vec3& c : colours) {
            const Vec3 a = hdrc::ref::tonemap_centre_pixel(p, c, nullptr);
            const Vec3 b = hdrc::ref::tonemap_centre_pixel(p, c, &lut);
            for (int k = 0; k < 3; ++k) {
              if (std::isnan(a[k]) || std::isnan(b[k])) {
                ++nan_pairs;
                continue;
              }
              errs.push_back(code_error(device, a[k], b[k]));
            }
          }
          std::sort(errs.begin(), errs.end());
          double sum = 0;
          for (double e : errs) sum += e;
          std::printf("| %d (%s) | %d | %s | %s | %.3f | %.3f | %.4f | %d |\n", device,
                      device == 0 ? "sRGB, 8-bit codes" : "PQ, 10-bit codes", size, formats[format],
                      layout ? "2-D" : "volume", errs.back(),
                      errs[static_cast<size_t>(errs.size() * 0.999)], sum / errs.size(), nan_pairs);
        }
      }
    }
  }
}

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void speed() {
  for (int device : {0, 3}) {
    const auto p = params(device, 32, 0, 0);
    auto t0 = std::chrono::steady_clock::now();
    const auto lut = hdrc::ref::bake_lut(p);
    std::printf("bake 32^3 device %d: %.3f s (%.2f us/texel)\n", device, seconds(t0),
                seconds(t0) / lut.texels.size() * 1e6);
  }
  const auto p = params(3, 32, 0, 0);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-5.0, 1.5);
  double sink = 0;
  auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < 1000000; ++i) {
    const Vec3 c{std::pow(10.0, u(rng)), std::pow(10.0, u(rng)), std::pow(10.0, u(rng))};
    sink += hdrc::ref::tonemap_centre_pixel(p, c, nullptr)[1];
  }
  std::printf("probe 1e6 pixels analytically (device 3): %.2f s (%.2f us/pixel) [%g]\n",
              seconds(t0), seconds(t0), sink);
}

}  // namespace

int main(int argc, char** argv) {
  const bool all = argc < 2;
  if (all || std::strcmp(argv[1], "precision") == 0) precision();
  if (all || std::strcmp(argv[1], "speed") == 0) speed();
  return 0;
}
