#include "gpu/shader_constants.h"

#include <cstdio>
#include <limits>

#include "reference/color/st2084.h"
#include "reference/color/ue_log_shaper.h"

namespace hdrc::gpu {

const std::vector<SharedConstant>& shared_constants() {
  namespace pq = ref::st2084;
  namespace lg = ref::ue_log;
  static const std::vector<SharedConstant> table = {
      {"PQ_M1", pq::kM1, "ST 2084 m1"},
      {"PQ_M2", pq::kM2, "ST 2084 m2"},
      {"PQ_C1", pq::kC1, "ST 2084 c1"},
      {"PQ_C2", pq::kC2, "ST 2084 c2"},
      {"PQ_C3", pq::kC3, "ST 2084 c3"},
      {"PQ_PEAK_NITS", pq::kPeakNits, "ST 2084 peak luminance"},
      {"LOG_LINEAR_RANGE", lg::kLinearRange, "TonemapCommon.ush LinearRange"},
      {"LOG_LINEAR_GREY", lg::kLinearGrey, "TonemapCommon.ush LinearGrey"},
      {"LOG_GREY_CODE", lg::kGreyCode, "TonemapCommon.ush ExposureGrey/1023"},
      {"LINEAR_TO_NITS_SCALE", ref::kLinearToNitsScale, "TonemapCommon.ush LinearToNitsScale"},
  };
  return table;
}

std::string glsl_shared_constants() {
  std::string out;
  for (const auto& c : shared_constants()) {
    char number[64];
    std::snprintf(number, sizeof number, "%.*g", std::numeric_limits<float>::max_digits10,
                  static_cast<float>(c.value));
    std::string literal = number;
    if (literal.find_first_of(".e") == std::string::npos) literal += ".0";
    out += "const float " + c.name + " = " + literal + ";  // " + c.source + "\n";
  }
  return out;
}

}  // namespace hdrc::gpu
