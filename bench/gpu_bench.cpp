// Measurements of the Vulkan engine (not tests; nothing here asserts).
//   gpu_bench speed    — throughput of the LUT bake (32³, each format) and of the Tonemap pass
//                        (1920×1080, CombineLUTs + Tonemap), seconds per engine run (median)
//   gpu_bench lut      — the baked LUT read back from the GPU against the reference's bake, per
//                        device, gamut, size, format and layout: values that differ, NaN on one
//                        side only, p99.9 and max difference in 10-bit code units
//   gpu_bench dither   — the dither stage against the reference on a flat grey: pixels whose grain
//                        differs (beyond float32 rounding of the sum), p99.9 and max difference
// Options: --device NAME|INDEX (default lavapipe), --shader-dir DIR.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "gpu/vulkan_engine.h"
#include "reference/reference_engine.h"
#include "reference/ue/combine_luts.h"
#include "reference/ue/cpp/resolve.h"
#include "reference/ue/tonemap.h"

namespace {

using Clock = std::chrono::steady_clock;

hdrc::ResolvedCase make_case(const char* stage, int device, int gamut, int size, int format,
                             int layout, hdrc::Image input) {
  hdrc::ResolvedCase rc;
  rc.spec.id = "bench";
  rc.spec.stage = hdrc::find_stage(stage);
  rc.spec.cvars.set("r.HDR.EnableHDROutput", 1);
  rc.spec.cvars.set("r.HDR.Display.OutputDevice", device);
  rc.spec.cvars.set("r.HDR.Display.ColorGamut", gamut);
  rc.spec.cvars.set("r.LUT.Size", size);
  rc.spec.settings.set("LUTFormat", {static_cast<double>(format), 0, 0, 0}, 1);
  rc.spec.settings.set("LUTLayout", {static_cast<double>(layout), 0, 0, 0}, 1);
  rc.spec.settings.set("FrameIndex", {3, 0, 0, 0}, 1);
  if (std::string(stage) == "combine_luts") input = hdrc::Image(size * size, size);
  rc.params = *hdrc::ref::resolve_params(rc.spec, input.width, input.height);
  rc.input = std::move(input);
  return rc;
}

// Scene colours over 1e-4 … 1e4 nits along x, hue varying along y.
hdrc::Image scene(int w, int h) {
  hdrc::Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double v = static_cast<float>(std::pow(10.0, -6.0 + 8.0 * x / (w - 1)));
      const double t = 6.2831853 * y / h;
      double* p = img.px(x, y);
      p[0] = v * (0.6 + 0.4 * std::cos(t));
      p[1] = v * (0.6 + 0.4 * std::cos(t + 2.094));
      p[2] = v * (0.6 + 0.4 * std::cos(t + 4.189));
      p[3] = 1.0;
    }
  return img;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Seconds per run: the first run (pipeline compilation) apart, then the median of `reps`.
void time_runs(hdrc::gpu::VulkanEngine& engine, const hdrc::ResolvedCase& rc, const char* what,
               double work_items, const char* unit, int reps) {
  auto t0 = Clock::now();
  auto first = engine.run(rc);
  const double first_s = std::chrono::duration<double>(Clock::now() - t0).count();
  if (!first) {
    std::printf("%-44s error: %s\n", what, first.error().to_string().c_str());
    return;
  }
  std::vector<double> s;
  for (int i = 0; i < reps; ++i) {
    t0 = Clock::now();
    auto out = engine.run(rc);
    s.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  const double m = median(s);
  std::printf("%-44s first %.3f s, then %.4f s (median of %d) = %.2f M%s/s\n", what, first_s, m,
              reps, work_items / m / 1e6, unit);
}

void speed(hdrc::gpu::VulkanEngine& engine) {
  std::printf("device: %s (%s)\n", engine.device().device.c_str(), engine.device().driver.c_str());
  const char* formats[] = {"A2B10G10R10", "RGBA16F", "RGBA32F"};
  for (int device : {0, 3})
    for (int format : {0, 1, 2}) {
      const std::string what =
          "LUT bake 32^3, device " + std::to_string(device) + ", " + formats[format] + ", volume";
      time_runs(engine, make_case("combine_luts", device, 2, 32, format, 0, {}), what.c_str(),
                32.0 * 32 * 32, "texel", 9);
    }
  const hdrc::Image hd = scene(1920, 1080);
  for (int device : {0, 3}) {
    const std::string what = "tonemap 1920x1080 (bake 32^3 + pass), dev " + std::to_string(device);
    time_runs(engine, make_case("tonemap", device, 2, 32, 0, 0, hd), what.c_str(), 1920.0 * 1080,
              "pixel", 5);
  }
  // The engine's fixed cost at that size (buffers, upload, read back): a trivial stage.
  time_runs(engine, make_case("shaper", 0, 2, 32, 0, 0, hd), "shaper 1920x1080 (engine overhead)",
            1920.0 * 1080, "pixel", 5);
  // The reference for comparison (double precision, one thread).
  hdrc::ref::ReferenceEngine ref;
  for (int device : {0, 3}) {
    auto rc = make_case("tonemap", device, 2, 32, 0, 0, hd);
    auto t0 = Clock::now();
    auto out = ref.run(rc);
    std::printf("reference tonemap 1920x1080, dev %d: %.3f s\n", device,
                std::chrono::duration<double>(Clock::now() - t0).count());
  }
}

void lut(hdrc::gpu::VulkanEngine& engine) {
  // Differences of stored values in 10-bit code units (×1023), whatever the format: the stored
  // value is the display signal / 1.05, so this is the error a 10-bit output would see. NaN on one
  // side only is counted apart (the reference's NaN texels: docs/ue55-decisions.md D-NaN).
  std::printf(
      "| device | gamut | N | format | layout | values differing | NaN on one side | p99.9 "
      "(codes) | max (codes) | worst at (r,g,b)ch: reference / GPU |\n"
      "|---|---|---|---|---|---|---|---|---|---|\n");
  const char* formats[] = {"10-bit UNORM", "RGBA16F", "RGBA32F"};
  for (int format : {0, 1, 2})
    for (int layout : {0, 1})
      for (int device = 0; device <= 9; ++device)
        for (int gamut : {0, 2})
          for (int n : {16, 32, 33}) {
            if (n != 32 && gamut != 2) continue;
            auto rc = make_case("combine_luts", device, gamut, n, format, layout, {});
            auto got = engine.run(rc);
            if (!got) {
              std::printf("| %d | %d | %d | %s | %d | error: %s |\n", device, gamut, n,
                          formats[format], layout, got.error().to_string().c_str());
              continue;
            }
            const hdrc::Image want = hdrc::ref::lut_image(hdrc::ref::bake_lut(rc.params));
            size_t differing = 0, nan_one_side = 0, at = 0;
            std::vector<double> codes;
            double worst = 0.0;
            for (size_t i = 0; i < want.data.size(); ++i) {
              if (i % 4 == 3) continue;
              const double a = want.data[i], b = got->data[i];
              if (std::isnan(a) != std::isnan(b)) {
                ++nan_one_side;
                continue;
              }
              const double d = std::isnan(a) ? 0.0 : std::fabs(a - b) * 1023.0;
              if (d > 0) ++differing;
              codes.push_back(d);
              if (d > worst) worst = d, at = i;
            }
            std::sort(codes.begin(), codes.end());
            const size_t px = at / 4;
            const int x = static_cast<int>(px % (n * n)), y = static_cast<int>(px / (n * n));
            std::printf(
                "| %d | %d | %d | %s | %s | %zu of %zu | %zu | %.3g | %.3g | (%d,%d,%d)%c: "
                "%.9g / %.9g |\n",
                device, gamut, n, formats[format], layout ? "2-D" : "volume", differing,
                want.data.size() / 4 * 3, nan_one_side,
                codes.empty() ? 0.0 : codes[codes.size() * 999 / 1000], worst, x % n, y, x / n,
                "RGB"[at % 4], want.data[at], got->data[at]);
          }
}

void dither(hdrc::gpu::VulkanEngine& engine) {
  hdrc::ref::ReferenceEngine ref;
  for (int device : {0, 3})
    for (int frame : {0, 3, 7})
      for (int size : {64, 1920}) {
        const int h = size == 64 ? 64 : 1080;
        hdrc::Image grey(size, h);
        for (double& v : grey.data) v = 0.5;
        auto rc = make_case("dither", device, 2, 32, 0, 0, grey);
        rc.spec.settings.set("FrameIndex", {static_cast<double>(frame), 0, 0, 0}, 1);
        rc.params = *hdrc::ref::resolve_params(rc.spec, size, h);
        auto got = engine.run(rc);
        auto want = ref.run(rc);
        if (!got || !want) {
          std::printf("dither dev %d frame %d: error\n", device, frame);
          continue;
        }
        size_t differ = 0;
        double worst = 0;
        std::vector<double> diffs;
        for (size_t i = 0; i < rc.input.pixel_count(); ++i) {
          const double d = std::fabs(got->data[i * 4] - want->data[i * 4]);
          // Above float32 rounding of the sum (0.5 + grain · amount): the grain itself differs.
          if (d > 1e-3 * rc.params.dither_amount) ++differ;
          diffs.push_back(d);
          worst = std::max(worst, d);
        }
        std::sort(diffs.begin(), diffs.end());
        const double amount = rc.params.dither_amount;
        std::printf(
            "dither dev %d frame %d %dx%d (amount 1/%.0f): grain differs at %zu of %zu pixels "
            "(%.3f %%); "
            "p99.9 %.3g, max %.3g = %.3f x amount\n",
            device, frame, size, h, 1.0 / amount, differ, diffs.size(),
            100.0 * differ / diffs.size(), diffs[diffs.size() * 999 / 1000], worst, worst / amount);
      }
}

}  // namespace

int main(int argc, char** argv) {
  std::string mode = argc > 1 ? argv[1] : "speed";
  hdrc::gpu::VulkanOptions o;
  for (int i = 2; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--device") == 0) o.device = argv[i + 1];
    if (std::strcmp(argv[i], "--shader-dir") == 0) o.shader_dir = argv[i + 1];
  }
  hdrc::gpu::VulkanEngine engine(o);
  if (auto st = engine.init(); !st) {
    std::fprintf(stderr, "gpu_bench: %s\n", st.error().to_string().c_str());
    return 3;
  }
  if (mode == "speed")
    speed(engine);
  else if (mode == "lut")
    lut(engine);
  else if (mode == "dither")
    dither(engine);
  else {
    std::fprintf(stderr, "usage: gpu_bench speed|lut|dither [--device D] [--shader-dir DIR]\n");
    return 2;
  }
  return 0;
}
