// Pieces that several pipeline modules (core/pipeline.h) share word for word: a pipeline with no
// console variables, a host derivation that is a function of the settings alone, no LUT lattice,
// and display-linear Rec.709 output. docs/pipelines.md, "Adding a pipeline".
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/pipeline.h"
#include "reference/color/ue_matrices.h"

namespace hdrc::ref {

// The cvar table of a pipeline that has none (every pipeline but UE 5.5's).
inline const std::vector<CvarInfo>& no_cvars() {
  static const std::vector<CvarInfo> none;
  return none;
}

// Pipeline::resolve for a pipeline whose parameter block is derived from its settings alone by
// `Derive` (e.g. derive_operators): the image size, then the derivation; never degenerate.
template <void (*Derive)(const SettingValues&, ParamBlock*)>
Result<Resolution> resolve_from_settings(const Case& c, int width, int height) {
  Resolution r;
  r.params.width = width;
  r.params.height = height;
  Derive(c.settings, &r.params);
  return r;
}

// Pipeline::lattice of a pipeline whose stages all take an input image (no LUT bake).
inline std::array<double, 3> no_lattice(const ParamBlock&, int, int, int) {
  return {0, 0, 0};
}

// Linear Rec.709 output where 1.0 is SDR white (100 nits); `transfer_name` says what the value is
// ("display-linear x 100 nits").
inline OutputEncoding linear_rec709_encoding(std::string transfer_name) {
  OutputEncoding e;
  e.transfer = OutputEncoding::Transfer::kLinear;
  e.nits_scale = 100.0;
  e.transfer_name = std::move(transfer_name);
  e.to_rec2020 = standard::rgb_to_rgb(standard::kSrgb, standard::kRec2020);
  e.gamut = "Rec.709";
  return e;
}

}  // namespace hdrc::ref
