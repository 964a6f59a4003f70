#include "color/vec.h"

namespace hdrc::ref {

Mat3 inverse(const Mat3& a) {
  const double c00 = a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1);
  const double c01 = a(1, 2) * a(2, 0) - a(1, 0) * a(2, 2);
  const double c02 = a(1, 0) * a(2, 1) - a(1, 1) * a(2, 0);
  const double det = a(0, 0) * c00 + a(0, 1) * c01 + a(0, 2) * c02;
  const double s = 1.0 / det;
  Mat3 r;
  r(0, 0) = c00 * s;
  r(0, 1) = (a(0, 2) * a(2, 1) - a(0, 1) * a(2, 2)) * s;
  r(0, 2) = (a(0, 1) * a(1, 2) - a(0, 2) * a(1, 1)) * s;
  r(1, 0) = c01 * s;
  r(1, 1) = (a(0, 0) * a(2, 2) - a(0, 2) * a(2, 0)) * s;
  r(1, 2) = (a(0, 2) * a(1, 0) - a(0, 0) * a(1, 2)) * s;
  r(2, 0) = c02 * s;
  r(2, 1) = (a(0, 1) * a(2, 0) - a(0, 0) * a(2, 1)) * s;
  r(2, 2) = (a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0)) * s;
  return r;
}

Mat3 to_float(const Mat3& a) {
  Mat3 r;
  for (int i = 0; i < 9; ++i) r.m[i] = static_cast<double>(static_cast<float>(a.m[i]));
  return r;
}

}  // namespace hdrc::ref
