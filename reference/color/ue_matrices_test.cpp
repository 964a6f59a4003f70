// UE's literal matrices vs matrices derived from primaries, and the products docs/spec/ue55.md §2
// prints.
#include "reference/color/ue_matrices.h"

#include <gtest/gtest.h>

#include <cmath>
#include <tuple>

namespace {

using hdrc::ref::Mat3;
using hdrc::ref::Vec3;
namespace lit = hdrc::ref::ue_literal;
namespace std_ = hdrc::ref::standard;
using hdrc::ref::max_abs_diff;

void expect_matrix(const Mat3& got, const Mat3& want, double tol) {
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(got.m[i], want.m[i], tol) << "entry " << i;
}

// Standard RGB→XYZ from primaries against published matrices (IEC 61966-2-1 with 4-digit
// primaries gives 0.4124, 0.3576, 0.1805 / 0.2126, 0.7152, 0.0722 / 0.0193, 0.1192, 0.9505).
TEST(UeMatrices, DerivedSrgbMatchesPublished) {
  const Mat3 m = std_::rgb_to_xyz(std_::kSrgb);
  expect_matrix(m, Mat3{{0.4124, 0.3576, 0.1805, 0.2126, 0.7152, 0.0722, 0.0193, 0.1192, 0.9505}},
                1e-4);
  // Spec §2.3 ToXYZ, computed from the same chromaticities.
  expect_matrix(m,
                Mat3{{0.4123907993, 0.3575843394, 0.1804807884, 0.2126390059, 0.7151686788,
                      0.0721923154, 0.0193308187, 0.1191947798, 0.9505321522}},
                1e-9);
}

// UE >= 5.3 writes every ACES.ush matrix as the one derived from the standards' chromaticities,
// rounded to 10 decimals: the gap to our derivation is the rounding (measured <= 5e-11).
TEST(UeMatrices, LiteralsAgreeWithDerivedToTheirPrecision) {
  EXPECT_LT(max_abs_diff(lit::kAp1ToXyz, std_::rgb_to_xyz(std_::kAp1)), 1e-9);
  EXPECT_LT(max_abs_diff(lit::kAp0ToXyz, std_::rgb_to_xyz(std_::kAp0)), 1e-9);
  for (const auto& [to_xyz, from_xyz, chroma] :
       {std::tuple{lit::kSrgbToXyz, lit::kXyzToSrgb, std_::kSrgb},
        std::tuple{lit::kRec2020ToXyz, lit::kXyzToRec2020, std_::kRec2020},
        std::tuple{lit::kP3D65ToXyz, lit::kXyzToP3D65, std_::kP3D65},
        std::tuple{lit::kAp1ToXyz, lit::kXyzToAp1, std_::kAp1}}) {
    EXPECT_LT(max_abs_diff(to_xyz, std_::rgb_to_xyz(chroma)), 1e-10);
    EXPECT_LT(max_abs_diff(from_xyz, hdrc::ref::inverse(std_::rgb_to_xyz(chroma))), 1e-10);
  }
  // The CATs are Bradford between the D60 and D65 whites of the chromaticities.
  const Vec3 d60 = std_::rgb_to_xyz(std_::kAp1) * Vec3{1, 1, 1};
  const Vec3 d65 = std_::rgb_to_xyz(std_::kSrgb) * Vec3{1, 1, 1};
  EXPECT_LT(max_abs_diff(lit::kD60ToD65Cat, std_::bradford(d60, d65)), 1e-10);
  EXPECT_LT(max_abs_diff(lit::kD65ToD60Cat, std_::bradford(d65, d60)), 1e-10);
}

// The 1.41e-4 the reference used to carry between UE's Rec.2020/P3 literals and the
// primaries-derived matrices came from the pre-5.3 literals (UE 5.0 ACES.ush, chenyong2github
// 09c29cbe, written here as data): they were derived with the D65 white (0.312713, 0.329016), not
// the standards' (0.3127, 0.3290), and rounded to 7 digits. UE 5.3.2 and 5.5.1 replaced them.
TEST(UeMatrices, PreUe53LiteralsUsedAnotherD65) {
  const Mat3 rec2020_ue50{{0.6369736, 0.1446172, 0.1688585, 0.2627066, 0.6779996, 0.0592938, 0.0,
                           0.0280728, 1.0608437}};
  const Mat3 p3d65_ue50{{0.4865906, 0.2656683, 0.1981905, 0.2289838, 0.6917402, 0.0792762, 0.0,
                         0.0451135, 1.0438031}};
  auto with_white = [](hdrc::ref::Chromaticities c, double wx, double wy) {
    c.wx = wx;
    c.wy = wy;
    return std_::rgb_to_xyz(c);
  };
  for (const auto& [old, chroma] :
       {std::pair{rec2020_ue50, std_::kRec2020}, std::pair{p3d65_ue50, std_::kP3D65}}) {
    const double gap_standard_white = max_abs_diff(old, std_::rgb_to_xyz(chroma));
    EXPECT_GT(gap_standard_white, 1.40e-4);  // the unexplained 1.41e-4
    EXPECT_LT(gap_standard_white, 1.42e-4);
    EXPECT_LT(max_abs_diff(old, with_white(chroma, 0.312713, 0.329016)), 2e-7);  // 7-digit rounding
  }
}

// OuputGamutMappingMatrix products of the 5.3+/5.5 literals, evaluated to 10 decimals outside the
// project (Python, plain double arithmetic from the ACES.ush digits). Spec §2.1 printed products of
// the pre-5.3 literals (erratum in docs/ue55-decisions.md).
TEST(UeMatrices, OutputGamutProductsOfUe55Literals) {
  expect_matrix(hdrc::ref::ap1_to_output_gamut(0),
                Mat3{{1.7050509926, -0.6217921205, -0.0832588722, -0.1302564175, 1.1408047365,
                      -0.0105483190, -0.0240033568, -0.1289689761, 1.1529723328}},
                1e-9);
  expect_matrix(hdrc::ref::ap1_to_output_gamut(1),
                Mat3{{1.3792141282, -0.3088641445, -0.0703499838, -0.0693348584, 1.0822967459,
                      -0.0129618876, -0.0021590095, -0.0454593249, 1.0476183344}},
                1e-9);
  expect_matrix(hdrc::ref::ap1_to_output_gamut(2),
                Mat3{{1.0258247477, -0.0200531908, -0.0057715569, -0.0022343695, 1.0045865018,
                      -0.0023521324, -0.0050133515, -0.0252900719, 1.0303034233}},
                1e-9);
  expect_matrix(hdrc::ref::ap1_to_output_gamut(3), lit::kAp1ToAp0, 0);
  expect_matrix(hdrc::ref::ap1_to_output_gamut(4), Mat3::identity(), 0);
}

// With the 10-digit CATs an AP1 grey stays grey in every output gamut (row sums 1 within 2e-10);
// the 6-digit CATs of UE <= 5.0 drifted by up to 1.3e-4 (docs/spec/ue55.md §2.1's numerical note,
// now an erratum).
TEST(UeMatrices, NoGreyDriftWithUe55Literals) {
  for (int gamut = 0; gamut <= 2; ++gamut) {
    const Vec3 grey = hdrc::ref::ap1_to_output_gamut(gamut) * Vec3{1, 1, 1};
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(grey[k], 1.0, 2e-10) << "gamut " << gamut;
  }
  // AP1 -> sRGB of the literals is the working colour space's FromAP1 (docs/spec/ue55.md §2.3), to
  // the literals' 10 digits, and to the float cast of FromAP1.
  EXPECT_LT(max_abs_diff(hdrc::ref::ap1_to_output_gamut(0),
                         hdrc::ref::inverse(std_::rgb_to_rgb(std_::kSrgb, std_::kAp1))),
            1e-9);
  const auto wcs = hdrc::ref::make_working_color_space(std_::kSrgb);
  EXPECT_LT(max_abs_diff(hdrc::ref::ap1_to_output_gamut(0), wcs.from_ap1), 2e-7);
}

// Working colour space as UE's CPU builds it (docs/spec/ue55.md §2.3).
TEST(UeMatrices, WorkingColorSpaceSrgb) {
  const auto wcs = hdrc::ref::make_working_color_space(std_::kSrgb);
  EXPECT_TRUE(wcs.is_srgb);
  expect_matrix(wcs.to_ap1,
                Mat3{{0.6130974024, 0.3395231462, 0.0473794514, 0.0701937225, 0.9163538791,
                      0.0134523985, 0.0206155929, 0.1095697729, 0.8698146342}},
                5e-8);  // float-rounded entries
  expect_matrix(wcs.from_ap1,
                Mat3{{1.7050509927, -0.6217921207, -0.0832588720, -0.1302564175, 1.1408047366,
                      -0.0105483191, -0.0240033568, -0.1289689761, 1.1529723329}},
                2e-7);
  expect_matrix(wcs.to_ap0,
                Mat3{{0.4396329819, 0.3829886982, 0.1773783199, 0.0897764430, 0.8134394287,
                      0.0967841283, 0.0175411704, 0.1115465533, 0.8709122763}},
                5e-8);
  for (int i = 0; i < 9; ++i) {  // every entry is exactly a float
    EXPECT_EQ(wcs.to_ap1.m[i], static_cast<double>(static_cast<float>(wcs.to_ap1.m[i])));
    EXPECT_EQ(wcs.from_ap1.m[i], static_cast<double>(static_cast<float>(wcs.from_ap1.m[i])));
  }
  EXPECT_FALSE(hdrc::ref::make_working_color_space(std_::kRec2020).is_srgb);
}

// Every Working Color Space preset (RendererSettings.h: EWorkingColorSpace) against published
// normalised primary matrices and luma coefficients: ST 2065-1 (AP0), TB-2014-004 (AP1), SMPTE
// RP 431-2 (P3-DCI, 7 digits), ITU-R BT.2020 and SMPTE EG 432-1 (luminance rows, 4 digits),
// IEC 61966-2-1 (sRGB, 4 digits).
TEST(UeMatrices, WorkingColorSpacePresetsAgainstPublishedMatrices) {
  using P = hdrc::ref::WorkingColorSpacePreset;
  auto wcs = [](P p) { return hdrc::ref::make_working_color_space(p); };
  expect_matrix(wcs(P::kSrgb).to_xyz,
                Mat3{{0.4124, 0.3576, 0.1805, 0.2126, 0.7152, 0.0722, 0.0193, 0.1192, 0.9505}},
                6e-5);
  expect_matrix(wcs(P::kAcesAp0).to_xyz,
                Mat3{{0.9525523959, 0.0, 0.0000936786, 0.3439664498, 0.7281660966, -0.0721325464,
                      0.0, 0.0, 1.0088251844}},
                6e-8);  // float-cast entries
  expect_matrix(wcs(P::kAcesAp1).to_xyz,
                Mat3{{0.6624541811, 0.1340042065, 0.1561876870, 0.2722287168, 0.6740817658,
                      0.0536895174, -0.0055746495, 0.0040607335, 1.0103391003}},
                6e-8);
  expect_matrix(wcs(P::kP3Dci).to_xyz,
                Mat3{{0.4451698, 0.2771344, 0.1722827, 0.2094917, 0.7215953, 0.0689131, 0.0,
                      0.0470606, 0.9073554}},
                1e-7);
  const Vec3 rec2020_y{0.2627, 0.6780, 0.0593}, p3d65_y{0.2290, 0.6917, 0.0793};
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(wcs(P::kRec2020).to_xyz(1, k), rec2020_y[k], 5e-5);
    EXPECT_NEAR(wcs(P::kP3D65).to_xyz(1, k), p3d65_y[k], 5e-5);
  }
  // Only the sRGB preset is bIsSRGB; custom chromaticities equal to sRGB's are too (1e-7).
  for (int p = 1; p <= 6; ++p)
    EXPECT_EQ(wcs(static_cast<P>(p)).is_srgb, p == 1) << hdrc::ref::working_color_space_name(p);
  hdrc::ref::Chromaticities c = std_::kSrgb;
  EXPECT_TRUE(hdrc::ref::make_working_color_space(c).is_srgb);
  c.wx += 2e-7;
  EXPECT_FALSE(hdrc::ref::make_working_color_space(c).is_srgb);
  // Same-white presets take no CAT: ACEScg's ToAP1 is the identity, AP0's is the AP0_2_AP1_MAT
  // literal (float-cast).
  EXPECT_LT(max_abs_diff(wcs(P::kAcesAp1).to_ap1, Mat3::identity()), 1e-7);
  EXPECT_LT(max_abs_diff(wcs(P::kAcesAp0).to_ap1, lit::kAp0ToAp1), 2e-7);
  EXPECT_LT(max_abs_diff(wcs(P::kAcesAp0).to_ap0, Mat3::identity()), 1e-7);
}

