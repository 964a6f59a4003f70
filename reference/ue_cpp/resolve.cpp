#include "reference/ue_cpp/resolve.h"

#include <algorithm>

namespace hdrc::ref {

const Chromaticities& default_working_chromaticities() {
  return standard::kSrgb;
}

Result<ParamBlock> resolve_params(const Case& c, int width, int height) {
  ParamBlock p;
  p.width = width;
  p.height = height;
  // RenderCore.cpp: HDRGetMetaData clamps both enums to their ranges (spec §7.1); the case loader
  // has already rejected values outside them.
  p.output_device = std::clamp(c.cvars.get_int("r.HDR.Display.OutputDevice"), 0, 9);
  p.output_gamut = std::clamp(c.cvars.get_int("r.HDR.Display.ColorGamut"), 0, 4);
  const WorkingColorSpace wcs = make_working_color_space(default_working_chromaticities());
  p.wcs_to_ap1 = wcs.to_ap1;
  p.ap1_to_output = ap1_to_output_gamut(p.output_gamut);
  return p;
}

}  // namespace hdrc::ref
