// A minimal port, written as an outside renderer would write one: it links nothing of hdrconform,
// only nlohmann-json (to read params.json) and OpenImageIO (to read and write EXR). It implements
// two per-pixel stages of UE 5.5's HDR output — `shaper` (the LUT shaper's round trip) and
// `linear_device` (the shaper, then devices 7/8) — and declines everything else through the
// candidate protocol (docs/candidate-protocol.md):
//
//   exit 0   the output image was written
//   exit 77  "unsupported: skip this case"  (here: an output device outside --devices)
//   exit 78  "unsupported: this whole stage" (here: any stage but shaper and linear_device)
//   exit 1   an error (message on stderr)
//
// The first line printed before a 77/78 is the reason hdrconform shows for the UNSUPPORTED case.
//
//   standalone_candidate --params params.json --output out.exr [--devices 3,4]
//   hdrconform verify --candidate-cmd 'standalone_candidate --params {params} --output {output}'
//
// The formulas are UE's (TonemapCommon.ush: LinearToST2084, ST2084ToLinear, LinToLog, LogToLin;
// PostProcessCombineLUTs.usf device 7/8 branches), evaluated in double; the README's
// "Verifying a port" walks through this file.
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

namespace {

using json = nlohmann::json;
constexpr int kDeclineCase = 77;
constexpr int kDeclineStage = 78;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// SMPTE ST 2084 constants in the standard's fractional form.
constexpr double kM1 = 2610.0 / 16384.0;
constexpr double kM2 = 2523.0 / 4096.0 * 128.0;
constexpr double kC1 = 3424.0 / 4096.0;
constexpr double kC2 = 2413.0 / 4096.0 * 32.0;
constexpr double kC3 = 2392.0 / 4096.0 * 32.0;

// LinearToST2084 exactly as UE writes it: no clamp (a negative is pow of a negative: NaN), and
// the division as a multiply by a reciprocal (+Inf gives Inf * 0 = NaN).
double linear_to_st2084(double nits) {
  const double lm = std::pow(nits / 10000.0, kM1);
  return std::pow((kC1 + kC2 * lm) * (1.0 / (1.0 + kC3 * lm)), kM2);
}
double st2084_to_linear(double pq) {
  const double np = std::pow(pq, 1.0 / kM2);
  return std::pow(std::fmax(np - kC1, 0.0) / (kC2 - kC3 * np), 1.0 / kM1) * 10000.0;
}

// UE's log shaper (devices 0-2): 14 stops, grey 0.18 at code 444/1023. saturate() of NaN is 0 on
// D3D, which UE ships on.
double log_to_lin(double x) {
  return std::exp2((x - 444.0 / 1023.0) * 14.0) * 0.18;
}
double saturate(double x) {
  return std::isnan(x) ? 0.0 : std::clamp(x, 0.0, 1.0);
}
double lin_to_log(double x) {
  return saturate(std::log2(x) / 14.0 - std::log2(0.18) / 14.0 + 444.0 / 1023.0);
}

// The shaper round trip: encode as the tonemapper does, clamp as the LUT sampler addresses
// (NaN stays NaN), decode as CombineLUTs does. Scene-linear 1.0 = 100 nits for the PQ shaper.
double shaper_round_trip(int device, double x) {
  if (device >= 3) {
    double e = (std::isnan(x) || x < 0) ? kNaN : linear_to_st2084(x * 100.0);
    if (!std::isnan(e)) e = std::clamp(e, 0.0, 1.0);
    return st2084_to_linear(e) / 100.0;
  }
  double e = lin_to_log(x + log_to_lin(0.0));
  return log_to_lin(e) - log_to_lin(0.0);
}

// A params.json number: a JSON number, or "NaN" / "Infinity" / "-Infinity".
double number(const json& v) {
  if (v.is_number()) return v.get<double>();
  const std::string s = v.get<std::string>();
  if (s == "NaN") return kNaN;
  return s == "-Infinity" ? -std::numeric_limits<double>::infinity()
                          : std::numeric_limits<double>::infinity();
}

struct Mat3 {
  double m[3][3];
  void apply(const double in[3], double out[3]) const {
    for (int r = 0; r < 3; ++r) out[r] = m[r][0] * in[0] + m[r][1] * in[1] + m[r][2] * in[2];
  }
};
Mat3 matrix(const json& rows) {
  Mat3 out{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out.m[r][c] = number(rows.at(r).at(c));
  return out;
}

int fail(const std::string& what) {
  std::fprintf(stderr, "standalone_candidate: %s\n", what.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  std::string params_path, output_path;
  std::set<int> devices;  // empty: every device
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--params") {
      params_path = value;
    } else if (key == "--output") {
      output_path = value;
    } else if (key == "--devices") {
      for (size_t at = 0; at < value.size();) {
        const size_t comma = value.find(',', at);
        devices.insert(std::stoi(value.substr(at, comma - at)));
        at = comma == std::string::npos ? value.size() : comma + 1;
      }
    } else {
      return fail("unknown option " + key);
    }
  }
  if (params_path.empty() || output_path.empty() || argc % 2 == 0)
    return fail("usage: standalone_candidate --params P --output O [--devices 3,4]");

  // 1. params.json: check the contract's version, then take what this port needs.
  json doc;
  try {
    std::ifstream f(params_path);
    doc = json::parse(f);
  } catch (const std::exception& e) {
    return fail(params_path + ": " + e.what());
  }
  if (doc.value("format_version", 0) != 3)
    return fail(params_path + ": format_version " + doc.value("format_version", json()).dump() +
                ", this port reads 2");
  const std::string stage = doc.at("stage");
  if (stage != "shaper" && stage != "linear_device") {
    std::printf("stage %s is not implemented by this port\n", stage.c_str());
    return kDeclineStage;
  }
  const json& p = doc.at("params");
  const int device = p.at("output_device");
  if (!devices.empty() && !devices.count(device)) {
    std::printf("output device %d is not implemented by this port\n", device);
    return kDeclineCase;
  }
  const Mat3 wcs_to_ap1 = matrix(p.at("wcs_to_ap1"));
  const Mat3 ap1_to_output = matrix(p.at("ap1_to_output"));

  // 2. The input image, as float RGBA.
  const std::string dir = params_path.substr(0, params_path.find_last_of('/') + 1);
  const std::string input_path = dir + doc.at("images").at("input").at("file").get<std::string>();
  auto in = OIIO::ImageInput::open(input_path);
  if (!in) return fail(input_path + ": " + OIIO::geterror());
  const OIIO::ImageSpec spec = in->spec();
  const int w = spec.width, h = spec.height, nc = spec.nchannels;
  if (nc < 3) return fail(input_path + ": fewer than 3 channels");
  std::vector<float> px(static_cast<size_t>(w) * h * nc);
  if (!in->read_image(0, 0, 0, nc, OIIO::TypeDesc::FLOAT, px.data()))
    return fail(input_path + ": " + in->geterror());
  in->close();

  // 3. The stage, per pixel. Alpha passes through.
  std::vector<float> out(static_cast<size_t>(w) * h * 4);
  for (size_t i = 0; i < static_cast<size_t>(w) * h; ++i) {
    double rgb[3];
    for (int c = 0; c < 3; ++c) rgb[c] = shaper_round_trip(device, px[i * nc + c]);
    if (stage == "linear_device" && device == 7) {
      // HDR_LinearEXR: LinearToST2084(AP1_2_Output * ToAP1 * x) stored, ST2084ToLinear read back:
      // the identity on non-negative nits, NaN on negative ones (pow of a negative base).
      double ap1[3], out_gamut[3];
      wcs_to_ap1.apply(rgb, ap1);
      ap1_to_output.apply(ap1, out_gamut);
      for (int c = 0; c < 3; ++c) {
        const double v = out_gamut[c];
        rgb[c] = st2084_to_linear((std::isnan(v) || v < 0) ? kNaN : linear_to_st2084(v));
      }
    } else if (stage == "linear_device" && device != 8) {
      std::printf("linear_device with output device %d is not implemented by this port\n", device);
      return kDeclineCase;
    }
    for (int c = 0; c < 3; ++c) out[i * 4 + c] = static_cast<float>(rgb[c]);
    out[i * 4 + 3] = nc > 3 ? px[i * nc + 3] : 1.0f;
  }

  // 4. The output: RGBA float32 EXR of the input's size (params.json "output").
  auto o = OIIO::ImageOutput::create(output_path);
  if (!o) return fail(output_path + ": " + OIIO::geterror());
  OIIO::ImageSpec ospec(w, h, 4, OIIO::TypeDesc::FLOAT);
  if (!o->open(output_path, ospec) || !o->write_image(OIIO::TypeDesc::FLOAT, out.data()))
    return fail(output_path + ": " + o->geterror());
  o->close();
  return 0;
}
