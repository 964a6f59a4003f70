// The golden comparison's bound (docs/goldens.md): when the reference's output of a case counts
// as equal to its golden. One set of goldens must hold for every supported build of the reference
// (GCC and clang, -O0 to -O3): those builds differ in the last bits of double-precision results
// (a libm call folded at compile time or made at run time, a different evaluation order after
// inlining), and where a value is the difference of much larger terms (a colour matrix taking a
// grey to ~0, a transfer curve near black) such a last-bit difference is no longer a last-bit
// difference of the result. A value therefore matches when it is within
//   kGoldenUlps float32 ULPs of the golden (the relative part), or
//   kGoldenScaleFloor * 2^-24 * S of it, S = the golden image's largest finite |value| of that
//   channel kind (colour channels together, alpha alone) (the absolute part: a fraction of the
//   image's own signal scale, far below any quantisation the suite judges);
// NaN matches NaN, an infinity only the same infinity.
#pragma once

#include <cstddef>
#include <string>

#include "core/image.h"

namespace hdrc {

inline constexpr int kGoldenUlps = 2;
inline constexpr double kGoldenScaleFloor =
    8.0;  // measured: at most 4.56 (GCC -O3), docs/goldens.md

// Distance in float32 units in the last place (finite, non-NaN arguments).
long long ulp_distance(float a, float b);

// The two scales of the absolute part: the golden's largest finite |colour value| (R, G, B) and
// its largest finite |alpha| (0 when there is none).
struct GoldenScale {
  double colour = 0, alpha = 0;
};
GoldenScale golden_scale(const Image& golden);

// Whether `value` matches `golden` under the bound, `scale` being its channel kind's S.
bool golden_value_close(float golden, float value, double scale);

// How far `value` is from `golden` in units of the bound: 0 equal, ≤ 1 within, > 1 a regression
// (the smaller of the ULP distance / kGoldenUlps and |difference| / the absolute part);
// infinity when NaN or infinities do not match.
double golden_deviation(float golden, float value, double scale);

struct GoldenDiff {
  size_t differ = 0;   // values over the bound
  size_t first = 0;    // index (into Image::data) of the first of them
  double largest = 0;  // the largest golden_deviation of any value (≤ 1 when differ == 0)
  size_t largest_at = 0;
};
// Compares two images of the same size value by value.
GoldenDiff compare_with_golden(const Image& golden, const Image& reference);

}  // namespace hdrc
