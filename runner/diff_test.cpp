// Diff metrics with hand-computed values and the non-finite rules (NaN vs NaN and same-sign Inf
// consistent, anything else a mismatch reported first; every comparison fails on NaN).
#include "runner/diff.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "reference/color/st2084.h"

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

hdrc::Tolerance tol(double rel, double floor, double pq) {
  hdrc::Tolerance t;
  t.linear_rel = rel;
  t.rel_floor = floor;
  t.pq_code10 = pq;
  return t;
}

hdrc::Image grey(int w, double v) {
  hdrc::Image img(w, 1);
  for (int x = 0; x < w; ++x)
    for (int c = 0; c < 4; ++c) img.px(x, 0)[c] = c == 3 ? 1.0 : v;
  return img;
}

TEST(Diff, HandComputedMetrics) {
  hdrc::Image in = grey(4, 0.5), ref = grey(4, 0.5), cand = grey(4, 0.5);
  cand.px(2, 0)[1] = 0.5005;  // abs 5e-4, rel 1e-3
  const auto s = hdrc::diff_images(in, ref, cand, hdrc::OutputEncoding{hdrc::StageId::kShaper, 3},
                                   tol(1e-2, 1e-6, 10));
  EXPECT_EQ(s.values, 12u);
  EXPECT_NEAR(s.max_abs, 5e-4, 1e-15);
  EXPECT_NEAR(s.max_rel, 1e-3, 1e-12);
  EXPECT_NEAR(s.mean_abs, 5e-4 / 12, 1e-15);
  EXPECT_EQ(s.worst_rel.x, 2);
  EXPECT_EQ(s.worst_rel.channel, 1);
  // Shaper outputs are scene-linear: 0.5 → 50 nits, 0.5005 → 50.05 nits.
  namespace pq = hdrc::ref::st2084;
  const double want = (pq::pq_from_nits(50.05) - pq::pq_from_nits(50.0)) * 1023.0;
  EXPECT_NEAR(s.max_pq10, want, 1e-9);
  EXPECT_NEAR(s.max_pq12, want / 1023.0 * 4095.0, 1e-9);
  EXPECT_TRUE(hdrc::judge(s, tol(1e-2, 1e-6, 10)).pass);
  EXPECT_FALSE(hdrc::judge(s, tol(1e-4, 1e-6, 10)).pass);
  EXPECT_FALSE(hdrc::judge(s, tol(1e-2, 1e-6, want / 2)).pass);
}

TEST(Diff, RelativeErrorUsesTheFloor) {
  hdrc::Image in = grey(1, 0), ref = grey(1, 0), cand = grey(1, 0);
  cand.px(0, 0)[0] = 1e-7;
  auto s = hdrc::diff_images(in, ref, cand, hdrc::OutputEncoding{hdrc::StageId::kShaper, 3},
                             tol(1, 1e-6, 10));
  EXPECT_NEAR(s.max_rel, 0.1, 1e-12);
  // With no floor a difference over a zero reference is infinitely wrong, never NaN.
  s = hdrc::diff_images(in, ref, cand, hdrc::OutputEncoding{hdrc::StageId::kShaper, 3},
                        tol(1, 0, 10));
  EXPECT_TRUE(std::isinf(s.max_rel));
  EXPECT_FALSE(hdrc::judge(s, tol(1, 0, 10)).pass);
}

struct NonFiniteCase {
  double ref, cand;
  bool consistent;
};

TEST(Diff, NonFiniteConsistencyRules) {
  const NonFiniteCase cases[] = {
      {kNaN, kNaN, true},  {kInf, kInf, true}, {-kInf, -kInf, true}, {kInf, -kInf, false},
      {kNaN, kInf, false}, {kNaN, 0.0, false}, {1.0, kNaN, false},   {0.0, kInf, false},
  };
  for (const auto& c : cases) {
    hdrc::Image in = grey(3, 0.1), ref = grey(3, 0.1), cand = grey(3, 0.1);
    ref.px(1, 0)[2] = c.ref;
    cand.px(1, 0)[2] = c.cand;
    const auto s = hdrc::diff_images(in, ref, cand, hdrc::OutputEncoding{hdrc::StageId::kShaper, 0},
                                     tol(1e-3, 1e-6, 1));
    EXPECT_EQ(s.nonfinite_mismatch, c.consistent ? 0u : 1u) << c.ref << " vs " << c.cand;
    const auto v = hdrc::judge(s, tol(1e-3, 1e-6, 1));
    EXPECT_EQ(v.pass, c.consistent) << v.reason;
    if (!c.consistent) {
      EXPECT_EQ(s.first_mismatch.x, 1);
      EXPECT_EQ(s.first_mismatch.channel, 2);
      EXPECT_NE(v.reason.find("non-finite"), std::string::npos) << v.reason;
    }
  }
}

// A non-finite mismatch is reported before (instead of) a numeric failure elsewhere.
TEST(Diff, NonFiniteMismatchIsReportedFirst) {
  hdrc::Image in = grey(2, 1), ref = grey(2, 1), cand = grey(2, 1);
  cand.px(0, 0)[0] = 2.0;   // numeric failure at x = 0
  cand.px(1, 0)[0] = kNaN;  // non-finite mismatch at x = 1
  const auto s = hdrc::diff_images(in, ref, cand, hdrc::OutputEncoding{hdrc::StageId::kShaper, 0},
                                   tol(1e-3, 1e-6, 1));
  const auto v = hdrc::judge(s, tol(1e-3, 1e-6, 1));
  EXPECT_FALSE(v.pass);
  EXPECT_EQ(v.reason.rfind("1 non-finite mismatch", 0), 0u) << v.reason;
}

// The mapping to nits per stage and device, against published values: sRGB 0.5 → 0.214041 (IEC
// 61966-2-1), PQ 0.5080784 → 100 nits, scRGB 1.0 → 80 nits.
TEST(Diff, OutputToNits) {
  using hdrc::OutputEncoding;
  using hdrc::StageId;
  EXPECT_EQ((OutputEncoding{StageId::kShaper, 0}.to_nits(0.5)), 50.0);
  EXPECT_EQ((OutputEncoding{StageId::kLinearDevice, 8}.to_nits(0.5)), 50.0);
  EXPECT_EQ((OutputEncoding{StageId::kLinearDevice, 7}.to_nits(0.5)), 0.5);
  EXPECT_NEAR((OutputEncoding{StageId::kTonemap, 0}.to_nits(0.5)), 21.4041, 1e-3);
  EXPECT_NEAR((OutputEncoding{StageId::kTonemap, 3}.to_nits(0.5080784)), 100.0, 1e-4);
  EXPECT_EQ((OutputEncoding{StageId::kTonemap, 5}.to_nits(1.0)), 80.0);
  EXPECT_NEAR((OutputEncoding{StageId::kCombineLuts, 3}.to_nits(0.5080784 / 1.05)), 100.0, 1e-4);
  EXPECT_NEAR((OutputEncoding{StageId::kTonemap, 2, 1 / 2.2}.to_nits(0.5)),
              100 * std::pow(0.5, 2.2), 1e-12);
}

}  // namespace
