// The console variables hdrconform understands: one table (name, type, default, range, what it
// feeds), validation with errors that name the valid choices, and typed access.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"

namespace hdrc {

enum class CvarType { kInt, kFloat };

struct CvarInfo {
  std::string_view name;
  CvarType type;
  double default_value;
  double min_value;        // inclusive
  double max_value;        // inclusive
  std::string_view feeds;  // what it drives in UE 5.5, with the UE source that reads it
};

// Every supported cvar, in a stable order.
const std::vector<CvarInfo>& cvar_table();
const CvarInfo* find_cvar(std::string_view name);

// Up to `n` known cvar names closest to `name` (edit distance, case-insensitive), for errors.
std::vector<std::string> nearest_cvar_names(std::string_view name, size_t n = 3);

// A set of cvar values. Unset cvars read as their default.
class CvarValues {
 public:
  // Validates name, type and range; the error's message/choices say what is wrong (the caller adds
  // file and pointer).
  Status set(std::string_view name, double value);
  double get(std::string_view name) const;
  int get_int(std::string_view name) const { return static_cast<int>(get(name)); }
  bool is_set(std::string_view name) const { return values_.count(std::string(name)) != 0; }
  const std::map<std::string, double>& explicit_values() const { return values_; }

 private:
  std::map<std::string, double> values_;
};

}  // namespace hdrc
