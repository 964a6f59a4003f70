// A .cube table sampled on the GPU the two ways an engine does it (issue 16), against core/cube's
// analytic evaluation (hdrc::cube::apply, trilinear and tetrahedral) on the same table, on
// lavapipe:
//  1. a 3-D texture N×N×N (RGBA32F, texel (r, g, b) = row r + N g + N² b) through the volume
//     binding lut_3d (linear filtering, clamp-to-edge: UE's Texture3DSample of the CombineLUTs
//     volume) at UVW = t·(N − 1)/N + 0.5/N, and
//  2. the strip N² × N through the user-LUT binding user_lut with two bilinear taps and the slice
//     lerp, exactly as pipeline pq_grading samples it (pqg_sample_strip).
// The probe is a two-pass stage in a shader-directory copy, put in place of the tonemap stage's
// passes (the one stage of the engine whose first pass runs over LUT texels and whose second runs
// over pixels): pass 1 (stages/combine_luts.comp, one invocation per texel) copies the .cube's
// rows from the strip the engine uploaded (texelFetch: exact) into lut_store_3d, the volume the
// engine makes for P.lut_layout 0; pass 2 (stages/tonemap.comp) samples both. No engine change.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "core/cube/cube.h"
#include "gpu/device_bounds_test.h"
#include "gpu/shader_probe.h"
#include "reference/color/strip_device_range.h"
#include "reference/ue/combine_luts.h"

namespace {

using hdrc::Image;
using hdrc::ResolvedCase;
using hdrc::cube::CubeLut;
using hdrc::cube::Interp;
using Point = std::array<float, 3>;

// Pass 1: texel (r, g, b) of the volume := strip texel (r + N b, g), i.e. row r + N g + N² b.
const char* kStoreVolume = R"(
void main() {
  int n = P.lut_size;
  int i = int(gl_GlobalInvocationID.x);
  if (i >= n * n * n) return;
  ivec3 rgb = ivec3(i % n, (i / n) % n, i / (n * n));
  imageStore(lut_store_3d, rgb, texelFetch(user_lut[0], ivec2(rgb.r + n * rgb.b, rgb.g), 0));
}
)";

// Pass 2: input row 0 through the volume, row 1 (the same points) through the strip.
const char* kSample = R"(
#include "../lib/lut_sample.glsl"
#include "../pq_grading/lib/pq_grading.glsl"
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(P.width * P.height)) return;
  vec3 t = in_px[i].rgb;
  vec3 s = i < uint(P.width) ? sample_lut_volume(lut_uvw(t, float(P.lut_size)))
                             : pqg_sample_strip(t);
  out_px[i] = vec4(s, 0.0);
}
)";

// Inputs in [0, 1]³ (the table's domain, as a lookup sees it after its DOMAIN mapping): the grid of
// lattice points and cell centres (k/(2(N − 1)) per axis, the domain edges 0 and 1 included); the
// domain edges and their float neighbours; lattice points nudged by ±2^-20 (either side of a cell
// boundary); uniform random points. Deterministic: std::mt19937's sequence is fixed by the
// standard and floats are made from its bits.
std::vector<Point> sample_points(int n) {
  std::vector<Point> p;
  const int k = 2 * (n - 1);
  for (int b = 0; b <= k; ++b)
    for (int g = 0; g <= k; ++g)
      for (int r = 0; r <= k; ++r)
        p.push_back({float(r) / float(k), float(g) / float(k), float(b) / float(k)});
  const float edges[] = {0.0f, 0x1p-20f, std::nextafter(1.0f, 0.0f), 1.0f};
  for (float b : edges)
    for (float g : edges)
      for (float r : edges) p.push_back({r, g, b});
  std::mt19937 rng(16);
  auto unit = [&] { return static_cast<float>(rng() >> 8) * 0x1p-24f; };  // [0, 1)
  for (int j = 0; j < 2000; ++j) {
    Point q;
    for (float& v : q) {
      const float lattice = static_cast<float>(rng() % n) / static_cast<float>(n - 1);
      const float nudge = std::array<float, 3>{-0x1p-20f, 0.0f, 0x1p-20f}[rng() % 3];
      v = std::clamp(lattice + nudge, 0.0f, 1.0f);
    }
    p.push_back(q);
  }
  for (int j = 0; j < 20000; ++j) p.push_back({unit(), unit(), unit()});
  return p;
}

