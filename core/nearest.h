// "Did you mean": the names closest to a misspelt one, for error messages.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace hdrc {

// Case-insensitive Levenshtein distance.
size_t edit_distance(std::string_view a, std::string_view b);

// Up to `n` of `names` closest to `name` by case-insensitive edit distance, closest first (ties
// keep the order of `names`).
std::vector<std::string> nearest_names(std::string_view name, const std::vector<std::string>& names,
                                       size_t n);

}  // namespace hdrc
