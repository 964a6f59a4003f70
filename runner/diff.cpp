#include "runner/diff.h"

#include <cmath>
#include <cstdio>

#include "reference/color/gamma_correction.h"
#include "reference/color/st2084.h"
#include "reference/color/ue_log_shaper.h"

namespace hdrc {

double OutputEncoding::to_nits(double v) const {
  namespace pq = ref::st2084;
  const double scene = ref::kLinearToNitsScale;  // scene-linear 1.0 = 100 nits
  const double sdr_white = 100.0;                // SDR signals: 1.0 = 100 nits
  switch (stage) {
    case StageId::kShaper:
      return v * scene;
    case StageId::kLinearDevice:
      return device == 7 ? v : v * scene;
    case StageId::kCombineLuts:
      v *= 1.05;  // stored texels are OutDeviceColor / 1.05
      break;
    case StageId::kUiComposite:
      // The composite writes the back buffer: PQ (devices 3/4) or scRGB (5/6).
      return (device == 5 || device == 6) ? v * 80.0 : ref::st2084::nits_from_pq(v);
    case StageId::kTonemap:
    case StageId::kDither:
    case StageId::kVisualizeHdr:
      if (device == 5 || device == 6) return v * 80.0;  // scRGB
      if (device == 7) return v;                        // ST2084ToLinear output: nits
      break;
  }
  switch (device) {
    case 0:
      return ref::srgb_to_linear(v) * sdr_white;
    case 1:
      return ref::rec709_to_linear(v) * sdr_white;
    case 2:
      return (v > 0 ? std::pow(v, 1.0 / inverse_gamma_z) : 0.0) * sdr_white;
    case 8:
    case 9:
      return v * scene;
    default:
      return pq::nits_from_pq(v);  // 3–7: PQ signals
  }
}

std::string OutputEncoding::describe() const {
  if (stage == StageId::kShaper || (stage == StageId::kLinearDevice && device == 8))
    return "scene-linear x 100 nits";
  if (stage == StageId::kLinearDevice) return "nits";
  const std::string lut = stage == StageId::kCombineLuts ? "texel x 1.05, " : "";
  if (stage != StageId::kCombineLuts && (device == 5 || device == 6)) return "scRGB x 80 nits";
  if (stage != StageId::kCombineLuts && device == 7) return "nits";
  switch (device) {
    case 0:
      return lut + "sRGB EOTF x 100 nits";
    case 1:
      return lut + "Rec.709 inverse OETF x 100 nits";
    case 2:
      return lut + "gamma x 100 nits";
    case 8:
    case 9:
      return lut + "scene-linear x 100 nits";
    default:
      return lut + "PQ EOTF";
  }
}

namespace {
double pq_signal(double nits) {
  if (!(nits > 0)) return ref::st2084::pq_from_nits(0.0);
  return ref::st2084::pq_from_nits(std::fmin(nits, ref::st2084::kPeakNits));
}

bool consistent_nonfinite(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return a == b;  // both infinite: same sign
}

const char* channel_name(int c) {
  static const char* names[] = {"R", "G", "B", "A"};
  return c >= 0 && c < 4 ? names[c] : "?";
}
}  // namespace

std::string describe_pixel(const PixelRef& p) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "(%d, %d) %s: input %.9g reference %.9g candidate %.9g", p.x, p.y,
                channel_name(p.channel), p.input, p.reference, p.candidate);
  return buf;
}

DiffStats diff_images(const Image& input, const Image& reference, const Image& candidate,
                      const OutputEncoding& encoding, const Tolerance& tol) {
  DiffStats s;
  double sum_abs = 0, sum_rel = 0, sum_pq = 0;
  size_t finite_values = 0;
  for (int y = 0; y < reference.height; ++y) {
    for (int x = 0; x < reference.width; ++x) {
      const double* r = reference.px(x, y);
      const double* c = candidate.px(x, y);
      const double* in = input.px(x, y);
      for (int ch = 0; ch < 4; ++ch) {
        const bool rf = std::isfinite(r[ch]), cf = std::isfinite(c[ch]);
        if (rf && cf) {
          if (ch == 3) continue;  // alpha: only its non-finite consistency is judged
          ++s.values;
          ++finite_values;
          const double abs = std::fabs(c[ch] - r[ch]);
          // abs > 0 over a zero denominator (rel_floor 0, reference 0) is an infinite relative
          // error.
          const double rel = abs == 0 ? 0.0 : abs / std::fmax(std::fabs(r[ch]), tol.rel_floor);
          const double pq =
              std::fabs(pq_signal(encoding.to_nits(c[ch])) - pq_signal(encoding.to_nits(r[ch])));
          sum_abs += abs;
          sum_rel += rel;
          sum_pq += pq * 1023.0;
          if (abs > s.max_abs) s.max_abs = abs;
          if (rel > s.max_rel || !s.worst_rel.valid()) {
            s.max_rel = std::fmax(rel, s.max_rel);
            s.worst_rel = {x, y, ch, in[ch], r[ch], c[ch]};
          }
          if (pq * 1023.0 > s.max_pq10 || !s.worst_pq.valid()) {
            s.max_pq10 = std::fmax(pq * 1023.0, s.max_pq10);
            s.max_pq12 = std::fmax(pq * 4095.0, s.max_pq12);
            s.worst_pq = {x, y, ch, in[ch], r[ch], c[ch]};
          }
          if (!(rel <= tol.linear_rel)) ++s.over_rel;
          if (!(pq * 1023.0 <= tol.pq_code10)) ++s.over_pq10;
          continue;
        }
        if (!rf) ++s.nonfinite_ref;
        if (!rf && !cf && consistent_nonfinite(r[ch], c[ch])) {
          ++s.nonfinite_consistent;
        } else {
          if (s.nonfinite_mismatch == 0) s.first_mismatch = {x, y, ch, in[ch], r[ch], c[ch]};
          ++s.nonfinite_mismatch;
        }
      }
    }
  }
  if (finite_values > 0) {
    s.mean_abs = sum_abs / finite_values;
    s.mean_rel = sum_rel / finite_values;
    s.mean_pq10 = sum_pq / finite_values;
  }
  return s;
}

Verdict judge(const DiffStats& s, const Tolerance& tol) {
  char buf[512];
  if (s.nonfinite_mismatch > 0) {
    std::snprintf(buf, sizeof buf, "%zu non-finite mismatch(es); first at %s", s.nonfinite_mismatch,
                  describe_pixel(s.first_mismatch).c_str());
    return {false, buf};
  }
  const bool rel_ok = s.max_rel <= tol.linear_rel;
  const bool pq_ok = s.max_pq10 <= tol.pq_code10;
  if (!rel_ok) {
    std::snprintf(buf, sizeof buf, "linear rel error %.3g > %.3g (%zu values over) at %s",
                  s.max_rel, tol.linear_rel, s.over_rel, describe_pixel(s.worst_rel).c_str());
    return {false, buf};
  }
  if (!pq_ok) {
    std::snprintf(buf, sizeof buf, "PQ error %.3g > %.3g 10-bit codes (%zu values over) at %s",
                  s.max_pq10, tol.pq_code10, s.over_pq10, describe_pixel(s.worst_pq).c_str());
    return {false, buf};
  }
  std::snprintf(buf, sizeof buf, "rel %.3g <= %.3g, pq10 %.3g <= %.3g", s.max_rel, tol.linear_rel,
                s.max_pq10, tol.pq_code10);
  return {true, buf};
}

}  // namespace hdrc
