// PQ-space grading with an artist's .cube LUT (pipeline `pq_grading`, issue 16), in double
// precision. Per pixel (docs/pq_grading.md has the formula table and every decision):
//
//   x   = store_rgba16f(scene)                the lighting target: half, clamped to ±65504
//   e   = saturate(x · ExposureFract)         ExposureFract = 1e-4 · Amplify
//   q   = PQ(e)                               ST 2084 inverse EOTF of e · 10000 nits
//   q'  = LUT(q)                              33³ .cube graded in PQ, DOMAIN honoured here
//   g   = PQ⁻¹(q') / 10000 / ExposureFract · Amplify
//   d   = HDR: UE's FilmToneMap(g) | SDR: Narkowicz's ACES fit(g)
//   out = the back buffer's encoding of d     PQ | scRGB | sRGB (as stored) | gamma 2.2
//
// One definition each: PQ is color/st2084.h (pq_from_nits / nits_from_pq), the display
// mappings are the `operators` pipeline's (operators::ue_filmic with UE's Default FilmToneMap
// parameters, operators::aces_narkowicz). GPU mirror: gpu/shaders/pq_grading/lib/pq_grading.glsl.
#pragma once

#include <array>
#include <memory>
#include <string_view>
#include <vector>

#include "color/vec.h"
#include "core/cube/cube.h"
#include "core/device_precision.h"
#include "core/image.h"
#include "core/settings.h"
#include "core/shader_interface.h"
#include "reference/color/noise_range.h"
#include "reference/color/spirv_precision.h"
#include "reference/operators/operators.h"

