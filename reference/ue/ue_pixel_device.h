// Device allowances for UE 5.5's per-pixel stages (the LUT shaper round trip, docs/spec/ue55.md
// §4.3 / §6.1 step 7, and the linear devices 7/8, docs/spec/ue55.md §4.12): the range of each
// output channel a conformant Vulkan device may produce evaluating the GLSL port
// (gpu/shaders/lib/lut_shaper.glsl, st2084.glsl, ue_log_shaper.glsl, matrix.glsl;
// gpu/shaders/stages/shaper.comp, linear_device.comp) in float32, step by step with the bounds of
// the Vulkan precision table (reference/color/spirv_precision.h; Vulkan spec, spirvenv-op-prec).
// docs/precision.md, "Device allowances".
//
// The steps follow the shader's own operation order (its PQ encode divides by the peak and
// multiplies by a reciprocal, unlike UE's LinearToST2084 that pq_encode_on_device models), and
// its float32 constants and uniforms enter as the interval between the float32 neighbours of the
// exact value (a conversion to float32 is correctly rounded: 0.5 ULP either way).
#pragma once

#include <functional>

#include "color/vec.h"
#include "core/image.h"
#include "core/shader_interface.h"
#include "core/stage.h"
#include "reference/color/spirv_precision.h"

namespace hdrc::ref::ue_device {

// A float32 constant or uniform of exact value v: its float32 neighbours.
spirv::Interval constant(double v);

// pow(x, y) for a constant y > 0 over x ≥ 0 (pow_d3d: pow(0, y > 0) = 0); y as float32 either way.
spirv::Interval pow_const(spirv::Interval x, double y);

// st2084.glsl pq_from_nits / nits_from_pq over a range (both increasing; nits.lo ≥ 0, pq ≥ 0).
spirv::Interval pq_from_nits(spirv::Interval nits);
spirv::Interval nits_from_pq(spirv::Interval pq);

// lut_shaper.glsl lut_encode (clamped as lut_clamp does) and lut_decode of one channel over a
// range. The PQ encode of a range with negative values is the caller's (NaN there).
spirv::Interval lut_encode_clamped(int output_device, spirv::Interval x);
spirv::Interval lut_decode(int output_device, spirv::Interval e);

// One pixel's device range per channel; nan: NaN admissible in the channel.
struct ChannelRanges {
  spirv::Interval c[3];
  bool nan[3] = {false, false, false};
  bool valid[3] = {true, true, true};  // false: the point value alone (e.g. a NaN input)
};

// shaper.comp of one pixel (x as the shader reads it, float32).
ChannelRanges shaper_device_range(int output_device, const Vec3& x);
// linear_device.comp of one pixel.
ChannelRanges linear_device_range(const ParamBlock& p, const Vec3& x);

// The device ranges of a per-pixel stage's output image (kShaper, kLinearDevice): every pixel
// whose range admits more than its reference value, each range containing the reference value.
std::vector<AdmissibleRange> per_pixel_device_ranges(StageId stage, const ParamBlock& p,
                                                     const Image& input, const Image& reference);

// The UI composite (gpu/shaders/lib/ui_composite.glsl, mode ≠ 0, PQ back buffer) of `scene`
// (back-buffer codes) under `ui`: per pixel, the back buffer's device decode (nits_from_pq above)
// carried through ComposeUIAndScene and ApplyColorDeficiency at the corners of its box (both are
// smooth: over boxes of a few 1e-4 relative their extremes lie at the corners to first order),
// widened by kShaderNoise × the largest |channel| for those steps' own float32 arithmetic (the
// UI colour's decode, the matrices, the compose; reference/color/noise_range.h), then the device
// PQ encode (pq_from_nits above); a range whose low end is negative admits NaN (pow of a negative
// base). scRGB back buffers (all steps linear): kShaderNoise × the largest |channel| around the
// reference. Mode 0 (the fixed-function blend) has no ranges here.
std::vector<AdmissibleRange> ui_composite_device_ranges(const ParamBlock& p, const Image& scene,
                                                        const Image& ui, const Image& reference);

// The same scheme for any composite over the same back-buffer decode and encode (UE 5.5's above,
// UE 5.8's reference/ue/ue58/ue58_ui_composite.cpp): `composed(i, scene_nits)` is the pass's colour
// after ApplyColorDeficiency for pixel i's UI texel over a scene colour in nits; it must be
// monotone in each scene channel or smooth over the box (its extremes at the box's corners).
std::vector<AdmissibleRange> ui_composite_device_ranges_of(
    int output_device, const Image& scene, const Image& reference,
    const std::function<Vec3(size_t, const Vec3&)>& composed);

}  // namespace hdrc::ref::ue_device
