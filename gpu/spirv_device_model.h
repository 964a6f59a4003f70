// The worst-case conformant device, shader side (core/device_precision.h, DeviceModel::kWorst):
// a word-level rewrite of the SPIR-V glslang produced, and the GLSL preamble of the in-shader
// filter. docs/precision.md, "The worst-case device", says what each freedom is, the bound the
// Vulkan specification puts on it and what the model does; docs/gpu-interface.md where it sits.
//
// Source (facts taken, no code): Vulkan spec, appendix "Vulkan Environment for SPIR-V",
// "Precision and Operation of SPIR-V Instructions" (ulp(x), the error bounds of OpFDiv and of
// GLSL.std.450 Exp/Exp2/Log/Log2/Pow, NoContraction) and chapter "Texel Filtering"
// (u = s·width − 0.5, i0 = ⌊u⌋, α = frac(u), subTexelPrecisionBits).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/result.h"

namespace hdrc::gpu {

// What apply_worst_device_model changed in a module (tests and docs read these counts).
struct DeviceModelRewrite {
  int fused = 0;      // OpFAdd/OpFSub of an OpFMul evaluated with one rounding
  int divisions = 0;  // OpFDiv results moved ±2 ULP
  int exp2 = 0;       // Exp2 results moved floor(2.5 + 2|x|) ULP
  int exp = 0;        // Exp results moved floor(2.5 + 2|x|) ULP
  int log2 = 0;       // Log2: 2 ULP outside [0.5, 2], kLogInsideShift absolute inside
  int log = 0;        // Log: the same
  int pow = 0;        // Pow: kPow* below
};

// The direction of a perturbation, from the bits of the correctly computed result: true moves
// it away from zero (Fibonacci hashing: the top bit of bits · 2^32/φ), so that both directions
// occur across a shader's values and the choice is reproducible.
inline constexpr uint32_t kPerturbHashMultiplier = 0x9E3779B1u;
inline bool perturb_away_from_zero(uint32_t result_bits) {
  return ((result_bits * kPerturbHashMultiplier) >> 31) != 0u;
}

// The ULP steps of each perturbation: the bound minus the 0.5 ULP of the driver's own rounding,
// rounded down to a whole number.
inline constexpr int kDivisionSteps = 2;  // 2.5 ULP
inline constexpr int kLogSteps = 2;       // 3 ULP outside [0.5, 2]
// log/log2 inside [0.5, 2]: the bound is an absolute error < 2^-21. The result R (|R| ≤ 1) is
// within 0.5 ulp ≤ 2^-25 of the exact value, R ± d is rounded once more (≤ 2^-24, |R ± d| ≤ 2):
// d = 3·2^-23 keeps the total ≤ 2^-21 − 2^-25, strictly inside the bound.
inline constexpr float kLogInsideShift = 0x3p-23f;
// pow(x, y), "inherited from exp2(y × log2(x))", with t = y·log2(x), to first order in the
// result's relative error ε (ULPs of the result ≥ ε·2^23): exp2's own 3 + 2|t| ULP; log2's
// error times |y| — outside [0.5, 2] 3 ulp(log2 x) ≤ 3|log2 x|·2^-23, i.e. 3 ln2 |t| ULP, inside
// 2^-21 absolute, i.e. 4 ln2 |y| ULP; and the rounding of y·log2(x), 0.5 ln2 |t| ULP. The model
// takes 0.999 of the sum of the |t| and |y| terms (the margin covers the second-order terms
// while the shift stays under kMaxPowSteps, and t's own rounding), plus 2.5, rounded down:
//   outside: floor(2.5 + 0.999·(2 + 3.5 ln2)|t|), inside: floor(2.5 + 0.999·((2 + 0.5 ln2)|t|
//   + 4 ln2 |y|)), at most kMaxPowSteps.
inline constexpr double kPowOutsideT = 0.999 * (2.0 + 3.5 * 0.69314718055994531);
inline constexpr double kPowInsideT = 0.999 * (2.0 + 0.5 * 0.69314718055994531);
inline constexpr double kPowInsideY = 0.999 * 4.0 * 0.69314718055994531;
inline constexpr int kMaxPowSteps = 4000;

// Rewrites a SPIR-V module (as glslang emits it: one module, functions after the globals) for the
// worst-case device, in place:
//  * FMA fusion: every float32 (scalar or vector) OpFAdd/OpFSub with an operand that is an OpFMul
//    of the same type becomes fma(a, b, ±c) (through OpFNegate for a subtraction), unless the
//    add/sub or the mul is decorated NoContraction (GLSL `precise`); the mul stays for other uses.
//    The fma is emulated exactly with float operations (Boldo–Melquiond; see the .cpp), not
//    GLSL.std.450 Fma: Mesa lowers that to a multiply and an add, so lavapipe would not fuse it.
//  * Every float32 OpFDiv, Exp2, Exp, Log2, Log and Pow result moved to the edge of its bound
//    (the constants above), in the direction perturb_away_from_zero picks; a move away from zero
//    that would leave the result's binade, or start at a power of two, goes toward zero instead
//    (so the move is at most the steps times the smaller ulp either side of the result, which is
//    ≤ ulp of the exact value). Results that are NaN, ±Inf, 0 or below 2^-125 are left alone.
// The model's own arithmetic is decorated NoContraction. Types and constants it needs are reused
// where the module declares them, else added; the id bound grows. An error names what in the module
// it could not parse.
Result<DeviceModelRewrite> apply_worst_device_model(std::vector<uint32_t>* spirv);

// The GLSL preamble of the worst-case device (glslang TShader::setPreamble, GLSL only):
// `#define HDRC_DEVICE_MODEL_WORST 1`; hdrc_filter_lod(sampler2D | sampler3D, coordinate, lod,
// bits): the engine's sampler (linear, clamp to edge, normalised coordinates, level 0) built from
// texelFetch and textureSize, with α truncated to `bits` fractional bits (bits < 0: unquantised);
// and `#define textureLod(s, c, l)` as hdrc_filter_lod with kWorstModelSubTexelBits.
std::string worst_device_glsl_preamble();

}  // namespace hdrc::gpu
