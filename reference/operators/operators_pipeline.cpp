// The classic tone-mapping operators as a pipeline module ("operators", core/pipeline.h): one
// stage, the chosen operator applied per pixel to a scene-linear Rec.709 image (operators.h).
#include "reference/operators/operators_pipeline.h"

#include "reference/color/ue_matrices.h"
#include "reference/operators/operators.h"
#include "reference/operators/operators_settings.h"

namespace hdrc::ref::operators {

namespace {

const std::vector<StageInfo>& operators_stages() {
  static const std::vector<StageInfo> table = {
      {StageId::kOther,
       "tone_curve",
       {{"operators/stages/curve.comp"}},
       "a classic tone-mapping operator per pixel (Reinhard, Reinhard with white point, Uncharted "
       "2 "
       "/ Hable, Narkowicz's ACES fit, Unity's Neutral, UE's FilmToneMap presets) after the "
       "exposure Key / AdaptedLuminance; scene-linear Rec.709 in, display-linear Rec.709 out",
       {},
       true,
       "operators"},
  };
  return table;
}

const std::vector<CvarInfo>& no_cvars() {
  static const std::vector<CvarInfo> none;
  return none;
}

Result<Resolution> resolve(const Case& c, int width, int height) {
  Resolution r;
  r.params.width = width;
  r.params.height = height;
  derive_operators(c.settings, &r.params);
  return r;
}

std::array<double, 3> no_lattice(const ParamBlock&, int, int, int) {
  return {0, 0, 0};
}

// Display-linear Rec.709: 1.0 is SDR white, 100 nits.
OutputEncoding encoding(const StageInfo&, const ParamBlock&) {
  OutputEncoding e;
  e.transfer = OutputEncoding::Transfer::kLinear;
  e.nits_scale = 100.0;
  e.transfer_name = "display-linear x 100 nits";
  e.to_rec2020 = standard::rgb_to_rgb(standard::kSrgb, standard::kRec2020);
  e.gamut = "Rec.709";
  return e;
}

Result<Image> reference(const ResolvedCase& c, bool /*analytic_lut: no LUT*/) {
  Image out(c.input.width, c.input.height);
  for (size_t i = 0; i < c.input.pixel_count(); ++i) {
    const double* in = &c.input.data[i * Image::kChannels];
    const Vec3 rgb = apply_operator(c.params, {in[0], in[1], in[2]});
    double* o = &out.data[i * Image::kChannels];
    o[0] = rgb[0];
    o[1] = rgb[1];
    o[2] = rgb[2];
    o[3] = in[3];  // alpha passes through (curve.comp)
  }
  return out;
}

}  // namespace

const Pipeline& operators_pipeline() {
  static const Pipeline pipeline{
      "operators",
      "Classic tone-mapping operators",
      "reference/operators/operators.h",
      "Reinhard, Uncharted 2 / Hable, Narkowicz's ACES fit, Unity's Neutral and UE's FilmToneMap "
      "presets, one definition each, shared by the other pipelines",
      &operators_stages,
      &no_cvars,
      &operators_setting_table,
      &operators_setting_choices,
      &resolve,
      &no_lattice,
      &encoding,
      &reference,
  };
  return pipeline;
}

}  // namespace hdrc::ref::operators
