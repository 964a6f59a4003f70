// t-way covering rows (runner/pairwise.h: covering_rows): every t-tuple of values covered, the
// `full` dimensions crossed, deterministic, and no larger than needed on designs whose optimum is
// known.
#include <gtest/gtest.h>

#include <functional>
#include <set>
#include <vector>

#include "runner/pairwise.h"

namespace {

using hdrc::covering_rows;
using hdrc::full_rows;
using hdrc::pairwise_rows;

using Rows = std::vector<std::vector<int>>;

// Counts the t-tuples (dimension subset × values) no row holds.
size_t uncovered(const Rows& rows, const std::vector<int>& sizes, int t) {
  const int n = static_cast<int>(sizes.size());
  size_t missing = 0;
  std::vector<int> dims(t);
  // Every t-subset of dimensions.
  std::function<void(int, int)> pick = [&](int from, int depth) {
    if (depth == t) {
      std::vector<int> sub;
      for (int d : dims) sub.push_back(sizes[d]);
      std::set<std::vector<int>> seen;
      for (const auto& r : rows) {
        std::vector<int> v;
        for (int d : dims) v.push_back(r[d]);
        seen.insert(v);
      }
      size_t total = 1;
      for (int s : sub) total *= static_cast<size_t>(s);
      missing += total - seen.size();
      return;
    }
    for (int d = from; d < n; ++d) {
      dims[depth] = d;
      pick(d + 1, depth + 1);
    }
  };
  pick(0, 0);
  return missing;
}

bool in_range(const Rows& rows, const std::vector<int>& sizes) {
  for (const auto& r : rows) {
    if (r.size() != sizes.size()) return false;
    for (size_t d = 0; d < r.size(); ++d)
      if (r[d] < 0 || r[d] >= sizes[d]) return false;
  }
  return true;
}

TEST(Covering, ThreeWayCoversEveryTriple) {
  for (const std::vector<int>& sizes : {std::vector<int>{3, 3, 3, 3},
                                        {4, 3, 3, 2, 2, 2},
                                        {2, 2, 2, 2, 2, 2, 2, 2, 2, 2},
                                        {5, 4, 4, 3, 3, 3, 2, 2}}) {
    const Rows rows = covering_rows(sizes, 3);
    EXPECT_TRUE(in_range(rows, sizes));
    EXPECT_EQ(uncovered(rows, sizes, 3), 0u) << sizes.size() << " dimensions";
    // At least the product of the three largest dimensions (every triple of them appears).
    EXPECT_GE(rows.size(), static_cast<size_t>(sizes[0] * sizes[1] * sizes[2]));
    // Far fewer than the cross product once there are more dimensions than t.
    size_t product = 1;
    for (int s : sizes) product *= static_cast<size_t>(s);
    EXPECT_LT(rows.size(), product);
  }
}

// 2^10 binary dimensions at strength 3: the best known covering array has 12 rows (Colbourn's
// covering array tables, CAN(3, 10, 2) = 12); IPOG is a greedy construction, so within 2x of it.
TEST(Covering, BinaryThreeWayNearTheKnownOptimum) {
  const Rows rows = covering_rows(std::vector<int>(10, 2), 3);
  EXPECT_EQ(uncovered(rows, std::vector<int>(10, 2), 3), 0u);
  EXPECT_LE(rows.size(), 24u);
  EXPECT_GE(rows.size(), 12u);
}

TEST(Covering, FullDimensionsAreCrossedAndTheRestThreeWay) {
  const std::vector<int> sizes{2, 10, 5, 4, 4, 3, 3};
  const Rows rows = covering_rows(sizes, 3, {0, 1, 2});
  std::set<std::vector<int>> full;
  for (const auto& r : rows) full.insert({r[0], r[1], r[2]});
  EXPECT_EQ(full.size(), 100u);
  EXPECT_EQ(uncovered(rows, sizes, 3), 0u);
  EXPECT_EQ(rows, covering_rows(sizes, 3, {0, 1, 2}));  // deterministic
}

TEST(Covering, StrengthTwoIsPairwiseAndFullStrengthIsTheCrossProduct) {
  const std::vector<int> sizes{3, 2, 4, 2};
  EXPECT_EQ(covering_rows(sizes, 2), pairwise_rows(sizes));
  EXPECT_EQ(covering_rows(sizes, 4), full_rows(sizes));
}

}  // namespace

// The loader: a covering matrix needs a strength in 2..4; "tier" is quick or exhaustive; the
// quick suite leaves exhaustive cases out and the exhaustive suite keeps both tiers.
#include "runner/case_loader.h"

namespace {

std::string errors_of(const std::string& text) {
  std::vector<hdrc::Error> errors;
  hdrc::parse_case_file("t.json", text, std::string(HDRC_SOURCE_DIR) + "/cases", "t", &errors);
  std::string all;
  for (const auto& e : errors) all += e.to_string() + "\n";
  return all;
}

TEST(CoveringLoader, StrengthAndTierAreChecked) {
  const std::string m = R"("matrix": {"mode": "covering", %s "cvars": {"r.LUT.Size": [16, 32]}})";
  auto file = [&](const std::string& strength, const std::string& tier) {
    std::string mm = m;
    mm.replace(mm.find("%s"), 2, strength);
    return R"({"stage": "combine_luts", )" + tier + mm + "}";
  };
  EXPECT_NE(
      errors_of(file("", "")).find("t.json: /matrix/strength: a covering matrix needs a strength"),
      std::string::npos);
  EXPECT_NE(errors_of(file(R"("strength": 5,)", "")).find("invalid strength 5"), std::string::npos);
  EXPECT_EQ(errors_of(file(R"("strength": 3,)", R"("tier": "exhaustive", )")), "");
  EXPECT_NE(errors_of(file(R"("strength": 3,)", R"("tier": "exhaustiv", )"))
                .find("/tier: unknown tier \"exhaustiv\", did you mean 'exhaustive'?"),
            std::string::npos);
  EXPECT_NE(
      errors_of(
          R"({"stage": "combine_luts", "matrix": {"strength": 3, "cvars": {"r.LUT.Size": [16]}}})")
          .find("\"strength\" applies to covering matrices only"),
      std::string::npos);
}

TEST(CoveringLoader, SuitesSelectTiers) {
  const auto quick = hdrc::load_cases(std::string(HDRC_SOURCE_DIR) + "/cases");
  const auto all = hdrc::load_cases(std::string(HDRC_SOURCE_DIR) + "/cases", "exhaustive");
  ASSERT_TRUE(quick.errors.empty());
  ASSERT_TRUE(all.errors.empty());
  size_t exhaustive = 0;
  for (const auto& c : quick.cases) EXPECT_EQ(c.tier, "quick") << c.id;
  for (const auto& c : all.cases) exhaustive += c.tier == "exhaustive";
  EXPECT_EQ(all.cases.size(), quick.cases.size() + exhaustive);
  EXPECT_GE(exhaustive, 5000u);
  EXPECT_FALSE(hdrc::load_cases(std::string(HDRC_SOURCE_DIR) + "/cases", "fast").errors.empty());
}

}  // namespace
