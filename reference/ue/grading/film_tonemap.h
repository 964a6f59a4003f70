// The SDR "film" path of the CombineLUTs pass (docs/spec/ue55.md §4.8): blue correction, UE's
// FilmToneMap and the un-blue-correction, all in AP1.
//
// FilmToneMap: Engine/Shaders/Private/TonemapCommon.ush: FilmToneMap (izzy2lost/UnrealEngineUWP
// 5.5, commit aff11acf0c218535669021f6e646b3bcf6ad94a5), with the ACES RRT helpers of
// film_common.h. Blue correction: PostProcessCombineLUTs.usf: CombineLUTsCommon (Toon_Engine
// ~5.1/5.2 copy, commit 2dc09e8226da45ca87f8fcb812453ad02a75987b; docs/ue55-decisions.md D1).
#pragma once

#include "color/vec.h"
#include "reference/color/ue_matrices.h"
#include "reference/named_values.h"

namespace hdrc::ref::grading {

// FilmSlope/Toe/Shoulder/BlackClip/WhiteClip; defaults from Scene.cpp FPostProcessSettings
// (docs/spec/ue55.md §4.1). TonemapCommon.ush lists other presets in a comment (Uncharted, HP,
// Legacy, ACES).
struct FilmParams {
  double slope = 0.88;
  double toe = 0.55;
  double shoulder = 0.26;
  double black_clip = 0.0;
  double white_clip = 0.04;
};

// The curve's match points, in log10 of the (pre-desaturated) AP1 value. InMatch = OutMatch = 0.18.
//  ToeMatch: Toe > 0.8 ? (1 − Toe − 0.18)/Slope + log10(0.18)
//            : log10(0.18) − ½·ln((1 + bt)/(1 − bt))·ToeScale/Slope, bt = (0.18 + B)/ToeScale − 1
//  StraightMatch = (1 − Toe)/Slope − ToeMatch;  ShoulderMatch = Shoulder/Slope − StraightMatch.
struct FilmCurveMatch {
  double toe_scale, shoulder_scale;  // 1 + BlackClip − Toe, 1 + WhiteClip − Shoulder
  double toe_match, straight_match, shoulder_match;
};
FilmCurveMatch film_curve_match(const FilmParams& p);

// FilmToneMap step 5 for one channel: toe / straight / shoulder segments blended by smoothstep
// between ToeMatch and ShoulderMatch (the blend runs backwards when ShoulderMatch < ToeMatch, which
// the defaults do). Input: linear AP1 value w >= 0. w = 0 gives NaN, exactly as the shader:
// log10(0) = −∞ makes the straight segment −∞ and lerp(toe, −∞, 0) = NaN (0·∞); FilmToneMap's final
// max(0, ·) turns that into 0 on D3D (docs/spec/ue55.md §4.8 says "−BlackClip", which is not what
// the lerp computes).
double film_curve(double w, const FilmParams& p);

// TonemapCommon.ush: FilmToneMap — AP1 in, AP1 out (>= 0):
//  1. AP0 = (XYZ_2_AP0 · AP1_2_XYZ) · C   (literal product)
//  2. glow: AP0 ·= 1 + glow_fwd(rgb_2_yc(AP0), 0.05·sigmoid_shaper((sat − 0.4)/0.2), 0.08)
//  3. red modifier (UE's approximation of the ACES one, see red_modifier_hue_weight):
//     AP0.r += w(hue)·sat·(0.03 − AP0.r)·(1 − 0.82), sat = rgb_2_saturation before the glow
//  4. W = max(0, AP0_2_AP1_MAT · AP0); W = lerp(dot(W, AP1_RGB2Y), W, 0.96)
//  5. per channel film_curve
//  6. lerp(dot(T, AP1_RGB2Y), T, 0.93), then max(0, ·) (D3D maxNum: NaN → 0)
// NaN anywhere in the input makes every AP0 channel NaN; step 4's max turns them into 0, so the
// result is 0 (on D3D; GLSL max is undefined for NaN and a port must guard).
Vec3 film_tone_map(const Vec3& ap1, const FilmParams& p);

// FilmToneMap's named intermediate values, in the order of the steps above (the worked pixel of
// docs/spec/film_tonemap.md lists each one; reference/spec_worked_pixels_test.cpp compares them).
struct FilmToneMapTrace {
  FilmCurveMatch match;            // the curve's match points (parameters only)
  Vec3 ap0;                        // 1. (XYZ_2_AP0 · AP1_2_XYZ) · C
  double saturation, yc, sigmoid;  // 2. rgb_2_saturation, rgb_2_yc, sigmoid_shaper((sat−0.4)/0.2)
  double glow;                     //    1 + glow_fwd(yc, 0.05 · sigmoid, 0.08)
  Vec3 ap0_glow;                   //    AP0 · glow
  double hue, hue_weight;          // 3. rgb_2_hue of ap0_glow (degrees), red_modifier_hue_weight
  Vec3 ap0_red;                    //    after the red modifier
  Vec3 ap1_clamped, ap1_desat;     // 4. max(0, AP0_2_AP1 · ap0_red), lerp(luma, ·, 0.96)
  Vec3 log_color;                  // 5. log10 of ap1_desat
  Vec3 toe, straight, shoulder;    //    the three segments at log_color
  Vec3 blend;                      //    the smoothstep weight of shoulder_color
  Vec3 tone;                       //    lerp(toe_color, shoulder_color, blend)
  Vec3 post_desat;                 // 6. lerp(luma, tone, 0.93), before max(0, ·)
};
Vec3 film_tone_map(const Vec3& ap1, const FilmParams& p, FilmToneMapTrace* trace);
// The trace by the names of docs/spec/film_tonemap.md (toe_scale ... post_desat), marked `detail`
// when FilmToneMap is a step of another pipeline's pixel.
void film_named_values(const FilmToneMapTrace& t, bool detail, std::vector<NamedValue>* out);
// FilmToneMap's worked pixel: input, the trace, out.
std::vector<NamedValue> film_tone_map_named_values(const Vec3& ap1, const FilmParams& p);

// FilmToneMap's red-modifier hue weight: smoothstep(0, 1, 1 − |2·centered_hue/135|)², hue in
// degrees. ACES 1.3's RRT uses cubic_basis_shaper(centered_hue, 135) instead (see the tests).
double red_modifier_hue_weight(double hue_deg);

// Blue correction literals, applied in AP0 (PostProcessCombineLUTs.usf: BlueCorrect,
// BlueCorrectInv). BlueCorrectInv has only ~6 significant digits and is not the exact inverse.
extern const Mat3 kBlueCorrectAp0;
extern const Mat3 kBlueCorrectInvAp0;

// The AP1 forms the shader builds: (XYZ_2_AP1 · AP0_2_XYZ) · M · (XYZ_2_AP0 · AP1_2_XYZ), both
// conversions from the XYZ literals (not the AP0_2_AP1_MAT literal).
Mat3 blue_correct_ap1();
Mat3 blue_correct_inv_ap1();

// The film-path controls of FCombineLUTParameters (defaults: Scene.cpp FPostProcessSettings).
struct FilmPathParams {
  double blue_correction = 0.6;    // BlueCorrection
  double tone_curve_amount = 1.0;  // ToneCurveAmount
  FilmParams film;
};

// CombineLUTsCommon, AP1 → AP1:
//  C = lerp(C, BlueCorrectAP1·C, BlueCorrection); C = lerp(C, FilmToneMap(C), ToneCurveAmount);
//  C = lerp(C, BlueCorrectInvAP1·C, BlueCorrection).
// A NaN input stays NaN here even though FilmToneMap returns 0 for it (lerp(NaN, 0, 1) = NaN);
// film_color's max(0, ·) then gives 0.
Vec3 film_path_ap1(const Vec3& color_ap1, const FilmPathParams& p);

// FilmColor = max(0, WorkingColorSpace.FromAP1 · film_path_ap1(C)) — linear working colour space.
Vec3 film_color(const Vec3& color_ap1, const FilmPathParams& p, const WorkingColorSpace& wcs);

}  // namespace hdrc::ref::grading
