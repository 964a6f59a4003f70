// CombineLUTs (PostProcessCombineLUTs.usf: CombineLUTsCommon, docs/spec/ue55.md §4): the colour
// function of one LUT texel, the bake of the whole LUT in its storage format and layout, and the
// tonemapper's lookup into it (PostProcessTonemap.usf: ColorLookupTable, docs/spec/ue55.md §6.1
// step 7).
#pragma once

#include <cstdint>
#include <vector>

#include "color/vec.h"
#include "core/device_precision.h"
#include "core/shader_interface.h"
#include "reference/color/noise_range.h"
#include "reference/color/ue_matrices.h"
#include "reference/ue/aces/aces_output.h"
#include "reference/ue/grading/color_correct.h"
#include "reference/ue/grading/color_polynomial.h"
#include "reference/ue/grading/film_tonemap.h"
#include "reference/ue/ue_lut_blend.h"

namespace hdrc::ref {

// Every intermediate value of one texel, for `hdrconform probe --stage`.
struct CombineLutsTrace {
  Vec3 lattice{};          // the neutral lattice coordinate (shaper-encoded)
  Vec3 decoded{};          // LinearColor: shaper decoded, working colour space
  Vec3 white_balanced{};   // after WhiteBalance (or skipped)
  Vec3 ap1{};              // ToAP1 · balanced
  Vec3 expanded{};         // after fake wide gamut
  Vec3 color_corrected{};  // after ColorCorrectAll (AP1)
  Vec3 film{};             // SDR film path: FilmColor after r.Color and fade, before gamma
  Vec3 graded{};           // GradedColor: FromAP1 · AP1 with fade (HDR / linear devices)
  Vec3 aces_nits{};        // ACES output transform, nits in AP1 (devices 3-6)
  Vec3 device{};           // OutDeviceColor
  Vec3 stored{};           // OutDeviceColor / 1.05 (before storage quantisation)
};

// ColorCorrectAll's parameters and the working colour space as the block carries them (shared with
// UE 5.8's CombineLUTs, reference/ue/ue58/).
grading::ColorCorrectParams color_correct_params(const ParamBlock& p);
WorkingColorSpace working_color_space(const ParamBlock& p);

// The ACES shader parameters as the shaders read them: ParamBlock's fields packed to float, as UE's
// CPU uploads them, then unpacked (TonemapCommon.ush: ComputeACESTonemapParams).
aces::AcesShaderParams aces_params(const ParamBlock& p);

// The colour function at a lattice coordinate (each channel in [0, 1]).
// `luts`: the user colour-grading LUTs of the blend (P.lut_blend_count > 1; docs/ue55-lut-blend-
// spec.md §3), blended into FilmColor after the film tone curve and before r.Color's polynomial;
// nullptr: no blend.
Vec3 combine_luts_texel(const ParamBlock& p, const Vec3& lattice, CombineLutsTrace* trace = nullptr,
                        const UeLutSet* luts = nullptr);

// What a texel's stored value (OutDeviceColor / 1.05) may be in a correct float32 evaluation where
// float32 cannot decide it (reference/color/noise_range.h): a channel within float32 noise of zero
// at FilmColor's pow (devices 0-2), device 2's explicit-gamma pow or the PQ encode (devices 3-7).
// Not ambiguous: the point value alone.
struct TexelRange {
  Range3 range;
  bool ambiguous = false;
};

// The range from the texel's values before those steps: `film` (FilmColorNoGamma after the fade,
// devices 0-2) and `pq_in` (LinearToST2084's input, devices 3-7; the other is ignored).
TexelRange stored_range(const ParamBlock& p, const grading::InverseGamma& inverse_gamma,
                        const Vec3& film, const Vec3& pq_in);

// combine_luts_texel without a trace, with everything that depends on the parameters alone
// (colour-correction zones, working colour space, fade, film and ACES parameters) unpacked once,
// and only the device's own path evaluated (the SDR film path is skipped on HDR and linear
// devices, GradedColor on the film devices). Results are bit-identical to combine_luts_texel;
// with fast_paths() off (reference/color/fast_paths.h) it evaluates combine_luts_texel itself.
// Used by the bake and the analytic tonemapper, once per parameter set.
class TexelEvaluator {
 public:
  explicit TexelEvaluator(const ParamBlock& p, const UeLutSet* luts = nullptr);
  // range: also the stored value's admissible range (TexelRange).
  Vec3 operator()(const Vec3& lattice, TexelRange* range = nullptr) const;