// Degenerate custom chromaticities are named, not turned into NaN matrices.
TEST(UeMatrices, ChromaticitiesProblems) {
  EXPECT_EQ(hdrc::ref::chromaticities_problem(std_::kRec2020), "");
  hdrc::ref::Chromaticities c = std_::kSrgb;
  c.wy = 0;
  EXPECT_NE(hdrc::ref::chromaticities_problem(c).find("y must be above 0"), std::string::npos);
  c = std_::kSrgb;
  c.gx = 0.395, c.gy = 0.195;  // on the line from red to blue
  EXPECT_NE(hdrc::ref::chromaticities_problem(c).find("collinear"), std::string::npos);
  c = std_::kSrgb;
  c.wx = 0.7, c.wy = 0.29;  // outside the triangle
  EXPECT_NE(hdrc::ref::chromaticities_problem(c).find("outside"), std::string::npos);
}

TEST(UeMatrices, InverseRoundTrip) {
  const Mat3 p = lit::kXyzToRec2020 * lit::kD60ToD65Cat * lit::kAp1ToXyz;  // a literal product
  const Mat3 i = hdrc::ref::inverse(p) * p;
  EXPECT_LT(max_abs_diff(i, Mat3::identity()), 1e-14);
}

}  // namespace

#include <OpenColorIO/OpenColorIO.h>

