// Small double-precision vector/matrix types for the reference. Matrices are row-major and applied
// as out = M · in (column vectors), the convention of UE's HLSL `mul(M, v)` (docs/spec/ue55.md
// §0.3).
#pragma once

#include <array>
#include <cmath>

namespace hdrc::ref {

using Vec3 = std::array<double, 3>;

struct Mat3 {
  std::array<double, 9> m{};  // row-major
  double operator()(int r, int c) const { return m[r * 3 + c]; }
  double& operator()(int r, int c) { return m[r * 3 + c]; }
  static Mat3 identity() { return Mat3{{1, 0, 0, 0, 1, 0, 0, 0, 1}}; }
  static Mat3 diag(const Vec3& d) { return Mat3{{d[0], 0, 0, 0, d[1], 0, 0, 0, d[2]}}; }
};

inline Vec3 operator*(const Mat3& a, const Vec3& v) {
  return {a(0, 0) * v[0] + a(0, 1) * v[1] + a(0, 2) * v[2],
          a(1, 0) * v[0] + a(1, 1) * v[1] + a(1, 2) * v[2],
          a(2, 0) * v[0] + a(2, 1) * v[1] + a(2, 2) * v[2]};
}

inline Mat3 operator*(const Mat3& a, const Mat3& b) {
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r(i, j) = a(i, 0) * b(0, j) + a(i, 1) * b(1, j) + a(i, 2) * b(2, j);
  return r;
}

inline double dot(const Vec3& a, const Vec3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

Mat3 inverse(const Mat3& a);

// The largest absolute difference between corresponding entries.
inline double max_abs_diff(const Mat3& a, const Mat3& b) {
  double m = 0;
  for (int i = 0; i < 9; ++i) m = std::fmax(m, std::fabs(a.m[i] - b.m[i]));
  return m;
}

// Rounds every entry to float32 and back, as UE does when a double matrix built on the CPU is
// copied into a shader parameter (FMatrix44d -> FMatrix44f).
Mat3 to_float(const Mat3& a);

}  // namespace hdrc::ref
