// UE 5.8's ACES 2.0 output transform (urn:ampas:aces:transformId:v2.0:Lib.Academy.OutputTransform.
// a2.v1), in double precision: the parameters UE derives, the three tables its C++ builds on the
// host and binds as textures, and every shader stage as a separate function, forward and inverse.
// Decisions and measured differences: docs/ue58-decisions.md.
//
// Sources (facts only, no code copied):
//  * unicorn2022/UE5.8.0 @ 5d9a05c15b1f8c6d7b3354b360677ce30d688149:
//    Engine/Shaders/Private/ACES/ACESOutputTransform.ush (the shader stages, init_ODTParams),
//    ACESUtilities.ush (spow, sdiv, satan2, smin), ACESDisplayEncoding.ush (white scale, peak
//    clamp), TonemapCommon.ush: ACESOutputTransform / ACESInvOutputTransform (how the stages are
//    called), Engine/Source/Runtime/Renderer/Private/PostProcess/ACESUtils.cpp (the tables,
//    "adapted from OpenColorIO ... ACES2 (v2.4.1)").
//  * ACESTonescale.ush is not in the public copy: init_TSParams / tonescale_fwd / tonescale_inv are
//    taken from ampas/aces-core @ 89a10fdcad5894553ec1c4cebd5b6cbca8c0b593 lib/Lib.Academy.
//    Tonescale.ctl (UE's struct members and call sites match it; ACESUtils.cpp:
//    InitToneScaleParams has the same constants).
//  * OpenColorIO v2.4.1 (ebd076ae6c4362d089edfbc63d8fbf3d7538ea01) src/OpenColorIO/ops/
//    fixedfunction/ACES2/Transform.cpp, Common.h: the implementation UE adapted; where it differs
//    from UE, Behaviour selects it.
//
// Units: ACES2065-1 (AP0) scene-linear in; "XYZ" is display-referred CIE XYZ with 1.0 = 100 nits
// (referenceLuminance); J, M in Hellwig 2022 units, h in degrees [0, 360).
#pragma once

#include <array>

#include "color/vec.h"

namespace hdrc::ref::aces2 {

// ACESOutputTransform.ush: tableSize, additionalTableEntries, baseIndex (ACESUtils.cpp: TABLE_SIZE,
// TABLE_ADDITION_ENTRIES, GAMUT_TABLE_BASE_INDEX).
inline constexpr int kTableSize = 360;
inline constexpr int kTotalTableSize = kTableSize + 2;
inline constexpr int kBaseIndex = 1;
inline constexpr double kReferenceLuminance = 100.0;  // nits that XYZ = 1.0 stands for

// ---- Where UE and OpenColorIO 2.4.1 differ ---------------------------------------------------
// Each difference has its own switch so a test can measure it alone (docs/ue58-decisions.md,
// table "UE vs Academy CTL vs OCIO").
enum class Flavour { kUe, kOcio };

struct Behaviour {
  // D1 clamp_AP1: UE's aces_to_JMh clamps AP1 to [0, 8·(128 + 768·log(peak/100)/log(100))]
  // (ACESOutputTransform.ush: clamp_AP1; the Academy CTL and OCIO's *builtin* transform do the
  // same). OCIO's fixed function ACES_OUTPUT_TRANSFORM_20, which produced the published vectors,
  // has no clamp (FixedFunctionOpCPU.cpp: Renderer_ACES_OutputTransform20::fwd).
  Flavour ap1_clamp = Flavour::kUe;
  // D2 matrices of the per-pixel path: UE multiplies by the 10-decimal float literals of
  // ACESCommon.ush (AP0_2_AP1_MAT, AP1_2_XYZ_MAT, AP0_2_XYZ_MAT, XYZ_2_AP0_MAT, XYZ_2_CAM16_MAT,
  // CAM16_2_XYZ_MAT); OCIO derives RGB→CAM16 from chromaticities (init_JMhParams).
  Flavour matrices = Flavour::kUe;
  // D3 compressGamut: OCIO returns (J, 0, h) when the gamut boundary's M is <= 0 (Transform.cpp:
  // compressGamut, "JMboundary[1] <= 0.0f"); UE's shader (like the CTL) divides by it.
  Flavour boundary_guard = Flavour::kUe;

