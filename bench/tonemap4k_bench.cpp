// The Vulkan engine's tonemap stage at 3840x2160 (bake 32³ + Tonemap pass, device 3): seconds per
// engine run. Uses only the engine's public interface of every version, so the same file builds
// against an older tree and the two are compared side by side (bench/performance.py runs them
// alternately). Prints "tonemap4k_first_s X" and "tonemap4k_s X" (median of the later runs), then
// "tonemap4k_fixed_s X" (the same case on a 1x1 input) and "tonemap4k_pixels_s X" (the difference).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "gpu/vulkan_engine.h"
#include "reference/ue/cpp/resolve.h"

int main(int argc, char** argv) {
  const int reps = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  hdrc::ResolvedCase rc;
  rc.spec.id = "bench";
  rc.spec.stage = hdrc::find_stage("tonemap");
  rc.spec.cvars.set("r.HDR.EnableHDROutput", 1);
  rc.spec.cvars.set("r.HDR.Display.OutputDevice", 3);
  rc.spec.cvars.set("r.HDR.Display.ColorGamut", 2);
  rc.spec.cvars.set("r.LUT.Size", 32);
  hdrc::Image img(3840, 2160);
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-6.0, 2.0);
  for (size_t i = 0; i < img.pixel_count(); ++i) {
    for (int c = 0; c < 3; ++c) img.data[i * 4 + c] = static_cast<float>(std::pow(10.0, u(rng)));
    img.data[i * 4 + 3] = 1.0;
  }
  rc.params = *hdrc::ref::resolve_params(rc.spec, img.width, img.height);
  rc.input = std::move(img);
  hdrc::gpu::VulkanEngine engine(hdrc::gpu::VulkanOptions{});
  if (auto st = engine.init(); !st) {
    std::printf("# vulkan unavailable: %s\n", st.error().to_string().c_str());
    return 3;
  }
  // Seconds of each of reps + 1 engine runs of `c` (the first is the fresh engine's); empty after
  // printing the error when a run fails.
  auto times = [&](const hdrc::ResolvedCase& c) {
    using Clock = std::chrono::steady_clock;
    std::vector<double> s;
    for (int i = 0; i <= reps; ++i) {
      const auto t0 = Clock::now();
      auto out = engine.run(c);
      s.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
      if (!out) {
        std::printf("# error: %s\n", out.error().to_string().c_str());
        return std::vector<double>{};
      }
    }
    return s;
  };
  // The median of the runs after the first.
  auto later_median = [](std::vector<double> s) {
    s.erase(s.begin());
    std::sort(s.begin(), s.end());
    return s[s.size() / 2];
  };
  const std::vector<double> s = times(rc);
  if (s.empty()) return 1;
  std::printf("tonemap4k_first_s %.4f\n", s[0]);
  const double per_run = later_median(s);
  std::printf("tonemap4k_s %.4f\n", per_run);
  // The same case on a 1x1 input: what a run costs whatever the image (the 32^3 bake, the
  // submission, the fence), so that the Tonemap pass and the image's transfers show apart:
  // tonemap4k_pixels_s = tonemap4k_s - tonemap4k_fixed_s. Same engine (its pipelines and
  // variants are warm), same public interface.
  hdrc::ResolvedCase one;
  one.spec = rc.spec;
  one.input = hdrc::Image(1, 1);
  for (int c = 0; c < 4; ++c) one.input.data[c] = 0.18;
  one.params = *hdrc::ref::resolve_params(one.spec, 1, 1);
  const std::vector<double> f = times(one);
  if (f.empty()) return 1;
  const double fixed = later_median(f);
  std::printf("tonemap4k_fixed_s %.4f\n", fixed);
  std::printf("tonemap4k_pixels_s %.4f\n", per_run - fixed);
  return 0;
}
