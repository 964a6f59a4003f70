// Covering designs for case matrices: every pair of values of every two dimensions in at least
// one row ("pairwise", strength 2), with chosen dimensions crossed exhaustively.
//
// The algorithm is IPOG (Lei, Kacker, Kuhn, Okun, Lawrence, "IPOG: A General Strategy for
// T-Way Software Testing", ECBS 2007) at strength 2, fully deterministic: no random choice, ties
// go to the value listed first, so the same matrix always expands to the same cases (and ids).
//   1. The `full` dimensions are crossed exhaustively (with fewer than two, the first two
//      dimensions in processing order are); the other dimensions follow in decreasing size
//      (ties in listed order).
//   2. Horizontal growth: each new dimension gets, row by row, the value that covers the most
//      pairs not yet covered (ties: the value listed first); a row that would cover nothing new
//      keeps a "don't care".
//   3. Vertical growth: each pair still uncovered goes into the first row whose cells for it are
//      free or already right, else into a new row.
//   4. Remaining "don't care" cells take the first listed value; duplicate rows are dropped.
#pragma once

#include <vector>

namespace hdrc {

// `sizes[d]`: number of values of dimension d (each >= 1). `full`: indices of dimensions to cross
// exhaustively. Returns rows of value indices (row[d] in [0, sizes[d])), every pair of values of
// every two dimensions in some row and every combination of the `full` dimensions in some row.
std::vector<std::vector<int>> pairwise_rows(const std::vector<int>& sizes,
                                            const std::vector<int>& full = {});

// Strength-t covering rows (IPOG generalised to t-way, same determinism rules): every
// combination of values of every t dimensions appears in at least one row, and every combination
// of the `full` dimensions. t = 2 is pairwise_rows; t >= the number of dimensions is full_rows.
//   1. Seed: the cross product of the `full` dimensions, or of the first t dimensions in processing
//      order when that is larger (processing order as pairwise_rows).
//   2. Horizontal growth: each new dimension k gets, row by row, the value covering the most
//      t-tuples (k with t−1 earlier dimensions) not yet covered; ties: the value listed first.
//   3. Vertical growth: each t-tuple still uncovered (earlier dimensions in processing order,
//      values in listed order) goes into the first row whose cells for it are free or already
//      right, else into a new row.
//   4. "Don't care" cells take the first listed value; duplicate rows are dropped.
std::vector<std::vector<int>> covering_rows(const std::vector<int>& sizes, int strength,
                                            const std::vector<int>& full = {});

// The cross product, last dimension fastest.
std::vector<std::vector<int>> full_rows(const std::vector<int>& sizes);

}  // namespace hdrc
