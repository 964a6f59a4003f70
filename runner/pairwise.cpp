#include "runner/pairwise.h"

#include <algorithm>
#include <numeric>
#include <set>

namespace hdrc {

std::vector<std::vector<int>> full_rows(const std::vector<int>& sizes) {
  size_t total = 1;
  for (int s : sizes) total *= static_cast<size_t>(std::max(s, 0));
  std::vector<std::vector<int>> rows;
  rows.reserve(total);
  for (size_t k = 0; k < total; ++k) {
    std::vector<int> row(sizes.size());
    size_t rest = k;
    for (size_t d = sizes.size(); d-- > 0;) {
      row[d] = static_cast<int>(rest % sizes[d]);
      rest /= sizes[d];
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

namespace {
constexpr int kFree = -1;  // a "don't care" cell
}

std::vector<std::vector<int>> pairwise_rows(const std::vector<int>& sizes,
                                            const std::vector<int>& full) {
  const int n = static_cast<int>(sizes.size());
  if (n == 0) return {{}};
  // Processing order: the full dimensions (as listed), then the rest by decreasing size.
  std::vector<int> order;
  std::vector<bool> is_full(n, false);
  for (int d : full)
    if (d >= 0 && d < n && !is_full[d]) {
      is_full[d] = true;
      order.push_back(d);
    }
  std::vector<int> rest;
  for (int d = 0; d < n; ++d)
    if (!is_full[d]) rest.push_back(d);
  std::stable_sort(rest.begin(), rest.end(), [&](int a, int b) { return sizes[a] > sizes[b]; });
  order.insert(order.end(), rest.begin(), rest.end());
  const size_t seed_dims = std::max<size_t>(std::min<size_t>(2, order.size()), full.size());

  // 1. The seed: the cross product of the first `seed_dims` dimensions in processing order.
  std::vector<int> seed_sizes;
  for (size_t i = 0; i < seed_dims; ++i) seed_sizes.push_back(sizes[order[i]]);
  std::vector<std::vector<int>> rows;
  for (const auto& s : full_rows(seed_sizes)) {
    std::vector<int> row(n, kFree);
    for (size_t i = 0; i < seed_dims; ++i) row[order[i]] = s[i];
    rows.push_back(std::move(row));
  }

  for (size_t step = seed_dims; step < order.size(); ++step) {
    const int k = order[step];
    // covered[j][vj * sizes[k] + vk] for every dimension j processed before k.
    std::vector<std::vector<char>> covered(n);
    for (size_t i = 0; i < step; ++i) {
      const int j = order[i];
      covered[j].assign(static_cast<size_t>(sizes[j]) * sizes[k], 0);
    }
    auto cell = [&](int j, int vj, int vk) -> char& {
      return covered[j][static_cast<size_t>(vj) * sizes[k] + vk];
    };
    // 2. Horizontal growth.
    for (auto& row : rows) {
      int best = kFree, best_gain = 0;
      for (int vk = 0; vk < sizes[k]; ++vk) {
        int gain = 0;
        for (size_t i = 0; i < step; ++i) {
          const int j = order[i];
          if (row[j] != kFree && !cell(j, row[j], vk)) ++gain;
        }
        if (gain > best_gain) {
          best_gain = gain;
          best = vk;
        }
      }
      if (best == kFree) continue;
      row[k] = best;
      for (size_t i = 0; i < step; ++i) {
        const int j = order[i];
        if (row[j] != kFree) cell(j, row[j], best) = 1;
      }
    }
    // 3. Vertical growth, pairs in dimension order then value order.
    for (size_t i = 0; i < step; ++i) {
      const int j = order[i];
      for (int vj = 0; vj < sizes[j]; ++vj)
        for (int vk = 0; vk < sizes[k]; ++vk) {
          if (cell(j, vj, vk)) continue;
          auto fits = [&](const std::vector<int>& r) {
            return (r[j] == kFree || r[j] == vj) && (r[k] == kFree || r[k] == vk);
          };
          auto it = std::find_if(rows.begin(), rows.end(), fits);
          if (it == rows.end()) {
            rows.emplace_back(n, kFree);
            it = std::prev(rows.end());
          }
          (*it)[j] = vj;
          (*it)[k] = vk;
          // The row may now cover other pairs of k with the dimensions it has set.
          for (size_t m = 0; m < step; ++m) {
            const int jm = order[m];
            if ((*it)[jm] != kFree) cell(jm, (*it)[jm], vk) = 1;
          }
        }
    }
  }
  // 4. Fill the don't-cares, drop duplicates (keeping the first).
  std::vector<std::vector<int>> out;
  std::set<std::vector<int>> seen;
  for (auto& row : rows) {
    for (int& v : row)
      if (v == kFree) v = 0;
    if (seen.insert(row).second) out.push_back(row);
  }
  return out;
}

}  // namespace hdrc
