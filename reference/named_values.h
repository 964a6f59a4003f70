// A pixel's named intermediate values: what the specification pages' worked pixels list
// (docs/spec/*.md; reference/spec_worked_pixels_test.cpp compares them) and `hdrconform probe
// --json` prints for the pipelines other than UE 5.5 (Pipeline::named_values). Each pipeline's
// reference fills them from its own stage functions' traces (operators::named_values,
// pq_grading::named_values, unity_urp::named_values, grading::film_tone_map_named_values), so the
// pages, probe and the reference share one list.
#pragma once

#include <string>
#include <vector>

#include "color/vec.h"
#include "core/named_value.h"

namespace hdrc::ref {

using NamedValue = hdrc::NamedValue;  // core/named_value.h

inline void add_named(std::vector<NamedValue>* out, std::string name, double v,
                      bool detail = false) {
  out->push_back({std::move(name), {v}, detail});
}
inline void add_named(std::vector<NamedValue>* out, std::string name, const Vec3& v,
                      bool detail = false) {
  out->push_back({std::move(name), {v[0], v[1], v[2]}, detail});
}

}  // namespace hdrc::ref
