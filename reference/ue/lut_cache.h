// A process-wide cache of baked LUTs: each distinct LUT is baked once per run and shared between
// cases and worker threads (the reference engine's bake dominated the suite's CPU, and a run
// re-baked identical LUTs: the same device and grading under different inputs, and the reference
// engine running as both reference and candidate).
//
// The key is every ParamBlock field except those that cannot reach the bake (image sizes, the
// tonemapper's own per-pixel parameters, UI, dither and VisualizeHDR fields: kNotBakeInputs in
// lut_cache.cpp), compared bit for bit, so a field added to the block is part of the key until
// someone proves it is not. A concurrent request for a LUT being baked waits for that bake.
// Memory is bounded (least recently used LUTs are dropped beyond kLutCacheBytes).
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "core/shader_interface.h"
#include "reference/ue/combine_luts.h"

namespace hdrc::ref {

inline constexpr size_t kLutCacheBytes = size_t{512} << 20;

// bake_lut(p), baked at most once per distinct key while it stays cached.
std::shared_ptr<const BakedLut> cached_bake_lut(const ParamBlock& p);

// The cache key of `p` (bytes; equal keys = the same LUT).
std::string lut_cache_key(const ParamBlock& p);

struct LutCacheStats {
  size_t hits = 0, bakes = 0, entries = 0, bytes = 0;
};
LutCacheStats lut_cache_stats();
void clear_lut_cache();  // drops every entry and zeroes the counters

// Off: cached_bake_lut bakes every time (for benchmarks of the uncached cost). Default on.
void set_lut_cache_enabled(bool on);

}  // namespace hdrc::ref
