#include "core/output_encoding.h"

#include <cmath>

#include "color/gamma_correction.h"
#include "color/st2084.h"

namespace hdrc {

double OutputEncoding::to_nits(double v) const {
  if (pre_scale != 1.0) v *= pre_scale;
  switch (transfer) {
    case Transfer::kLinear:
      return v * nits_scale;
    case Transfer::kPq:
      return ref::st2084::nits_from_pq(v) * nits_scale;
    case Transfer::kSrgb:
      return ref::srgb_to_linear(v) * nits_scale;
    case Transfer::kRec709:
      return ref::rec709_to_linear(v) * nits_scale;
    case Transfer::kGamma:
      return (v > 0 ? std::pow(v, gamma) : 0.0) * nits_scale;
  }
  return v;
}

}  // namespace hdrc
