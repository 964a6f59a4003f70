// What a conformant Vulkan device may do differently from exact float32 arithmetic, as the Vulkan
// specification bounds it, and the worst-case device model that takes each freedom to its edge.
//
// Sources (facts taken, no code):
//  * Vulkan spec, "Precision and Operation of SPIR-V Instructions": exp2 3 + 2|x| ULP, log2 3 ULP
//    outside [0.5, 2] and 2^-21 absolute inside, pow inherited from exp2(y log2 x), division 2.5
//    ULP over |y| in [2^-126, 2^126], a*b + c may be fused unless NoContraction decorates it;
//    float -> float16 conversions may round either way unless the device's float controls say RTE.
//  * Vulkan spec, "Fixed-Point Data Conversions": float -> UNORM picks one of the two nearest codes
//    ("should" round to nearest, may round either way).
//  * Vulkan spec, "Texel Filtering" / VkPhysicalDeviceLimits::subTexelPrecisionBits: the filter's
//    weights have at least this many fractional bits (core minimum 4; Roadmap 2022 and Vulkan 1.4
//    require 8).
#pragma once

#include <string>

namespace hdrc {

// The shader compiler's and engine's device model (`run --device-model`).
//  kNone: the device as it is.
//  kWorst: a device that takes every freedom the specification allows to its edge, run on any
//    Vulkan device (lavapipe in CI): hardware filtering replaced by an in-shader filter whose
//    weights are quantised to DevicePrecision::sub_texel_bits, log2/exp2/pow/division perturbed
//    deterministically to the edge of their error bounds, every a*b + c that may be fused fused,
//    float16 and UNORM stores rounded toward zero, and every image and buffer a pass may read
//    before writing poisoned (NaN or garbage) before each pass. docs/precision.md, "The worst-case
//    device".
enum class DeviceModel { kNone, kWorst };

inline const char* device_model_name(DeviceModel m) {
  return m == DeviceModel::kWorst ? "worst" : "none";
}

// The sub-texel bits of the worst-case model: Roadmap 2022 / Vulkan 1.4's minimum. A core-1.0
// device may have 4 (docs/precision.md says what such a device would need).
inline constexpr int kWorstModelSubTexelBits = 8;

// The precision properties of the device a case ran on, recorded in results.json, the report and
// the provenance. The allowances (docs/precision.md) are derived from these.
struct DevicePrecision {
  int sub_texel_bits = 4;    // VkPhysicalDeviceLimits::subTexelPrecisionBits (spec minimum 4)
  int mipmap_bits = 4;       // VkPhysicalDeviceLimits::mipmapPrecisionBits
  bool fp16_rte = false;     // shaderRoundingModeRTEFloat16: float16 conversions round to nearest
  bool fp32_denorm = false;  // shaderDenormPreserveFloat32
  std::string model;         // "" for the device itself, else device_model_name()
  // sin/cos/division and filtering evaluated as float32-exact, the hash deterministic: the
  // dither's exact pattern (the reference's grain) is judged only on such a candidate
  // (core/case.h DitherCriterion). The runner sets it (runner/dither.h float32_exact_device):
  // the reference engine, and the Vulkan engine on llvmpipe without a device model.
  bool float32_exact = false;
};

}  // namespace hdrc
