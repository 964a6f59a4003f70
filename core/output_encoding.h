// How a stage's output values map to absolute luminance and to BT.2020 (docs/diff-metrics.md): the
// diff, the report and export read every pipeline's outputs through this one description. A
// pipeline fills it for each of its stages (core/pipeline.h: Pipeline::output_encoding).
#pragma once

#include <string>

#include "core/stage.h"
#include "color/vec.h"

namespace hdrc {

struct OutputEncoding {
  // The transfer function a value goes through to become luminance; nits = transfer(pre_scale · v)
  // · nits_scale.
  enum class Transfer {
    kLinear,  // the value itself
    kPq,      // SMPTE ST 2084 EOTF (nits_scale 1: the EOTF gives nits)
    kSrgb,    // IEC 61966-2-1 sRGB EOTF, piecewise
    kRec709,  // the inverse of the BT.709 OETF
    kGamma,   // max(v, 0)^gamma (v ≤ 0: 0)
  };

  StageId stage = StageId::kOther;  // UE 5.5's non-finite census rules read its stage and device
  int device = 0;
  Transfer transfer = Transfer::kLinear;
  double pre_scale = 1.0;     // applied before the transfer (UE's LUT texels are value / 1.05)
  double nits_scale = 100.0;  // nits of a decoded 1.0
  double gamma = 2.2;         // kGamma's exponent
  ref::Mat3 to_rec2020 = ref::Mat3::identity();           // output gamut RGB → BT.2020 RGB (D65)
  std::string gamut = "BT.2020";                          // the output gamut's name
  std::string transfer_name = "scene-linear x 100 nits";  // for describe()
  // True when the output is a power-law encoding (PQ, explicit gamma) of a value that can be
  // negative, so that a NaN marks a negative value. Where this holds, the census applies the
  // sign-boundary rule (docs/diff-metrics.md).
  bool nan_marks_negative_value = false;

  double to_nits(double value) const;  // per channel
  bool nan_marks_negative() const { return nan_marks_negative_value; }
  std::string describe() const { return transfer_name + ", " + gamut; }  // "PQ EOTF, Rec.2020"
};

}  // namespace hdrc
