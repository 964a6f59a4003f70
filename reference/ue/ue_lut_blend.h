// UE 5.5's user colour-grading LUT blend in CombineLUTs (docs/ue55-lut-blend-spec.md §3): the
// LUT texture as UE holds it (a 16-point LUT unwrapped to a 256 × 16 strip, 8-bit UNORM as the
// ColorLookupTable texture group forces), UE's UnwrappedTexture3DSample of it, and the blend of
// the neutral colour with up to four LUTs by the host's weights (reference/ue/cpp/
// lut_blend_table.h), in sRGB-encoded space.
//
// Sources (lakeone/UE5.51MagicM, stock 5.5.1): Engine/Shaders/Private/PostProcessCombineLUTs.usf
// (CombineLUTsCommon, the `#if BLENDCOUNT > 1` block), PostProcessCommon.ush
// (UnwrappedTexture3DSample), GammaCorrectionCommon.ush (LinearToSrgb, sRGBToLinear),
// Engine/Source/Runtime/Engine/Private/Texture.cpp (UTexture::ValidateSettingsAfterImportOrEdit:
// TEXTUREGROUP_ColorLookupTable → SRGB off, no mips, uncompressed: BGRA8).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/image.h"
#include "core/shader_interface.h"
#include "reference/color/noise_range.h"
#include "reference/color/spirv_precision.h"
#include "color/vec.h"

namespace hdrc::ref {

// The user LUT's edge: the 16, 15/16, 0.5/16 and 1/16 are shader literals
// (PostProcessCombineLUTs.usf: CombineLUTsCommon); the texture's own size is never read.
inline constexpr int kUeUserLutSize = 16;
inline constexpr int kUeUserLutWidth = kUeUserLutSize * kUeUserLutSize;  // 256
inline constexpr int kUeUserLutHeight = kUeUserLutSize;                  // 16

// The float → 8-bit UNORM storage of a LUT texel (BGRA8): NaN → 0, clamped to [0, 1], rounded to
// the nearest k/255. Both engines get the texels this makes (the host quantises once).
uint8_t unorm8_from_value(double v);

// A user LUT texture as UE samples it: 256 × 16 texels, texel (r + 16 b, g) the LUT output for
// input (r, g, b)/15, row 0 = texture v = 0 (g = 0). Values as the texture holds them.
struct UeLutTexture {
  std::vector<Vec3> texels;  // kUeUserLutWidth × kUeUserLutHeight, row-major
  const Vec3& at(int x, int y) const {
    return texels[static_cast<size_t>(y) * kUeUserLutWidth + static_cast<size_t>(x)];
  }
};

// The texture of a 16-point table (16³ rows, red fastest, then green, then blue; the .cube
// order): 8-bit UNORM texels (`quantize_8bit`, UE's storage) or the table's values unchanged (the
// spec's float-texel worked examples). Empty texels when the table has not 16³ rows.
UeLutTexture ue_lut_texture(const std::vector<std::array<float, 3>>& table, bool quantize_8bit);

// PostProcessCommon.ush: UnwrappedTexture3DSample(Texture, Sampler, UVW, 16, 1/16) with the
// pass's bilinear, clamp-addressed sampler, exact filter weights: IntW = floor(UVW.z·16 − 0.5),
// FracW = UVW.z·16 − 0.5 − IntW, U = (UVW.x + IntW)/16; lerp(bilinear(U, UVW.y), bilinear(U +
// 1/16, UVW.y), FracW).
Vec3 unwrapped_texture3d_sample(const UeLutTexture& lut, const Vec3& uvw);

// The blend (CombineLUTsCommon, BLENDCOUNT = count ≥ 2): g = LinearToSrgb(saturate(F)) (the
// desktop branching version); UVW = g·15/16 + 0.5/16; G = w0·g + Σ_{i=1}^{count−1} wi ·
// UnwrappedTexture3DSample(Textures_i, UVW); returns sRGBToLinear(G) (with 5.5's 6.10352e-5
// clamp). count 1 (or less): F unchanged (the block is compiled out). `luts[i - 1]` is
// Textures_i.
Vec3 blend_user_luts(const Vec3& film_color, int count, const std::array<double, 5>& weights,
                     const std::array<const UeLutTexture*, 4>& luts);

// The textures of the user-LUT slots (Textures_1..4) from the strips both engines bind
// (ResolvedCase::user_luts: 256 × 16, values as stored); an empty slot stays empty.
struct UeLutSet {
  std::array<UeLutTexture, kUserLutSlots> slots;
};
UeLutSet ue_lut_set(const std::array<Image, kUserLutSlots>& strips);

// blend_user_luts with the host's table: BLENDCOUNT P.lut_blend_count, LUTWeights
// (P.lut_weights, P.lut_weight_4), Textures_i = luts.slots[i − 1].
Vec3 blend_user_luts(const Vec3& film_color, const ParamBlock& p, const UeLutSet& luts);

// The same lookup as a conformant Vulkan device may evaluate it, over a coordinate interval per
// axis (docs/precision.md, "Device allowances"): the shader's slice arithmetic (w = UVW.z·16 − 0.5,
// FracW, U = (UVW.x + IntW)/16 and U + 1/16) within the bounds of the Vulkan specification's
// "Precision and Operation of SPIR-V Instructions" (spirv_precision.h; both IntW a rounded w may
// floor to), each hardware bilinear sample with the sub-texel weight box of "Texel Filtering"
// (subTexelPrecisionBits `bits`, device_allowance.h linear_tap_box; both texel pairs where the
// coordinate interval crosses a texel centre) at its corners, and the shader's lerp by FracW
// (shader arithmetic: FracW's interval, not a filter weight). Per channel: [min, max] of what the
// device may return; the texels are the texture's values (points).
Range3 unwrapped_texture3d_sample_device(const UeLutTexture& lut,
                                         const std::array<spirv::Interval, 3>& uvw, int bits);

// blend_user_luts (BLENDCOUNT ≥ 2) as a conformant device may evaluate it: FilmColor widened by
// the upstream arithmetic's allowance (kShaderNoise of its largest channel, noise_range.h), the
// saturate, LinearToSrgb's pow pair (pow(x, 1/2.4)·1.055 − 0.055 or 12.92·x), UVW's multiply-add,
// unwrapped_texture3d_sample_device, the weighted sum and sRGBToLinear (its clamp, then
// pow(c/1.055 + 0.0521327, 2.4) or c/12.92), each step within the specification's bounds
// (spirv_precision.h). Per channel: the range of the blend's linear result. count ≤ 1: FilmColor's
// point.
Range3 blend_user_luts_device_range(const Vec3& film_color, int count,
                                    const std::array<double, 5>& weights,
                                    const std::array<const UeLutTexture*, 4>& luts, int bits);
Range3 blend_user_luts_device_range(const Vec3& film_color, const ParamBlock& p,
                                    const UeLutSet& luts, int bits);

}  // namespace hdrc::ref
