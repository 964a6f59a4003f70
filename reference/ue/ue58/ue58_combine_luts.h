// UE 5.8's CombineLUTs in double precision (pipeline "ue58", stage ue58_combine_luts): the inner
// LUT bake (PostProcessCombineLUTsInner.usf: MainCS / MethodLUTsCommon) and the outer LUT bake
// (PostProcessCombineLUTs.usf: MainCS / CombineLUTsCommon / ApplyToneCurve / InnerLookupTable),
// both tone-mapping methods (Filmic, StandardACES), ACES 1.3 and 2.0, devices 0-9, gamuts 0-4.
// What 5.8 changed since 5.5: docs/ue58-differences.md §1a; decisions: docs/ue58-decisions.md E.
//
// Sources (facts only, no code copied): unicorn2022/UE5.8.0 @
// 5d9a05c15b1f8c6d7b3354b360677ce30d688149, Engine/Shaders/Private/PostProcessCombineLUTs.usf,
// PostProcessCombineLUTsInner.usf, Engine/Source/Runtime/Renderer/Private/PostProcess/
// PostProcessCombineLUTs.cpp (GetTonemappingMethod, GetTonemappingMax, GetInnerLUTParameters,
// AddCombineLUTPass). The grading steps 5.8 shares with 5.5 are reference/ue/grading/.
#pragma once

#include <cstdint>
#include <vector>

#include "color/vec.h"
#include "core/device_precision.h"
#include "core/shader_interface.h"
#include "reference/color/noise_range.h"
#include "reference/ue/aces2/aces2.h"

namespace hdrc::ref::ue58 {

// EDisplayOutputFormat / ETonemappingMethod values the block carries.
enum class Method { kFilmic = 0, kStandardAces = 1 };

// The ACES 2.0 parameters and tables of one set of the block (ue58_aces2_params / _reach_table /
// _cusp_table / _gamma_table, or their _sdr twins), unpacked to the reference's types.
struct Aces2Set {
  aces2::Params params;
  aces2::Tables tables;
};
Aces2Set unpack_aces2_set(const ParamBlock& p, bool sdr);
// Writes `params` and `tables` into the block's set (the inverse of unpack_aces2_set).
void pack_aces2_set(const aces2::Params& params, const aces2::Tables& tables, bool sdr,
                    ParamBlock* p);

// One parameter block's CombineLUTs, unpacked once.
class CombineLuts58 {
 public:
  explicit CombineLuts58(const ParamBlock& p);

  // MethodLUTsCommon: the inner LUT's value at lattice coordinate `e` (each channel in [0, 1])
  // before storage: PQ (OutputMaxLuminance > 100) or sRGB-encoded output-gamut colour.
  Vec3 inner_texel(const Vec3& e) const;
  // The inner LUT's stored texel (r, g, b): inner_texel at (r, g, b) / (M - 1), rounded to
  // P.ue58_inner_format. Evaluated on first use and kept (a lookup reads 8 texels; the outer
  // bake reads a fraction of the M^3): the values are those of a bake of every texel.
  const Vec3& inner_stored(int r, int g, int b) const;
  // The whole inner LUT (M^3 texels, r fastest, then g, then b); empty when
  // P.ue58_inner_needed is 0.
  std::vector<Vec3> inner_lut() const;
  // InnerLookupTable(encoded, inv_eotf_pq): trilinear sample of the stored inner LUT at UVW =
  // encoded * (1 - 1/M) + 0.5/M, clamp-to-edge, with exact weights; then the decode to linear
  // (or PQ) the shader applies.
  Vec3 inner_lookup(const Vec3& encoded, bool inv_eotf_pq) const;
  // CombineLUTsCommon at outer lattice coordinate `e`: the stored value OutDeviceColor * LUTInvMax
  // before the outer LUT's storage rounding.
  Vec3 outer_texel(const Vec3& e) const;
  // Measurement only (bench/ue58_differences.cpp, docs/ue58-decisions.md F): with `exact`,
  // inner_lookup evaluates MethodLUTsCommon at the lookup coordinate itself (clamped to [0, 1], as
  // the clamp addressing does) instead of sampling the stored inner LUT — 5.8's output transform
  // without the inner LUT's interpolation and storage rounding (docs/ue58-differences.md L2).
  // UE has no such path.
  void set_exact_inner(bool exact) { exact_inner_ = exact; }

