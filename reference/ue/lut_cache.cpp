#include "reference/ue/lut_cache.h"

#include <atomic>
#include <cstring>
#include <future>
#include <list>
#include <map>
#include <mutex>
#include <string_view>

namespace hdrc::ref {

namespace {

// ParamBlock fields that do not reach bake_lut (combine_luts.cpp reads none of them): they stay
// out of the key, so cases that differ only in these share one LUT.
constexpr std::string_view kNotBakeInputs[] = {"width",
                                               "height",
                                               "frame_index",
                                               "ui_composite_mode",
                                               "cvd_type",
                                               "cvd_severity",
                                               "cvd_correct",
                                               "cvd_show_correction",
                                               "visualize_debug_type",
                                               "aux0_width",
                                               "aux0_height",
                                               "aux1_width",
                                               "aux1_height",
                                               "exposure",
                                               "pre_exposure",
                                               "vignette_intensity",
                                               "sharpen_div6",
                                               "dither_amount",
                                               "ui_level",
                                               "ui_luminance",
                                               "scene_color_tint",
                                               "bloom_dirt_tint",
                                               "grain_random",
                                               "fringe"};

bool bake_input(std::string_view name) {
  for (std::string_view n : kNotBakeInputs)
    if (n == name) return false;
  return true;
}

template <typename T>
void append(std::string& key, const T& v) {
  key.append(reinterpret_cast<const char*>(&v), sizeof v);
}

struct Entry {
  std::shared_future<std::shared_ptr<const BakedLut>> lut;
  size_t bytes = 0;
  std::list<std::string>::iterator lru;
};

struct Cache {
  std::mutex mu;
  std::map<std::string, Entry> entries;
  std::list<std::string> lru;  // most recent first
  size_t bytes = 0, hits = 0, bakes = 0;
  std::atomic<bool> enabled{true};
};

Cache& cache() {
  static Cache c;
  return c;
}

size_t lut_bytes(const ParamBlock& p) {
  const size_t n = p.lut_size > 0 ? static_cast<size_t>(p.lut_size) : 0;
  // The texels; a LUT with admissible ranges (BakedLut::lo/hi/flags) is recounted once baked.
  return n * n * n * sizeof(Vec3);
}

}  // namespace

std::string lut_cache_key(const ParamBlock& p) {
  std::string key;
  key.reserve(sizeof(ParamBlock));
  for_each_param(p, [&](FieldKind, const char* name, const auto& v) {
    if (bake_input(name)) append(key, v);
  });
  return key;
}

std::shared_ptr<const BakedLut> cached_bake_lut(const ParamBlock& p) {
  Cache& c = cache();
  if (!c.enabled.load()) return std::make_shared<const BakedLut>(bake_lut(p));
  const std::string key = lut_cache_key(p);
  std::promise<std::shared_ptr<const BakedLut>> mine;
  std::shared_future<std::shared_ptr<const BakedLut>> theirs;
  {
    std::lock_guard<std::mutex> lock(c.mu);
    if (auto it = c.entries.find(key); it != c.entries.end()) {
      ++c.hits;
      c.lru.splice(c.lru.begin(), c.lru, it->second.lru);
      theirs = it->second.lut;
    } else {
      ++c.bakes;
      c.lru.push_front(key);
      Entry e;
      e.lut = mine.get_future().share();
      e.bytes = lut_bytes(p);
      e.lru = c.lru.begin();
      c.bytes += e.bytes;
      c.entries.emplace(key, std::move(e));
      // Drop the least recently used finished LUTs beyond the budget (holders keep theirs).
      for (auto it = std::prev(c.lru.end()); c.bytes > kLutCacheBytes && it != c.lru.begin();) {
        const auto prev = std::prev(it);
        const auto victim = c.entries.find(*it);
        if (victim->second.lut.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
          c.bytes -= victim->second.bytes;
          c.entries.erase(victim);
          c.lru.erase(it);
        }
        it = prev;
      }
    }
  }
  if (theirs.valid()) return theirs.get();  // waits while another thread bakes it
  try {
    auto lut = std::make_shared<const BakedLut>(bake_lut(p));
    if (lut->has_ranges()) {  // its ranges count against the budget too
      const size_t extra = lut->texels.size() * (2 * sizeof(Vec3) + sizeof(uint8_t));
      std::lock_guard<std::mutex> lock(c.mu);
      if (auto it = c.entries.find(key); it != c.entries.end()) {
        it->second.bytes += extra;
        c.bytes += extra;
      }
    }
    mine.set_value(lut);
    return lut;
  } catch (...) {
    mine.set_exception(std::current_exception());
    std::lock_guard<std::mutex> lock(c.mu);
    if (auto it = c.entries.find(key); it != c.entries.end()) {
      c.bytes -= it->second.bytes;
      c.lru.erase(it->second.lru);
      c.entries.erase(it);
    }
    throw;
  }
}

LutCacheStats lut_cache_stats() {
  Cache& c = cache();
  std::lock_guard<std::mutex> lock(c.mu);
  return {c.hits, c.bakes, c.entries.size(), c.bytes};
}

void clear_lut_cache() {
  Cache& c = cache();
  std::lock_guard<std::mutex> lock(c.mu);
  c.entries.clear();
  c.lru.clear();
  c.bytes = c.hits = c.bakes = 0;
}

void set_lut_cache_enabled(bool on) {
  cache().enabled.store(on);
}

}  // namespace hdrc::ref
