#include "reference/ue/ui/composite.h"

#include <cmath>
#include <string>

#include "color/d3d_math.h"
#include "color/st2084.h"
#include "reference/color/ue_matrices.h"

namespace hdrc::ref::ui {
namespace {

namespace lit = ue_literal;

Vec3 rgb(const Vec4& v) {
  return {v[0], v[1], v[2]};
}

Error param_error(const std::string& pointer, const std::string& message,
                  const std::string& choices = "") {
  return Error{"", pointer, message, choices};
}

}  // namespace

// Mode 0: the fixed-function premultiplied blend (BF_One, BF_InverseSourceAlpha for colour and
// alpha) into the back buffer. UNORM targets clamp blender inputs and the result to [0, 1].
Vec4 standard_blend(const Vec4& scene, const Vec4& ui, BackBufferEncoding encoding) {
  Vec4 out{};
  if (encoding == BackBufferEncoding::kPq) {
    const double a = d3d::saturate(ui[3]);
    for (int c = 0; c < 4; ++c) {
      out[c] = d3d::saturate(d3d::saturate(ui[c]) + (1.0 - a) * d3d::saturate(scene[c]));
    }
  } else {
    for (int c = 0; c < 4; ++c) out[c] = ui[c] + (1.0 - ui[3]) * scene[c];
  }
  return out;
}

Status validate(const UiCompositeParams& p) {
  if (!std::isfinite(p.ui_level)) {
    return param_error("r.HDR.UI.Level", "must be finite, got " + std::to_string(p.ui_level));
  }
  if (!std::isfinite(p.ui_luminance)) {
    return param_error("r.HDR.UI.Luminance",
                       "must be finite, got " + std::to_string(p.ui_luminance));
  }
  if (p.output_device < 0 || p.output_device > 9) {
    return param_error("output_device",
                       "EDisplayOutputFormat out of range: " + std::to_string(p.output_device),
                       "0..9");
  }
  const int type = static_cast<int>(p.cvd.type);
  if (type < 0 || type > 3) {
    return param_error("cvd.type", "unknown EColorVisionDeficiency " + std::to_string(type),
                       "0 NormalVision, 1 Deuteranope, 2 Protanope, 3 Tritanope");
  }
  if (p.cvd.severity < 0 || p.cvd.severity >= kCvdSeverityCount) {
    return param_error("cvd.severity", "out of range: " + std::to_string(p.cvd.severity), "0..10");
  }
  if (p.composite_mode == 0 && color_deficiency_active(p.cvd)) {
    return param_error("r.HDR.UI.CompositeMode",
                       "mode 0 with an active colour-vision deficiency is not modelled (Slate "
                       "applies it in its own post-process, not in the composite)");
  }
  return {};
}

BackBufferEncoding back_buffer_encoding(int output_device) {
  return output_device == 5 || output_device == 6 ? BackBufferEncoding::kScRgb
                                                  : BackBufferEncoding::kPq;
}

bool color_deficiency_active(const CvdSettings& cvd) {
  return cvd.type != CvdType::kNormalVision && cvd.severity > 0;
}

const Mat3& srgb_to_rec2020() {
  static const Mat3 m = lit::kXyzToRec2020 * lit::kSrgbToXyz;
  return m;
}

const Mat3& rec2020_to_srgb() {
  static const Mat3 m = lit::kXyzToSrgb * lit::kRec2020ToXyz;
  return m;
}

Vec3 linearize_ui_color(const Vec3& encoded, const UiCompositeParams& p) {
  return p.use_709 ? rec709_to_linear(encoded, p.min_normal_clamp)
                   : srgb_to_linear(encoded, p.min_normal_clamp);
}

Vec4 compute_hdr_ui_color(const Vec4& ui, const UiCompositeParams& p) {
  const Vec3 rec2020 = srgb_to_rec2020() * linearize_ui_color(rgb(ui), p);
  return {rec2020[0] * p.ui_luminance, rec2020[1] * p.ui_luminance, rec2020[2] * p.ui_luminance,
          ui[3]};
}

Vec3 compute_hdr_scene_color(const Vec3& scene, BackBufferEncoding encoding) {
  if (encoding == BackBufferEncoding::kPq) {
    return {st2084::nits_from_pq(scene[0]), st2084::nits_from_pq(scene[1]),
            st2084::nits_from_pq(scene[2])};
  }
  const Vec3 rec2020 = srgb_to_rec2020() * scene;
  return {rec2020[0] * kScRgbScaleFactor, rec2020[1] * kScRgbScaleFactor,
          rec2020[2] * kScRgbScaleFactor};
}

Vec3 reinhard_under_ui(Vec3 scene, double a, double ui_level) {
  // "Clamp gamut to sRGB as extended gamut colors bleeding into the UI can look funny".
  for (double& c : scene) c = std::fmax(c, 0.0);
  // Reinhard to the UI's level, faded in with the UI's opacity.
  const double luminance = dot(scene, kRec2020LumaWeights) / ui_level;
  const double out_l = 1.0 / (luminance + 1.0);
  const double scale = 1.0 + (out_l * ui_level - 1.0) * a;  // lerp(1, OutL · Level, a)
  for (double& c : scene) c *= scale;
  return scene;
}

Vec3 compose_ui_and_scene(Vec3 scene, const Vec4& ui, double ui_level) {
  const double a = ui[3];
  if (a > 0.0 && a < 1.0) scene = reinhard_under_ui(scene, a, ui_level);
  return {scene[0] * (1.0 - a) + ui[0] * ui_level, scene[1] * (1.0 - a) + ui[1] * ui_level,
          scene[2] * (1.0 - a) + ui[2] * ui_level};
}

Vec3 apply_color_deficiency(const Vec3& rec2020, const CvdSettings& cvd) {
  if (!color_deficiency_active(cvd)) return rec2020;
  const Vec3 srgb = rec2020_to_srgb() * rec2020;
  const Vec3 out =
      color_deficiency(srgb, cvd.type, static_cast<double>(cvd.severity), cvd.correct ? 1.0 : 0.0,
                       cvd.show_correction_with_deficiency ? 1.0 : 0.0);
  return srgb_to_rec2020() * out;
}

Vec3 encode_output(const Vec3& rec2020_nits, BackBufferEncoding encoding) {
  if (encoding == BackBufferEncoding::kPq) {
    return {st2084::pq_from_nits(rec2020_nits[0]), st2084::pq_from_nits(rec2020_nits[1]),
            st2084::pq_from_nits(rec2020_nits[2])};
  }
  const Vec3 scaled{rec2020_nits[0] / kScRgbScaleFactor, rec2020_nits[1] / kScRgbScaleFactor,
                    rec2020_nits[2] / kScRgbScaleFactor};
  return rec2020_to_srgb() * scaled;
}

Vec4 composite_pixel(const Vec4& scene, const Vec4& ui, const UiCompositeParams& p,
                     UiCompositeTrace* trace) {
  const BackBufferEncoding encoding = back_buffer_encoding(p.output_device);
  if (p.composite_mode == 0) return standard_blend(scene, ui, encoding);

  const Vec4 ui_nits = compute_hdr_ui_color(ui, p);
  const Vec3 scene_nits = compute_hdr_scene_color(rgb(scene), encoding);
  const Vec3 composed = compose_ui_and_scene(scene_nits, ui_nits, p.ui_level);
  const Vec3 after_cvd = apply_color_deficiency(composed, p.cvd);
  const Vec3 encoded = encode_output(after_cvd, encoding);
  const Vec4 out{encoded[0], encoded[1], encoded[2], 1.0};
  if (trace) *trace = {ui_nits, scene_nits, composed, after_cvd, out};
  return out;
}

Status check_ui_size(const Image& scene, const Image& ui) {
  if (scene.width == ui.width && scene.height == ui.height) return {};
  return Error{"", "ui",
               "UI image is " + std::to_string(ui.width) + "x" + std::to_string(ui.height) +
                   ", scene is " + std::to_string(scene.width) + "x" +
                   std::to_string(scene.height) + "; the composite needs equal sizes",
               ""};
}

Result<Image> composite_ui(const Image& scene, const Image& ui, const UiCompositeParams& p) {
  if (Status s = validate(p); !s) return s.error();
  if (Status st = check_ui_size(scene, ui); !st) return st.error();
  Image out(scene.width, scene.height);
  for (int y = 0; y < scene.height; ++y) {
    for (int x = 0; x < scene.width; ++x) {
      const double* s = scene.px(x, y);
      const double* u = ui.px(x, y);
      const Vec4 o = composite_pixel({s[0], s[1], s[2], s[3]}, {u[0], u[1], u[2], u[3]}, p);
      double* d = out.px(x, y);
      for (int c = 0; c < 4; ++c) d[c] = o[c];
    }
  }
  return out;
}

}  // namespace hdrc::ref::ui