// How far a path's filter weights may be from the exact trilinear weights of its input, per axis
// (r, g, b), in units of one texel (a weight of 1).
struct PathModel {
  const char* name;
  std::array<double, 3> quantisation;  // the sampler's sub-texel weight precision
  std::array<double, 3> coordinate;    // float32 rounding of the texel coordinate
  // Per axis, true: a coordinate rounded past the lattice's edge reaches an unrelated texel.
  std::array<bool, 3> bleeds;
};

// The bound (per channel) on |path − trilinear| at lattice position x = t·(N − 1).
//
// Derivation. Trilinear interpolation in a cell is multilinear in the three weights. Change the
// weights one axis at a time, from the exact ones to those the path used: each change moves the
// result by |δ_a| times the difference of the cell's two faces across axis a, evaluated at weights
// in [0, 1] for the other axes — a convex combination of the cell's four edge differences along
// a, so at most S_a, the largest of them. Hence |Δ| ≤ Σ_a |δ_a| · S_a, exactly, with no second-
// order term. A path may put the point in the neighbouring cell when its coordinate is within δ_a
// of a cell boundary; trilinear interpolation is continuous there, so the same holds with S_a
// taken over every cell within the coordinate error (the box below).
//  * |δ_a| ≤ quantisation + coordinate rounding. The quantisation is the sub-texel precision of
//    the sampler's weights: D3D requires 8 bits (UE's platform; the bound
//    gpu/tonemap_shader_test.cpp asserts), and a weight quantised to 8 bits is within 2^-8 of the
//    exact one whether the hardware truncates or rounds. (Vulkan itself only guarantees
//    subTexelPrecisionBits ≥ 4; a device with fewer bits than D3D's fails this test, as it
//    would fail UE's.) The strip's slice lerp is shader arithmetic: no quantisation on b.
//  * Coordinate rounding, in texels: UVW = t·((N−1)/N) + 0.5/N in float32 is off by at most
//    four roundings of values ≤ 1 (≤ 4·2^-24), and the sampler's UVW·N − 0.5 adds one rounding of a
//    value ≤ N: ≤ N·2^-22 + N·2^-24 < N·2^-21 texels. The strip's red coordinate
//    (UVW.r + slice)/N is rounded at magnitude N and scaled by N² in the sampler: ≤ N²·2^-22.
//  * Where the coordinate error can carry a strip coordinate past the lattice's edge (red within
//    that error of 0 or N − 1: the neighbouring slice's texel; blue at the ends: the clamp at the
//    strip's ends; green is clamped within the strip), the texel reached is not a lattice
//    neighbour: that axis's rounding term is taken times the channel's whole range R instead of
//    S_a. (A volume coordinate past the edge is clamped to the edge texel: no such term.)
//  * Float32 arithmetic of the filter: at most 32 roundings of values ≤ M (the largest |texel| of
//    the cells): 7 lerps of 3 roundings each (or 8 weight products and 7 sums), plus the strip's
//    slice lerp: ≤ 32·2^-24·M = 2^-19·M.
std::array<double, 3> trilinear_bound(const CubeLut& lut, const std::array<double, 3>& x,
                                      const PathModel& m, const std::array<double, 3>& range) {
  const int n = lut.size_3d;
  std::array<int, 3> lo{}, hi{};
  std::array<bool, 3> at_edge{};
  for (int a = 0; a < 3; ++a) {
    const double e = m.coordinate[a];
    lo[a] = std::clamp(static_cast<int>(std::floor(x[a] - e)), 0, n - 2);
    hi[a] = std::clamp(static_cast<int>(std::floor(x[a] + e)), 0, n - 2);
    at_edge[a] = x[a] - e < 0.0 || x[a] + e > n - 1.0;
  }
  std::array<std::array<double, 3>, 3> step{};  // [axis][channel]
  std::array<double, 3> largest{};              // M per channel
  for (int b = lo[2]; b <= hi[2] + 1; ++b)
    for (int g = lo[1]; g <= hi[1] + 1; ++g)
      for (int r = lo[0]; r <= hi[0] + 1; ++r) {
        const auto& t = lut.at(r, g, b);
        const int next[3][3] = {{r + 1, g, b}, {r, g + 1, b}, {r, g, b + 1}};
        for (int c = 0; c < 3; ++c) {
          largest[c] = std::fmax(largest[c], std::fabs(t[c]));
          for (int a = 0; a < 3; ++a) {
            const int* q = next[a];
            if (q[a] > hi[a] + 1) continue;
            step[a][c] = std::fmax(step[a][c], std::fabs(lut.at(q[0], q[1], q[2])[c] - t[c]));
          }
        }
      }
  std::array<double, 3> bound{};
  for (int c = 0; c < 3; ++c) {
    double sum = std::ldexp(largest[c], -19);
    for (int a = 0; a < 3; ++a) {
      const double rounding_on = m.bleeds[a] && at_edge[a] ? range[c] : step[a][c];
      sum += m.quantisation[a] * step[a][c] + m.coordinate[a] * rounding_on;
    }
    bound[c] = sum;
  }
  return bound;
}

