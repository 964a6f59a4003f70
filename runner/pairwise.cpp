#include "runner/pairwise.h"

#include <algorithm>
#include <cstdint>
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

// The processing order of the generators below: the full dimensions (as listed, each once, valid
// ones only), then the rest by decreasing size (stable). `n_full` receives how many are full.
std::vector<int> processing_order(const std::vector<int>& sizes, const std::vector<int>& full,
                                  size_t& n_full) {
  const int n = static_cast<int>(sizes.size());
  std::vector<int> order;
  std::vector<bool> is_full(n, false);
  for (int d : full)
    if (d >= 0 && d < n && !is_full[d]) {
      is_full[d] = true;
      order.push_back(d);
    }
  n_full = order.size();
  std::vector<int> rest;
  for (int d = 0; d < n; ++d)
    if (!is_full[d]) rest.push_back(d);
  std::stable_sort(rest.begin(), rest.end(), [&](int a, int b) { return sizes[a] > sizes[b]; });
  order.insert(order.end(), rest.begin(), rest.end());
  return order;
}

// The seed rows: the cross product of the first `seed_dims` dimensions of `order`, the other
// cells free.
std::vector<std::vector<int>> seed_rows(const std::vector<int>& sizes,
                                        const std::vector<int>& order, size_t seed_dims) {
  std::vector<int> seed_sizes;
  for (size_t i = 0; i < seed_dims; ++i) seed_sizes.push_back(sizes[order[i]]);
  std::vector<std::vector<int>> rows;
  for (const auto& s : full_rows(seed_sizes)) {
    std::vector<int> row(sizes.size(), kFree);
    for (size_t i = 0; i < seed_dims; ++i) row[order[i]] = s[i];
    rows.push_back(std::move(row));
  }
  return rows;
}
// The generators' last step: don't-care cells take value 0, and repeated rows are dropped
// (keeping the first).
std::vector<std::vector<int>> finished_rows(std::vector<std::vector<int>> rows) {
  std::vector<std::vector<int>> out;
  std::set<std::vector<int>> seen;
  for (auto& row : rows) {
    for (int& v : row)
      if (v == kFree) v = 0;
    if (seen.insert(row).second) out.push_back(row);
  }
  return out;
}
}  // namespace

std::vector<std::vector<int>> pairwise_rows(const std::vector<int>& sizes,
                                            const std::vector<int>& full) {
  const int n = static_cast<int>(sizes.size());
  if (n == 0) return {{}};
  size_t n_full = 0;
  const std::vector<int> order = processing_order(sizes, full, n_full);
  const size_t seed_dims = std::max<size_t>(std::min<size_t>(2, order.size()), n_full);
  // 1. The seed: the cross product of the first `seed_dims` dimensions in processing order.
  std::vector<std::vector<int>> rows = seed_rows(sizes, order, seed_dims);

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
  return finished_rows(std::move(rows));
}

namespace {

// Every k-subset of {0 … n−1} in lexicographic order.
std::vector<std::vector<int>> subsets(int n, int k) {
  std::vector<std::vector<int>> out;
  if (k < 0 || k > n) return out;
  std::vector<int> s(k);
  for (int i = 0; i < k; ++i) s[i] = i;
  for (;;) {
    out.push_back(s);
    int i = k - 1;
    while (i >= 0 && s[i] == n - k + i) --i;
    if (i < 0) break;
    ++s[i];
    for (int j = i + 1; j < k; ++j) s[j] = s[j - 1] + 1;
  }
  return out;
}

}  // namespace

std::vector<std::vector<int>> covering_rows(const std::vector<int>& sizes, int strength,
                                            const std::vector<int>& full) {
  const int n = static_cast<int>(sizes.size());
  if (strength <= 2) return pairwise_rows(sizes, full);
  if (strength >= n) return full_rows(sizes);
  const int t = strength;
  size_t n_full = 0;
  const std::vector<int> order = processing_order(sizes, full, n_full);
  const size_t seed_dims = std::max<size_t>(static_cast<size_t>(t), n_full);
  std::vector<std::vector<int>> rows = seed_rows(sizes, order, seed_dims);

  for (size_t step = seed_dims; step < order.size(); ++step) {
    const int k = order[step];
    // The (t−1)-subsets of the dimensions processed so far (as positions in `order`), and for
    // each its covered tuples: index = mixed-radix value tuple · sizes[k] + value of k.
    const auto groups = subsets(static_cast<int>(step), t - 1);
    std::vector<std::vector<char>> covered(groups.size());
    for (size_t g = 0; g < groups.size(); ++g) {
      size_t count = static_cast<size_t>(sizes[k]);
      for (int pos : groups[g]) count *= static_cast<size_t>(sizes[order[pos]]);
      covered[g].assign(count, 0);
    }
    // The tuple index of `row` in group g with k = vk, or SIZE_MAX when a cell is free.
    auto index = [&](const std::vector<int>& row, size_t g, int vk) -> size_t {
      size_t idx = 0;
      for (int pos : groups[g]) {
        const int v = row[order[pos]];
        if (v == kFree) return SIZE_MAX;
        idx = idx * static_cast<size_t>(sizes[order[pos]]) + static_cast<size_t>(v);
      }
      return idx * static_cast<size_t>(sizes[k]) + static_cast<size_t>(vk);
    };
    // 2. Horizontal growth.
    for (auto& row : rows) {
      int best = kFree, best_gain = 0;
      for (int vk = 0; vk < sizes[k]; ++vk) {
        int gain = 0;
        for (size_t g = 0; g < groups.size(); ++g) {
          const size_t idx = index(row, g, vk);
          if (idx != SIZE_MAX && !covered[g][idx]) ++gain;
        }
        if (gain > best_gain) {
          best_gain = gain;
          best = vk;
        }
      }
      if (best == kFree) continue;
      row[k] = best;
      for (size_t g = 0; g < groups.size(); ++g)
        if (const size_t idx = index(row, g, best); idx != SIZE_MAX) covered[g][idx] = 1;
    }
    // 3. Vertical growth.
    for (size_t g = 0; g < groups.size(); ++g) {
      std::vector<int> dims;
      for (int pos : groups[g]) dims.push_back(order[pos]);
      std::vector<int> tuple_sizes;
      for (int d : dims) tuple_sizes.push_back(sizes[d]);
      tuple_sizes.push_back(sizes[k]);
      const auto tuples = full_rows(tuple_sizes);
      for (size_t ti = 0; ti < tuples.size(); ++ti) {
        if (covered[g][ti]) continue;
        const auto& tv = tuples[ti];
        auto fits = [&](const std::vector<int>& r) {
          for (size_t j = 0; j < dims.size(); ++j)
            if (r[dims[j]] != kFree && r[dims[j]] != tv[j]) return false;
          return r[k] == kFree || r[k] == tv.back();
        };
        auto it = std::find_if(rows.begin(), rows.end(), fits);
        if (it == rows.end()) {
          rows.emplace_back(n, kFree);
          it = std::prev(rows.end());
        }
        for (size_t j = 0; j < dims.size(); ++j) (*it)[dims[j]] = tv[j];
        (*it)[k] = tv.back();
        for (size_t g2 = 0; g2 < groups.size(); ++g2)
          if (const size_t idx = index(*it, g2, tv.back()); idx != SIZE_MAX) covered[g2][idx] = 1;
      }
    }
  }
  return finished_rows(std::move(rows));
}

}  // namespace hdrc
