// The Tonemap pass (PostProcessTonemap.usf: TonemapCommonPS, docs/spec/ue55.md §6.1) in double
// precision, and its quantisation dither (step 10) as a separate stage: the dither's hash
// frac(sin(·)·493013) amplifies sin's last-bit differences ~5e5 times, so it is judged on its own
// (docs/precision.md).
#pragma once

#include <vector>

#include "color/vec.h"
#include "core/image.h"
#include "core/shader_interface.h"
#include "reference/ue/combine_luts.h"

namespace hdrc::ref {

struct TonemapTrace {
  Vec3 scene{};          // after fringe and sharpen
  Vec3 exposed{};        // FinalLinear: tint, exposure, vignette, bloom
  Vec3 encoded{};        // the shaper-encoded lookup coordinate
  Vec3 lut{};            // OutDevice: LUT sample × 1.05
  Vec3 output{};         // after the per-device post conversion (scRGB, LinearEXR)
  double luminance = 0;  // OutLuminance = dot(OutDevice, (0.299, 0.587, 0.114))
};

// The vignette's parameters (PostProcessTonemap.usf: VignetteType, VignetteParams0/1/2, set by
// PostProcessTonemap.cpp AddTonemapPass; PostProcessCommon.ush ComputeVignetteMask, UE 5.8). UE
// 5.5's vignette (the cosine-fourth law on VignetteSpace · Intensity, a scalar) is 5.8's at type
// CosineFourthLaw, centre (0.5, 0.5) and black colour, to the bit (Centre − 0.5 = 0, lerp(0, 1, w)
// = w): ue55_vignette (docs/ue58-differences.md T3).
struct Vignette {
  int type = 0;                     // EVignetteType: 0 CosineFourthLaw, 1 Texture, 2 Oval
  bool advanced = false;            // USE_ADVANCED_VIGNETTE: type != CosineFourthLaw
  double intensity = 0.0;           // VignetteParams0.x
  Vec3 color{};                     // VignetteParams0.yzw
  double center[2] = {0.5, 0.5};    // VignetteParams1.xy
  double inv_size[2] = {1.0, 1.0};  // VignetteParams1.zw: 1 / max(0.001, VignetteSize)
  double softness = 1.0;            // VignetteParams2
  // USE_VIGNETTE_TEXTURE (5.8: type Texture at feature level SM6, RemapPermutation) and the
  // VignetteTexture's red channel, row-major, row 0 at V 0 (UE's white dummy: one texel of 1).
  bool use_texture = false;
  int tex_width = 1, tex_height = 1;
  std::vector<double> tex{1.0};
};
Vignette ue55_vignette(const ParamBlock& p);  // UE 5.5: p.vignette_intensity, the rest default
// The steps of vignette_mask as computed (docs/spec/ue58.md §4's worked pixels): the texture
// branch's V, UV, texel coordinate (UV · size − 0.5), the four taps (i0, j0), (i1, j0), (i0, j1),
// (i1, j1) after clamp-to-edge and their bilinear sample (`textured` says the branch ran), and
// every branch's weight.
struct VignetteTrace {
  bool textured = false;
  double space[2] = {0, 0};
  double uv[2] = {0, 0};
  double texel[2] = {0, 0};
  double taps[4] = {0, 0, 0, 0};
  double sample = 0;
  double weight = 1;
};
// ComputeVignetteMask(VignetteSpace(pos, type, aspect), ...) at screen position (pos_x, pos_y) in
// [-1, 1] (y up), aspect = ViewportHeight / ViewportWidth.
Vec3 vignette_mask(const Vignette& v, double pos_x, double pos_y, double aspect,
                   VignetteTrace* trace = nullptr);
// The Texture branch's sample coordinate (InvSize · V − (Centre − 0.5)) · 0.5 + 0.5, V being
// VignetteSpace's Texture variant Pos · (saturate(1 / AspectRatio), saturate(AspectRatio)).
void vignette_texture_uv(const Vignette& v, double pos_x, double pos_y, double aspect, double* u,
                         double* w, VignetteTrace* trace = nullptr);
// The VignetteTexture's red channel sampled bilinearly with clamp-to-edge addressing at (u, w)
// (AddTonemapPass's TStaticSamplerState<SF_Bilinear>: AM_Clamp on both axes; SampleLevel 0).
double vignette_texture_sample(const Vignette& v, double u, double w,
                               VignetteTrace* trace = nullptr);

// Steps 1-5 of TonemapCommonPS at pixel (x, y) of `scene` (UE 5.5 and 5.8 alike): colour fringe,
// sharpen, FinalLinearColor = S · SceneColorTint · (exposure · VignetteMask) + Bloom · (exposure ·
// VignetteMask); `bloom`/`dirt` as tonemap_image's.
// `parts`, where set, receives the operands of steps 4-5 (for tonemap_encoded_device_range).
struct FinalLinearParts {
  Vec3 scene;      // S after the fringe and the sharpen
  Vec3 bloom_rgb;  // the bloom sample with its dirt (zero without bloom)
  Vec3 vignette;   // the vignette mask per channel
  bool bloom = false;
};
Vec3 tonemap_final_linear(const ParamBlock& p, const Image& scene, const Image* bloom,
                          const Image* dirt, int x, int y, const Vignette& vignette,
                          FinalLinearParts* parts = nullptr);

// UE 5.5's lookup coordinate (the log or PQ shaper of `p.output_device`) on a conformant device,
// per channel: steps 4-5's products and the shaper's encode op by op with the Vulkan precision
// table's bounds (for sample_lut_device_range's `encoded_range`).
void tonemap_encoded_device_range(const ParamBlock& p, const FinalLinearParts& parts,
                                  spirv::Interval out[3]);

// Step 9, the per-device post conversion: device 7 ST2084ToLinear; devices 5/6 ST2084ToScRGB when
// `scrgb_in_pass` (UE 5.5; 5.8's LUT already holds scRGB and the pass writes it unchanged,
// docs/ue58-differences.md T1); every other device unchanged.
Vec3 post_convert(const ParamBlock& p, const Vec3& out_device, bool scrgb_in_pass);

// One pixel's range on a conformant device (the pass's lookup of `device_lut`, a device bake with
// ranges, at the shader-encoded coordinate `encoded`): sample_lut_device_range × `lut_max` with
// `sub_texel_bits`, then the post conversion on the device (post_convert's, `scrgb_in_pass`),
// holding the reference's own output `rgb` / luminance `alpha` and, where set, the pixel's tight
// range `tight`. False for a NaN coordinate (no range). UE 5.5's and 5.8's pass alike.
bool tonemap_device_range(const ParamBlock& p, const BakedLut& device_lut, const Vec3& encoded,
                          int sub_texel_bits, double lut_max, bool scrgb_in_pass, const Vec3& rgb,
                          double alpha, size_t pixel, const AdmissibleRange* tight,
                          AdmissibleRange* out, const spirv::Interval* encoded_range = nullptr);

// One pixel at the centre of the screen (no vignette, fringe, sharpen or bloom), as `probe` uses
// it. `lut` null: CombineLUTs evaluated analytically at the encoded coordinate (clamped as the
// sampler addresses it); else the baked LUT sampled as UE samples it.
Vec3 tonemap_centre_pixel(const ParamBlock& p, const Vec3& scene, const BakedLut* lut,
                          TonemapTrace* trace = nullptr);
// The same with the analytic lookup's parameters unpacked once by the caller (`texel` built from
// `p`; null: as above).
Vec3 tonemap_centre_pixel(const ParamBlock& p, const Vec3& scene, const BakedLut* lut,
                          TonemapTrace* trace, const TexelEvaluator* texel);

// The whole pass over `scene` (the viewport is the image). `bloom` and `dirt` may be null (no
// bloom, no dirt mask); Bloom = RawBloom · (1 + Dirt · BloomDirtMaskTint), both sampled bilinearly
// at the pixel's buffer UV (LensUV·(1, −1)·0.5 + 0.5 with the default lens transform). Output RGB
// is the device-encoded colour before dither, alpha is OutLuminance.
Image tonemap_image(const ParamBlock& p, const Image& scene, const Image* bloom, const Image* dirt,
                    const BakedLut* lut);
// The same with the LUT baked lazily, only the texels the pass reads (`lazy` built from `p`; `lut`
// ignored when it is set): bit for bit the output of the whole LUT's bake.
Image tonemap_image(const ParamBlock& p, const Image& scene, const Image* bloom, const Image* dirt,
                    const BakedLut* lut, LazyBakedLut* lazy);
// The same, and with `device_lut` (bake_lut_device of `p`) the device allowances too: every
// pixel's range on a conformant device with `sub_texel_bits` (Image::device_admissible).
Image tonemap_image(const ParamBlock& p, const Image& scene, const Image* bloom, const Image* dirt,
                    const BakedLut* lut, LazyBakedLut* lazy, const BakedLut* device_lut,
                    int sub_texel_bits);

// The baked pass's LUT for `p` over an image of `pixels` pixels: true when baking only the texels
// read (at most 8 per pixel) costs less than the whole LUT's bake (which the process-wide cache
// can share between cases).
bool lazy_bake_pays(const ParamBlock& p, size_t pixels);

// Step 10: the triangular quantisation dither added to `in` (p.dither_amount, p.grain_random).
// The grain hash is evaluated in float32 as the shader does; see docs/precision.md.
double dither_grain(double u, double v);  // the uniform grain g in [0, 1)
Image dither_image(const ParamBlock& p, const Image& in);

// TonemapCommon.ush: ST2084ToScRGB for devices 5/6 (docs/spec/ue55.md §3.5).
Vec3 st2084_to_scrgb(const Vec3& pq, double max_odt_nits);

}  // namespace hdrc::ref
