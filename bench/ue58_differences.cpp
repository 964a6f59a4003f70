// ue58_differences: the effect of each UE 5.5 -> 5.8 difference of docs/ue58-differences.md,
// measured alone where the references allow it (bench/ue58_effects.h: two configurations of the
// colour path that differ in one behaviour, on ramps, the ColorChecker and saturated hues at high
// luminance; for the UI composite's rows U1-U5 two composites of back-buffer pixels and UI texels,
// ui_stimuli), and the rest computed from the formulas. Prints the markdown rows of
// docs/ue58-decisions.md F. A measurement, not a test (bench/ is not in the test command); the test
// bench/ue58_effects_test.cpp pins some of its numbers against hand computations.
//
// Usage: ue58_differences [ROW_PREFIX]   (e.g. "L7" for the shaper rows only, "U" for the UI)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "bench/ue58_effects.h"
#include "color/gamma_correction.h"
#include "color/st2084.h"
#include "core/shader_interface.h"
#include "reference/ue/ui/composite.h"

namespace {

using hdrc::ParamBlock;
using namespace hdrc::ue58fx;

struct Row {
  std::string id;
  std::string what;  // the configuration compared
  Config a;          // the 5.5 behaviour
  Config b;          // the 5.8 behaviour
  bool same_display = false;
  bool greys_only = false;
};

using KV = std::vector<std::pair<std::string, double>>;

Config u55(KV cvars, KV settings = {}) {
  Config c;
  c.ue55 = true;
  c.cvars = std::move(cvars);
  c.settings = std::move(settings);
  return c;
}
Config u58(KV cvars, KV settings = {}) {
  Config c;
  c.cvars = std::move(cvars);
  c.settings = std::move(settings);
  return c;
}
template <class F>
Config with(Config c, F tweak) {
  c.tweak = tweak;
  return c;
}
Config exact(Config c) {
  c.exact_inner = true;
  return c;
}

// An output device and gamut; the HDR devices with HDR output enabled (5.5's ACES 1.3 parameters
// come from HDRConfigureCVars only then).
KV dev(int device, int gamut = 0) {
  KV kv = {{"r.HDR.Display.OutputDevice", device}, {"r.HDR.Display.ColorGamut", gamut}};
  if (device >= 3 && device <= 6) kv.push_back({"r.HDR.EnableHDROutput", 1});
  return kv;
}
KV plus(KV a, const KV& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}
const KV kAces = {{"TonemappingMethod", 1}};

std::vector<Row> rows() {
  std::vector<Row> r;
  // Whole: 5.5 at its defaults against 5.8 at its defaults, device by device.
  const int gamut_of[10] = {0, 0, 0, 2, 2, 0, 0, 0, 0, 0};
  for (int d = 0; d <= 9; ++d)
    r.push_back({"all d" + std::to_string(d),
                 "device " + std::to_string(d) + (gamut_of[d] ? ", Rec.2020" : ", sRGB") +
                     ": 5.5 defaults vs 5.8 defaults (Filmic, ACES 2.0)",
                 u55(dev(d, gamut_of[d])), u58(dev(d, gamut_of[d]))});
  // L1: the method (a 5.8 option; 5.5 = Filmic for SDR).
  r.push_back({"L1 d0", "device 0: Filmic vs StandardACES (ACES 2.0 100 nits, BT.1886)",
               u58(dev(0)), u58(dev(0), kAces)});
  r.push_back({"L1 d3", "device 3 Rec.2020: Filmic (automatic HDR) vs StandardACES", u58(dev(3, 2)),
               u58(dev(3, 2), kAces)});
  // L2: the inner LUT (64^3 stored) vs the transform evaluated exactly.
  r.push_back({"L2 d3A", "device 3 Rec.2020 StandardACES: exact transform vs inner LUT 64^3",
               exact(u58(dev(3, 2), kAces)), u58(dev(3, 2), kAces)});
  r.push_back({"L2 d3F", "device 3 Rec.2020 Filmic: exact transforms vs inner LUT 64^3",
               exact(u58(dev(3, 2))), u58(dev(3, 2))});
  r.push_back({"L2 d0A", "device 0 StandardACES: exact transform vs inner LUT 64^3 (sRGB-coded)",
               exact(u58(dev(0), kAces)), u58(dev(0), kAces)});
  r.push_back({"L2 d5A", "device 5 StandardACES: exact transform vs inner LUT 64^3 (RGBA16F)",
               exact(u58(dev(5), kAces)), u58(dev(5), kAces)});
  // L3: ACES 1.3 vs 2.0 (StandardACES: both through the inner LUT).
  for (const auto& [d, g, extra, label] : std::vector<std::tuple<int, int, KV, std::string>>{
           {0, 0, {}, "device 0"},
           {1, 0, {}, "device 1"},
           {3, 2, {}, "device 3 Rec.2020"},
           {4, 2, {{"r.HDR.Display.MaxLuminance", 2000}}, "device 4 Rec.2020 2000 nits"},
           {5, 0, {}, "device 5 sRGB"},
           {9, 0, {}, "device 9"}}) {
    r.push_back({"L3 d" + std::to_string(d), label + " StandardACES: ACES 1.3 vs 2.0",
                 u58(plus(dev(d, g), extra), plus(kAces, {{"r.HDR.Aces.Version", 1}})),
                 u58(plus(dev(d, g), extra), kAces)});
  }
  // L4: automatic HDR. 5.5 device 3 (ACES 1.3 on the graded colour) vs 5.8 Filmic device 3 with
  // 5.5's PQ shaper and LUT scale put back (L7, L8), so only L4 (with its inner LUT, L2) differs.
  const auto as55 = [](ParamBlock& p) { p.ue58_lut_inv_max = static_cast<double>(1.f / 1.05f); };
  r.push_back({"L4 d3", "device 3 Rec.2020: 5.5 vs 5.8 Filmic, PQ shaper and /1.05 as 5.5",
               u55(dev(3, 2)), with(u58(dev(3, 2), {{"r.LUT.Shaper", 1}}), as55)});
  r.push_back({"L4 d3v1", "the same with r.HDR.Aces.Version 1 (the constant magenta inverse)",
               u55(dev(3, 2)),
               with(u58(dev(3, 2), {{"r.LUT.Shaper", 1}, {"r.HDR.Aces.Version", 1}}), as55)});
  // L6: paper white (a platform value; 203 at defaults is exactly 5.5's multiplier 1.5).
  for (const double pw : {80.0, 100.0, 300.0})
    r.push_back({"L6 " + std::to_string(static_cast<int>(pw)),
                 "device 3 Rec.2020 StandardACES: paper white 203 vs " +
                     std::to_string(static_cast<int>(pw)) + " nits",
                 u58(dev(3, 2), kAces), u58(dev(3, 2), plus(kAces, {{"r.HDR.PaperWhite", pw}}))});
  // L7: the shaper, PQ (5.5 for devices >= 3) vs log (5.8 default).
  r.push_back({"L7 d3F", "device 3 Rec.2020 Filmic: PQ vs log shaper",
               u58(dev(3, 2), {{"r.LUT.Shaper", 1}}), u58(dev(3, 2))});
  r.push_back({"L7 d3A", "device 3 Rec.2020 StandardACES: PQ vs log shaper",
               u58(dev(3, 2), plus(kAces, {{"r.LUT.Shaper", 1}})), u58(dev(3, 2), kAces)});
  r.push_back({"L7 d5F", "device 5 sRGB Filmic: PQ vs log shaper",
               u58(dev(5), {{"r.LUT.Shaper", 1}}), u58(dev(5))});
  r.push_back(
      {"L7 d7", "device 7: PQ vs log shaper", u58(dev(7), {{"r.LUT.Shaper", 1}}), u58(dev(7))});
  // The grey-ramp rows that bench/ue58_effects_test.cpp computes by hand (ExpandGamut 0: every
  // CombineLUTs step acts on each channel alone).
  Row greys7{"L7 d7 grey", "device 7, greys, ExpandGamut 0: PQ vs log shaper",
             u58(dev(7), {{"r.LUT.Shaper", 1}, {"ExpandGamut", 0}}),
             u58(dev(7), {{"ExpandGamut", 0}})};
  greys7.greys_only = true;
  r.push_back(greys7);
  // L8: LUTInvMax 1/1.05 (5.5) vs 1 (5.8) where 5.8 changed it.
  r.push_back({"L8 d3F", "device 3 Rec.2020 Filmic: LUT / 1.05 vs / 1", with(u58(dev(3, 2)), as55),
               u58(dev(3, 2))});
  r.push_back({"L8 d2", "device 2: LUT / 1.05 vs / 1 (5.8 stores no value above 1)",
               with(u58(dev(2)), as55), u58(dev(2))});
  r.push_back({"L8 d7", "device 7: LUT / 1.05 vs / 1", with(u58(dev(7)), as55), u58(dev(7))});
  Row greys8{"L8 d7 grey", "device 7, greys, ExpandGamut 0: LUT / 1.05 vs / 1",
             with(u58(dev(7), {{"ExpandGamut", 0}}), as55), u58(dev(7), {{"ExpandGamut", 0}})};
  greys8.greys_only = true;
  r.push_back(greys8);
  r.push_back({"L8 d0A", "device 0 StandardACES: LUT / 1.05 vs / 1", with(u58(dev(0), kAces), as55),
               u58(dev(0), kAces)});
  // L9: device 0's encode, sRGB OETF vs BT.1886, shown on the same (sRGB) display.
  Row l9{"L9 d0A", "device 0 StandardACES: sRGB vs BT.1886 encode, same sRGB display",
         u58(dev(0), plus(kAces, {{"r.LUT.TonemappingSDRInvEOTF", 0}})),
         u58(dev(0), plus(kAces, {{"r.LUT.TonemappingSDRInvEOTF", 1}}))};
  l9.same_display = true;
  r.push_back(l9);
  // L10: UE-29935's shortcut. 5.5 took it on device 0 for any output gamut; 5.8 only for sRGB.
  // 5.5's behaviour put back by making AP1_2_Output undo WorkingColorSpace.ToAP1.
  const auto shortcut = [](ParamBlock& p) { p.ap1_to_output = hdrc::ref::inverse(p.wcs_to_ap1); };
  Row l10{"L10 d0", "device 0, output gamut Rec.2020: 5.5's shortcut vs 5.8's conversion",
          with(u58(dev(0, 2)), shortcut), u58(dev(0, 2))};
  l10.same_display = true;
  r.push_back(l10);
  r.push_back({"L10 d1", "device 1, sRGB/sRGB: 5.8's shortcut vs the conversion",
               with(u58(dev(1)), [](ParamBlock& p) { p.wcs_is_srgb = 0; }), u58(dev(1))});
  // L11: device 9, 5.5 vs 5.8 with 5.5's PQ shaper put back: only InverseGamma.y differs.
  r.push_back({"L11 d9", "device 9: 5.5 vs 5.8 (PQ shaper as 5.5)", u55(dev(9)),
               u58(dev(9), {{"r.LUT.Shaper", 1}})});
  r.push_back({"L11 d9m", "the same with r.Color.Min -0.05",
               u55(plus(dev(9), {{"r.Color.Min", -0.05}})),
               u58(plus(dev(9), {{"r.Color.Min", -0.05}}), {{"r.LUT.Shaper", 1}})});
  // L12: the peak from the display's metadata (example: a 600-nit display named device 3).
  r.push_back({"L12 600", "device 3 Rec.2020 StandardACES: 1000 vs 600 nits peak",
               u58(dev(3, 2), kAces),
               u58(plus(dev(3, 2), {{"r.HDR.Display.MaxLuminance", 600}}), kAces)});
  // L14: 5.5's 2-D unwrapped LUT (gone in 5.8) vs the volume LUT.
  r.push_back({"L14 d0", "device 0 (5.5): 2-D unwrapped vs volume LUT",
               u55(dev(0), {{"LUTLayout", 1}}), u55(dev(0))});
  r.push_back({"L14 d3", "device 3 Rec.2020 (5.5): 2-D unwrapped vs volume LUT",
               u55(dev(3, 2), {{"LUTLayout", 1}}), u55(dev(3, 2))});
  return r;
}

// The UI composite's rows (docs/ue58-differences.md §1c): two composites of one back buffer and
// UI texel that differ in one behaviour, A the 5.5 one, B the 5.8 one (measure_ui).
struct UiRow {
  std::string id;
  std::string what;
  UiConfig a;
  UiConfig b;
  int device = 3;
  bool alpha0_colour = false;  // add the alpha-0 texels that hold a colour
  // Which stimuli: all, only fully transparent UI texels (0, 0, 0, 0), or only alpha-0 texels
  // holding a colour.
  enum class Only { kAll, kTransparent, kAlpha0Colour } only = Only::kAll;
};

UiConfig ui55(KV cvars, KV settings = {}) {
  UiConfig c;
  c.ue55 = true;
  c.cvars = std::move(cvars);
  c.settings = std::move(settings);
  return c;
}
UiConfig ui58(KV cvars, KV settings = {}) {
  UiConfig c;
  c.cvars = std::move(cvars);
  c.settings = std::move(settings);
  return c;
}

std::vector<UiRow> ui_rows() {
  std::vector<UiRow> r;
  const KV d3 = dev(3, 2), d5 = dev(5);
  // Every difference together: 5.5 at its defaults (UILuminance 300, sRGBToLinear with its
  // min-normal clamp, premultiplied composite) against 5.8 at its defaults.
  r.push_back({"U all d3", "device 3 Rec.2020: 5.5 defaults vs 5.8 defaults (U1-U5 and L16)",
               ui55(d3), ui58(d3)});
  r.push_back({"U all d5", "device 5 scRGB: 5.5 defaults vs 5.8 defaults (U1-U5 and L16)", ui55(d5),
               ui58(d5), 5});
  // 5.5's sRGBToLinear min-normal clamp (L16) in its composite: decode(0) = 4.72e-6, x 300 nits,
  // added under every texel whose colour is 0 (docs/ue55-decisions.md D3).
  UiConfig noclamp = ui55(d3);
  noclamp.tweak55 = [](hdrc::ref::ui::UiCompositeParams& p) {
    p.min_normal_clamp = hdrc::ref::MinNormalClamp::kOff;
  };
  r.push_back({"L16 ui", "device 3, 5.5's composite: sRGBToLinear with vs without the clamp",
               ui55(d3), noclamp});
  // U1: UILuminance 300 (5.5's r.HDR.UI.Luminance; in 5.8 r.HDR.UI.Luminance.Mode 1 with 300) vs
  // the paper white 203 (5.8's mode 0).
  const KV lum300 = {{"r.HDR.UI.Luminance.Mode", 1}};
  const KV cv300 = plus(d3, {{"r.HDR.UI.Luminance", 300}});
  r.push_back({"U1", "device 3, 5.8's composite: UILuminance 300 vs the paper white 203",
               ui58(cv300, lum300), ui58(d3)});
  // U2: the UI EOTF, sRGB (r.HDR.UI.CompositeEOTF 1: 5.8's sRGBToLinear, no clamp) vs gamma 2.4.
  r.push_back({"U2", "device 3, 5.8's composite at 203 nits: UI EOTF sRGB vs gamma 2.4",
               ui58(d3, {{"r.HDR.UI.CompositeEOTF", 1}}), ui58(d3)});
  r.push_back({"U1+U2", "device 3, 5.8's composite: (300 nits, sRGB) vs (203, gamma 2.4)",
               ui58(cv300, plus(lum300, {{"r.HDR.UI.CompositeEOTF", 1}})), ui58(d3)});
  // U3: translucent UI blended linearly (r.HDR.UI.CompositeBlend 1: 5.5's Reinhard, then
  // lerp(scene, UI, a)) vs in a gamma space (0, gamma 2.4).
  r.push_back({"U3",
               "device 3, 5.8's composite: linear blend (Reinhard, lerp) vs gamma-space blend",
               ui58(d3, {{"r.HDR.UI.CompositeBlend", 1}}), ui58(d3)});
  // U5: 5.5's composite of the premultiplied code vs 5.8's un-premultiplied one, everything else
  // the same: 5.5 at 300 nits with its sRGBToLinear's min-normal clamp taken off (5.8's, L16);
  // 5.8 at 300 nits (mode 1), sRGB EOTF, linear blend.
  UiConfig u5a = ui55(cv300);
  u5a.tweak55 = noclamp.tweak55;
  const UiConfig u5b =
      ui58(cv300, plus(lum300, {{"r.HDR.UI.CompositeEOTF", 1}, {"r.HDR.UI.CompositeBlend", 1}}));
  r.push_back({"U5",
               "device 3: 5.5's composite of the premultiplied code vs 5.8's un-premultiply "
               "(both 300 nits, sRGB without clamp, linear blend)",
               u5a, u5b});
  UiRow u5z{"U5 a0", "the same, UI texels of alpha 0 that hold a colour (5.5 adds it, 5.8 not)",
            u5a,     u5b,
            3,       true};
  u5z.only = UiRow::Only::kAlpha0Colour;
  r.push_back(u5z);
  // U4: the scRGB back buffer's decode and encode alone (transparent UI, 5.5's clamp off so that
  // its decode(0) adds nothing: L16): 80 nits either way.
  UiConfig u4a = ui55(d5);
  u4a.tweak55 = noclamp.tweak55;
  UiRow u4{"U4", "device 5 scRGB, transparent UI: 5.5 (clamp off) vs 5.8 defaults (80 nits)", u4a,
           ui58(d5), 5};
  u4.only = UiRow::Only::kTransparent;
  r.push_back(u4);
  return r;
}

void print_ui_rows(const char* prefix) {
  bool header = false;
  for (const UiRow& row : ui_rows()) {
    if (std::strncmp(row.id.c_str(), prefix, std::strlen(prefix)) != 0) continue;
    if (!header) {
      std::printf(
          "\nUI composite (back buffer x UI texel; A = 5.5 behaviour, B = 5.8):\n\n"
          "| # | Configuration | Unit | Max | p99 | ΔE_ITP max | Worst stimulus |\n"
          "|---|---|---|---|---|---|---|\n");
      header = true;
    }
    std::vector<UiStimulus> set;
    for (UiStimulus& s : ui_stimuli(row.device, row.alpha0_colour)) {
      const bool transparent = s.ui[3] == 0.0;
      const bool empty = transparent && s.ui[0] == 0.0 && s.ui[1] == 0.0 && s.ui[2] == 0.0;
      if (row.only == UiRow::Only::kTransparent && !empty) continue;
      if (row.only == UiRow::Only::kAlpha0Colour && (!transparent || empty)) continue;
      set.push_back(std::move(s));
    }
    const auto t0 = std::chrono::steady_clock::now();
    const Effect e = measure_ui(row.a, row.b, set);
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("| %s | %s | %s | %.3g | %.3g | %.3g | %s |\n", row.id.c_str(), row.what.c_str(),
                e.unit.c_str(), e.max, e.p99, e.de_itp, e.worst.c_str());
    std::fprintf(stderr, "%s: %.2f s, %zu values\n", row.id.c_str(), sec, e.values);
    std::fflush(stdout);
  }
}

// PQ code difference of two nit levels (10-bit, full range).
double pq_codes(double a, double b) {
  return std::fabs(pq_code(a) - pq_code(b));
}

// Effects from the formulas (docs/ue58-differences.md U1, U2, L16): the opaque UI's nits by hand,
// which the UI rows above measure through the composites.
void by_hand() {
  std::printf("\nFrom the formulas:\n");
  // U1: UI white 300 -> 203 nits (r.HDR.UI.Luminance 300 in 5.5; paper white 203 in 5.8).
  std::printf("U1 UI white 300 vs 203 nits: %.2f PQ codes (%.1f vs %.1f)\n", pq_codes(300, 203),
              pq_code(300), pq_code(203));
  // U1 + U2 on a UI value v (sRGB-coded): 5.5 300 * sRGB^-1(v), 5.8 203 * v^2.4.
  double u2max = 0, u2at = 0, u12max = 0, u12at = 0;
  for (int i = 0; i <= 1023; ++i) {
    const double v = i / 1023.0;
    const double srgb = hdrc::ref::srgb_to_linear(v, hdrc::ref::MinNormalClamp::kOff);
    const double d2 = pq_codes(203 * srgb, 203 * std::pow(v, 2.4));
    const double d12 = pq_codes(300 * srgb, 203 * std::pow(v, 2.4));
    if (d2 > u2max) u2max = d2, u2at = v;
    if (d12 > u12max) u12max = d12, u12at = v;
  }
  std::printf("U2 UI EOTF sRGB vs gamma 2.4 at 203 nits: max %.2f PQ codes at UI code %.0f\n",
              u2max, u2at * 1023);
  std::printf("U1+U2 5.5 UI (300, sRGB) vs 5.8 (203, 2.4): max %.2f PQ codes at UI code %.0f\n",
              u12max, u12at * 1023);
  // L16: 5.5's sRGBToLinear(max(6.10352e-5, x)) floor at x = 0.
  const double floor_lin = hdrc::ref::srgb_to_linear(0.0, hdrc::ref::MinNormalClamp::kOn);
  std::printf(
      "L16 sRGBToLinear(0): 5.5 %.4g (UI at 300 nits: %.4g nits = %.2f PQ codes; "
      "device 0 re-encode %.4g = %.3f codes)\n",
      floor_lin, 300 * floor_lin, pq_code(300 * floor_lin) - pq_code(0),
      hdrc::ref::linear_to_srgb(floor_lin), 1023 * hdrc::ref::linear_to_srgb(floor_lin));
}

}  // namespace

