// The GLSL port of UE 5.5's user-LUT blend (gpu/shaders/lib/ue_lut_blend.glsl) against the
// double reference (reference/ue/ue_lut_blend.cpp) on the GPU engine, through the user-LUT binding
// (kBindingUserLut: a 16-point LUT's strip is 256 × 16, UE's layout): the lookup alone and the
// blend at BLENDCOUNT 2 (intensity 0.5 and 1), with 8-bit texels (UE's BGRA8 storage, quantised
// on the host for both engines) from the 16-point .cube files of cases/lut/cube/.
// Planted defects (issue 16): red and blue swapped in the lookup, a half-texel offset in the
// slice coordinate, and the neutral weight dropped must each exceed the measured bound.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <utility>

#include "core/cube/cube.h"
#include "gpu/device_bounds_test.h"
#include "gpu/shader_probe.h"
#include "reference/ue/ue_lut_blend.h"

namespace {

using hdrc::Image;
using hdrc::ref::UeLutTexture;
using hdrc::ref::Vec3;

const std::string kRoot = HDRC_SOURCE_DIR;

std::string read_text(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
  return s;
}

// The library inlined into the probe (its includes re-rooted at lib/), after `edit` (a planted
// defect, or none).
std::string library(const std::function<std::string(std::string)>& edit) {
  std::string lib = read_text(kRoot + "/gpu/shaders/lib/ue_lut_blend.glsl");
  const std::string edited = edit(lib);
  return replace_all(edited, "#include \"", "#include \"../lib/");
}

// in_px[i] = (F, w1): out_px[i].rgb = the lookup of F as UVW (mode 0) or the blend of F with
// weights (1 − w1, w1) (mode 1).
std::string probe(const std::string& lib, int mode) {
  std::string s = hdrc::gpu::testing::probe_preamble() + lib;
  s += "void main() {\n  uint i = gl_GlobalInvocationID.x;\n"
       "  if (i >= uint(P.width * P.height)) return;\n  vec4 x = in_px[i];\n";
  s += mode == 0
           ? "  out_px[i] = vec4(ue_unwrapped_texture3d_sample(user_lut[0], x.rgb), 0.0);\n"
           : "  out_px[i] = vec4(ue_lut_blend_one(x.rgb, 1.0 - x.a, x.a, user_lut[0]), 0.0);\n";
  s += "}\n";
  return s;
}

struct Lut {
  UeLutTexture ref;
  Image strip;  // the same 8-bit texels, as the engine binds them
};

Lut load(const char* file) {
  auto cube = hdrc::cube::read_cube_file(kRoot + "/cases/lut/cube/" + file);
  EXPECT_TRUE(cube.ok()) << file;
  Lut l;
  l.ref = hdrc::ref::ue_lut_texture(cube->table_3d, true);
  l.strip = Image(hdrc::ref::kUeUserLutWidth, hdrc::ref::kUeUserLutHeight);
  for (int y = 0; y < l.strip.height; ++y)
    for (int x = 0; x < l.strip.width; ++x) {
      double* px = l.strip.px(x, y);
      for (int c = 0; c < 3; ++c) px[c] = l.ref.at(x, y)[c];
      px[3] = 1.0;
    }
  return l;
}

// A 21³ grid of FilmColor over [−0.05, 1.15] (past saturate's range on both sides) with the
// weight in alpha; for the lookup probe, the same grid mapped into UVW's range.
Image grid(double w1) {
  constexpr int k = 21;
  Image img(k * k, k);
  for (int b = 0; b < k; ++b)
    for (int g = 0; g < k; ++g)
      for (int r = 0; r < k; ++r) {
        double* px = img.px(r + k * g, b);
        px[0] = -0.05 + 1.2 * r / (k - 1);
        px[1] = -0.05 + 1.2 * g / (k - 1);
        px[2] = -0.05 + 1.2 * b / (k - 1);
        px[3] = w1;
      }
  return img;
}

struct Measured {
  double lookup = 0, blend_half = 0, blend_one = 0;  // max |GPU − reference|
};

Measured measure(const std::function<std::string(std::string)>& edit, const Lut& lut) {
  Measured m;
  for (int mode = 0; mode < 3; ++mode) {
    const double w1 = mode == 2 ? 1.0 : 0.5;
    Image in = grid(w1);
    if (mode == 0)
      for (size_t i = 0; i < in.pixel_count(); ++i)
        for (int c = 0; c < 3; ++c) {
          double& v = in.data[i * 4 + c];
          v = std::fmin(std::fmax(v, 0.0), 1.0) * (15.0 / 16.0) + 0.5 / 16.0;
        }
    hdrc::ResolvedCase rc = hdrc::gpu::testing::make_case("shaper", 0, in);
    rc.user_luts[0] = lut.strip;
    rc.params.user_lut_size = hdrc::ref::kUeUserLutSize;
    rc.params.user_lut_domain_max = {1, 1, 1, 0};
    auto out = hdrc::gpu::testing::run_probe(probe(library(edit), mode == 0 ? 0 : 1), rc);
    EXPECT_TRUE(out.ok()) << (out.ok() ? "" : out.error().to_string());
    if (!out.ok()) return m;
    double worst = 0;
    for (size_t i = 0; i < in.pixel_count(); ++i) {
      const Vec3 x = {in.data[i * 4], in.data[i * 4 + 1], in.data[i * 4 + 2]};
      const Vec3 want = mode == 0
                            ? hdrc::ref::unwrapped_texture3d_sample(lut.ref, x)
                            : hdrc::ref::blend_user_luts(x, 2, {1.0 - w1, w1, 0, 0, 0}, {&lut.ref});
      for (int c = 0; c < 3; ++c) {
        const double e = std::fabs(out->data[i * 4 + c] - want[c]);
        worst = std::isnan(e) ? INFINITY : std::fmax(worst, e);
      }
    }
    (mode == 0 ? m.lookup : mode == 1 ? m.blend_half : m.blend_one) = worst;
  }
  return m;
}

// The bound (docs/ue55-lut-blend-spec.md §3.6, docs/precision.md "UE user-LUT blend"): the
// GPU's filter quantises the bilinear weights of red and green (lavapipe: 8 sub-texel bits, so
// half a weight step 2^-9 times the difference of two neighbouring texels along x or y; blue is
// lerped by the shader in float), plus float32 arithmetic (1e-6). The blend's sRGBToLinear has a
// slope of at most 2.4 / 1.055 · (1 / 1.055 + 0.0521327)^1.4 < 2.3 over [0, 1].
double lookup_bound(const UeLutTexture& t) {
  double step = 0;
  for (int y = 0; y < hdrc::ref::kUeUserLutHeight; ++y)
    for (int x = 0; x < hdrc::ref::kUeUserLutWidth; ++x)
      for (int c = 0; c < 3; ++c) {
        if (x % hdrc::ref::kUeUserLutSize != 15)
          step = std::fmax(step, std::fabs(t.at(x + 1, y)[c] - t.at(x, y)[c]));
        if (y != 15) step = std::fmax(step, std::fabs(t.at(x, y + 1)[c] - t.at(x, y)[c]));
      }
  // Elsewhere than on a float32-exact device the weight may be either grid value around the exact
  // one ("Texel Filtering": the rounding to subTexelPrecisionBits is not specified;
  // device_allowance .h linear_tap_box), a whole step 2^-bits on each of the two filtered axes.
  if (!hdrc::gpu::testing::exact_device())
    return 2.0 * step *
               hdrc::gpu::testing::weight_precision(
                   hdrc::gpu::testing::test_device().precision.sub_texel_bits) +
           1e-6;
  return step / 512.0 + 1e-6;
}
double blend_bound(const UeLutTexture& t) {
  return 2.3 * lookup_bound(t);
}

const char* const kLuts[] = {"ue16_identity.cube", "ue16_contrast.cube", "ue16_hue.cube",
                             "ue16_swap_rb.cube", "ue16_square.cube"};

TEST(UeLutBlendShader, MatchesReference) {
  for (const char* file : kLuts) {
    const Lut lut = load(file);
    const Measured m = measure([](std::string s) { return s; }, lut);
    std::printf("%s: lookup %.3g (bound %.3g), blend 0.5 %.3g, blend 1 %.3g (bound %.3g)\n", file,
                m.lookup, lookup_bound(lut.ref), m.blend_half, m.blend_one, blend_bound(lut.ref));
    EXPECT_LE(m.lookup, lookup_bound(lut.ref)) << file;
    EXPECT_LE(m.blend_half, blend_bound(lut.ref)) << file;
    EXPECT_LE(m.blend_one, blend_bound(lut.ref)) << file;
  }
}

std::string swap_red_blue(std::string s) {
  s = replace_all(s, "uvw.z", "uvw.QQ");
  s = replace_all(s, "uvw.x", "uvw.z");
  return replace_all(s, "uvw.QQ", "uvw.x");
}
std::string half_texel(std::string s) {
  return replace_all(s, "uvw.z * UE_USER_LUT_SIZE - 0.5", "uvw.z * UE_USER_LUT_SIZE");
}
std::string drop_neutral(std::string s) {
  return replace_all(s, "w0 * g + ", "");
}

TEST(UeLutBlendShader, PlantedDefectsFail) {
  const Lut hue = load("ue16_hue.cube");
  for (auto [name, edit] :
       {std::pair{"red/blue swapped", &swap_red_blue}, std::pair{"half-texel offset", &half_texel},
        std::pair{"neutral weight dropped", &drop_neutral}}) {
    ASSERT_NE((*edit)(read_text(kRoot + "/gpu/shaders/lib/ue_lut_blend.glsl")),
              read_text(kRoot + "/gpu/shaders/lib/ue_lut_blend.glsl"))
        << name << ": the edit no longer applies";
    const Measured m = measure(edit, hue);
    std::printf("%s: blend 0.5 off by %.3g\n", name, m.blend_half);
    EXPECT_GT(m.blend_half, 10 * blend_bound(hue.ref)) << name;
  }
}

}  // namespace