namespace hdrc::ref::pq_grading {

// The values of pq_display / the "Display" setting.
enum class Display : int { kSdr = 0, kHdr = 1 };
// The values of pq_back_buffer / the "BackBuffer" setting.
enum class BackBuffer : int { kR10G10B10A2 = 0, kRgba16f = 1, kSrgb8 = 2, kRgb8 = 3 };
inline constexpr int kBackBufferCount = 4;
const char* display_name(int d);      // "SDR", "HDR"; nullptr outside 0-1
const char* back_buffer_name(int b);  // "R10G10B10A2", "RGBA16F", "SRGB8", "RGB8"; nullptr outside

// The constants.
inline constexpr double kExposureFractPerAmplify = 1e-4;  // ExposureFract = 1e-4 · Amplify
inline constexpr double kDefaultAmplify = 3.0;
inline constexpr int kLutSize = 33;  // Resolve's "Generate 3D LUT (33 Point Cube)"
// Decisions (docs/pq_grading.md): the nits of display value 1.0 in the PQ and RGBA16F encodings.
inline constexpr double kDefaultPeakNits = 1000.0;  // HDR: the display's peak, a setting
inline constexpr double kSdrWhiteNits = 100.0;      // SDR: reference white (BT.1886 / sRGB)
inline constexpr double kScRgbWhiteNits = 80.0;     // scRGB 1.0 (IEC 61966-2-2; Windows' FP16)
inline constexpr double kRgb8Gamma = 2.2;           // RGB8 UNORM: pure power 1/2.2
inline constexpr double kHalfMax = 65504.0;         // largest finite IEEE binary16

// The lighting target RGBA16F: the value rounded to the nearest half (ties to even) after clamping
// to ±65504 (±Inf clamp too); NaN stays NaN.
double store_rgba16f(double v);

// IEC 61966-2-1:1999 sRGB encoding (what an sRGB8 store computes before its 8-bit rounding):
// v ≤ 0.0031308 ? 12.92 v : 1.055 v^(1/2.4) − 0.055.
double srgb_encode(double v);

// The user LUT as both engines receive it: the strip texture (N² × N, .cube row (r, g, b) at texel
// (r + N b, g)), its size and its domain (P.user_lut_*).
struct StripLut {
  const Image* strip = nullptr;
  int size = 0;
  Vec3 domain_min{0, 0, 0}, domain_max{1, 1, 1};
  // The same table and domain as a .cube (the strip holds its float32 rows unchanged), for the
  // analytic evaluations of `lookup`.
  std::shared_ptr<const cube::CubeLut> cube;
};
StripLut strip_lut(const Image& strip, const ParamBlock& p);

// The lookup's normalised coordinate: saturate((v − min) / (max − min)) per channel. DOMAIN is
// honoured here, in the lookup (the texture holds the .cube's rows unchanged); outside the domain
// the input clamps to it, as the .cube spec, OpenColorIO and core/cube do.
Vec3 domain_normalise(const StripLut& lut, const Vec3& v);

// An engine's sampling of the strip (UE's PostProcessCommon.ush UnwrappedTexture3DSample, the
// same two-slice scheme every engine's 2-D LUT uses): UVW = t · (N − 1)/N + 0.5/N; slice
// w = UVW.b · N − 0.5, i = floor(w), f = w − i; two bilinear taps of the strip (linear filtering,
// clamp-to-edge) at u = (UVW.r + i)/N and u + 1/N, v = UVW.g; lerp by f. The bilinear tap is
// Vulkan's (spec "Texel Filtering": texel coordinate u · width − 0.5, weights its fraction),
// evaluated exactly in double.
Vec3 sample_strip(const StripLut& lut, const Vec3& t);
// The same with its named intermediate values (docs/spec/pq_grading.md, the worked pixels).
struct StripTrace {
  Vec3 uvw;         // t · (N − 1)/N + 0.5/N
  double w, i, f;   // the slice: uvw.b · N − 0.5, floor(w), w − i
  double u;         // (uvw.r + i)/N, the first tap's horizontal coordinate
  Vec3 tap0, tap1;  // bilinear(u, uvw.g), bilinear(u + 1/N, uvw.g)
};
Vec3 sample_strip(const StripLut& lut, const Vec3& t, StripTrace* trace);

// The .cube evaluated analytically (core/cube: trilinear or tetrahedral) on the same table and
// domain, for comparison with the strip sampling (`verify --reference analytic`,
// docs/precision.md).
enum class LutEval { kStrip, kTrilinear, kTetrahedral };
Vec3 lookup(const StripLut& lut, const Vec3& pq, LutEval eval);

// UE's Default FilmToneMap (Scene.cpp FPostProcessSettings) on Rec.709, through the `operators`
// pipeline's operators::ue_filmic, with the matrices of P.pq_rec709_to_ap1 / pq_ap1_to_rec709.
Vec3 display_map(const ParamBlock& p, const Vec3& graded);
// The same, HDR with FilmToneMap's intermediate values in *filmic (untouched for SDR).
Vec3 display_map(const ParamBlock& p, const Vec3& graded, operators::UeFilmicTrace* filmic);

// The back buffer's encoding of a display-mapped value (docs/pq_grading.md, decisions):
// R10G10B10A2: saturate(PQ(d · pq_white_nits)); RGBA16F: d · pq_white_nits / 80;
// sRGB8: srgb_encode(saturate(d)); RGB8: saturate(d)^(1/2.2). NaN for an unknown back buffer.
double encode_output(const ParamBlock& p, double d);

// The named intermediate values of one pixel (probe, tests, docs/spec/pq_grading.md's worked
// pixels). lut_coord and strip are filled for LutEval::kStrip, filmic for the HDR display.
struct Trace {
  Vec3 stored, exposed, pq, lut_coord, graded_pq, graded, display, out;
  StripTrace strip;
  operators::UeFilmicTrace filmic;
};
Trace grade(const ParamBlock& p, const StripLut& lut, const Vec3& scene, LutEval eval);
// The same pixel (kStrip) by the names of docs/spec/pq_grading.md (its worked pixels; probe
// --json): input, exposure_fract, white_nits, stored ... graded, the HDR mapping's ap1,
// FilmToneMap's steps (`detail`), tone_ap1, rec709, then display, out.
std::vector<NamedValue> named_values(const ParamBlock& p, const StripLut& lut, const Vec3& scene);

// --- Device allowances (docs/precision.md, "Device allowances") ---

// GLSL pq_from_nits (gpu/shaders/lib/st2084.glsl) over a range of nits as a conformant device may
// evaluate it: nits / 10000 (OpFDiv), lm = pow(., m1) (0 for 0, pow_d3d), (c1 + c2·lm) ·
// (1 / (1 + c3·lm)), pow(., m2), each step within the precision table's bound
// (reference/color/spirv_precision.h). Increasing; nits ≤ 0 gives lm = 0.
spirv::Interval pq_from_nits_on_device(spirv::Interval nits);

// The range of `grade`'s output (kStrip) on a conformant device with precision `d`, per channel:
// the RGBA16F store either way (unless d.fp16_rte), the exposure multiply, the PQ encode
// (pq_from_nits_on_device), the strip lookup with the weight box of d.sub_texel_bits
// (strip_lookup_device_range; the RGBA32F strip holds the .cube's floats exactly), the PQ decode
// (pq_decode_on_device) and the divisions, the display mapping over the box of its input
// (corners) widened by kShaderNoise of its largest channel for its float32 arithmetic, the back
// buffer's encoding (nondecreasing: the device bounds of its ends). Contains t.out.
Range3 grade_device_range(const ParamBlock& p, const StripLut& lut, const Vec3& scene,
                          const DevicePrecision& d);

// --- Settings and host derivation ---

// Amplify, Display (named SDR, HDR), BackBuffer (named R10G10B10A2, RGBA16F, SRGB8, RGB8),
// PeakNits; defaults and ranges in the table.
const std::vector<SettingInfo>& pq_grading_setting_table();
const std::vector<SettingChoice>* pq_grading_setting_choices(std::string_view setting);
// Every pq_* field, and film_* (UE's Default FilmToneMap parameters).
void derive_pq_grading(const SettingValues& s, ParamBlock* p);

}  // namespace hdrc::ref::pq_grading
