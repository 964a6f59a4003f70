// UE 5.5's stages (pipeline "ue55"): what a case names, the GPU passes (gpu/shaders/stages/), and
// the output devices each is defined for. The stage ids are the UE family's (core/stage.h StageId).
#include "reference/ue/ue55/ue55_pipeline.h"

namespace hdrc::ref {

const std::vector<StageInfo>& ue55_stage_table() {
  static const std::vector<StageInfo> table = {
      {StageId::kShaper,
       "shaper",
       {{"stages/shaper.comp"}},
       "LUT shaper of the output device: encode (PQ of 100x for devices 3-9, LinToLog(x + "
       "LogToLin(0)) for 0-2), clamp to the LUT's [0,1] as the sampler does, decode as "
       "CombineLUTs does (spec 3.1, 3.2, 3.4, 4.3, 6.1 step 7)",
       {0, 1, 2, 3, 4, 5, 6, 7, 8, 9},
       true},
      {StageId::kLinearDevice,
       "linear_device",
       {{"stages/linear_device.comp"}},
       "shaper round trip, then device 8 (HDR_LinearNoToneCurve: working colour space) or "
       "device 7 (HDR_LinearEXR: PQ in the output gamut, decoded by the tonemapper) "
       "(spec 4.12 rows 7-8, 6.1 step 9)",
       {7, 8},
       true},
      {StageId::kCombineLuts,
       "combine_luts",
       {{"stages/combine_luts.comp", Dispatch::kLutTexels}},
       "CombineLUTs: every texel of the LUT as stored (OutDeviceColor / 1.05, quantised to the "
       "storage format), for any device, gamut, r.LUT.Size, format and layout (spec 4); output "
       "N^2 x N with texel (r, g, b) at (r + N b, g); with user colour-grading LUTs (16-point, "
       "8-bit, blended by ColorGradingIntensity and lut_blend) on devices 0-2 and 9",
       {0, 1, 2, 3, 4, 5, 6, 7, 8, 9},
       false,
       "ue55",
       // The user colour-grading LUT (docs/ue55-lut-blend-spec.md §2.9): 16 points (shader
       // literals), optional, up to four blended (Textures_1..4), stored 8-bit (BGRA8).
       16,
       true,
       4,
       true},
      {StageId::kTonemap,
       "tonemap",
       {{"stages/combine_luts.comp", Dispatch::kLutTexels}, {"stages/tonemap.comp"}},
       "the Tonemap pass: fringe, sharpen, vignette, tint and exposure, the shaper encode, the "
       "baked LUT's lookup x 1.05, the per-device post conversion; alpha = OutLuminance (spec 6.1 "
       "steps 1-9)",
       {0, 1, 2, 3, 4, 5, 6, 7, 8, 9},
       true,
       "ue55",
       0,
       false,
       1,
       false,
       "",
       true},
      {StageId::kDither,
       "dither",
       {{"stages/dither.comp"}},
       "the tonemapper's triangular quantisation dither added to the input (spec 6.1 step 10)",
       {0, 1, 2, 3, 4, 5, 6, 7, 8, 9}},
      {StageId::kUiComposite,
       "ui_composite",
       {{"stages/ui_composite.comp"}},
       "the HDR UI composite (CompositeUIPixelShader.usf): the input is the back buffer (PQ "
       "signals for devices 3/4, scRGB for 5/6), the UI is the ui_overlay stimulus of the same "
       "size; UI decode, Reinhard for translucent UI, colour deficiency, encode (spec 8)",
       {3, 4, 5, 6},
       true},
      {StageId::kVisualizeHdr,
       "visualize_hdr",
       {{"stages/combine_luts.comp", Dispatch::kLutTexels},
        {"stages/tonemap.comp", Dispatch::kPixels, true},
        {"stages/visualize_histogram.comp", Dispatch::kOneGroup},
        {"stages/visualize_hdr.comp"}},
       "VisualizeHDR (PostProcessVisualizeHDR.usf: MainPS): the input is the HDR scene colour; "
       "the tonemapped scene, the 64-bucket histogram and the average luminance come from the "
       "reference pipeline; the printed numbers go to results.json (spec 9)",
       {0, 1, 2, 3, 4, 5, 6, 7, 8, 9},
       true},
  };
  return table;
}

}  // namespace hdrc::ref