 private:
  ParamBlock p_;
  grading::ColorCorrectParams cc_;
  WorkingColorSpace wcs_;
  grading::Fade fade_;
  grading::FilmPathParams film_;
  grading::MappingPolynomial polynomial_;
  grading::InverseGamma inverse_gamma_;
  aces::AcesShaderParams aces_;
  const UeLutSet* luts_;  // the user LUTs of the blend (nullptr: none); outlives the evaluator
};

// Rounds a stored value to what the LUT's storage format holds (p.lut_format): 10-bit UNORM
// (clamped to [0, 1], round to nearest k/1023, NaN → 0 as D3D's float→UNORM conversion), IEEE
// half (round to nearest even, overflow → ±Inf), or float32.
double quantize_lut_value(int lut_format, double v);

// The baked LUT: N³ texels (r fastest, then g, then b), stored values after quantisation.
struct BakedLut {
  int size = 0;
  int layout = 0;      // 0 volume, 1 2-D unwrapped
  int lut_format = 2;  // the storage format (p.lut_format): 0 10-bit UNORM, 1 RGBA16F, 2 RGBA32F
  std::vector<Vec3> texels;
  // The texels float32 cannot decide (TexelRange), after quantisation: per texel the bounds of the
  // stored value and a flags byte (bit c: NaN may be stored in channel c; kAmbiguous: the texel is
  // ambiguous). All three empty when no texel is.
  static constexpr uint8_t kAmbiguous = 0x80;
  std::vector<Vec3> lo, hi;
  std::vector<uint8_t> flags;
  const Vec3& at(int r, int g, int b) const { return texels[index(r, g, b)]; }
  size_t index(int r, int g, int b) const { return (static_cast<size_t>(b) * size + g) * size + r; }
  bool has_ranges() const { return !flags.empty(); }
};

// Bakes the LUT as the GPU does: volume texels at (i, j, k)/(N−1); 2-D texels with UE's
// +1e-5/(N−1) bias on r and g from the 0.49999 half-texel trick (docs/spec/ue55.md §4.2).
// `luts`: the user LUTs of the blend (combine_luts_texel).
BakedLut bake_lut(const ParamBlock& p, const UeLutSet* luts = nullptr);

// The LUT as a conformant Vulkan device with precision `device` may store it (docs/precision.md,
// "Device allowances"): the same texels as bake_lut, and for every texel the range of what such a
// device may store there (kAmbiguous on all): the shader arithmetic's derived noise carried
// through the device's encode (PQ with the specification's transcendental bounds), then the
// storage format's either-way rounding (10-bit UNORM: either neighbouring code; RGBA16F: either
// neighbouring half unless float16 rounds to nearest; RGBA32F: either float). Every range holds
// the tight one of bake_lut.
BakedLut bake_lut_device(const ParamBlock& p, const DevicePrecision& device,
                         const UeLutSet* luts = nullptr);

// The value (before storage) a conformant device may compute for the texel function at `lattice`
// without a user-LUT blend: the range bake_lut_device stores from before the format's rounding
// (the shader arithmetic's derived noise through the device's encode), holding
// combine_luts_texel(p, lattice) itself. For a test that evaluates the texel function off the
// LUT's lattice (gpu/grading_shader_test.cpp on a device that is not float32-exact).
Range3 combine_luts_texel_device_range(const ParamBlock& p, const Vec3& lattice);

// The range a conformant device's hardware filter may return for a lookup of a device LUT: the
// weight box of `sub_texel_bits` around each axis's weight (device_allowance.h linear_tap_box),
// the lower texel bounds at the box corner that minimises, the upper at the one that maximises,
// per channel, the filter's products and sums rounded outward in the storage format's precision
// (device_allowance.h filter_taps: VK-GL-CTS's filtering precision of lut_format); the 2-D layout's
// shader lerp between its two bilinear samples is exact. Output scaled by 1.05 as sample_lut's.
// False for a NaN coordinate.
bool sample_lut_device_range(const BakedLut& device_lut, const Vec3& encoded, int sub_texel_bits,
                             Range3* out);

// The bake of only the texels that lookups read, each once, for a pass over fewer pixels than the
// LUT has texels (a Tonemap case of a few hundred pixels reads a few thousand of a 32³ LUT's
// 32 768 texels). Every texel a lookup reads, and its admissible range, is bit for bit what
// bake_lut stores there (the same store_texel); the others are never read. One per pass: not
// shared between threads.
class LazyBakedLut {
 public:
  explicit LazyBakedLut(const ParamBlock& p);
  // Bakes the texels sample_lut (and sample_lut_range) reads for `encoded`; returns the LUT.
  const BakedLut& prepare(const Vec3& encoded);
  size_t baked_texels() const { return baked_; }

 private:
  void bake(int r, int g, int b);
  ParamBlock p_;
  TexelEvaluator texel_;
  BakedLut lut_;
  std::vector<uint8_t> done_;
  size_t baked_ = 0;
};

// The lattice coordinate of texel (r, g, b) for the layout (docs/spec/ue55.md §4.2).
Vec3 lattice_coordinate(int layout, int size, int r, int g, int b);

// The tonemapper's lookup of an encoded colour (`ColorLookupTable` after the shaper encode):
// UVW = enc·(N−1)/N + 0.5/N, exact trilinear for the volume LUT or UE's two-tap
// UnwrappedTexture3DSample for the 2-D LUT, clamp-to-edge addressing; returns the sample × LUTMax:
// 1.05 in UE 5.5, GetTonemappingMax's 1.05 or 1 in UE 5.8 (docs/ue58-differences.md L8, T2).
Vec3 sample_lut(const BakedLut& lut, const Vec3& encoded, double lut_max = 1.05);

// The same lookup over the LUT's admissible ranges (BakedLut::lo/hi, the same taps and weights:
// a convex combination keeps the bounds); NaN is admissible where any tap may hold it. Returns
// false (and leaves *out alone) when no tap is ambiguous.
bool sample_lut_range(const BakedLut& lut, const Vec3& encoded, Range3* out);

}  // namespace hdrc::ref
