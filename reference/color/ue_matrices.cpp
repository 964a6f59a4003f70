#include "reference/color/ue_matrices.h"

#include <cmath>

namespace hdrc::ref {

namespace ue_literal {
// Engine/Shaders/Private/ACES.ush (UE 5.0 copy, chenyong2github/UnrealEngine; unchanged literals in
// the 4.18, 4.27 and 5.8 copies) and TonemapCommon.ush, spec §2.1.
const Mat3 kAp0ToXyz{{0.9525523959, 0.0000000000, 0.0000936786,   //
                      0.3439664498, 0.7281660966, -0.0721325464,  //
                      0.0000000000, 0.0000000000, 1.0088251844}};
const Mat3 kXyzToAp0{{1.0498110175, 0.0000000000, -0.0000974845,  //
                      -0.4959030231, 1.3733130458, 0.0982400361,  //
                      0.0000000000, 0.0000000000, 0.9912520182}};
const Mat3 kAp1ToXyz{{0.6624541811, 0.1340042065, 0.1561876870,  //
                      0.2722287168, 0.6740817658, 0.0536895174,  //
                      -0.0055746495, 0.0040607335, 1.0103391003}};
const Mat3 kXyzToAp1{{1.6410233797, -0.3248032942, -0.2364246952,  //
                      -0.6636628587, 1.6153315917, 0.0167563477,   //
                      0.0117218943, -0.0082844420, 0.9883948585}};
const Mat3 kAp0ToAp1{{1.4514393161, -0.2365107469, -0.2149285693,  //
                      -0.0765537734, 1.1762296998, -0.0996759264,  //
                      0.0083161484, -0.0060324498, 0.9977163014}};
const Mat3 kAp1ToAp0{{0.6954522414, 0.1406786965, 0.1638690622,  //
                      0.0447945634, 0.8596711185, 0.0955343182,  //
                      -0.0055258826, 0.0040252103, 1.0015006723}};
const Mat3 kXyzToSrgb{{3.2409699419, -1.5373831776, -0.4986107603,  //
                       -0.9692436363, 1.8759675015, 0.0415550574,   //
                       0.0556300797, -0.2039769589, 1.0569715142}};
const Mat3 kSrgbToXyz{{0.4124564, 0.3575761, 0.1804375,  //
                       0.2126729, 0.7151522, 0.0721750,  //
                       0.0193339, 0.1191920, 0.9503041}};
const Mat3 kXyzToRec2020{{1.7166084, -0.3556621, -0.2533601,  //
                          -0.6666829, 1.6164776, 0.0157685,   //
                          0.0176422, -0.0427763, 0.94222867}};
const Mat3 kRec2020ToXyz{{0.6369736, 0.1446172, 0.1688585,  //
                          0.2627066, 0.6779996, 0.0592938,  //
                          0.0000000, 0.0280728, 1.0608437}};
const Mat3 kXyzToP3D65{{2.4933963, -0.9313459, -0.4026945,  //
                        -0.8294868, 1.7626597, 0.0236246,   //
                        0.0358507, -0.0761827, 0.9570140}};
const Mat3 kP3D65ToXyz{{0.4865906, 0.2656683, 0.1981905,  //
                        0.2289838, 0.6917402, 0.0792762,  //
                        0.0000000, 0.0451135, 1.0438031}};
const Mat3 kD65ToD60Cat{{1.01303, 0.00610531, -0.014971,     //
                         0.00769823, 0.998165, -0.00503203,  //
                         -0.00284131, 0.00468516, 0.924507}};
const Mat3 kD60ToD65Cat{{0.987224, -0.00611327, 0.0159533,  //
                         -0.00759836, 1.00186, 0.00533002,  //
                         0.00307257, -0.00509595, 1.08168}};
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
  const bool same_white = std::fabs(src.wx - dst.wx) < 1e-7 && std::fabs(src.wy - dst.wy) < 1e-7;
  if (same_white) return inverse(dst_to_xyz) * src_to_xyz;
  const Vec3 ws = src_to_xyz * Vec3{1, 1, 1};
  const Vec3 wd = dst_to_xyz * Vec3{1, 1, 1};
  return inverse(dst_to_xyz) * bradford(ws, wd) * src_to_xyz;
}
}  // namespace standard

WorkingColorSpace make_working_color_space(const Chromaticities& c) {
  // SceneManagement.cpp: FDefaultWorkingColorSpaceUniformBuffer::Update and
  // ColorSpace.cpp: FColorSpace / FColorSpaceTransform (spec §2.3).
  WorkingColorSpace w;
  w.chroma = c;
  const Mat3 to_xyz = standard::rgb_to_xyz(c);
  w.to_xyz = to_float(to_xyz);
  w.from_xyz = to_float(inverse(to_xyz));
  w.to_ap1 = to_float(standard::rgb_to_rgb(c, standard::kAp1));
  w.from_ap1 = to_float(inverse(w.to_ap1));
  w.to_ap0 = to_float(standard::rgb_to_rgb(c, standard::kAp0));
  const auto& s = standard::kSrgb;
  auto near = [](double a, double b) { return std::fabs(a - b) < 1e-7; };
  w.is_srgb = near(c.rx, s.rx) && near(c.ry, s.ry) && near(c.gx, s.gx) && near(c.gy, s.gy) &&
              near(c.bx, s.bx) && near(c.by, s.by) && near(c.wx, s.wx) && near(c.wy, s.wy);
  return w;
}

}  // namespace hdrc::ref
