#include "reference/color/device_allowance.h"

#include <Imath/half.h>

#include <cstdint>

namespace hdrc::ref {

namespace {

// The half next to `h` toward +inf (up) or −inf, by its bit pattern: magnitudes are ordered as
// their bits, so toward +inf is one more for a positive half and one less for a negative one.
double half_next(Imath::half h, bool up) {
  const uint16_t b = h.bits();
  const bool negative = (b & 0x8000u) != 0;
  const uint16_t magnitude = b & 0x7fffu;
  uint16_t next;
  if (magnitude == 0) {
    next = up ? 0x0001u : 0x8001u;  // ±2^-24, the smallest subnormals
  } else if (negative == up) {
    next = static_cast<uint16_t>(b - 1);  // toward zero
  } else {
    next = static_cast<uint16_t>(b + 1);  // away from zero (0x7bff + 1 = +Inf)
  }
  Imath::half out;
  out.setBits(next);
  return static_cast<double>(static_cast<float>(out));
}

double half_round(double v, bool up) {
  if (std::isnan(v)) return v;
  const Imath::half h(static_cast<float>(v));  // round to nearest even
  const double hv = static_cast<double>(static_cast<float>(h));
  if (hv == v || (up && hv > v) || (!up && hv < v)) return hv;
  return half_next(h, up);
}

}  // namespace

double half_round_down(double v) {
  return half_round(v, false);
}
double half_round_up(double v) {
  return half_round(v, true);
}

}  // namespace hdrc::ref
