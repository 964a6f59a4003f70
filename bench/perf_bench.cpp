// Performance measurements for docs/performance.md (not tests; nothing here asserts). Each figure
// that is a comparison is measured in this one process, interleaved (A, B, A, B, ...), and the
// median of the rounds is reported, because the machine is shared and wall time is noisy.
//   perf_bench aces     — the reference's ACES 1000-nit output transform vs OpenColorIO's CPU
//                         processor (HDR-VIDEO-1000nit built-in) on the same 1e6 pixels
//   perf_bench texel    — reference CombineLUTs: µs per texel, fast paths on and off; bake with
//                         the LUT cache (hit) vs without
//   perf_bench tonemap  — the reference's full analytic Tonemap pass, µs per pixel, one core
//   perf_bench probe    — `probe` on 1e6 colours (parse + evaluate + print), fast paths on/off
//   perf_bench vulkan   — the Vulkan engine: tonemap pass at 3840x2160 (Mpx/s, fresh engine's
//                         first run and reused runs), LUT bake per texel, fixed cost per case,
//                         and memcpy bandwidth for comparison
//   perf_bench fixed    — per-case fixed cost of each engine (a 1x1 shaper case)
// Output: "key value unit" lines, one figure each (bench/perf_table.py makes the table).
#include <OpenColorIO/OpenColorIO.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "gpu/vulkan_engine.h"
#include "reference/color/fast_paths.h"
#include "reference/reference_engine.h"
#include "reference/ue/aces/aces_output.h"
#include "reference/ue/combine_luts.h"
#include "reference/ue/cpp/resolve.h"
#include "reference/ue/lut_cache.h"
#include "reference/ue/tonemap.h"
#include "runner/probe.h"

namespace {

namespace OCIO = OCIO_NAMESPACE;
using Clock = std::chrono::steady_clock;
using hdrc::ref::Vec3;

// CPU seconds of the calling thread (CLOCK_THREAD_CPUTIME_ID): on a shared machine wall time
// counts the time other processes hold the cores. The single-threaded figures use this.
double seconds(const std::function<void()>& f) {
  timespec a, b;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &a);
  f();
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &b);
  return static_cast<double>(b.tv_sec - a.tv_sec) +
         1e-9 * static_cast<double>(b.tv_nsec - a.tv_nsec);
}

// Wall seconds: for the Vulkan engine, whose work runs on lavapipe's own threads.
double wall_seconds(const std::function<void()>& f) {
  const auto t0 = Clock::now();
  f();
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void report(const char* key, double value, const char* unit) {
  std::printf("%s %.6g %s\n", key, value, unit);
  std::fflush(stdout);
}

hdrc::Case make_spec(const char* stage, int device, int gamut, int size) {
  hdrc::Case c;
  c.id = "bench";
  c.stage = hdrc::find_stage(stage);
  c.cvars.set("r.HDR.EnableHDROutput", 1);
  c.cvars.set("r.HDR.Display.OutputDevice", device);
  c.cvars.set("r.HDR.Display.ColorGamut", gamut);
  c.cvars.set("r.LUT.Size", size);
  return c;
}

hdrc::ResolvedCase make_case(const char* stage, int device, int gamut, int size, hdrc::Image in) {
  hdrc::ResolvedCase rc;
  rc.spec = make_spec(stage, device, gamut, size);
  if (std::string(stage) == "combine_luts") in = hdrc::Image(size * size, size);
  rc.params = *hdrc::ref::resolve_params(rc.spec, in.width, in.height);
  rc.input = std::move(in);
  return rc;
}

// Log-uniform scene colours, 1e-4 … 1e4 nits, hue varying.
hdrc::Image scene(int w, int h) {
  hdrc::Image img(w, h);
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-6.0, 2.0);
  for (size_t i = 0; i < img.pixel_count(); ++i) {
    double* p = &img.data[i * 4];
    for (int c = 0; c < 3; ++c) p[c] = static_cast<float>(std::pow(10.0, u(rng)));
    p[3] = 1.0;
  }
  return img;
}