  // Device allowances (docs/precision.md "Device allowances", docs/ue58-decisions.md E8): what a
  // conformant Vulkan device with precision `device` may store, as ranges. Each holds the point
  // value of the float32-exact evaluation above.
  //
  // The inner texel (r, g, b) as such a device may store it: MethodLUTsCommon's output (nits, or
  // sRGB-range linear) at the point and at the 8 corners of the device's decode of the lattice
  // coordinate (pq_decode_on_device; docs/ue58-decisions.md E9), each widened by kShaderNoise of
  // its largest channel (the upstream arithmetic, ACES 1.3 / 2.0 included: noise_range.h), the
  // union through the device's PQ (pq_encode_on_device) or sRGB encode (monotone, plus
  // kEncodePowNoise), then either neighbouring value of the inner format (store_either_way).
  // Evaluated on first use and kept.
  const Range3& inner_stored_range(int r, int g, int b, const DevicePrecision& device) const;
  // InnerLookupTable over a range of coordinates `encoded` on such a device: per axis the texel
  // planes the range spans and the weight box of the device's sub-texel bits (UE samples the
  // inner LUT with a hardware bilinear sampler: linear_tap_boxes), the 8 stored texels' ranges
  // at the box corners that minimise / maximise each channel, the filter's own arithmetic, then
  // the decode as inner_lookup does it (PQ on a device: pq_decode_on_device).
  Range3 inner_lookup_range(const Range3& encoded, bool inv_eotf_pq,
                            const DevicePrecision& device) const;
  // CombineLUTsCommon at `e` on such a device, before the outer store.
  Range3 outer_texel_range(const Vec3& e, const DevicePrecision& device) const;

 private:
  Vec3 graded_color(const Vec3& color_ap1) const;
  Vec3 film_color_no_gamma(const Vec3& color_ap1) const;
  Vec3 apply_tone_curve(const Vec3& color_ap1, double peak, bool inv_eotf_pq) const;
  Vec3 output_aces(const Vec3& graded) const;
  Vec3 inv_output_aces(const Vec3& film_nits) const;
  Vec3 inner_output(const Vec3& e) const;      // MethodLUTsCommon before its encode (nits)
  Vec3 inner_input_nits(const Vec3& e) const;  // its decode of the lattice coordinate (nits)
  Vec3 inner_output_from_nits(const Vec3& nits) const;  // and the rest, from that decode
  Vec3 inner_encode(Vec3 out) const;                    // and its encode
  Vec3 color_corrected(const Vec3& e) const;
  Range3 tone_curve_range(const Vec3& color_ap1, double peak, bool inv_eotf_pq,
                          const DevicePrecision& device) const;

  ParamBlock p_;
  Aces2Set fwd_, sdr_;
  // Not thread-safe: one evaluator per thread.
  mutable std::vector<Vec3> inner_;
  mutable std::vector<Vec3> inner_out_;  // inner_output at each kept texel, before its encode
  mutable std::vector<uint8_t> inner_done_;
  bool exact_inner_ = false;
  mutable std::vector<Range3> inner_range_;
  mutable std::vector<uint8_t> inner_range_done_;
};

// The outer LUT as stored: N^3 texels (r fastest), each channel rounded to P.lut_format.
std::vector<Vec3> bake_outer_lut(const ParamBlock& p);
// The same with an evaluator of `p` (its inner texels kept for a later bake_outer_lut_device).
std::vector<Vec3> bake_outer_lut(const CombineLuts58& luts, const ParamBlock& p);

// The outer LUT as a conformant device with precision `device` may store it: per texel (r
// fastest) outer_texel_range stored either way in P.lut_format (store_either_way), holding the
// texel bake_outer_lut stores; `nan` bit c where NaN may be stored in channel c.
struct DeviceLutRanges {
  std::vector<Vec3> lo, hi;
  std::vector<uint8_t> nan;
};
DeviceLutRanges bake_outer_lut_device(const ParamBlock& p, const DevicePrecision& device);
DeviceLutRanges bake_outer_lut_device(const CombineLuts58& luts, const ParamBlock& p,
                                      const DevicePrecision& device);

}  // namespace hdrc::ref::ue58
