// One named intermediate value of a pixel: the rows of the specification pages' worked pixels
// (docs/spec/*.md) and what `hdrconform probe --json` prints. The pipelines' references fill them
// (reference/named_values.h has the helpers); the runner reaches them through
// Pipeline::named_values (core/pipeline.h).
#pragma once

#include <string>
#include <vector>

namespace hdrc {

struct NamedValue {
  std::string name;       // the spec page's name of the value ("ap1", "graded_pq", ...)
  std::vector<double> v;  // one number (a scalar) or three (r, g, b)
  bool detail = false;    // a step of a shared function (FilmToneMap inside another pipeline's
                          // pixel), listed in full on that function's own page
};

}  // namespace hdrc
