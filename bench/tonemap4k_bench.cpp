// The Vulkan engine's tonemap stage at 3840x2160 (bake 32³ + Tonemap pass, device 3): seconds per
// engine run. Uses only the engine's public interface of every version, so the same file builds
// against an older tree and the two are compared side by side (bench/performance.py runs them
// alternately). Prints "tonemap4k_first_s X" and "tonemap4k_s X" (median of the later runs).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "gpu/vulkan_engine.h"
#include "reference/ue_cpp/resolve.h"

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
  using Clock = std::chrono::steady_clock;
  std::vector<double> s;
  for (int i = 0; i <= reps; ++i) {
    const auto t0 = Clock::now();
    auto out = engine.run(rc);
    s.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    if (!out) {
      std::printf("# error: %s\n", out.error().to_string().c_str());
      return 1;
    }
  }
  std::printf("tonemap4k_first_s %.4f\n", s[0]);
  s.erase(s.begin());
  std::sort(s.begin(), s.end());
  std::printf("tonemap4k_s %.4f\n", s[s.size() / 2]);
  return 0;
}
