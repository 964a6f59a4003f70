// The reference engine: every pipeline's reference in double precision (core/pipeline.h); UE 5.5's
// is run_ue55.
#pragma once

#include "core/engine.h"
#include "core/pipeline.h"
#include "reference/ue/combine_luts.h"
#include "reference/ue/ui/composite.h"
#include "reference/ue/visualize/histogram.h"

namespace hdrc::ref {

class ReferenceEngine final : public Engine {
 public:
  // analytic_lut: the tonemapper (tonemap and visualize_hdr stages) evaluates CombineLUTs at each
  // pixel's encoded coordinate instead of sampling the baked LUT (`verify --reference analytic`:
  // ports that do not bake a LUT). Every other stage is the same in both modes.
  explicit ReferenceEngine(bool analytic_lut = false) : analytic_lut_(analytic_lut) {}
  std::string name() const override { return "reference"; }
  Status init() override { return {}; }
  DeviceInfo device() const override;
  Result<Image> run(const ResolvedCase& c) override;

 private:
  bool analytic_lut_ = false;
};

// UE 5.5's reference: the output of the case's stage (Pipeline::reference of "ue55").
Result<Image> run_ue55(const ResolvedCase& c, bool analytic_lut);

// One pixel of a per-pixel stage (shaper, linear_device), for tests: rgb in, rgb out.
Vec3 run_pixel(StageId stage, const ParamBlock& p, const Vec3& rgb);

// The UI composite's and VisualizeHDR's parameters from the block (shared with `probe`).
ui::UiCompositeParams ui_composite_params(const ParamBlock& p);
visualize::EyeAdaptationParameters eye_adaptation_parameters(const ParamBlock& p);

// VisualizeHDR (PostProcessVisualizeHDR.usf: MainPS, docs/spec/ue55.md §9) over `hdr_scene` and
// `tonemapped`, the Tonemap pass's image of it: UE 5.5's or UE 5.8's pass, VisualizeHDR being one
// pass in both (docs/ue58-differences.md §1c′). Its image and printed numbers (Image::values); with
// device_allowances, a conformant device's ranges: `tonemapped.device_admissible` (the Tonemap
// pass's) carried through the histogram pass and the panel (reference/ue/visualize_device.h).
Image visualize_hdr_over(const ParamBlock& p, const Image& hdr_scene, const Image& tonemapped,
                         bool device_allowances);

// The LUT laid out as the combine_luts stage outputs it: texel (r, g, b) at (r + N·b, g).
Image lut_image(const BakedLut& lut);

}  // namespace hdrc::ref
