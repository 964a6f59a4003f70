#include "runner/budget.h"

#include <OpenImageIO/imageio.h>
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string_view>
#include <utility>

#include "core/exr_header.h"
#include "core/pipeline.h"

namespace hdrc {

namespace {

// How each pipeline module's per-pixel figures (Pipeline::bytes_per_pixel, cpu_ns_per_pixel) were
// measured, as what one pixel of a case's image costs in a `run`: /usr/bin/time -v of
// `hdrconform run -j 1` on one case of each pipeline at 2048x2048 and at 256x256 (a "random"
// stimulus; every image kept, the report written), lavapipe on 2 cores; the figure is the
// difference of the two over the pixels between them, rounded up by 3-8 %
// (docs/performance-notes.md, "Memory and time per case", 2026-11-27: bytes 281 / 220 / 242 /
// 231, CPU µs 3.41 / 2.27 / 2.33 / 3.20 for ue55, unity_urp, operators, pq_grading). Memory: the
// input, reference and candidate images (doubles, 32 bytes a pixel each), the Vulkan engine's
// float32 input and output buffers (16 each; kept for the next case), the case images kept for the
// report (float32, 16 each), the EXR encoder's buffer and the report page's float data. CPU: user +
// system of the process (the reference, lavapipe's threads, the diff, the EXRs and the report
// page). ue55 was measured on its tonemap stage (the LUT bake, then the pass; its other image
// stages are passes of the same kind).
struct PixelCost {
  double bytes, cpu_ns;
};
// The largest LUT a bake stage makes: 65³ texels (Unity's LutSize clamps to [16, 65]; UE's
// r.LUT.Size to [16, 64]), unwrapped 65² x 65.
constexpr int kLargestLutEdge = 65;

// The stage's pipeline's measured figures (Pipeline::bytes_per_pixel, cpu_ns_per_pixel); for a
// pipeline not measured yet, the dearest of those measured.
PixelCost pixel_cost(const StageInfo& stage) {
  const Pipeline& pipeline = pipeline_of(stage);
  if (pipeline.bytes_per_pixel > 0 && pipeline.cpu_ns_per_pixel > 0)
    return {pipeline.bytes_per_pixel, pipeline.cpu_ns_per_pixel};
  PixelCost dearest{0, 0};
  for (const Pipeline* p : pipeline_table()) {
    dearest.bytes = std::max(dearest.bytes, p->bytes_per_pixel);
    dearest.cpu_ns = std::max(dearest.cpu_ns, p->cpu_ns_per_pixel);
  }
  return dearest;
}

// An input's width and height: a stimulus's own, a file's from its header (checked first by
// core/exr_header.h: OpenEXR allocates what a header declares); {0, 0} when unreadable (the run
// then reports the file's error).
std::pair<int, int> input_size(const InputSpec& in) {
  if (in.file.empty()) return {in.width, in.height};
  if (!check_exr_header(in.file)) return {0, 0};
  auto file = OIIO::ImageInput::open(in.file);
  if (!file) {
    (void)OIIO::geterror();  // cleared: the run reports it
    return {0, 0};
  }
  return {file->spec().width, file->spec().height};
}

std::string size_text(const CaseCost& cost) {
  return std::to_string(cost.width) + "x" + std::to_string(cost.height);
}

}  // namespace

struct CaseBudget {
  double memory = kCaseMemoryBudgetBytes, cpu = kCaseCpuBudgetSeconds;
};
CaseBudget& case_budget() {
  static CaseBudget b;
  return b;
}

void set_case_budget(double memory_bytes, double cpu_seconds) {
  case_budget() = CaseBudget{memory_bytes, cpu_seconds};
}
double case_memory_budget() {
  return case_budget().memory;
}
double case_cpu_budget() {
  return case_budget().cpu;
}

std::string format_bytes(double bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f GB", bytes / 1e9);
  return buf;
}

CaseCost case_cost(const Case& c) {
  CaseCost cost;
  if (!c.stage) return cost;
  if (c.stage->takes_input) {
    const auto [w, h] = input_size(c.input);
    cost.width = std::max(1, w);
    cost.height = std::max(1, h);
  } else {
    cost.width = kLargestLutEdge * kLargestLutEdge;
    cost.height = kLargestLutEdge;
  }
  cost.pixels = static_cast<double>(cost.width) * cost.height;
  // A bloom texture (tonemap) is one more input image of its own size.
  if (!c.bloom.stimulus.empty() || !c.bloom.file.empty()) {
    const auto [w, h] = input_size(c.bloom);
    cost.pixels += static_cast<double>(std::max(1, w)) * std::max(1, h);
  }
  const PixelCost& p = pixel_cost(*c.stage);
  cost.bytes = p.bytes * cost.pixels;
  cost.cpu_seconds = p.cpu_ns * 1e-9 * cost.pixels;
  return cost;
}

double case_budget_max_pixels(const StageInfo& stage) {
  const PixelCost& p = pixel_cost(stage);
  return std::floor(std::min((case_memory_budget() - kProcessFixedBytes) / p.bytes,
                             case_cpu_budget() / (p.cpu_ns * 1e-9)));
}

Status check_case_budget(const Case& c, double memory_budget) {
  const bool run_budget = memory_budget >= 0;
  if (!run_budget) memory_budget = case_memory_budget();
  const CaseCost cost = case_cost(c);
  const bool memory = kProcessFixedBytes + cost.bytes > memory_budget;
  const bool time = cost.cpu_seconds > case_cpu_budget();
  if (!memory && !time) return {};
  char estimate[160];
  std::snprintf(estimate, sizeof estimate, "needs an estimated %s and %.1f s of CPU",
                format_bytes(kProcessFixedBytes + cost.bytes).c_str(), cost.cpu_seconds);
  std::string over;
  if (memory)
    over = "the memory budget of " + format_bytes(memory_budget) +
           (run_budget ? " (this run's: --memory-budget or the machine's)" : " per case");
  if (time) {
    char t[64];
    std::snprintf(t, sizeof t, "the CPU budget of %.0f s per case", case_cpu_budget());
    over += std::string(over.empty() ? "" : " and ") + t;
  }
  const double max_pixels =
      std::max(0.0, std::min(case_budget_max_pixels(*c.stage),
                             (memory_budget - kProcessFixedBytes) / pixel_cost(*c.stage).bytes));
  const int side = static_cast<int>(std::floor(std::sqrt(max_pixels)));
  return Error{c.file, "",
               "case " + c.id + ": a " + size_text(cost) + " " + std::string(c.stage->name) +
                   " case " + estimate + " (with the process's own " +
                   format_bytes(kProcessFixedBytes) + "), over " + over +
                   "; refused before any work",
               "images of at most " + std::to_string(static_cast<long long>(max_pixels)) +
                   " pixels for a case of pipeline " + std::string(pipeline_of(*c.stage).name) +
                   " (e.g. " + std::to_string(side) + "x" + std::to_string(side) +
                   "; run --memory-budget GB and --time-budget S set other limits)"};
}

double run_memory_budget(double configured, int jobs) {
  if (configured > 0) return configured;
  double budget = 0;
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kb = 0;
  std::string unit;
  while (meminfo >> key >> kb >> unit)
    if (key == "MemAvailable:") {
      budget = kb * 1024.0;
      break;
    }
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
    const double left = std::max(0.0, static_cast<double>(as.rlim_cur) - kAddressSpaceReserve -
                                          kAddressSpacePerWorker * std::max(0, jobs - 1));
    budget = budget > 0 ? std::min(budget, left) : left;
  }
  return budget;
}

}  // namespace hdrc
