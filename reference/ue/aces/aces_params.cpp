// Float32 emulation of RenderCore.cpp's ACES parameter computation (UE 5.5; izzy2lost/
// UnrealEngineUWP, Engine/Source/Runtime/RenderCore/Private/RenderCore.cpp, read at commit
// 05f702e24c9321c3a363582fdc38835dc3f3913c). Each expression keeps UE's operand types: `float`
// where UE has float, `double` where a double literal (0.5, 3., 2., 4., 0.18) promotes it.
#include "reference/ue/aces/aces_params.h"

#include <cmath>
#include <sstream>
#include <string>

namespace hdrc::ref::aces {
namespace {

// RenderCore.cpp constants (float in UE): MIN_STOP_SDR, MAX_STOP_SDR, MIN_STOP_RRT, MAX_STOP_RRT,
// MIN_LUM_SDR, MAX_LUM_SDR, MIN_LUM_RRT, MAX_LUM_RRT.
constexpr float kMinStopSdr = -6.5f;
constexpr float kMaxStopSdr = 6.5f;
constexpr float kMinStopRrt = -15.0f;
constexpr float kMaxStopRrt = 18.0f;
constexpr float kMinLumSdr = 0.02f;     // nits
constexpr float kMaxLumSdr = 48.0f;     // nits
constexpr float kMinLumRrt = 0.0001f;   // nits
constexpr float kMaxLumRrt = 10000.0f;  // nits

// FMath::LogX(10, float): Loge(v) / Loge(10) with Loge(float) = logf.
float log10_f(float v) {
  return std::log(v) / std::log(10.0f);
}

// FMath::LogX(10, double): the double overload (MIX_FLOATS_2_ARGS promotes (int, double)).
double log10_d(double v) {
  return std::log(v) / std::log(10.0);
}

// FMath::Clamp: (X < Min) ? Min : (X < Max) ? X : Max.
float ue_clamp(float x, float lo, float hi) {
  return x < lo ? lo : (x < hi ? x : hi);
}

// RenderCore.cpp: shift(float inValue, float expShift) = pow(2., log2(inValue) − expShift), all in
// double, the return stored to float. The unqualified log2 of the float resolves to the double
// function in UE's build: with log2f, Min.x and Max.x come out 3 and 4 ULP away from UE's own
// float defaults (HDRHelper.h); with double log2 all 18 packed values are bit-identical
// (aces_test.cpp, DefaultLuminancesReproduceUeFloatsBitExactly). Decisions D5.3 assumed float.
float shift(float in_value, float exp_shift) {
  const double e = std::log2(static_cast<double>(in_value)) - static_cast<double>(exp_shift);
  return static_cast<float>(std::pow(2.0, e));
}

// One straddling coefficient, RenderCore.cpp: init_coefsLow / init_coefsHigh:
//   slope·(log10(p.x) ± 0.5·knotInc) + (log10(p.y) − slope·log10(p.x))
// where `log10(p.x) ± 0.5·knotInc` and the product with slope are double, the second bracket
// float, and the sum is rounded to float on store.
float straddle(const TsPointF& p, float knot_inc, double sign) {
  const double lx = static_cast<double>(log10_f(p.x)) + sign * 0.5 * static_cast<double>(knot_inc);
  const float offset = log10_f(p.y) - p.slope * log10_f(p.x);
  return static_cast<float>(static_cast<double>(p.slope) * lx + static_cast<double>(offset));
}

// (log10(hi.x) − log10(lo.x)) / 3. — float difference, double division, float store.
float knot_increment(const TsPointF& lo, const TsPointF& hi) {
  return static_cast<float>(static_cast<double>(log10_f(hi.x) - log10_f(lo.x)) / 3.0);
}

// RenderCore.cpp: init_coefsLow.
std::array<float, 5> init_coefs_low(const TsPointF& low, const TsPointF& mid) {
  const float knot_inc = knot_increment(low, mid);
  std::array<float, 5> c{};
  c[0] = straddle(low, knot_inc, -1.0);
  c[1] = straddle(low, knot_inc, +1.0);
  c[3] = straddle(mid, knot_inc, -1.0);
  c[4] = straddle(mid, knot_inc, +1.0);
  // Bend table ((MIN_STOP_RRT, 0.18), (MIN_STOP_SDR, 0.35)), the 0.18/0.35 rounded to float.
  const std::array<TablePointF, 2> bends{{{kMinStopRrt, 0.18f}, {kMinStopSdr, 0.35f}}};
  const float pct =
      interpolate_1d(bends, static_cast<float>(std::log2(static_cast<double>(low.x) / 0.18)));
  c[2] = log10_f(low.y) + pct * (log10_f(mid.y) - log10_f(low.y));
  return c;
}

// RenderCore.cpp: init_coefsHigh.
std::array<float, 5> init_coefs_high(const TsPointF& mid, const TsPointF& max) {
  const float knot_inc = knot_increment(mid, max);
  std::array<float, 5> c{};
  c[0] = straddle(mid, knot_inc, -1.0);
  c[1] = straddle(mid, knot_inc, +1.0);
  c[3] = straddle(max, knot_inc, -1.0);
  c[4] = straddle(max, knot_inc, +1.0);
  // Bend table ((MAX_STOP_SDR, 0.89), (MAX_STOP_RRT, 0.90)).
  const std::array<TablePointF, 2> bends{{{kMaxStopSdr, 0.89f}, {kMaxStopRrt, 0.90f}}};
  const float pct =
      interpolate_1d(bends, static_cast<float>(std::log2(static_cast<double>(max.x) / 0.18)));
  c[2] = log10_f(mid.y) + pct * (log10_f(max.y) - log10_f(mid.y));
  return c;
}

// RenderCore.cpp: inv_ssts, one spline half. `knot_y` are the knot luminances (c_i + c_{i+1})/2.,
// `first_inclusive` selects the high spline's `>=` on the first interval's lower bound.
std::optional<float> inv_spline(float logy, const std::array<float, 5>& coefs, float log_lo_x,
                                float knot_inc, bool first_inclusive) {
  std::array<float, 4> knot_y{};
  for (int i = 0; i < 4; ++i) {
    knot_y[i] = static_cast<float>(static_cast<double>(coefs[i] + coefs[i + 1]) / 2.0);
  }
  int j = -1;
  if ((first_inclusive ? logy >= knot_y[0] : logy > knot_y[0]) && logy <= knot_y[1]) {
    j = 0;
  } else if (logy > knot_y[1] && logy <= knot_y[2]) {
    j = 1;
  } else if (logy > knot_y[2] && logy <= knot_y[3]) {
    j = 2;
  }
  if (j < 0) return std::nullopt;  // UE: FVector4f cf left uninitialised
  const float c0 = coefs[j], c1 = coefs[j + 1], c2 = coefs[j + 2];
  // RenderCore.cpp: ApplyM1Matrix, in float.
  const float a = 0.5f * c0 - 1.0f * c1 + 0.5f * c2;
  const float b = -1.0f * c0 + 1.0f * c1 + 0.0f * c2;
  const float c = 0.5f * c0 + 0.5f * c1 + 0.0f * c2 - logy;
  // sqrt(b·b − 4.·a·c): float b·b minus a double product, double sqrt, float store.
  const float d = static_cast<float>(std::sqrt(
      static_cast<double>(b * b) - 4.0 * static_cast<double>(a) * static_cast<double>(c)));
  // (2.·c) / (−d − b): double numerator over a float denominator, float store.
  const float t = static_cast<float>((2.0 * static_cast<double>(c)) / static_cast<double>(-d - b));
  return log_lo_x + (t + static_cast<float>(j)) * knot_inc;
}

}  // namespace

float interpolate_1d(const std::array<TablePointF, 2>& table, float value) {
  const float t = ue_clamp((value - table[0].x) / (table[1].x - table[0].x), 0.0f, 1.0f);
  return table[0].y + t * (table[1].y - table[0].y);  // FMath::Lerp(A, B, t) = A + t·(B − A)
}

float lookup_aces_min(float min_luminance) {
  const std::array<TablePointF, 2> table{
      {{log10_f(kMinLumRrt), kMinStopRrt}, {log10_f(kMinLumSdr), kMinStopSdr}}};
  const float stop = interpolate_1d(table, log10_f(min_luminance));
  return static_cast<float>(0.18 * std::pow(2.0, static_cast<double>(stop)));
}

float lookup_aces_max(float max_luminance) {
  const std::array<TablePointF, 2> table{
      {{log10_f(kMaxLumSdr), kMaxStopSdr}, {log10_f(kMaxLumRrt), kMaxStopRrt}}};
  const float stop = interpolate_1d(table, log10_f(max_luminance));
  return static_cast<float>(0.18 * std::pow(2.0, static_cast<double>(stop)));
}

TsParamsF init_ts_params(float min_luminance, float max_luminance, float exp_shift) {
  // MID_PT = { 0.18, 4.8, 1.55 } (double literals stored into float members).
  TsPointF min_pt{lookup_aces_min(min_luminance), min_luminance, 0.0f};
  TsPointF mid_pt{0.18f, 4.8f, 1.55f};
  TsPointF max_pt{lookup_aces_max(max_luminance), max_luminance, 0.0f};
  TsParamsF p;
  p.coefs_low = init_coefs_low(min_pt, mid_pt);
  p.coefs_high = init_coefs_high(mid_pt, max_pt);
  min_pt.x = shift(lookup_aces_min(min_luminance), exp_shift);
  mid_pt.x = shift(0.18f, exp_shift);
  max_pt.x = shift(lookup_aces_max(max_luminance), exp_shift);
  p.min = min_pt;
  p.mid = mid_pt;
  p.max = max_pt;
  return p;
}

std::optional<float> inv_ssts(float luminance, const TsParamsF& c) {
  // KNOT_INC_* = (log10 upper.x − log10 lower.x) / (N_KNOTS − 1.): float difference, double
  // division, float store.
  const float knot_inc_low = knot_increment(c.min, c.mid);
  const float knot_inc_high = knot_increment(c.mid, c.max);
  // FMath::Max(float y, 1e-10) promotes to double (Max(A, B) = A >= B ? A : B, so NaN → 1e-10),
  // then LogX(10, double) is the double overload; the result is stored in a float.
  const double y = static_cast<double>(luminance);
  const float logy = static_cast<float>(log10_d(y >= 1e-10 ? y : 1e-10));

  float logx;
  if (logy <= log10_f(c.min.y)) {
    logx = log10_f(c.min.x);
  } else if (logy > log10_f(c.min.y) && logy <= log10_f(c.mid.y)) {
    const auto v = inv_spline(logy, c.coefs_low, log10_f(c.min.x), knot_inc_low, false);
    if (!v) return std::nullopt;
    logx = *v;
  } else if (logy > log10_f(c.mid.y) && logy < log10_f(c.max.y)) {
    const auto v = inv_spline(logy, c.coefs_high, log10_f(c.mid.x), knot_inc_high, true);
    if (!v) return std::nullopt;
    logx = *v;
  } else {
    logx = log10_f(c.max.x);
  }
  return std::pow(10.0f, logx);  // FMath::Pow(10, float) = powf
}

Status validate_aces_luminances(float min_luminance, float mid_luminance, float max_luminance) {
  const auto describe = [&] {
    std::ostringstream s;
    s.precision(9);
    s << "(Min, Mid, Max) = (" << min_luminance << ", " << mid_luminance << ", " << max_luminance
      << ") nits";
    return s.str();
  };
  const std::string choices = "finite luminances with 0 < Min < Mid < Max";
  for (const float v : {min_luminance, mid_luminance, max_luminance}) {
    if (!std::isfinite(v) || !(v > 0.0f)) {
      return Error{"", "",
                   "ACES tone scale luminance is not finite and positive (log10 of it is "
                   "taken): " +
                       describe(),
                   choices};
    }
  }
  if (!(min_luminance < mid_luminance && mid_luminance < max_luminance)) {
    return Error{"", "", "ACES tone scale luminances are not increasing: " + describe(), choices};
  }
  return {};
}

AcesConfigured configure_aces_tonemap_params(float min_luminance, float mid_luminance,
                                             float max_luminance, float scene_color_multiplier,
                                             float gamut_compression_cvar) {
  AcesConfigured out;
  out.status = validate_aces_luminances(min_luminance, mid_luminance, max_luminance);

  const TsParamsF params_default = init_ts_params(min_luminance, max_luminance);
  const std::optional<float> tmp = inv_ssts(mid_luminance, params_default);
  if (!tmp && out.status.ok()) {
    std::ostringstream s;
    s.precision(9);
    s << "inv_ssts(" << mid_luminance << " nits) falls between the knot intervals UE tests and "
      << "would read uninitialised spline coefficients";
    out.status = Error{"", "", s.str(), ""};
  }
  // With no value UE's result is undefined; NaN makes that visible in every derived parameter.
  const float mid_aces = tmp ? *tmp : std::nanf("");
  // expShift = log2(tmp) − log2(0.18) in double (log2 of the float is the double function, see
  // shift()), stored to float.
  out.exp_shift = static_cast<float>(std::log2(static_cast<double>(mid_aces)) - std::log2(0.18));
  out.ts = init_ts_params(min_luminance, max_luminance, out.exp_shift);

  AcesTonemapParams& p = out.packed;
  p.min_max_data = {out.ts.min.x, out.ts.min.y, out.ts.max.x, out.ts.max.y};
  p.mid_data[0] = out.ts.mid.x;
  p.mid_data[1] = out.ts.mid.y;
  p.mid_data[2] = out.ts.mid.slope;  // mid_data[3] keeps the constructor's 1.0
  p.coefs_low_0 = {out.ts.coefs_low[0], out.ts.coefs_low[1], out.ts.coefs_low[2],
                   out.ts.coefs_low[3]};
  p.coefs_low_4 = out.ts.coefs_low[4];
  p.coefs_high_0 = {out.ts.coefs_high[0], out.ts.coefs_high[1], out.ts.coefs_high[2],
                    out.ts.coefs_high[3]};
  p.coefs_high_4 = out.ts.coefs_high[4];
  p.scene_color_multiplier = scene_color_multiplier;
  // HDRHelper.h: GetACESTonemapParameters clamps with FMath::Clamp (NaN → 1).
  p.gamut_compression = ue_clamp(gamut_compression_cvar, 0.0f, 1.0f);
  return out;
}

}  // namespace hdrc::ref::aces