void aces(int rounds) {
  constexpr int kPixels = 1000000;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-4.0, 3.0);
  std::vector<float> px(kPixels * 3);
  for (float& v : px) v = static_cast<float>(std::pow(10.0, u(rng)));
  const hdrc::ParamBlock p = *hdrc::ref::resolve_params(make_spec("tonemap", 3, 2, 32), 1, 1);
  const auto params = hdrc::ref::aces_params(p);
  auto bt = OCIO::BuiltinTransform::Create();
  bt->setStyle("ACES-OUTPUT - ACES2065-1_to_CIE-XYZ-D65 - HDR-VIDEO-1000nit-15nit-REC2020lim_1.1");
  OCIO::ConfigRcPtr cfg = OCIO::Config::CreateRaw()->createEditableCopy();
  const auto cpu = cfg->getProcessor(bt)->getOptimizedCPUProcessor(OCIO::OPTIMIZATION_DEFAULT);
  std::vector<double> ours, theirs;
  double sink = 0;
  for (int r = 0; r < rounds; ++r) {
    ours.push_back(seconds([&] {
      for (int i = 0; i < kPixels; ++i) {
        const Vec3 in{px[3 * i], px[3 * i + 1], px[3 * i + 2]};
        sink += hdrc::ref::aces::aces_output_transforms_1000(in, hdrc::ref::Mat3::identity(),
                                                             params)[1];
      }
    }));
    std::vector<float> img = px;
    theirs.push_back(seconds([&] {
      OCIO::PackedImageDesc desc(img.data(), kPixels, 1, 3);
      cpu->apply(desc);
    }));
    sink += img[1];
  }
  const double a = median(ours) / kPixels * 1e6, b = median(theirs) / kPixels * 1e6;
  report("aces_reference_us_per_px", a, "us/px");
  report("aces_ocio_us_per_px", b, "us/px");
  report("aces_ratio_reference_over_ocio", a / b, "x");
  if (sink == 12345) std::printf("#\n");
}

void texel(int rounds) {
  for (int device : {0, 3}) {
    const hdrc::ParamBlock p =
        *hdrc::ref::resolve_params(make_spec("combine_luts", device, 2, 32), 1, 1);
    std::vector<double> fast, plain;
    for (int r = 0; r < rounds; ++r) {
      hdrc::ref::set_fast_paths(true);
      fast.push_back(seconds([&] { (void)hdrc::ref::bake_lut(p); }));
      hdrc::ref::set_fast_paths(false);
      plain.push_back(seconds([&] { (void)hdrc::ref::bake_lut(p); }));
    }
    hdrc::ref::set_fast_paths(true);
    const double n = 32.0 * 32 * 32;
    const std::string dev = std::to_string(device);
    report(("bake_us_per_texel_fast_dev" + dev).c_str(), median(fast) / n * 1e6, "us/texel");
    report(("bake_us_per_texel_plain_dev" + dev).c_str(), median(plain) / n * 1e6, "us/texel");
    report(("bake_speedup_dev" + dev).c_str(), median(plain) / median(fast), "x");
  }
  const hdrc::ParamBlock p = *hdrc::ref::resolve_params(make_spec("combine_luts", 3, 2, 32), 1, 1);
  hdrc::ref::clear_lut_cache();
  (void)hdrc::ref::cached_bake_lut(p);
  std::vector<double> hit;
  for (int r = 0; r < rounds; ++r)
    hit.push_back(seconds([&] { (void)hdrc::ref::cached_bake_lut(p); }));
  report("bake_cache_hit_us", median(hit) * 1e6, "us");
}

void tonemap(int rounds) {
  const hdrc::Image img = scene(256, 256);
  for (int device : {0, 3}) {
    const hdrc::ParamBlock p =
        *hdrc::ref::resolve_params(make_spec("tonemap", device, 2, 32), img.width, img.height);
    std::vector<double> fast, plain;
    for (int r = 0; r < rounds; ++r) {
      hdrc::ref::set_fast_paths(true);
      fast.push_back(
          seconds([&] { (void)hdrc::ref::tonemap_image(p, img, nullptr, nullptr, nullptr); }));
      hdrc::ref::set_fast_paths(false);
      plain.push_back(
          seconds([&] { (void)hdrc::ref::tonemap_image(p, img, nullptr, nullptr, nullptr); }));
    }
    hdrc::ref::set_fast_paths(true);
    const double n = img.pixel_count();
    const std::string dev = std::to_string(device);
    report(("analytic_tonemap_us_per_px_fast_dev" + dev).c_str(), median(fast) / n * 1e6, "us/px");
    report(("analytic_tonemap_us_per_px_plain_dev" + dev).c_str(), median(plain) / n * 1e6,
           "us/px");
    // With the baked 32^3 LUT (what the suite's tonemap cases run), per pixel.
    const auto lut = hdrc::ref::bake_lut(p);
    std::vector<double> baked;
    for (int r = 0; r < rounds; ++r)
      baked.push_back(
          seconds([&] { (void)hdrc::ref::tonemap_image(p, img, nullptr, nullptr, &lut); }));
    report(("baked_tonemap_us_per_px_dev" + dev).c_str(), median(baked) / n * 1e6, "us/px");
  }
}