int main(int argc, char** argv) {
  const char* prefix = argc > 1 ? argv[1] : "";
  const auto all = stimuli();
  const auto greys = grey_ramp();
  std::printf(
      "| # | Configuration (A = 5.5 behaviour, B = 5.8) | Unit | Max | p99 | ΔE_ITP max | "
      "Worst stimulus |\n|---|---|---|---|---|---|---|\n");
  for (const Row& row : rows()) {
    if (std::strncmp(row.id.c_str(), prefix, std::strlen(prefix)) != 0) continue;
    const auto t0 = std::chrono::steady_clock::now();
    Path a(row.a), b(row.b);
    const Effect e = measure(a, b, row.greys_only ? greys : all, row.same_display);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!e.skipped.empty()) {
      std::printf("| %s | %s | — | degenerate: %s | | | |\n", row.id.c_str(), row.what.c_str(),
                  e.skipped.c_str());
      continue;
    }
    std::printf("| %s | %s | %s | %.3g | %.3g | %.3g | %s |\n", row.id.c_str(), row.what.c_str(),
                e.unit.c_str(), e.max, e.p99, e.de_itp, e.worst.c_str());
    std::fprintf(stderr, "%s: %.1f s, %zu values\n", row.id.c_str(), s, e.values);
    std::fflush(stdout);
  }
  print_ui_rows(prefix);
  if (!*prefix) by_hand();
  return 0;
}
