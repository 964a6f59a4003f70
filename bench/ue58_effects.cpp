#include "bench/ue58_effects.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include "color/st2084.h"
#include "core/pipeline.h"
#include "reference/color/ue_log_shaper.h"
#include "reference/reference_engine.h"
#include "reference/ue/combine_luts.h"
#include "reference/ue/lut_shaper.h"
#include "reference/ue/ue58/ue58_combine_luts.h"
#include "reference/ue/ue58/ue58_pipeline.h"
#include "reference/ue/ue58/ue58_ui_composite.h"
#include "runner/diff.h"
#include "runner/stimuli.h"

namespace hdrc::ue58fx {

namespace {

using KV = std::vector<std::pair<std::string, double>>;

// A case of `stage` of UE 5.5's or 5.8's pipeline with these settings and cvars, resolved by the
// pipeline's own host derivation.
ParamBlock resolve_case(bool ue55, const char* stage, const KV& settings, const KV& cvars,
                        std::string* degenerate) {
  const Pipeline& pl = ue55 ? default_pipeline() : ref::ue58::ue58_pipeline();
  Case k;
  k.stage = find_stage(pl, stage);
  k.settings = pl.new_settings();
  for (const auto& [name, v] : settings) {
    const auto st = k.settings.set(name, {v, 0, 0, 0}, 1);
    if (!st.ok()) {
      std::fprintf(stderr, "setting %s: %s\n", name.c_str(), st.error().to_string().c_str());
      std::abort();
    }
  }
  for (const auto& [name, v] : cvars) {
    const auto st = k.cvars.set(name, v);
    if (!st.ok()) {
      std::fprintf(stderr, "cvar %s: %s\n", name.c_str(), st.error().to_string().c_str());
      std::abort();
    }
  }
  auto r = pl.resolve(k, 32 * 32, 32);
  if (!r) {
    std::fprintf(stderr, "resolve: %s\n", r.error().to_string().c_str());
    std::abort();
  }
  *degenerate = r->degenerate;
  return r->params;
}

ParamBlock resolve_config(const Config& c, std::string* degenerate) {
  ParamBlock p = resolve_case(c.ue55, c.ue55 ? "combine_luts" : "ue58_combine_luts", c.settings,
                              c.cvars, degenerate);
  if (c.tweak) c.tweak(p);
  return p;
}

// Exact trilinear weights of a volume lookup with clamp-to-edge addressing at lattice coordinate
// e (PostProcessTonemap.usf: ColorLookupTable, UVW = e (N - 1)/N + 0.5/N, so the texel coordinate
// is e (N - 1)): the two texels and the weight of the upper one per axis.
struct Taps {
  int i0[3], i1[3];
  double f[3];
};
Taps taps(const Vec3& e, int n) {
  Taps t;
  for (int c = 0; c < 3; ++c) {
    const double x = std::clamp(e[c], 0.0, 1.0) * (n - 1);
    const double fl = std::floor(x);
    t.i0[c] = std::clamp(static_cast<int>(fl), 0, n - 1);
    t.i1[c] = std::min(t.i0[c] + 1, n - 1);
    t.f[c] = x - fl;
  }
  return t;
}

}  // namespace

struct Path::Impl {
  ParamBlock p;
  std::string degenerate;
  bool ue55 = false;
  OutputEncoding enc;
  // 5.5: the project's lazy bake (bit for bit bake_lut).
  std::optional<ref::LazyBakedLut> lut55;
  // 5.8: the outer texels as bake_outer_lut stores them, evaluated on first use.
  std::unique_ptr<ref::ue58::CombineLuts58> luts58;
  std::vector<Vec3> texels;
  std::vector<uint8_t> done;