void probe(int rounds) {
  constexpr int kLines = 1000000;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-5.0, 2.0);
  std::string text;
  char line[128];
  for (int i = 0; i < kLines; ++i) {
    std::snprintf(line, sizeof line, "%.9g %.9g %.9g\n", std::pow(10.0, u(rng)),
                  std::pow(10.0, u(rng)), std::pow(10.0, u(rng)));
    text += line;
  }
  hdrc::ProbeOptions o;
  o.set = {"r.HDR.EnableHDROutput=1", "r.HDR.Display.OutputDevice=3", "r.HDR.Display.ColorGamut=2"};
  std::vector<double> fast, plain;
  for (int r = 0; r < rounds; ++r) {
    for (bool on : {true, false}) {
      hdrc::ref::set_fast_paths(on);
      std::istringstream in(text);
      std::ostringstream out;
      (on ? fast : plain).push_back(seconds([&] { (void)hdrc::run_probe(o, in, out); }));
    }
  }
  hdrc::ref::set_fast_paths(true);
  report("probe_1e6_seconds_fast", median(fast), "s");
  report("probe_1e6_seconds_plain_evaluation", median(plain), "s");
}

double memcpy_bandwidth() {
  const size_t bytes = size_t{256} << 20;
  std::vector<char> a(bytes, 1), b(bytes, 0);
  std::vector<double> s;
  for (int r = 0; r < 5; ++r)
    s.push_back(wall_seconds([&] { std::memcpy(b.data(), a.data(), bytes); }));
  return 2.0 * bytes / median(s);  // read + write
}

void vulkan(int rounds) {
  hdrc::gpu::VulkanOptions o;
  hdrc::gpu::VulkanEngine engine(o);
  if (auto st = engine.init(); !st) {
    std::printf("# vulkan unavailable: %s\n", st.error().to_string().c_str());
    return;
  }
  const double bw = memcpy_bandwidth();
  report("memcpy_bandwidth_GBps", bw / 1e9, "GB/s");
  auto rc = make_case("tonemap", 3, 2, 32, scene(3840, 2160));
  std::vector<double> s;
  const double first = wall_seconds([&] { (void)engine.run(rc); });
  for (int r = 0; r < rounds; ++r) s.push_back(wall_seconds([&] { (void)engine.run(rc); }));
  const double px = 3840.0 * 2160;
  report("vulkan_tonemap_4k_first_run_s", first, "s");
  report("vulkan_tonemap_4k_s", median(s), "s");
  report("vulkan_tonemap_4k_Mpx_per_s", px / median(s) / 1e6, "Mpx/s");
  // Bytes the pass must move per pixel: input and output RGBA32F (16 + 16).
  report("vulkan_tonemap_4k_fraction_of_memcpy_bandwidth", px * 32 / median(s) / bw, "");
  for (int n : {32, 64}) {
    auto lut = make_case("combine_luts", 3, 2, n, {});
    (void)engine.run(lut);
    std::vector<double> b;
    for (int r = 0; r < rounds; ++r) b.push_back(wall_seconds([&] { (void)engine.run(lut); }));
    report(("vulkan_bake_us_per_texel_" + std::to_string(n)).c_str(),
           median(b) / (double(n) * n * n) * 1e6, "us/texel");
  }
  report("vulkan_pipeline_creations", engine.pipeline_creations(), "");
  report("vulkan_reused_work", engine.reused_work_count(), "cases");
}

void fixed(int rounds) {
  hdrc::Image one(1, 1);
  auto rc = make_case("shaper", 3, 2, 32, one);
  hdrc::ref::ReferenceEngine ref;
  (void)ref.init();
  std::vector<double> r_s, v_s;
  hdrc::gpu::VulkanEngine vk({});
  const bool have_vk = static_cast<bool>(vk.init());
  if (have_vk) (void)vk.run(rc);
  for (int r = 0; r < rounds * 20; ++r) {
    r_s.push_back(seconds([&] { (void)ref.run(rc); }));
    if (have_vk) v_s.push_back(wall_seconds([&] { (void)vk.run(rc); }));
  }
  report("fixed_cost_reference_us", median(r_s) * 1e6, "us/case");
  if (have_vk) report("fixed_cost_vulkan_us", median(v_s) * 1e6, "us/case");
}

}  // namespace

int main(int argc, char** argv) {
  const std::string what = argc > 1 ? argv[1] : "all";
  const int rounds = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
  if (what == "all" || what == "aces") aces(rounds);
  if (what == "all" || what == "texel") texel(rounds);
  if (what == "all" || what == "tonemap") tonemap(rounds);
  if (what == "all" || what == "probe") probe(std::max(1, rounds / 2));
  if (what == "all" || what == "fixed") fixed(rounds);
  if (what == "all" || what == "vulkan") vulkan(rounds);
  return 0;
}