// The scale of sample_lut_device_range's output (combine_luts.h: "Output scaled by 1.05 as
// sample_lut's"; UE's LUT sample · 1.05).
constexpr double kLutScale = 1.05;

struct Measured {
  double vs_trilinear = 0, vs_tetrahedral = 0, ratio_to_bound = 0;
  double outside_range = 0;  // a device that is not float32-exact: the distance outside the range
  double vs_trilinear_inside = 0;         // at points whose strip coordinates cannot cross an edge
  long outside_bound_of_tetrahedral = 0;  // (point, channel)s where tetrahedral would fail
};

struct LutUnderTest {
  const char* file;
  // true: a per-channel function (or the identity), which both schemes interpolate identically
  // (each tetrahedron's weights add up, per axis, to the linear weights): no scheme to identify.
  bool separable;
};

// Every listed .cube, both GPU paths, at every sample point: within the derived bound of
// core/cube's trilinear; on the non-separable LUTs, outside that bound of tetrahedral somewhere
// (so the comparison identifies the scheme: a tetrahedral port fails it); and the two paths within
// the sum of their bounds of each other. The measured maxima are printed for docs/precision.md.
//
// On a device that is not float32-exact (device_bounds_test.h exact_device: a real GPU, the
// worst-case model) each path is judged by the range the suite's references give that lookup on
// such a device, not by the bound above: the 3-D texture by UE's volume lookup
// (combine_luts.h sample_lut_device_range over the .cube's texels, RGBA32F: the weight boxes of
// subTexelPrecisionBits, kShaderNoise of the coordinate, the filter's arithmetic in float32 as
// VK-GL-CTS verifies it), the strip by pq_grading's (strip_device_range.h
// strip_lookup_device_range, kFloat32Noise of the coordinate, as pq_grading.cpp
// grade_device_range). A value outside its range fails; tetrahedral values must still fall
// outside the volume's and the strip's ranges somewhere on the non-separable tables. The two
// paths' agreement with each other is then what their ranges imply, not checked on its own.
TEST(CubeSamplingShader, VolumeAndStripAreTrilinearWithinTheSamplersPrecision) {
  hdrc::gpu::testing::ShaderDirCopy dir("cube_sampling");
  const std::string preamble = hdrc::gpu::testing::probe_preamble();
  dir.write("stages/combine_luts.comp", preamble + kStoreVolume);
  dir.write("stages/tonemap.comp", preamble + kSample);
  const bool derived = !hdrc::gpu::testing::exact_device();
  const int bits = hdrc::gpu::testing::test_device().precision.sub_texel_bits;
  hdrc::gpu::VulkanOptions o = hdrc::gpu::testing::test_options();
  o.shader_dir = dir.path();
  hdrc::gpu::VulkanEngine gpu(o);
  ASSERT_TRUE(gpu.init().ok());

  const LutUnderTest luts[] = {{"identity_17.cube", true},
                               {"contrast_17.cube", true},
                               {"hue_rotate_17.cube", false},
                               {"pq_look_33.cube", false},
                               {"pq_hue_33.cube", false}};
  for (const LutUnderTest& l : luts) {
    SCOPED_TRACE(l.file);
    auto cube =
        hdrc::cube::read_cube_file(std::string(HDRC_SOURCE_DIR) + "/cases/lut/cube/" + l.file);
    ASSERT_TRUE(cube.ok()) << cube.error().to_string();
    ASSERT_EQ(cube->size_1d, 0);
    // The inputs are lattice coordinates t ∈ [0, 1]³, which core/cube maps from [0, 1] domains.
    ASSERT_EQ(cube->domain_min_3d, (hdrc::cube::Rgb{0.f, 0.f, 0.f}));
    ASSERT_EQ(cube->domain_max_3d, (hdrc::cube::Rgb{1.f, 1.f, 1.f}));
    const int n = cube->size_3d;

    const std::vector<Point> points = sample_points(n);
    const int count = static_cast<int>(points.size());
    Image in(count, 2);
    for (int p = 0; p < count; ++p)
      for (int y = 0; y < 2; ++y)
        for (int c = 0; c < 3; ++c) in.px(p, y)[c] = points[p][c];
    ResolvedCase rc = hdrc::gpu::testing::make_case("tonemap", 3, in);
    auto lut = std::make_shared<hdrc::UserLut>();
    lut->size = n;
    lut->table = cube->table_3d;
    rc.spec.lut = lut;
    rc.user_luts[0] = hdrc::user_lut_strip(*lut);
    rc.params.user_lut_size = n;
    for (int c = 0; c < 3; ++c) {
      rc.params.user_lut_domain_min[c] = 0.0;
      rc.params.user_lut_domain_max[c] = 1.0;
    }
    rc.params.lut_size = n;
    rc.params.lut_format = 2;  // RGBA32F: every float32 of the .cube reaches the sampler
    rc.params.lut_layout = 0;  // the volume: lut_store_3d / lut_3d
    auto got = gpu.run(rc);
    ASSERT_TRUE(got.ok()) << got.error().to_string();

    std::array<double, 3> range{};
    for (int c = 0; c < 3; ++c) {
      auto [lo, hi] = std::minmax_element(
          cube->table_3d.begin(), cube->table_3d.end(),
          [c](const hdrc::cube::Rgb& u, const hdrc::cube::Rgb& v) { return u[c] < v[c]; });
      range[c] = static_cast<double>((*hi)[c]) - (*lo)[c];
    }
    const double coord = n * 0x1p-21;
    const PathModel volume{
        "3-D texture", {0x1p-8, 0x1p-8, 0x1p-8}, {coord, coord, coord}, {false, false, false}};
    const PathModel strip{"strip",
                          {0x1p-8, 0x1p-8, 0.0},
                          {double(n) * n * 0x1p-22, coord, coord},
                          {true, false, true}};

    // The table as a device LUT whose texels are exactly the .cube's floats (the RGBA32F volume
    // and strip hold them): the ranges come from the sampling alone.
    hdrc::ref::BakedLut table;
    table.size = n;
    table.layout = 0;
    table.lut_format = 2;
    for (const hdrc::cube::Rgb& v : cube->table_3d) table.texels.push_back({v[0], v[1], v[2]});
    table = hdrc::gpu::testing::as_device_lut(std::move(table));
    const hdrc::ref::StripBounds strip_bounds{&rc.user_luts[0], &rc.user_luts[0], n};

    // The derived ranges cost about a millisecond a point (interval filters over every corner of
    // the weight boxes): there, a deterministic stride through the points, about kDerivedPoints of
    // them (each kind of point keeps its share).
    constexpr int kDerivedPoints = 5000;
    const int stride = derived ? std::max(1, (count + kDerivedPoints - 1) / kDerivedPoints) : 1;
    int judged = 0;
    Measured mv, ms;
    double volume_vs_strip = 0, scheme_gap = 0;
    int failures = 0;
    for (int p = 0; p < count; p += stride) {
      ++judged;
      const std::array<double, 3> t{points[p][0], points[p][1], points[p][2]};
      const auto tri = hdrc::cube::apply(*cube, t, Interp::trilinear);
      const auto tet = hdrc::cube::apply(*cube, t, Interp::tetrahedral);
      const std::array<double, 3> x{t[0] * (n - 1), t[1] * (n - 1), t[2] * (n - 1)};
      std::array<double, 3> bv{}, bs{};
      hdrc::ref::Range3 rv, rs;  // the derived ranges, the volume's scaled by kLutScale
      if (derived) {
        ASSERT_TRUE(hdrc::ref::sample_lut_device_range(table, {t[0], t[1], t[2]}, bits, &rv));
        rs = hdrc::ref::strip_lookup_device_range(
            strip_bounds, hdrc::ref::Range3::point({t[0], t[1], t[2]}), bits, hdrc::kFloat32Noise,
            hdrc::ref::FilterArithmetic::float32());
      } else {
        bv = trilinear_bound(*cube, x, volume, range);
        bs = trilinear_bound(*cube, x, strip, range);
      }
      bool inside = true;  // no strip coordinate within its rounding of the lattice's edge
      for (int a = 0; a < 3; ++a)
        inside = inside && (!strip.bleeds[a] ||
                            (x[a] >= strip.coordinate[a] && x[a] <= n - 1 - strip.coordinate[a]));
      for (int c = 0; c < 3; ++c) {
        scheme_gap = std::fmax(scheme_gap, std::fabs(tri[c] - tet[c]));
        const double v = got->px(p, 0)[c], s = got->px(p, 1)[c];
        for (auto [value, bound, m, path, r, scale] :
             {std::tuple{v, bv[c], &mv, &volume, &rv, kLutScale},
              std::tuple{s, bs[c], &ms, &strip, &rs, 1.0}}) {
          const double err = std::fabs(value - tri[c]);
          m->vs_trilinear = std::fmax(m->vs_trilinear, err);
          if (inside) m->vs_trilinear_inside = std::fmax(m->vs_trilinear_inside, err);
          m->vs_tetrahedral = std::fmax(m->vs_tetrahedral, std::fabs(value - tet[c]));
          if (derived) {
            // Scaling by kLutScale is monotone in double, so a value is inside the volume's
            // scaled range exactly where it is inside the unscaled one.
            const double out = hdrc::gpu::testing::outside(*r, c, value * scale) / scale;
            m->outside_range = std::fmax(m->outside_range, out);
            if (hdrc::gpu::testing::outside(*r, c, tet[c] * scale) > 0)
              ++m->outside_bound_of_tetrahedral;
            if (!(out == 0) && failures++ < 8)
              ADD_FAILURE() << path->name << " at t = (" << t[0] << ", " << t[1] << ", " << t[2]
                            << ") channel " << c << ": GPU " << value << ", trilinear " << tri[c]
                            << ", " << out << " outside the device range [" << r->lo[c] / scale
                            << ", " << r->hi[c] / scale << "] ("
                            << hdrc::gpu::testing::test_device().device << ", " << bits
                            << " sub-texel bits)";
            continue;
          }
          m->ratio_to_bound = std::fmax(m->ratio_to_bound, err / bound);
          if (!(std::fabs(value - tet[c]) <= bound)) ++m->outside_bound_of_tetrahedral;
          if (!(err <= bound) && failures++ < 8)
            ADD_FAILURE() << path->name << " at t = (" << t[0] << ", " << t[1] << ", " << t[2]
                          << ") channel " << c << ": GPU " << value << ", trilinear " << tri[c]
                          << ", |error| " << err << " > bound " << bound;
        }
        volume_vs_strip = std::fmax(volume_vs_strip, std::fabs(v - s));
        if (!derived && !(std::fabs(v - s) <= bv[c] + bs[c]) && failures++ < 8)
          ADD_FAILURE() << "3-D texture vs strip at t = (" << t[0] << ", " << t[1] << ", " << t[2]
                        << ") channel " << c << ": " << v << " vs " << s << ", bound "
                        << bv[c] + bs[c];
      }
    }
    if (l.separable) {
      // The label is checked: both schemes agree to double rounding on this table.
      EXPECT_LE(scheme_gap, 16 * DBL_EPSILON) << "not separable";
    } else {
      // Tetrahedral values fall outside the trilinear bound somewhere: the test tells them apart.
      EXPECT_GT(mv.outside_bound_of_tetrahedral, 0) << "3-D texture cannot tell the schemes apart";
      EXPECT_GT(ms.outside_bound_of_tetrahedral, 0) << "strip cannot tell the schemes apart";
    }
    for (const auto& [m, name] : {std::pair{&mv, "3-D texture"}, std::pair{&ms, "strip"}})
      std::printf(
          "%s, %d points, %s: max |GPU - trilinear| %.3g (%.3g of its bound; %.3g away from the "
          "strip's red and blue edges), |GPU - tetrahedral| %.3g (%ld channel values outside the "
          "trilinear %s of tetrahedral)%s\n",
          l.file, judged, name, m->vs_trilinear, m->ratio_to_bound, m->vs_trilinear_inside,
          m->vs_tetrahedral, m->outside_bound_of_tetrahedral, derived ? "device range" : "bound",
          derived ? (", max outside the device range " + std::to_string(m->outside_range)).c_str()
                  : "");
    std::printf("%s: max |3-D - strip| %.3g, max |trilinear - tetrahedral| (reference) %.3g\n",
                l.file, volume_vs_strip, scheme_gap);
    const std::string stem = std::string(l.file).substr(0, std::string(l.file).find('.'));
    RecordProperty(stem + "_volume_vs_trilinear", std::to_string(mv.vs_trilinear));
    RecordProperty(stem + "_strip_vs_trilinear", std::to_string(ms.vs_trilinear));
    RecordProperty(stem + "_volume_vs_strip", std::to_string(volume_vs_strip));
  }
}

}  // namespace