namespace {

namespace OCIO = OCIO_NAMESPACE;

// OpenColorIO's built-in AP1 → linear Rec.709 (Bradford) as an independent oracle for the
// matrices derived here, and the size of the gap to UE's literal product (which a port must use).
TEST(UeMatrices, Ap1ToRec709AgainstOcioBuiltin) {
  auto bt = OCIO::BuiltinTransform::Create();
  bt->setStyle("UTILITY - ACES-AP1_to_LINEAR-REC709_BFD");
  auto cpu = OCIO::Config::CreateRaw()->getProcessor(bt)->getOptimizedCPUProcessor(
      OCIO::BIT_DEPTH_F32, OCIO::BIT_DEPTH_F32, OCIO::OPTIMIZATION_NONE);
  const Mat3 derived = std_::rgb_to_rgb(std_::kAp1, std_::kSrgb);
  const Mat3 ue = hdrc::ref::ap1_to_output_gamut(0);
  double gap_derived = 0, gap_ue = 0;
  for (int col = 0; col < 3; ++col) {
    float rgb[3] = {0, 0, 0};
    rgb[col] = 1.0f;
    cpu->applyRGB(rgb);
    for (int row = 0; row < 3; ++row) {
      gap_derived = std::fmax(gap_derived, std::fabs(rgb[row] - derived(row, col)));
      gap_ue = std::fmax(gap_ue, std::fabs(rgb[row] - ue(row, col)));
    }
  }
  RecordProperty("gap_derived", std::to_string(gap_derived));
  RecordProperty("gap_ue", std::to_string(gap_ue));
  EXPECT_LT(gap_derived, 2e-7);  // float32 evaluation in OCIO
  // UE 5.5's product of its 10-digit literals agrees with OCIO to OCIO's float32 evaluation (the
  // pre-5.3 6-digit CATs were measured 1.88e-6 away).
  EXPECT_LT(gap_ue, 2e-7);
}

}  // namespace

