// The LUT cache (reference/ue/lut_cache.h): one bake per distinct key, shared; every field that
// reaches the bake is in the key; results equal a fresh bake.
#include "reference/ue/lut_cache.h"

#include <gtest/gtest.h>

#include <cstring>
#include <thread>
#include <vector>

#include "reference/ue/cpp/resolve.h"

namespace {

hdrc::ParamBlock params(int device) {
  hdrc::Case c;
  c.stage = hdrc::find_stage("tonemap");
  c.cvars.set("r.HDR.EnableHDROutput", 1);
  c.cvars.set("r.HDR.Display.OutputDevice", device);
  c.cvars.set("r.LUT.Size", 16);
  return *hdrc::ref::resolve_params(c, 4, 4);
}

bool equal(const hdrc::ref::BakedLut& a, const hdrc::ref::BakedLut& b) {
  auto same = [](const auto& x, const auto& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof x[0]) == 0;
  };
  return a.size == b.size && a.layout == b.layout && same(a.texels, b.texels) &&
         same(a.lo, b.lo) && same(a.hi, b.hi) && same(a.flags, b.flags);
}

TEST(LutCache, BakesEachDistinctLutOnceAndSharesIt) {
  hdrc::ref::clear_lut_cache();
  const auto p = params(3);
  auto q = p;  // differs only in fields that cannot reach the bake
  q.width = 99;
  q.exposure = 4.0;
  q.frame_index = 5;
  q.ui_level = 0.5;
  const auto a = hdrc::ref::cached_bake_lut(p);
  const auto b = hdrc::ref::cached_bake_lut(q);
  EXPECT_EQ(a.get(), b.get());
  EXPECT_TRUE(equal(*a, hdrc::ref::bake_lut(p)));
  const auto s = hdrc::ref::lut_cache_stats();
  EXPECT_EQ(s.bakes, 1u);
  EXPECT_EQ(s.hits, 1u);
  const size_t n = static_cast<size_t>(p.lut_size);
  // The texels, and the admissible ranges (lo, hi, flags) when the LUT has them.
  const size_t per_texel =
      sizeof(hdrc::ref::Vec3) + (a->has_ranges() ? 2 * sizeof(hdrc::ref::Vec3) + 1 : 0);
  EXPECT_EQ(s.bytes, n * n * n * per_texel);
}

// Each field that reaches the bake changes the key, and the cached LUT is that field's bake.
TEST(LutCache, EveryBakeInputIsInTheKey) {
  hdrc::ref::clear_lut_cache();
  const auto base = params(0);
  std::vector<hdrc::ParamBlock> variants;
  auto add = [&](auto edit) {
    auto p = base;
    edit(p);
    variants.push_back(p);
  };
  add([](hdrc::ParamBlock& p) { p.output_device = 3; });
  add([](hdrc::ParamBlock& p) { p.lut_format = 1; });
  add([](hdrc::ParamBlock& p) { p.lut_layout = 1; });
  add([](hdrc::ParamBlock& p) { p.lut_size = 9; });
  add([](hdrc::ParamBlock& p) { p.cc_gamma_highlights[1] = 1.5; });
  add([](hdrc::ParamBlock& p) { p.film_toe = 0.3; });
  add([](hdrc::ParamBlock& p) { p.ap1_to_output(0, 1) += 1e-3; });
  add([](hdrc::ParamBlock& p) { p.overlay_color[3] = 0.5; });
  add([](hdrc::ParamBlock& p) { p.inverse_gamma[1] = 0.9; });
  const auto first = hdrc::ref::cached_bake_lut(base);
  for (size_t i = 0; i < variants.size(); ++i) {
    EXPECT_NE(hdrc::ref::lut_cache_key(variants[i]), hdrc::ref::lut_cache_key(base)) << i;
    const auto lut = hdrc::ref::cached_bake_lut(variants[i]);
    EXPECT_NE(lut.get(), first.get()) << i;
    EXPECT_TRUE(equal(*lut, hdrc::ref::bake_lut(variants[i]))) << i;
  }
  EXPECT_EQ(hdrc::ref::lut_cache_stats().bakes, variants.size() + 1);
}

TEST(LutCache, ConcurrentRequestsBakeOnce) {
  hdrc::ref::clear_lut_cache();
  const auto p = params(5);
  std::vector<std::shared_ptr<const hdrc::ref::BakedLut>> got(4);
  std::vector<std::thread> threads;
  for (size_t i = 0; i < got.size(); ++i)
    threads.emplace_back([&, i] { got[i] = hdrc::ref::cached_bake_lut(p); });
  for (auto& t : threads) t.join();
  for (const auto& g : got) EXPECT_EQ(g.get(), got[0].get());
  EXPECT_EQ(hdrc::ref::lut_cache_stats().bakes, 1u);
}

}  // namespace