  const Vec3& texel58(int r, int g, int b) {
    const int n = p.lut_size;
    const size_t i = (static_cast<size_t>(b) * n + g) * n + r;
    if (!done[i]) {
      const double step = 1.0 / (n - 1);
      const Vec3 v = luts58->outer_texel({r * step, g * step, b * step});
      for (int c = 0; c < 3; ++c) texels[i][c] = ref::quantize_lut_value(p.lut_format, v[c]);
      done[i] = 1;
    }
    return texels[i];
  }
};

Path::Path(const Config& c) : impl_(std::make_unique<Impl>()) {
  impl_->ue55 = c.ue55;
  impl_->p = resolve_config(c, &impl_->degenerate);
  const Pipeline& pl = c.ue55 ? default_pipeline() : ref::ue58::ue58_pipeline();
  const StageInfo* stage = find_stage(pl, c.ue55 ? "combine_luts" : "ue58_combine_luts");
  impl_->enc = output_encoding(*stage, impl_->p);
  impl_->enc.pre_scale = 1.0;  // signal() already applies LUTMax
  if (!impl_->degenerate.empty()) return;
  if (c.ue55) {
    impl_->lut55.emplace(impl_->p);
  } else {
    impl_->luts58 = std::make_unique<ref::ue58::CombineLuts58>(impl_->p);
    impl_->luts58->set_exact_inner(c.exact_inner);
    const size_t n = static_cast<size_t>(impl_->p.lut_size);
    impl_->texels.resize(n * n * n);
    impl_->done.assign(n * n * n, 0);
  }
}

Path::~Path() = default;

const ParamBlock& Path::params() const {
  return impl_->p;
}
const std::string& Path::degenerate() const {
  return impl_->degenerate;
}
bool Path::sdr() const {
  return impl_->p.output_device <= 2;
}

Vec3 Path::signal(const Vec3& x) {
  Impl& m = *impl_;
  if (m.ue55) {
    // PostProcessTonemap.usf (5.5): ColorLookupTable — shaper by device, sample, * 1.05.
    const Vec3 e{ref::lut_encode(m.p.output_device, x[0]), ref::lut_encode(m.p.output_device, x[1]),
                 ref::lut_encode(m.p.output_device, x[2])};
    return ref::sample_lut(m.lut55->prepare(e), e);
  }
  // 5.8: LUTShaper chooses PQ(x * 100) or the log shaper for every device; * LUTMax.
  Vec3 e;
  for (int c = 0; c < 3; ++c)
    e[c] = m.p.ue58_lut_shaper ? ref::st2084::pq_from_nits(x[c] * ref::kLinearToNitsScale)
                               : ref::ue_log::log_from_lin(x[c] + ref::ue_log::lin_from_log(0.0));
  const int n = m.p.lut_size;
  const Taps t = taps(e, n);
  Vec3 out{0, 0, 0};
  for (int corner = 0; corner < 8; ++corner) {
    const int r = corner & 1 ? t.i1[0] : t.i0[0];
    const int g = corner & 2 ? t.i1[1] : t.i0[1];
    const int b = corner & 4 ? t.i1[2] : t.i0[2];
    const double w = (corner & 1 ? t.f[0] : 1 - t.f[0]) * (corner & 2 ? t.f[1] : 1 - t.f[1]) *
                     (corner & 4 ? t.f[2] : 1 - t.f[2]);
    if (w == 0.0) continue;
    const Vec3& v = m.texel58(r, g, b);
    for (int c = 0; c < 3; ++c) out[c] += w * v[c];
  }
  const double lut_max = 1.0 / m.p.ue58_lut_inv_max;
  return {out[0] * lut_max, out[1] * lut_max, out[2] * lut_max};
}

Vec3 Path::nits(const Vec3& signal) const {
  const OutputEncoding& e = impl_->enc;
  return e.to_rec2020 * Vec3{e.to_nits(signal[0]), e.to_nits(signal[1]), e.to_nits(signal[2])};
}

double pq_code(double nits) {
  if (std::isnan(nits) || nits <= 0.0) return ref::st2084::pq_from_nits(0.0) * 1023.0;
  return ref::st2084::pq_from_nits(std::min(nits, 10000.0)) * 1023.0;
}

std::vector<Stimulus> grey_ramp() {
  std::vector<Stimulus> out;
  out.push_back({"grey 0", {0, 0, 0}});
  for (int i = 0; i < 240; ++i) {
    const double v = std::exp2(-14.0 + 22.0 * i / 239.0);
    char name[64];
    std::snprintf(name, sizeof name, "grey %.4g", v);
    out.push_back({name, {v, v, v}});
  }
  return out;
}

std::vector<Stimulus> stimuli() {
  std::vector<Stimulus> out = grey_ramp();
  int k = 0;
  for (const auto& patch : stimulus_data::colorchecker24()) {
    ++k;
    const Vec3 lin{stimulus_data::srgb_decode(patch.r / 255.0),
                   stimulus_data::srgb_decode(patch.g / 255.0),
                   stimulus_data::srgb_decode(patch.b / 255.0)};
    for (const double ex : {0.25, 1.0, 4.0, 16.0}) {
      char name[96];
      std::snprintf(name, sizeof name, "cc %d %s x%g", k, std::string(patch.name).c_str(), ex);
      out.push_back({name, {lin[0] * ex, lin[1] * ex, lin[2] * ex}});
    }
  }
  for (int h = 0; h < 360; h += 3) {
    // HSV(h, 1, 1): the fully saturated hue with max channel 1.
    const double hp = h / 60.0;
    const double xx = 1.0 - std::fabs(std::fmod(hp, 2.0) - 1.0);
    Vec3 rgb;
    switch (static_cast<int>(hp)) {
      case 0:
        rgb = {1, xx, 0};
        break;
      case 1:
        rgb = {xx, 1, 0};
        break;
      case 2:
        rgb = {0, 1, xx};
        break;
      case 3:
        rgb = {0, xx, 1};
        break;
      case 4:
        rgb = {xx, 0, 1};
        break;
      default:
        rgb = {1, 0, xx};
    }
    for (const double ex : {1.0, 4.0, 16.0, 64.0}) {
      char name[64];
      std::snprintf(name, sizeof name, "hue %d x%g", h, ex);
      out.push_back({name, {rgb[0] * ex, rgb[1] * ex, rgb[2] * ex}});
    }
  }
  return out;
}

namespace {

// One channel's difference d on stimulus `name` into the effect's maximum (and its stimulus) and
// the list the 99th percentile is taken over (finish_effect).
void add_difference(double d, const std::string& name, Effect* e, std::vector<double>* diffs) {
  diffs->push_back(d);
  if (d > e->max || e->worst.empty()) {
    e->max = std::max(e->max, d);
    e->worst = name;
  }
}
void finish_effect(std::vector<double>* diffs, Effect* e) {
  e->values = diffs->size();
  std::sort(diffs->begin(), diffs->end());
  if (!diffs->empty()) e->p99 = (*diffs)[static_cast<size_t>(std::ceil(0.99 * diffs->size())) - 1];
}

}  // namespace

Effect measure(Path& a, Path& b, const std::vector<Stimulus>& set, bool same_display) {
  Effect e;
  if (!a.degenerate().empty() || !b.degenerate().empty()) {
    e.skipped = a.degenerate().empty() ? b.degenerate() : a.degenerate();
    return e;
  }
  const bool sdr = a.sdr() && b.sdr();
  e.unit = sdr ? "10-bit device codes" : "10-bit PQ codes";
  std::vector<double> diffs;
  for (const Stimulus& s : set) {
    const Vec3 sa = a.signal(s.x), sb = b.signal(s.x);
    const Vec3 na = a.nits(sa), nb = same_display ? a.nits(sb) : b.nits(sb);
    for (int c = 0; c < 3; ++c) {
      double d;
      if (sdr) {
        const auto code = [](double v) { return 1023.0 * ref::ue_log::saturate_d3d(v); };
        d = std::fabs(code(sa[c]) - code(sb[c]));
      } else {
        d = std::fabs(pq_code(na[c]) - pq_code(nb[c]));
      }
      add_difference(d, s.name, &e, &diffs);
    }
    const double de = delta_e_itp(ictcp_from_rec2020_nits(na), ictcp_from_rec2020_nits(nb));
    if (de > e.de_itp) e.de_itp = de;
  }
  finish_effect(&diffs, &e);
  return e;
}

// ---- The UI composite ---------------------------------------------------------------------

namespace {

// One side of a UI comparison, resolved: the composite of its UE version with its parameters.
class UiSide {
 public:
  explicit UiSide(const UiConfig& c) : ue55_(c.ue55) {
    std::string degenerate;
    const ParamBlock p = resolve_case(c.ue55, c.ue55 ? "ui_composite" : "ue58_ui_composite",
                                      c.settings, c.cvars, &degenerate);
    if (c.ue55) {
      p55_ = ref::ui_composite_params(p);
      if (c.tweak55) c.tweak55(p55_);
      check(ref::ui::validate(p55_));
    } else {
      p58_ = ref::ue58::ui_composite58_params(p);
      check(ref::ue58::validate(p58_));
    }
  }
  // The back buffer after the UI pass.
  ref::ui::Vec4 composite(const ref::ui::Vec4& scene, const ref::ui::Vec4& ui) const {
    return ue55_ ? ref::ui::composite_pixel(scene, ui, p55_)
                 : ref::ue58::composite_pixel58(scene, ui, p58_);
  }
  int device() const { return ue55_ ? p55_.output_device : p58_.common.output_device; }

