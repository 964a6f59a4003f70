// Procedural, deterministic input images, parameterised from case files.
//
// Values are scene-linear in the working colour space (sRGB / Rec.709 primaries, D65: UE's default
// working colour space), where 1.0 is 100 nits on the PQ shaper's scale (TonemapCommon.ush:
// LinearToNitsScale), except `pq_codes` (back-buffer signals) and `ui_overlay` and `ui_srgb_codes`
// (premultiplied sRGB-encoded UI). Every stimulus is defined for any width × height; its parameters
// have defaults, so `{"stimulus": "hue_sweep"}` is a complete input. docs/cases.md describes each
// one.
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/image.h"
#include "core/result.h"

namespace hdrc {

// Parameter values by name: a number is a one-element list; a choice is the index of the choice.
using StimulusParams = std::map<std::string, std::vector<double>>;

enum class ParamKind {
  kNumber,      // one number in [min, max]
  kInteger,     // one integer in [min, max]
  kNumberList,  // a non-empty array of numbers, each in [min, max]
  kChoice,      // one of `choices` (a string in JSON)
};

struct StimulusParam {
  std::string_view name;
  ParamKind kind;
  std::vector<double> default_value;
  double min_value, max_value;            // inclusive (numbers, integers, list elements)
  std::vector<std::string_view> choices;  // kChoice only
  std::string_view description;           // with units
};

struct StimulusInfo {
  std::string_view name;
  int default_width, default_height;
  std::string_view description;
  std::vector<StimulusParam> params;
};

const std::vector<StimulusInfo>& stimulus_table();
const StimulusInfo* find_stimulus(std::string_view name);
const StimulusParam* find_stimulus_param(const StimulusInfo& info, std::string_view name);
std::string stimulus_names();
std::string stimulus_param_names(const StimulusInfo& info);

// The parameter's value in `params`, or its default.
std::vector<double> stimulus_param(const StimulusInfo& info, const StimulusParams& params,
                                   std::string_view name);

// The image size a stimulus gets when a case gives none (pq_lattice: n² × n).
void stimulus_default_size(const StimulusInfo& info, const StimulusParams& params, int* width,
                           int* height);

// Checks that `params` are known, in range, and that width × height can hold the stimulus
// (pq_codes: every code needs 1024 pixels; ui_srgb_codes 256; pq_lattice: n³). The error names the
// parameter and the valid choices; the caller adds file and pointer.
Status check_stimulus(const StimulusInfo& info, const StimulusParams& params, int width,
                      int height);

// Builds the image; width/height <= 0 take the stimulus' default size.
Result<Image> make_stimulus(std::string_view name, int width, int height,
                            const StimulusParams& params = {});

// Published and derived data the stimuli use, exposed for tests.
namespace stimulus_data {
// ColorChecker 24 (classic, 2005 formulation) in 8-bit sRGB, patches 1-24 in chart order:
// D. Pascale, "RGB coordinates of the Macbeth ColorChecker", The BabelColor Company, 2006,
// Table 3 (sRGB, 8 bits, average of 30 charts measured under D50, adapted to D65 by Bradford).
struct ColorCheckerPatch {
  std::string_view name;
  int r, g, b;  // 8-bit sRGB-encoded
};
const std::vector<ColorCheckerPatch>& colorchecker24();
// IEC 61966-2-1 sRGB decoding (exact piecewise EOTF, 0.04045 threshold).
double srgb_decode(double encoded);
// Rec.709 luminance weights (ITU-R BT.709-6 item 3.2, derived from its primaries and D65).
double rec709_luminance(double r, double g, double b);
}  // namespace stimulus_data

}  // namespace hdrc
