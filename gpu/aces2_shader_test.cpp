// The GLSL ACES 2.0 output transform (gpu/shaders/lib/aces2_*.glsl, float32) against the
// double-precision reference (reference/ue/aces2/aces2.h), through a probe shader: the parameter
// block (ParamsT<float>, reference/ue/aces2 to_gpu) and the three tables (as float, as UE's R32F
// textures hold them) travel in the probe's input buffer behind the stimuli, and the probe defines
// the table reads UE does with Texture2D.Load. No pipeline, case or golden is involved.
//
// Stimuli: OpenColorIO 2.4.1's 35 inputs and a hue sweep of saturated ACEScg colours (HSV(h, 1, 1),
// h = 0…359°, exposures 0.18, 1, 16) forward; the 35 published outputs inverse. Errors use OCIO's
// criterion |gpu − ref| / max(|ref|, 1) on the limiting-primaries RGB (forward) or AP0 (inverse).
// Bounds: measured on lavapipe with a margin of about 2×, stated beside each.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "gpu/shader_probe.h"
#include "reference/ue/aces2/aces2.h"

namespace {

using hdrc::ref::Vec3;
namespace a2 = hdrc::ref::aces2;

// OpenColorIO v2.4.1 tests/cpu/ops/fixedfunction/FixedFunctionOpCPU_tests.cpp:413
// aces_output_transform_20: inputs (also in reference/ue/aces2/aces2_test.cpp).
constexpr std::array<Vec3, 35> kOcioInputs{{
    {2.781808965, 0.179178253, -0.022103530}, {3.344523751, 3.617862727, -0.006002689},
    {0.562714786, 3.438684474, 0.016100841},  {1.218191035, 3.820821747, 4.022103530},
    {0.655476249, 0.382137273, 4.006002689},  {3.437285214, 0.561315526, 3.983899159},
    {0.110000000, 0.020000000, 0.040000000},  {0.710000000, 0.510000000, 0.810000000},
    {0.430000000, 0.820000000, 0.710000000},  {0.118770000, 0.087090000, 0.058950000},
    {0.400020000, 0.319160000, 0.237360000},  {0.184760000, 0.203980000, 0.313110000},
    {0.109010000, 0.135110000, 0.064930000},  {0.266840000, 0.246040000, 0.409320000},
    {0.322830000, 0.462080000, 0.406060000},  {0.386050000, 0.227430000, 0.057770000},
    {0.138220000, 0.130370000, 0.337030000},  {0.302020000, 0.137520000, 0.127580000},
    {0.093100000, 0.063470000, 0.135250000},  {0.348760000, 0.436540000, 0.106130000},
    {0.486550000, 0.366850000, 0.080610000},  {0.087320000, 0.074430000, 0.272740000},
    {0.153660000, 0.256920000, 0.090710000},  {0.217420000, 0.070700000, 0.051300000},
    {0.589190000, 0.539430000, 0.091570000},  {0.309040000, 0.148180000, 0.274260000},
    {0.149010000, 0.233780000, 0.359390000},  {0.866530000, 0.867920000, 0.858180000},
    {0.573560000, 0.572560000, 0.571690000},  {0.353460000, 0.353370000, 0.353910000},
    {0.202530000, 0.202430000, 0.202870000},  {0.094670000, 0.095200000, 0.096370000},
    {0.037450000, 0.037660000, 0.038950000},  {0.180000000, 0.180000000, 0.180000000},
    {0.977840000, 0.977840000, 0.977840000},
}};

Vec3 f32(const Vec3& v) {
  return {static_cast<double>(static_cast<float>(v[0])),
          static_cast<double>(static_cast<float>(v[1])),
          static_cast<double>(static_cast<float>(v[2]))};
}

// The probe reads the parameter block and the tables from the input buffer behind the n stimuli
// (dynamically indexed constant arrays of this size are far too slow on llvmpipe): 19 vec4 of
// parameters, 90 of reach M, 362 cusp rows (J, M, h, 0), 91 of gamma (the last one padded).
constexpr int kParamVec4 = 19, kReachVec4 = 90, kCuspVec4 = 362, kGammaVec4 = 91;

std::vector<float> table_texels(const a2::Params& p, const a2::Tables& t) {
  const a2::Aces2ParamsGpu g = a2::to_gpu(p);
  const auto* gf = reinterpret_cast<const float*>(&g);
  std::vector<float> v(gf, gf + 76);
  for (double m : t.reach_m) v.push_back(static_cast<float>(m));
  for (const auto& row : t.gamut_cusp) {
    for (double c : row) v.push_back(static_cast<float>(c));
    v.push_back(0.0f);
  }
  for (double g2 : t.upper_hull_gamma) v.push_back(static_cast<float>(g2));
  v.resize(4 * (kParamVec4 + kReachVec4 + kCuspVec4 + kGammaVec4), 0.0f);
  return v;
}

// The probe: w = 0 → forward (limiting RGB); w = 1 → inverse from limiting RGB (AP0).
std::string probe_source(size_t n) {
  std::string s = hdrc::gpu::testing::probe_preamble();
  s += "#include \"lib/aces2_output.glsl\"\n";
  s += "const int kN = " + std::to_string(n) + ";\n";
  s += "const int kParam = kN, kReach = kParam + " + std::to_string(kParamVec4) +
       ", kCusp = kReach + " + std::to_string(kReachVec4) + ", kGamma = kCusp + " +
       std::to_string(kCuspVec4) + ";\n";
  s += R"(
float texel(int base, int i) { return in_px[base + i / 4][i % 4]; }
float aces2_reach_load(int i) { return (i >= 0 && i < 360) ? texel(kReach, i) : 0.0; }
float aces2_cusp_load(int c, int row) {
  return (row >= 0 && row < 362 && c >= 0 && c < 3) ? in_px[kCusp + row][c] : 0.0;
}
float aces2_gamma_load(int i) { return (i >= 0 && i < 362) ? texel(kGamma, i) : 0.0; }
void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= kN) return;
  float v76[76];
  for (int k = 0; k < 76; ++k) v76[k] = texel(kParam, k);
  Aces2Params p = aces2_unpack(v76);
  vec4 v = in_px[i];
  vec3 r = v.w == 0.0 ? aces2_limit_rgb_from_xyz(aces2_output_transform_fwd(v.xyz, p), p)
                      : aces2_output_transform_inv(aces2_xyz_from_limit_rgb(v.xyz, p), p);
  out_px[i] = vec4(r, v.w);
}
)";
  return s;
}