 private:
  static void check(const Status& st) {
    if (st.ok()) return;
    std::fprintf(stderr, "UI composite parameters: %s\n", st.error().to_string().c_str());
    std::abort();
  }
  bool ue55_;
  ref::ui::UiCompositeParams p55_;
  ref::ue58::UiComposite58Params p58_;
};

// The back-buffer code of Rec.2020 nits for `device`'s encoding (the composite's output encode,
// ui::encode_output: PQ, or scRGB through Rec2020→sRGB / 80).
ref::ui::Vec4 back_buffer(const Vec3& nits, int device) {
  const Vec3 v = ref::ui::encode_output(nits, ref::ui::back_buffer_encoding(device));
  return {v[0], v[1], v[2], 1.0};
}

}  // namespace

std::vector<UiStimulus> ui_stimuli(int device, bool alpha0_colour) {
  struct Scene {
    std::string name;
    Vec3 nits;
  };
  std::vector<Scene> scenes;
  for (const double n : {0.0, 0.1, 1.0, 10.0, 100.0, 203.0, 1000.0, 10000.0}) {
    char name[48];
    std::snprintf(name, sizeof name, "%g nits", n);
    scenes.push_back({name, {n, n, n}});
  }
  scenes.push_back({"(1000, 50, 5) nits", {1000, 50, 5}});
  scenes.push_back({"(5, 50, 1000) nits", {5, 50, 1000}});
  struct Colour {
    std::string name;
    Vec3 rgb;
  };
  std::vector<Colour> colours;
  for (int k = 0; k <= 255; ++k)
    colours.push_back({std::to_string(k) + "/255", {k / 255.0, k / 255.0, k / 255.0}});
  colours.push_back({"red", {1, 0, 0}});
  colours.push_back({"green", {0, 1, 0}});
  colours.push_back({"blue", {0, 0, 1}});
  colours.push_back({"yellow", {1, 1, 0}});
  colours.push_back({"cyan", {0, 1, 1}});
  colours.push_back({"magenta", {1, 0, 1}});
  std::vector<UiStimulus> out;
  for (const Scene& s : scenes) {
    const ref::ui::Vec4 scene = back_buffer(s.nits, device);
    for (const Colour& c : colours) {
      for (const double a : {0.0, 0.1, 0.25, 0.5, 0.75, 0.9, 1.0}) {
        char name[96];
        std::snprintf(name, sizeof name, "ui %s a%g over %s", c.name.c_str(), a, s.name.c_str());
        out.push_back({name, scene, {c.rgb[0] * a, c.rgb[1] * a, c.rgb[2] * a, a}});
      }
      if (alpha0_colour)
        out.push_back({"ui " + c.name + " at a0 (not premultiplied) over " + s.name,
                       scene,
                       {c.rgb[0], c.rgb[1], c.rgb[2], 0.0}});
    }
  }
  return out;
}

Effect measure_ui(const UiConfig& a, const UiConfig& b, const std::vector<UiStimulus>& set) {
  const UiSide sa(a), sb(b);
  Effect e;
  e.unit = "10-bit PQ codes";
  std::vector<double> diffs;
  const auto nits = [](const UiSide& side, const ref::ui::Vec4& out) {
    return ref::ui::compute_hdr_scene_color({out[0], out[1], out[2]},
                                            ref::ui::back_buffer_encoding(side.device()));
  };
  for (const UiStimulus& s : set) {
    const Vec3 na = nits(sa, sa.composite(s.scene, s.ui));
    const Vec3 nb = nits(sb, sb.composite(s.scene, s.ui));
    for (int c = 0; c < 3; ++c) {
      const double d = std::fabs(pq_code(na[c]) - pq_code(nb[c]));
      add_difference(d, s.name, &e, &diffs);
    }
    const double de = delta_e_itp(ictcp_from_rec2020_nits(na), ictcp_from_rec2020_nits(nb));
    if (de > e.de_itp) e.de_itp = de;
  }
  finish_effect(&diffs, &e);
  return e;
}

}  // namespace hdrc::ue58fx
