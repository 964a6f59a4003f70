// What the VisualizeHDR histogram pass leaves in the scratch buffer for the visualize pass (and
// for the engine to read back as the numbers MainPS prints). Stage layout (core/stage.cpp):
// scratch_px[0, W·H) = the tonemapped scene (the tonemap pass's output), and from VIS_BASE = W·H:
//
//   VIS_BASE + 0 .. 15   the histogram, 4 buckets per texel (bucket 4k + c in texel k, .c)
//   VIS_BASE + 16        (histogram max, histogram sum, AverageSceneLuminance, 0)
//   VIS_BASE + 17        (meter HDR mean · OneOverPreExposure (rgb), meter luminance "NIT")
//   VIS_BASE + 18        (meter tonemapped mean = the swatch colour (rgb), meter EV100)
//   VIS_BASE + 19        (illuminance rgb · π (rgb), illuminance "LUX")
//   VIS_BASE + 20        (exposure-without-bias EV, its line in panel pixels, exposure EV100, its
//                         line in panel pixels)
//   VIS_BASE + 21        (average-luminance line in panel pixels, pos(MinAverageLuminance / 0.18),
//                         pos(MaxAverageLuminance / 0.18), EyeAdaptationResult)
//
// The names of reference_engine.cpp visualize_hdr_stage's Image::values map to: meter_luminance
// 17.a, meter_ev100 18.a, illuminance_lux 19.a, exposure_without_bias_ev 20.x, exposure_ev100
// 20.z, exposure_px 20.w, average_luminance_px 21.x, average_scene_luminance 16.z.
#ifndef HDRC_VISUALIZE_SCRATCH_GLSL
#define HDRC_VISUALIZE_SCRATCH_GLSL

const int VIS_HISTOGRAM_TEXELS = 16;
const int VIS_HISTOGRAM_STATS = 16;
const int VIS_METER_HDR = 17;
const int VIS_METER_SCENE = 18;
const int VIS_ILLUMINANCE = 19;
const int VIS_EXPOSURE = 20;
const int VIS_LINES = 21;
const int VIS_SCRATCH_TEXELS = 22;  // of the 1024 the stage reserves

#endif