  static constexpr Behaviour all(Flavour f) { return {f, f, f}; }
};

// ---- Chromaticities ---------------------------------------------------------------------------
struct Chromaticities {
  std::array<double, 2> red, green, blue, white;
};
// ACES2065-1 (SMPTE ST 2065-1), ACEScg (S-2014-004), ITU-R BT.709, SMPTE EG 432-1 (P3-D65),
// ITU-R BT.2020.
extern const Chromaticities kAp0, kAp1, kRec709, kP3D65, kRec2020;
// Lib.Academy.OutputTransform.ctl: CAM16_PRI (OCIO Common.h: CAM16::primaries; UE:
// EColorSpace::ACESCAM16).
extern const Chromaticities kCam16;

// RGB→XYZ with Y(white) = 1 (SMPTE RP 177 normalised primary matrix), in double.
Mat3 rgb_to_xyz(const Chromaticities& c);

// The per-pixel matrices of Behaviour::matrices, row-major for out = M · v.
struct PixelMatrices {
  Mat3 ap0_to_ap1, ap1_to_xyz, ap0_to_xyz, xyz_to_ap0, xyz_to_cam16, cam16_to_xyz;
};
const PixelMatrices& pixel_matrices(Flavour f);

// ---- Parameters -------------------------------------------------------------------------------
// ACESOutputTransform.ush: ODTParams (fed by init_ODTParams, which calls init_TSParams) plus the
// AP1 clamp limit, computed once per (peak luminance, limiting primaries, encoding primaries).
// Uploadable unchanged to a shader when T = float: every member is a 4-byte scalar, a 4-vector or
// three 4-vector rows, in std430 layout with no implicit padding (offsets in floats on the right;
// Aces2ParamsGpu static_asserts them).
template <typename T>
struct ParamsT {
  using Row = std::array<T, 4>;       // x, y, z, 0
  using Rows = std::array<Row, 3>;    // a 3×3 matrix, row r = Rows[r] (mul(M, v) = dot(row, v))
  T peak_luminance;                   // [0] nits
  T n_r, g, t_1, c_t, s_2, u_2, m_2;  // [1..7] init_TSParams (n = peak_luminance)
  T limit_j_max;                      // [8] Y_to_Hellwig_J(peak)
  T mid_j;                            // [9] Y_to_Hellwig_J(c_t · 100)
  T model_gamma;                      // [10] 1 / (0.59 · (1.48 + sqrt(Y_b / L_A)))
  T sat, sat_thr, compr;              // [11..13] chroma compression
  T chroma_compress_scale;            // [14] (0.03379 · n)^0.30596 − 0.45135
  T focus_dist;                       // [15] 1.35 + 1.35 · 1.75 · log10(n / n_r)
  T lower_hull_gamma;                 // [16] 1.14 + 0.07 · log10(n / n_r)
  T ap1_clamp_upper;                  // [17] clamp_AP1: 8 · (128 + 768 · ln(n/100) / ln(100))
  T pad0, pad1;                       // [18..19] 0
  Row xyz_w_limit;                    // [20..23] LIMIT_RGB_TO_XYZ · 100
  Row xyz_w_output;                   // [24..27] OUTPUT_RGB_TO_XYZ · 100
  Rows limit_rgb_to_xyz;              // [28..39]
  Rows limit_xyz_to_rgb;              // [40..51]
  Rows output_rgb_to_xyz;             // [52..63]
  Rows output_xyz_to_rgb;             // [64..75]
};
using Params = ParamsT<double>;
using Aces2ParamsGpu = ParamsT<float>;
static_assert(sizeof(Aces2ParamsGpu) == 76 * sizeof(float));

// init_ODTParams / init_TSParams in double, from chromaticities (UE passes the limiting matrices
// from the host and the encoding matrices from TonemapCommon.ush: GetColorSpace; here both are
// derived in double).
Params make_params(double peak_luminance, const Chromaticities& limit,
                   const Chromaticities& output);
// The float block a shader would receive (every member rounded to float).
Aces2ParamsGpu to_gpu(const Params& p);

// ---- Tables (ACESUtils.cpp) -------------------------------------------------------------------
// The three textures UE binds, in double, with their texel layout (all PF_R32_FLOAT, point
// sampled, read with Load):
//  * reach_m          ACES_ReachMTable, 360 × 1: texel i = reach M at hue i° (no wrap entries).
//  * gamut_cusp       ACES_GamutCuspTable, 3 × 362: texel (c, row) = cusp J, M, h of row; rows
//  1…360
//                     the 360 HSV-sampled cusps sorted by hue, row 0 = row 360 with h − 360, row
//                     361 = row 1 with h + 360.
//  * upper_hull_gamma ACES_UpperHullGammaTable, 362 × 1: texel 1 + i = gamma at hue i°, texel 0 =
//                     gamma(359°), texel 361 = gamma(0°).
template <typename T>
struct TablesT {
  std::array<T, kTableSize> reach_m;
  std::array<std::array<T, 3>, kTotalTableSize> gamut_cusp;
  std::array<T, kTotalTableSize> upper_hull_gamma;
};
using Tables = TablesT<double>;

// ACESUtils.cpp: JMhParams / InitJMhParams — the host's Hellwig 2022 constants for one RGB space
// (RGB 1.0 = 100 nits).
struct JMhParams {
  double f_l, z, a_w, a_w_j;
  Vec3 xyz_w, d_rgb;
  Mat3 rgb_to_cam16;  // RGB → CAM16 (no adaptation) · 100
  Mat3 cam16_to_rgb;
};
JMhParams make_jmh_params(const Chromaticities& c);
// ACESUtils.cpp: RGB_to_JMh, JMh_to_RGB (host side, used to build the tables).
Vec3 host_rgb_to_jmh(const Vec3& rgb, const JMhParams& p);
Vec3 host_jmh_to_rgb(const Vec3& jmh, const JMhParams& p);

// The scalar type the host searches run in. UE (ACESUtils.cpp) and OCIO 2.4.1 (Transform.cpp)
// both run them in float; the bisections' last decisions are precision-sensitive (an entry can
// move by one bisection step, 50/2^13 = 0.0061 in reach M), docs/ue58-decisions.md A3.
enum class TableScalar { kDouble, kFloat32 };

// ACESUtils.cpp: MakeReachMTable — for hue i = 0…359, the largest M at J = limit_j_max whose AP1
// RGB stays non-negative: steps of 50 below 1300, then bisection to 1e-2; the upper end is stored.
std::array<double, kTableSize> make_reach_m_table(double peak_luminance,
                                                  TableScalar s = TableScalar::kDouble);
// ACESUtils.cpp: MakeGamutTable — HSV(i/360, 1, 1) · peak/100 in the limiting primaries → JMh.
std::array<std::array<double, 3>, kTotalTableSize> make_gamut_cusp_table(
    const Chromaticities& limit, double peak_luminance, TableScalar s = TableScalar::kDouble);
// ACESUtils.cpp: MakeUpperHullGamma — per hue i°, the smallest gamma in steps of 0.4 then bisected
// to 1e-5 for which the boundary at 1 %, 50 % and 99 % between cusp J and limit_j_max lies outside
// the limiting RGB cube.
std::array<double, kTotalTableSize> make_upper_hull_gamma_table(
    const std::array<std::array<double, 3>, kTotalTableSize>& gamut_cusp, double peak_luminance,
    const Chromaticities& limit, TableScalar s = TableScalar::kDouble);
Tables make_tables(const Params& p, const Chromaticities& limit,
                   TableScalar s = TableScalar::kDouble);

// ---- Shader stages (ACESOutputTransform.ush), forward and inverse ------------------------------
// Tonescale (Lib.Academy.Tonescale.ctl): scene-linear → nits, and nits/100 → scene-linear.
double tonescale_fwd(double x, const Params& p);
double tonescale_inv(double y, const Params& p);
// Hellwig_J_to_Y / Y_to_Hellwig_J (achromatic, dim surround 0.59, L_A = 100, Y_b = 20); Y in nits.
double hellwig_j_to_y(double j);
double y_to_hellwig_j(double y);
// XYZ_to_Hellwig2022_JMh / Hellwig2022_JMh_to_XYZ: XYZ in nits (XYZ · 100), white XYZ_w in nits.
Vec3 xyz_to_jmh(const Vec3& xyz_nits, const Vec3& xyz_w, Flavour matrices = Flavour::kUe);
Vec3 jmh_to_xyz(const Vec3& jmh, const Vec3& xyz_w, Flavour matrices = Flavour::kUe);

// aces_to_JMh (AP0 → AP1 → clamp_AP1 → XYZ → JMh against the ACES white) and JMh_to_aces.
Vec3 aces_to_jmh(const Vec3& aces, const Params& p, const Behaviour& b = {});
Vec3 jmh_to_aces(const Vec3& jmh, const Behaviour& b = {});

// reachMFromTable, cuspFromTable (J, M), hueDependentUpperHullGamma, chromaCompressionNorm.
double reach_m_from_table(double h, const Tables& t);
std::array<double, 2> cusp_from_table(double h, const Tables& t);
double upper_hull_gamma_from_table(double h, const Tables& t);
double chroma_compression_norm(double h, const Params& p);

// findGamutBoundaryIntersection: the boundary (J, M) on the projection line through jmh_s towards
// j_focus, and that line's J at M = 0.
Vec3 find_gamut_boundary_intersection(const Vec3& jmh_s, const std::array<double, 2>& cusp,
                                      double j_focus, double j_max, double slope_gain,
                                      double gamma_top, double gamma_bottom);

// chromaCompression: the M of `jmh` (J already tonemapped) given the J before the tonescale.
double chroma_compression(const Vec3& jmh, double orig_j, const Params& p, const Tables& t,
                          bool invert);
// tonemapAndCompress_fwd / _inv: tonescale J (through Y), then chroma compression of M.
Vec3 tonemap_and_compress_fwd(const Vec3& jmh, const Params& p, const Tables& t);
Vec3 tonemap_and_compress_inv(const Vec3& jmh, const Params& p, const Tables& t);
// gamutMap_fwd / gamutMap_inv (compressGamut against the cusp, hull gammas and reach boundary).
Vec3 gamut_map_fwd(const Vec3& jmh, const Params& p, const Tables& t, const Behaviour& b = {});
Vec3 gamut_map_inv(const Vec3& jmh, const Params& p, const Tables& t, const Behaviour& b = {});
// JMh_to_output_XYZ / XYZ_output_to_JMh (against the limiting white).
Vec3 jmh_to_output_xyz(const Vec3& jmh, const Params& p, const Behaviour& b = {});
Vec3 xyz_output_to_jmh(const Vec3& xyz, const Params& p, const Behaviour& b = {});

// outputTransform_fwd / outputTransform_inv: AP0 ↔ display XYZ (1.0 = 100 nits), no clamp.
Vec3 output_transform_fwd(const Vec3& aces, const Params& p, const Tables& t,
                          const Behaviour& b = {});
Vec3 output_transform_inv(const Vec3& xyz, const Params& p, const Tables& t,
                          const Behaviour& b = {});

// The limiting-primaries RGB of a display XYZ (what OCIO's fixed function returns):
// LIMIT_XYZ_TO_RGB · XYZ, and back.
Vec3 limit_rgb_from_xyz(const Vec3& xyz, const Params& p);
Vec3 xyz_from_limit_rgb(const Vec3& rgb, const Params& p);

// TonemapCommon.ush: ACESOutputTransform after the working-space → AP0 matrix: outputTransform_fwd,
// clamp_zero_to_peakLuminance (limiting RGB in [0, peak/100]), apply_white_scale when scale_white,
// then OUTPUT_XYZ_TO_RGB · XYZ · 100 — encoding-primaries RGB in nits.
Vec3 aces_output_transform_nits(const Vec3& aces, const Params& p, const Tables& t,
                                bool scale_white, const Behaviour& b = {});
// ACESInvOutputTransform (without the AP0 → working-space matrix): encoding nits → AP0.
Vec3 aces_inv_output_transform_nits(const Vec3& nits, const Params& p, const Tables& t,
                                    bool scale_white, const Behaviour& b = {});

}  // namespace hdrc::ref::aces2