namespace {

// The working colour spaces' AP0/AP1 matrices against OpenColorIO's built-in Bradford transforms
// AP1 -> CIE XYZ (D65) and AP0 -> CIE XYZ (D65): for every D65 preset, ToXYZ · ToAP1^-1 and
// ToXYZ · ToAP0^-1 must be OCIO's matrices (columns read by applying OCIO to unit vectors).
Mat3 ocio_matrix(const char* style) {
  auto bt = OCIO::BuiltinTransform::Create();
  bt->setStyle(style);
  auto cpu = OCIO::Config::CreateRaw()->getProcessor(bt)->getOptimizedCPUProcessor(
      OCIO::BIT_DEPTH_F32, OCIO::BIT_DEPTH_F32, OCIO::OPTIMIZATION_NONE);
  Mat3 m = Mat3::identity();
  for (int col = 0; col < 3; ++col) {
    float rgb[3] = {0, 0, 0};
    rgb[col] = 1.0f;
    cpu->applyRGB(rgb);
    for (int row = 0; row < 3; ++row) m.m[row * 3 + col] = rgb[row];
  }
  return m;
}

TEST(UeMatrices, WorkingColorSpacePresetsAgainstOcioBuiltins) {
  using P = hdrc::ref::WorkingColorSpacePreset;
  const Mat3 ap1_to_xyz_d65 = ocio_matrix("UTILITY - ACES-AP1_to_CIE-XYZ-D65_BFD");
  const Mat3 ap0_to_xyz_d65 = ocio_matrix("UTILITY - ACES-AP0_to_CIE-XYZ-D65_BFD");
  double worst = 0;
  for (P p : {P::kSrgb, P::kRec2020, P::kP3D65}) {
    const auto w = hdrc::ref::make_working_color_space(p);
    const double gap1 = max_abs_diff(w.to_xyz * hdrc::ref::inverse(w.to_ap1), ap1_to_xyz_d65);
    const double gap0 = max_abs_diff(w.to_xyz * hdrc::ref::inverse(w.to_ap0), ap0_to_xyz_d65);
    EXPECT_LT(gap1, 5e-7) << hdrc::ref::working_color_space_name(static_cast<int>(p));
    EXPECT_LT(gap0, 5e-7) << hdrc::ref::working_color_space_name(static_cast<int>(p));
    worst = std::fmax(worst, std::fmax(gap0, gap1));
  }
  RecordProperty("worst_gap", std::to_string(worst));
  // The AP1 and AP0 presets are D60: their ToXYZ followed by OCIO's Bradford to D65 is ACES'
  // AP1 -> XYZ D65, i.e. ToAP1 must be the identity there (checked above) and the D60 → D65 CAT
  // the 10-digit literal.
  const auto ap1 = hdrc::ref::make_working_color_space(P::kAcesAp1);
  EXPECT_LT(max_abs_diff(lit::kD60ToD65Cat * ap1.to_xyz, ap1_to_xyz_d65), 5e-7);
}

}  // namespace
