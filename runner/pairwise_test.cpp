// The covering design: every pair covered (checked by brute force), the full dimensions crossed,
// deterministic and pinned, and not much larger than the known optimum.
#include "runner/pairwise.h"

#include <gtest/gtest.h>

#include <set>
#include <tuple>

namespace {

// Every (d1, v1, d2, v2) with d1 < d2 appears in some row.
int uncovered_pairs(const std::vector<int>& sizes, const std::vector<std::vector<int>>& rows) {
  std::set<std::tuple<int, int, int, int>> seen;
  for (const auto& r : rows)
    for (size_t a = 0; a < sizes.size(); ++a)
      for (size_t b = a + 1; b < sizes.size(); ++b)
        seen.emplace(static_cast<int>(a), r[a], static_cast<int>(b), r[b]);
  int missing = 0;
  for (size_t a = 0; a < sizes.size(); ++a)
    for (size_t b = a + 1; b < sizes.size(); ++b)
      for (int va = 0; va < sizes[a]; ++va)
        for (int vb = 0; vb < sizes[b]; ++vb)
          missing += !seen.count({static_cast<int>(a), va, static_cast<int>(b), vb});
  return missing;
}

bool rows_in_range(const std::vector<int>& sizes, const std::vector<std::vector<int>>& rows) {
  for (const auto& r : rows) {
    if (r.size() != sizes.size()) return false;
    for (size_t d = 0; d < sizes.size(); ++d)
      if (r[d] < 0 || r[d] >= sizes[d]) return false;
  }
  return true;
}

TEST(Pairwise, CoversEveryPairOfManyShapes) {
  const std::vector<std::vector<int>> shapes = {{2},
                                                {3, 3},
                                                {3, 3, 3, 3},
                                                {2, 2, 2, 2, 2, 2, 2, 2, 2, 2},
                                                {10, 5, 2},
                                                {4, 4, 4, 4, 4},
                                                {10, 5, 2, 3, 3, 2},
                                                {1, 7, 1, 3},
                                                {5, 1, 1, 1},
                                                {6, 6, 3, 4, 2, 2, 5, 3, 3, 4, 4, 4, 3}};
  for (const auto& sizes : shapes) {
    const auto rows = hdrc::pairwise_rows(sizes);
    EXPECT_TRUE(rows_in_range(sizes, rows));
    EXPECT_EQ(uncovered_pairs(sizes, rows), 0) << ::testing::PrintToString(sizes);
    EXPECT_EQ(std::set<std::vector<int>>(rows.begin(), rows.end()).size(), rows.size())
        << "duplicate rows";
  }
}

// Known optima: 3^4 needs 9 rows (an orthogonal array), 2^10 needs 6, 4^5 needs 16. A greedy
// design is allowed some slack, not a blow-up.
TEST(Pairwise, CloseToTheOptimum) {
  EXPECT_LE(hdrc::pairwise_rows({3, 3, 3, 3}).size(), 11u);
  EXPECT_LE(hdrc::pairwise_rows(std::vector<int>(10, 2)).size(), 10u);
  EXPECT_LE(hdrc::pairwise_rows({4, 4, 4, 4, 4}).size(), 25u);
  // Pairs of the largest two dimensions bound it below: 10 x 5.
  const auto rows = hdrc::pairwise_rows({10, 5, 2, 3, 3, 2});
  EXPECT_GE(rows.size(), 50u);
  EXPECT_LE(rows.size(), 55u);
}

TEST(Pairwise, FullDimensionsAreCrossedAndOthersPairwise) {
  // The default suite's tonemap display matrix: HDR x device x gamut crossed, LUT size, format
  // and layout pairwise with each of them and with each other.
  const std::vector<int> sizes = {2, 10, 5, 3, 3, 2};
  const auto rows = hdrc::pairwise_rows(sizes, {0, 1, 2});
  EXPECT_EQ(uncovered_pairs(sizes, rows), 0);
  std::set<std::tuple<int, int, int>> triples;
  for (const auto& r : rows) triples.emplace(r[0], r[1], r[2]);
  EXPECT_EQ(triples.size(), 100u);
  EXPECT_EQ(rows.size(), 100u) << "100 rows hold every pair of the three small dimensions";
  // Ties go to the value listed first: the first-listed LUT size is the most frequent.
  int count[3] = {0, 0, 0};
  for (const auto& r : rows) ++count[r[3]];
  EXPECT_GT(count[0], count[2]);
}

TEST(Pairwise, DeterministicAndPinned) {
  const std::vector<int> sizes = {3, 2, 2, 2};
  const auto a = hdrc::pairwise_rows(sizes);
  EXPECT_EQ(a, hdrc::pairwise_rows(sizes));
  // Pinned: case ids derive from these rows, so a change here renames cases.
  const std::vector<std::vector<int>> expected = {{0, 0, 0, 0}, {0, 1, 1, 1}, {1, 0, 1, 0},
                                                  {1, 1, 0, 1}, {2, 0, 0, 1}, {2, 1, 1, 0}};
  EXPECT_EQ(a, expected) << ::testing::PrintToString(a);
}

TEST(Pairwise, FullRowsIsTheCrossProductLastFastest) {
  const auto rows = hdrc::full_rows({2, 3});
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_EQ(rows[0], (std::vector<int>{0, 0}));
  EXPECT_EQ(rows[1], (std::vector<int>{0, 1}));
  EXPECT_EQ(rows[5], (std::vector<int>{1, 2}));
}

}  // namespace