double ocio_error(const Vec3& got, const Vec3& want) {
  double e = 0;
  for (int c = 0; c < 3; ++c) {
    const double ce = std::fabs(got[c] - want[c]) / std::fmax(std::fabs(want[c]), 1.0);
    if (!(ce <= e)) e = ce;  // NaN propagates
  }
  return e;
}

TEST(Aces2Shader, MatchesReferenceOnOcioInputsAndHueSweep) {
  const a2::Params p = a2::make_params(1000.0, a2::kP3D65, a2::kP3D65);
  const a2::Tables t = a2::make_tables(p, a2::kP3D65);

  // Forward stimuli, then the inverse ones (the reference's own forward outputs, so the inverse is
  // compared where the reference round-trips).
  std::vector<Vec3> fwd(kOcioInputs.begin(), kOcioInputs.end());
  const hdrc::ref::Mat3 ap1_to_ap0 =
      hdrc::ref::inverse(a2::rgb_to_xyz(a2::kAp0)) * a2::rgb_to_xyz(a2::kAp1);
  for (const double exposure : {0.18, 1.0, 16.0}) {
    for (int h = 0; h < 360; ++h) {
      const double f = 1.0 - std::fabs(std::fmod(h / 60.0, 2.0) - 1.0);
      const Vec3 hsv[6] = {{1, f, 0}, {f, 1, 0}, {0, 1, f}, {0, f, 1}, {f, 0, 1}, {1, 0, f}};
      const Vec3& c = hsv[h / 60];
      fwd.push_back(ap1_to_ap0 * Vec3{c[0] * exposure, c[1] * exposure, c[2] * exposure});
    }
  }
  std::vector<Vec3> inv;
  for (const Vec3& in : kOcioInputs) {
    inv.push_back(a2::limit_rgb_from_xyz(a2::output_transform_fwd(f32(in), p, t), p));
  }

  const size_t n = fwd.size() + inv.size();
  const std::vector<float> texels = table_texels(p, t);
  hdrc::Image image(static_cast<int>(n + texels.size() / 4), 1);
  std::copy(texels.begin(), texels.end(), image.data.begin() + 4 * n);
  std::vector<Vec3> want;
  for (size_t k = 0; k < fwd.size() + inv.size(); ++k) {
    const bool forward = k < fwd.size();
    const Vec3 in = f32(forward ? fwd[k] : inv[k - fwd.size()]);
    for (int c = 0; c < 3; ++c) image.data[k * 4 + c] = static_cast<float>(in[c]);
    image.data[k * 4 + 3] = forward ? 0.0f : 1.0f;
    want.push_back(forward ? a2::limit_rgb_from_xyz(a2::output_transform_fwd(in, p, t), p)
                           : a2::output_transform_inv(a2::xyz_from_limit_rgb(in, p), p, t));
  }
  auto out = hdrc::gpu::testing::run_probe(
      probe_source(n), hdrc::gpu::testing::make_case("shaper", 3, std::move(image)));
  ASSERT_TRUE(out.ok()) << out.error().to_string();

  double worst_fwd = 0, worst_inv = 0;
  size_t at_fwd = 0, at_inv = 0;
  for (size_t k = 0; k < want.size(); ++k) {
    const Vec3 got{out->data[k * 4], out->data[k * 4 + 1], out->data[k * 4 + 2]};
    const double e = ocio_error(got, want[k]);
    double& worst = k < fwd.size() ? worst_fwd : worst_inv;
    size_t& at = k < fwd.size() ? at_fwd : at_inv;
    if (!(e <= worst)) {
      worst = e;
      at = k;
    }
  }
  std::printf(
      "GLSL vs reference (OCIO criterion): forward worst %.3g at stimulus %zu (of %zu), "
      "inverse worst %.3g at stimulus %zu\n",
      worst_fwd, at_fwd, fwd.size(), worst_inv, at_inv);
  // Measured on lavapipe (llvmpipe): forward 3.15e-5 (ACEScg hue 108° at exposure 16, through the
  // gamut compressor), inverse 1.45e-5; bounds about 2×.
  EXPECT_LE(worst_fwd, 6e-5);
  EXPECT_LE(worst_inv, 3e-5);
}

}  // namespace
