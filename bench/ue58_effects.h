// The effect of each UE 5.5 -> 5.8 difference (docs/ue58-differences.md §1) on the picture,
// measured with the project's double-precision references: a stimulus set goes through two
// configurations of the colour path that differ in one behaviour (the 5.5 one and the 5.8 one),
// and the outputs are compared in 10-bit code units and ΔE_ITP. The table this measures is
// docs/ue58-decisions.md F; the tool is bench/ue58_differences.cpp, the pinning test
// bench/ue58_effects_test.cpp.
//
// The colour path of one configuration, per pixel of scene-linear working-colour-space colour x:
//   the Tonemap pass's LUT lookup (PostProcessTonemap.usf: ColorLookupTable) — the shaper encode
//   (5.5: PQ(x * 100) for devices >= 3, else LinToLog(x + LogToLin(0)); 5.8: the same two chosen by
//   r.LUT.Shaper), an exact trilinear sample of the LUT as stored (volume, clamp-to-edge, UVW =
//   e (N - 1)/N + 0.5/N), times LUTMax (5.5: 1.05; 5.8: 1 / LUTInvMax) — the device signal;
//   then the pipeline's output encoding of its CombineLUTs stage (the signal's transfer and gamut)
//   to nits in BT.2020.
// Only the LUT texels a stimulus reads are baked (each as bake_lut / bake_outer_lut stores it),
// so a configuration costs a few thousand texel evaluations, not N^3.
// Not on this path: the Tonemap pass's other effects (bloom, vignette, grain, dither) and 5.5's
// ST2084ToScRGB conversion of devices 5/6 (its [1e-4, peak] nit clamp; the LUT stage's own
// encoding is used). The UI composite is compared on its own (UiConfig, measure_ui below): it
// takes the back buffer, not the scene.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "color/vec.h"
#include "core/shader_interface.h"
#include "reference/ue/ui/composite.h"

namespace hdrc::ue58fx {

using ref::Vec3;

// One side of a comparison: a case of UE 5.5's "combine_luts" or UE 5.8's "ue58_combine_luts",
// resolved by the pipeline's own host derivation, then optionally edited (`tweak`) to put back one
// 5.5 behaviour that 5.8's settings cannot express.
struct Config {
  bool ue55 = false;
  std::vector<std::pair<std::string, double>> settings;
  std::vector<std::pair<std::string, double>> cvars;
  std::function<void(ParamBlock&)> tweak;
  bool exact_inner = false;  // 5.8: the inner LUT's transform evaluated exactly (CombineLuts58)
};

// A resolved configuration and its lazily baked LUT.
class Path {
 public:
  explicit Path(const Config& c);
  ~Path();
  Path(const Path&) = delete;
  Path& operator=(const Path&) = delete;
  const ParamBlock& params() const;
  const std::string& degenerate() const;
  // The device signal (the Tonemap pass's colour after the LUT lookup) for scene-linear `x`.
  Vec3 signal(const Vec3& x);
  // The signal's BT.2020 nits through this configuration's encoding (display = this side's).
  Vec3 nits(const Vec3& signal) const;
  // True for devices 0-2 (an SDR back buffer: codes are 1023 * saturate(signal)).
  bool sdr() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The stimulus set: a grey ramp (0 and 240 values log-spaced over 2^-14 .. 2^8), the ColorChecker
// 24 (BabelColor sRGB, decoded) at exposures 1/4, 1, 4, 16, and fully saturated hues HSV(h, 1, 1),
// h = 0, 3, ..., 357 degrees, at exposures 1, 4, 16, 64 (working colour space sRGB).
struct Stimulus {
  std::string name;  // "grey 0.18", "cc 13 Blue x4", "hue 120 x16"
  Vec3 x;
};
std::vector<Stimulus> stimuli();
std::vector<Stimulus> grey_ramp();

struct Effect {
  std::string unit;     // "10-bit PQ codes" (BT.2020) or "10-bit device codes"
  double max = 0;       // largest per-channel code difference
  double p99 = 0;       // its 99th percentile over every channel of every stimulus
  double de_itp = 0;    // largest ΔE_ITP (BT.2124)
  std::string worst;    // the stimulus of `max`
  size_t values = 0;    // channel values compared
  std::string skipped;  // why nothing was compared ("" when measured)
};

// Compares the two paths on `set`. Codes: SDR devices (both sides 0-2) 1023 * saturate(signal)
// per channel; otherwise 1023 * PQ(BT.2020 nits), NaN and negatives black, capped at 10 000 nits
// (the diff's convention, docs/diff-metrics.md). `same_display`: B's signal is shown on A's
// display (A's encoding for both) — for a difference in the encode itself.
Effect measure(Path& a, Path& b, const std::vector<Stimulus>& set, bool same_display = false);

// 1023 * PQ(nits) (SMPTE ST 2084 inverse EOTF).
double pq_code(double nits);

// The HDR UI composite (docs/ue58-differences.md §1c U1-U5): one back-buffer pixel and one UI
// texel through UE 5.5's composite (reference/ue/ui/composite.h composite_pixel) or UE 5.8's
// (reference/ue/ue58/ue58_ui_composite.h composite_pixel58), each side a case of its pipeline's
// UI stage ("ui_composite", "ue58_ui_composite") resolved by that pipeline's host derivation,
// then optionally edited (`tweak55`: a field of 5.5's composite parameters that no 5.5 cvar sets,
// e.g. the min-normal clamp of its sRGBToLinear, to isolate one 5.8 behaviour).
struct UiConfig {
  bool ue55 = false;
  std::vector<std::pair<std::string, double>> settings;
  std::vector<std::pair<std::string, double>> cvars;
  std::function<void(ref::ui::UiCompositeParams&)> tweak55;
};

// A back-buffer pixel (the device's code: PQ signal in Rec.2020 for devices 3/4, scRGB for 5/6)
// and a UI texel as Slate writes it (premultiplied, the colour in the UI's EOTF, linear alpha).
struct UiStimulus {
  std::string name;  // "ui 128/255 a0.5 over 100 nits"
  ref::ui::Vec4 scene;
  ref::ui::Vec4 ui;
};

// The UI stimulus set for `device` (3: PQ back buffer, 5: scRGB): back buffers grey at 0, 0.1, 1,
// 10, 100, 203, 1000 and 10 000 nits and two colours (Rec.2020 (1000, 50, 5) and (5, 50, 1000)
// nits); UI colours: the 256 greys k/255 and the six primaries and secondaries (sRGB-coded);
// alphas 0, 0.1, 0.25, 0.5, 0.75, 0.9 and 1, premultiplied (rgb · a); and with `alpha0_colour`,
// each UI colour also at alpha 0 holding its colour (a texel premultiplication says is empty).
std::vector<UiStimulus> ui_stimuli(int device, bool alpha0_colour = false);

// Compares the two composites on `set`: per channel 1023 · |PQ(nits A) − PQ(nits B)| with the
// composed back buffer decoded to BT.2020 nits (ComputeHDRSceneColor: ST2084ToLinear, or scRGB ·
// 80 through sRGB→Rec2020), NaN and negatives black as the diff; ΔE_ITP (BT.2124) per pixel.
// Alpha (5.8 writes the UI's, 5.5 writes 1) is not compared.
Effect measure_ui(const UiConfig& a, const UiConfig& b, const std::vector<UiStimulus>& set);

}  // namespace hdrc::ue58fx
