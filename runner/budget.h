// What a case costs before it runs (issue 29): its peak memory and CPU time, estimated from its
// stage's pipeline and the pixels it holds, with figures measured per pixel on 4096x4096 and
// 2048x2048 cases of every pipeline (docs/performance.md, "Memory and time per case"). A case
// over the per-case budget is refused when it is loaded, before any work, with an error naming
// the case, its size, the estimate and the budget (as the stimulus size limit refuses); a run
// refuses a case over the run's memory budget before it starts, and runs no more cases at once
// than that budget holds (-j N: fewer concurrent large cases).
#pragma once

#include <cstddef>
#include <string>

#include "core/case.h"
#include "core/result.h"

namespace hdrc {

// The per-case budget: 1.5 GB resident and 60 s of CPU (issue 29), the process's own fixed part
// included. Every pipeline's largest image follows from it (case_budget_max_pixels): 2048x2048 is
// within it for every pipeline, 4096x4096 for none. `run --memory-budget GB` and `--time-budget S`
// set other limits for the process (set_case_budget, before the cases are loaded).
inline constexpr double kCaseMemoryBudgetBytes = 1.5e9;
inline constexpr double kCaseCpuBudgetSeconds = 60.0;
// What a process running one case holds whatever the case's size: the binary, lavapipe, the
// shaders and pipelines, OpenImageIO (measured: 242-265 MB peak for a 256x256 case of each
// pipeline, lavapipe, docs/performance-notes.md).
inline constexpr double kProcessFixedBytes = 0.26e9;
void set_case_budget(double memory_bytes, double cpu_seconds);
double case_memory_budget();  // kCaseMemoryBudgetBytes unless set_case_budget changed it
double case_cpu_budget();

struct CaseCost {
  int width = 0, height = 0;  // the image the case holds (a LUT bake: its unwrapped N² x N)
  double pixels = 0;          // width x height, plus a bloom texture's pixels
  double bytes = 0;           // estimated peak resident memory the case adds to the process
                              // (the process's own: kProcessFixedBytes)
  double cpu_seconds = 0;     // estimated CPU seconds of the case, its images and report page
};

// The estimate: a fixed part plus per-pixel figures of the case's pipeline (runner/budget.cpp).
CaseCost case_cost(const Case& c);

// The most pixels an image of a case of this stage may have within the per-case budget.
double case_budget_max_pixels(const StageInfo& stage);

// OK, or an error naming the case (file, id), its size, the estimated memory and CPU time and
// the budget it is over, with the stage's largest image as the valid choice: kProcessFixedBytes
// + bytes must be within `memory_budget` (< 0: case_memory_budget(), as the loader checks; a
// run's: run_memory_budget) and cpu_seconds within case_cpu_budget().
Status check_case_budget(const Case& c, double memory_budget = -1);

// The memory a run of `jobs` workers may use (its cases and the process's own
// kProcessFixedBytes): `configured` (bytes, --memory-budget) when > 0, else the machine's:
// MemAvailable (/proc/meminfo) and, under an address-space limit (ulimit -v, RLIMIT_AS), the limit
// less the address space the process reserves without making it resident: its threads' stacks
// and allocator arenas, kAddressSpaceReserve and kAddressSpacePerWorker for each worker after the
// first (measured: VmPeak - VmHWM of a 256x256 case, 1.02 GB at -j 1, 1.50 GB at -j 2; rounded
// up). 0 when none is known (no gate).
double run_memory_budget(double configured, int jobs = 1);
inline constexpr double kAddressSpaceReserve = 1.1e9;
inline constexpr double kAddressSpacePerWorker = 0.6e9;
// What a run holds besides its running cases: the case images it keeps for its report
// (core/image.h written_images, main.cpp sets this capacity), up to 384 MiB, held from case to
// case. The cases' share of a run's budget is the budget less this and kProcessFixedBytes
// (measured: -j 2 under a 3 GB address-space limit ran out with three 2048x2048 cases when it
// was counted as the cases').
inline constexpr size_t kKeptImagesBytes = size_t{384} << 20;

// "1.50 GB": a byte count for messages.
std::string format_bytes(double bytes);

}  // namespace hdrc
