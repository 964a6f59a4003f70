// UE 5.5's HDR output pipeline as a module (core/pipeline.h): its tables, host derivation
// (resolve.cpp), reference (reference_engine.cpp) and the encoding of each stage's output.
#include "reference/ue/ue55/ue55_pipeline.h"

#include "core/cvars.h"
#include "core/settings.h"
#include "core/stage.h"
#include "reference/color/ue_log_shaper.h"
#include "reference/color/ue_matrices.h"
#include "reference/reference_engine.h"
#include "reference/ue/combine_luts.h"
#include "reference/ue/cpp/resolve.h"

namespace hdrc::ref {

namespace {

constexpr double kSdrWhiteNits = 100.0;  // SDR signals: 1.0 = 100 nits (docs/diff-metrics.md)
constexpr double kScRgbNits = 80.0;      // scRGB 1.0 = 80 nits (TonemapCommon.ush: ST2084ToScRGB)

enum class Gamut { kWorking, kOutput, kAp1, kRec709, kRec2020 };

const Chromaticities& gamut_chromaticities(int output_gamut) {
  namespace s = standard;
  switch (output_gamut) {
    case 1:
      return s::kP3D65;
    case 2:
      return s::kRec2020;
    case 3:
      return s::kAp0;
    case 4:
      return s::kAp1;
    default:
      return s::kSrgb;
  }
}

// Which gamut a stage's output is in (docs/spec/ue55.md §4.12 device encoding, §3.5 ST2084ToScRGB,
// §6.1 step 9): the working colour space where UE skips the gamut matrix, AP1 for the scRGB
// devices' LUT texels, scRGB's Rec.709 after the tonemapper's conversion, else the output gamut.
Gamut output_gamut_kind(StageId stage, const ParamBlock& p) {
  const int d = p.output_device;
  switch (stage) {
    case StageId::kShaper:
      return Gamut::kWorking;
    case StageId::kLinearDevice:
      return d == 8 ? Gamut::kWorking : Gamut::kOutput;
    case StageId::kUiComposite:
      // The HDR back buffer: PQ Rec.2020 (3/4) or scRGB (5/6).
      return (d == 5 || d == 6) ? Gamut::kRec709 : Gamut::kRec2020;
    default:
      break;
  }
  if (d == 8) return Gamut::kWorking;
  if (d == 0 && p.wcs_is_srgb) return Gamut::kWorking;  // 5.5 skips AP1_2_Output for an sRGB WCS
  if (d == 5 || d == 6) return stage == StageId::kCombineLuts ? Gamut::kAp1 : Gamut::kRec709;
  return Gamut::kOutput;
}

using Transfer = OutputEncoding::Transfer;

void set_transfer(OutputEncoding* e, Transfer t, double nits_scale, const std::string& name) {
  e->transfer = t;
  e->nits_scale = nits_scale;
  e->transfer_name = name;
}

// The transfer of an output device's signal (docs/spec/ue55.md §4.12): sRGB, Rec.709, gamma,
// scene-linear or PQ (devices 3-7).
void set_device_transfer(OutputEncoding* e, const ParamBlock& p, const std::string& prefix) {
  switch (p.output_device) {
    case 0:
      set_transfer(e, Transfer::kSrgb, kSdrWhiteNits, prefix + "sRGB EOTF x 100 nits");
      break;
    case 1:
      set_transfer(e, Transfer::kRec709, kSdrWhiteNits, prefix + "Rec.709 inverse OETF x 100 nits");
      break;
    case 2:
      set_transfer(e, Transfer::kGamma, kSdrWhiteNits, prefix + "gamma x 100 nits");
      e->gamma = 1.0 / p.inverse_gamma[2];  // device 2's 1/Gamma is InverseGamma.z
      break;
    case 8:
    case 9:
      set_transfer(e, Transfer::kLinear, kLinearToNitsScale, prefix + "scene-linear x 100 nits");
      break;
    default:
      set_transfer(e, Transfer::kPq, 1.0, prefix + "PQ EOTF");
  }
}

OutputEncoding ue55_output_encoding(const StageInfo& info, const ParamBlock& p) {
  OutputEncoding e;
  const StageId stage = info.id;
  const int d = p.output_device;
  e.stage = stage;
  e.device = d;
  namespace s = standard;
  switch (output_gamut_kind(stage, p)) {
    case Gamut::kWorking:
      // WorkingColorSpace.ToAP1, then AP1 → BT.2020 (Bradford ACES white → D65).
      e.to_rec2020 = s::rgb_to_rgb(s::kAp1, s::kRec2020) * p.wcs_to_ap1;
      e.gamut = p.wcs_is_srgb ? "working colour space (sRGB)" : "working colour space";
      break;
    case Gamut::kOutput:
      e.to_rec2020 = s::rgb_to_rgb(gamut_chromaticities(p.output_gamut), s::kRec2020);
      e.gamut = output_gamut_name(p.output_gamut);
      break;
    case Gamut::kAp1:
      e.to_rec2020 = s::rgb_to_rgb(s::kAp1, s::kRec2020);
      e.gamut = "AP1";
      break;
    case Gamut::kRec709:
      e.to_rec2020 = s::rgb_to_rgb(s::kSrgb, s::kRec2020);
      e.gamut = "Rec.709";
      break;
    case Gamut::kRec2020:
      e.gamut = "Rec.2020";
      break;
  }
  // Scene-linear 1.0 = 100 nits; scRGB 1.0 = 80 nits; device 7's tonemapper output is nits.
  const std::string scene = "scene-linear x 100 nits";
  switch (stage) {
    case StageId::kShaper:
      set_transfer(&e, Transfer::kLinear, kLinearToNitsScale, scene);
      break;
    case StageId::kLinearDevice:
      if (d == 7)
        set_transfer(&e, Transfer::kLinear, 1.0, "nits");
      else
        set_transfer(&e, Transfer::kLinear, kLinearToNitsScale, scene);
      break;
    case StageId::kCombineLuts:
      e.pre_scale = 1.05;  // stored texels are OutDeviceColor / 1.05 (PostProcessCombineLUTs.usf)
      set_device_transfer(&e, p, "texel x 1.05, ");
      break;
    case StageId::kUiComposite:
      if (d == 5 || d == 6)
        set_transfer(&e, Transfer::kLinear, kScRgbNits, "scRGB x 80 nits");
      else
        set_transfer(&e, Transfer::kPq, 1.0, "PQ EOTF");
      break;
    default:  // tonemap, dither, visualize_hdr: the back buffer's encoding
      if (d == 5 || d == 6)
        set_transfer(&e, Transfer::kLinear, kScRgbNits, "scRGB x 80 nits");
      else if (d == 7)
        set_transfer(&e, Transfer::kLinear, 1.0, "nits");
      else
        set_device_transfer(&e, p, "");
  }
  // A NaN marks a negative value where the output is a power-law encoding of a value that can be
  // negative: devices 2–7 from CombineLUTs on, and linear_device 7 (LinearEXR: the PQ encode and
  // decode of the output-gamut value).
  const bool after_luts = stage == StageId::kCombineLuts || stage == StageId::kTonemap ||
                          stage == StageId::kDither || stage == StageId::kVisualizeHdr;
  e.nan_marks_negative_value =
      stage == StageId::kLinearDevice ? d == 7 : (after_luts && d >= 2 && d <= 7);
  return e;
}

std::array<double, 3> ue55_lattice(const ParamBlock& p, int r, int g, int b) {
  const Vec3 v = lattice_coordinate(p.lut_layout, p.lut_size, r, g, b);
  return {v[0], v[1], v[2]};
}

}  // namespace

const Pipeline& ue55_pipeline() {
  static const Pipeline pipeline{
      "ue55",
      "Unreal Engine 5.5 HDR output",
      "docs/ue55-decisions.md",
      "CombineLUTs, ACES 1.3 output, the Tonemap pass, HDR UI composite, VisualizeHDR and the cvar "
      "semantics of UE 5.5 (docs/ue55-decisions.md)",
      &ue55_stage_table,
      &cvar_table,
      &setting_table,
      &setting_choices,
      &resolve,
      &ue55_lattice,
      &ue55_output_encoding,
      &run_ue55,
      // Measured per pixel, 2048x2048 minus 256x256, lavapipe (runner/budget.h).
      290,
      3600,
      nullptr,  // named values: probe's UE path prints them (runner/probe.cpp)
      // Each stage's seconds per case, fitted to a default-suite run (2026-11-27, --images all,
      // -j 2, lavapipe; bench/shard_balance.py fit; docs/performance-notes.md, "Shard balance"):
      // µs per case, per pixel, per baked LUT texel.
      {{"shaper", 272, 0.934, 0},
       {"linear_device", 431, 1.08, 0},
       {"combine_luts", 1426, 2.12, 0},
       {"tonemap", 2775, 3.71, 0.401},
       {"dither", 93, 1.22, 0},
       {"ui_composite", 2194, 0, 0},
       {"visualize_hdr", 79926, 0, 0}},
  };
  return pipeline;
}

}  // namespace hdrc::ref
