#include "reference/color/ue_matrices.h"

#include <cmath>

namespace hdrc::ref {

namespace ue_literal {
// Engine/Shaders/Private/ACES.ush, the static const float3x3 literals at the top of the file, as
// UE 5.3.2 (Mephisto1024/Toon_Engine, Build.version 5.3.2) and UE 5.5.1 (lakeone/UE5.51MagicM,
// Build.version 5.5.1, commit 262077e8) write them: the two files are byte-identical. Every matrix
// has 10 decimals. UE 5.0 and earlier (chenyong2github/UnrealEngine 09c29cbe, the 4.x copies) wrote
// sRGB_2_XYZ_MAT, the Rec.2020 and P3-D65 pairs with 7 digits and the CATs with 6
// (docs/ue55-decisions.md "Colour matrix literals").
// AP0_2_XYZ_MAT
const Mat3 kAp0ToXyz{{0.9525523959, 0.0000000000, 0.0000936786,   //
                      0.3439664498, 0.7281660966, -0.0721325464,  //
                      0.0000000000, 0.0000000000, 1.0088251844}};
// XYZ_2_AP0_MAT
const Mat3 kXyzToAp0{{1.0498110175, 0.0000000000, -0.0000974845,  //
                      -0.4959030231, 1.3733130458, 0.0982400361,  //
                      0.0000000000, 0.0000000000, 0.9912520182}};
// AP1_2_XYZ_MAT
const Mat3 kAp1ToXyz{{0.6624541811, 0.1340042065, 0.1561876870,  //
                      0.2722287168, 0.6740817658, 0.0536895174,  //
                      -0.0055746495, 0.0040607335, 1.0103391003}};
// XYZ_2_AP1_MAT
const Mat3 kXyzToAp1{{1.6410233797, -0.3248032942, -0.2364246952,  //
                      -0.6636628587, 1.6153315917, 0.0167563477,   //
                      0.0117218943, -0.0082844420, 0.9883948585}};
// AP0_2_AP1_MAT (a literal, not computed in the shader)
const Mat3 kAp0ToAp1{{1.4514393161, -0.2365107469, -0.2149285693,  //
                      -0.0765537734, 1.1762296998, -0.0996759264,  //
                      0.0083161484, -0.0060324498, 0.9977163014}};
// AP1_2_AP0_MAT (a literal)
const Mat3 kAp1ToAp0{{0.6954522414, 0.1406786965, 0.1638690622,  //
                      0.0447945634, 0.8596711185, 0.0955343182,  //
                      -0.0055258826, 0.0040252103, 1.0015006723}};
// XYZ_2_sRGB_MAT (the same 10 digits since UE 4.x)
const Mat3 kXyzToSrgb{{3.2409699419, -1.5373831776, -0.4986107603,  //
                       -0.9692436363, 1.8759675015, 0.0415550574,   //
                       0.0556300797, -0.2039769589, 1.0569715142}};
// sRGB_2_XYZ_MAT (UE <= 5.0: 0.4124564, 0.3575761, ...)
const Mat3 kSrgbToXyz{{0.4123907993, 0.3575843394, 0.1804807884,  //
                       0.2126390059, 0.7151686788, 0.0721923154,  //
                       0.0193308187, 0.1191947798, 0.9505321522}};
// XYZ_2_Rec2020_MAT (UE <= 5.0: 1.7166084, -0.3556621, ...)
const Mat3 kXyzToRec2020{{1.7166511880, -0.3556707838, -0.2533662814,  //
                          -0.6666843518, 1.6164812366, 0.0157685458,   //
                          0.0176398574, -0.0427706133, 0.9421031212}};
// Rec2020_2_XYZ_MAT (UE <= 5.0: 0.6369736, 0.1446172, ...)
const Mat3 kRec2020ToXyz{{0.6369580483, 0.1446169036, 0.1688809752,  //
                          0.2627002120, 0.6779980715, 0.0593017165,  //
                          0.0000000000, 0.0280726930, 1.0609850577}};
// XYZ_2_P3D65_MAT (UE <= 5.0: 2.4933963, -0.9313459, ...)
const Mat3 kXyzToP3D65{{2.4934969119, -0.9313836179, -0.4027107845,  //
                        -0.8294889696, 1.7626640603, 0.0236246858,   //
                        0.0358458302, -0.0761723893, 0.9568845240}};
// P3D65_2_XYZ_MAT (UE <= 5.0: 0.4865906, 0.2656683, ...)
const Mat3 kP3D65ToXyz{{0.4865709486, 0.2656676932, 0.1982172852,  //
                        0.2289745641, 0.6917385218, 0.0792869141,  //
                        0.0000000000, 0.0451133819, 1.0439443689}};
// D65_2_D60_CAT, Bradford (UE <= 5.0: 1.01303, 0.00610531, ...)
const Mat3 kD65ToD60Cat{{1.0130349146, 0.0061052578, -0.0149709436,  //
                         0.0076982301, 0.9981633521, -0.0050320385,  //
                         -0.0028413174, 0.0046851567, 0.9245061375}};
// D60_2_D65_CAT, Bradford (UE <= 5.0: 0.987224, -0.00611327, ...)
const Mat3 kD60ToD65Cat{{0.9872240087, -0.0061132286, 0.0159532883,  //
                         -0.0075983718, 1.0018614847, 0.0053300358,  //
                         0.0030725771, -0.0050959615, 1.0816806031}};
// AP1_RGB2Y (row 1 of AP1_2_XYZ_MAT)
const Vec3 kAp1RgbToY{0.2722287168, 0.6740817658, 0.0536895174};
}  // namespace ue_literal

const char* output_gamut_name(int gamut) {
  switch (gamut) {
    case 0:
      return "sRGB_D65";
    case 1:
      return "DCIP3_D65";
    case 2:
      return "Rec2020_D65";
    case 3:
      return "ACES_D60";
    case 4:
      return "ACEScg_D60";
    default:
      return "unknown";
  }
}

Mat3 ap1_to_output_gamut(int gamut) {
  using namespace ue_literal;
  switch (gamut) {
    case 1:
      return kXyzToP3D65 * kD60ToD65Cat * kAp1ToXyz;
    case 2:
      return kXyzToRec2020 * kD60ToD65Cat * kAp1ToXyz;
    case 3:
      return kAp1ToAp0;
    case 4:
      return Mat3::identity();
    default:
      return kXyzToSrgb * kD60ToD65Cat * kAp1ToXyz;  // 0 and anything else
  }
}

namespace standard {
const Chromaticities kSrgb{0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290};
const Chromaticities kRec2020{0.708, 0.292, 0.170, 0.797, 0.131, 0.046, 0.3127, 0.3290};
const Chromaticities kP3D65{0.680, 0.320, 0.265, 0.690, 0.150, 0.060, 0.3127, 0.3290};
const Chromaticities kAp0{0.7347, 0.2653, 0.0, 1.0, 0.0001, -0.0770, 0.32168, 0.33767};
const Chromaticities kAp1{0.713, 0.293, 0.165, 0.830, 0.128, 0.044, 0.32168, 0.33767};
const Chromaticities kP3Dci{0.680, 0.320, 0.265, 0.690, 0.150, 0.060, 0.314, 0.351};

Mat3 rgb_to_xyz(const Chromaticities& c) {
  const Mat3 p{{c.rx, c.gx, c.bx,  //
                c.ry, c.gy, c.by,  //
                1 - c.rx - c.ry, 1 - c.gx - c.gy, 1 - c.bx - c.by}};
  const Vec3 w{c.wx / c.wy, 1.0, (1 - c.wx - c.wy) / c.wy};
  const Vec3 s = inverse(p) * w;
  return p * Mat3::diag(s);
}

Mat3 bradford(const Vec3& src, const Vec3& dst) {
  const Mat3 b{{0.8951, 0.2664, -0.1614, -0.7502, 1.7135, 0.0367, 0.0389, -0.0685, 1.0296}};
  const Vec3 cs = b * src, cd = b * dst;
  return inverse(b) * Mat3::diag({cd[0] / cs[0], cd[1] / cs[1], cd[2] / cs[2]}) * b;
}

Mat3 rgb_to_rgb(const Chromaticities& src, const Chromaticities& dst) {
  const Mat3 src_to_xyz = rgb_to_xyz(src);
  const Mat3 dst_to_xyz = rgb_to_xyz(dst);
  const Vec3 ws = src_to_xyz * Vec3{1, 1, 1};
  const Vec3 wd = dst_to_xyz * Vec3{1, 1, 1};
  // FVector3d::Equals(DstWhite, 1e-7): every component within the tolerance.
  const bool same_white = std::fabs(ws[0] - wd[0]) <= 1e-7 && std::fabs(ws[1] - wd[1]) <= 1e-7 &&
                          std::fabs(ws[2] - wd[2]) <= 1e-7;
  if (same_white) return inverse(dst_to_xyz) * src_to_xyz;
  return inverse(dst_to_xyz) * bradford(ws, wd) * src_to_xyz;
}
}  // namespace standard

const char* working_color_space_name(int preset) {
  switch (preset) {
    case 1:
      return "sRGB";
    case 2:
      return "Rec2020";
    case 3:
      return "ACESAP0";
    case 4:
      return "ACESAP1";
    case 5:
      return "P3DCI";
    case 6:
      return "P3D65";
    case 7:
      return "Custom";
    default:
      return nullptr;
  }
}

const Chromaticities* working_color_space_chromaticities(int preset) {
  switch (preset) {
    case 1:
      return &standard::kSrgb;
    case 2:
      return &standard::kRec2020;
    case 3:
      return &standard::kAp0;
    case 4:
      return &standard::kAp1;
    case 5:
      return &standard::kP3Dci;
    case 6:
      return &standard::kP3D65;
    default:
      return nullptr;
  }
}

namespace {
// SceneManagement.cpp: FDefaultWorkingColorSpaceUniformBuffer::Update and ColorSpace.cpp:
// FColorSpace / FColorSpaceTransform (docs/spec/ue55.md §2.3).
WorkingColorSpace build(const Chromaticities& c, bool is_srgb) {
  WorkingColorSpace w;
  w.chroma = c;
  const Mat3 to_xyz = standard::rgb_to_xyz(c);
  w.to_xyz = to_float(to_xyz);
  w.from_xyz = to_float(inverse(to_xyz));
  w.to_ap1 = to_float(standard::rgb_to_rgb(c, standard::kAp1));
  // Parameters.ToAP1.Inverse(): UE inverts the float matrix (FMatrix44f); the reference inverts
  // the same float entries in double and rounds once (docs/ue55-decisions.md).
  w.from_ap1 = to_float(inverse(w.to_ap1));
  w.to_ap0 = to_float(standard::rgb_to_rgb(c, standard::kAp0));
  w.is_srgb = is_srgb;
  return w;
}
}  // namespace

WorkingColorSpace make_working_color_space(const Chromaticities& c) {
  const auto& s = standard::kSrgb;
  auto near = [](double a, double b) { return std::fabs(a - b) <= 1e-7; };
  return build(c, near(c.rx, s.rx) && near(c.ry, s.ry) && near(c.gx, s.gx) && near(c.gy, s.gy) &&
                      near(c.bx, s.bx) && near(c.by, s.by) && near(c.wx, s.wx) && near(c.wy, s.wy));
}

WorkingColorSpace make_working_color_space(WorkingColorSpacePreset preset) {
  const int p = static_cast<int>(preset);
  const Chromaticities* c = working_color_space_chromaticities(p);
  if (!c) return build(standard::kSrgb, true);
  return build(*c, preset == WorkingColorSpacePreset::kSrgb);
}

std::string chromaticities_problem(const Chromaticities& c) {
  if (!(c.wy > 0.0)) return "the white's y must be above 0";
  for (double v : {c.rx, c.ry, c.gx, c.gy, c.bx, c.by, c.wx, c.wy})
    if (!std::isfinite(v)) return "every coordinate must be finite";
  // The primaries' xyz columns must be independent (|det| well above rounding) and the white
  // must be a positive mix of them (S = P^-1 W > 0), or RGB→XYZ is singular or flips a channel.
  const Mat3 p{{c.rx, c.gx, c.bx,  //
                c.ry, c.gy, c.by,  //
                1 - c.rx - c.ry, 1 - c.gx - c.gy, 1 - c.bx - c.by}};
  const double det = p(0, 0) * (p(1, 1) * p(2, 2) - p(1, 2) * p(2, 1)) -
                     p(0, 1) * (p(1, 0) * p(2, 2) - p(1, 2) * p(2, 0)) +
                     p(0, 2) * (p(1, 0) * p(2, 1) - p(1, 1) * p(2, 0));
  if (!(std::fabs(det) > 1e-6)) return "the three primaries are (nearly) collinear";
  const Vec3 s = inverse(p) * Vec3{c.wx / c.wy, 1.0, (1 - c.wx - c.wy) / c.wy};
  if (!(s[0] > 0.0 && s[1] > 0.0 && s[2] > 0.0))
    return "the white lies outside the triangle of the primaries";
  return "";
}

}  // namespace hdrc::ref
