#include "runner/goldens.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include "core/atomic_file.h"
#include "core/utf8.h"
#include "reference/reference_engine.h"
#include "runner/case_loader.h"
#include "runner/golden_compare.h"
#include "runner/goldens_diff.h"
#include "runner/json_read.h"
#include "runner/results.h"
#include "runner/tolerance.h"

namespace hdrc {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

// ---- SHA-256, FIPS 180-4 §6.2 ----

namespace {
constexpr std::array<uint32_t, 64> kK = {
    0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4, 0xab1c5ed5,
    0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe, 0x9bdc06a7, 0xc19bf174,
    0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f, 0x4a7484aa, 0x5cb0a9dc, 0x76f988da,
    0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7, 0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967,
    0x27b70a85, 0x2e1b2138, 0x4d2c6dfc, 0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85,
    0xa2bfe8a1, 0xa81a664b, 0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070,
    0x19a4c116, 0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
    0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7, 0xc67178f2};

inline uint32_t rotr(uint32_t x, int n) {
  return (x >> n) | (x << (32 - n));
}
}  // namespace

std::string sha256_hex(const std::string& data) {
  uint32_t h[8] = {0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a,
                   0x510e527f, 0x9b05688c, 0x1f83d9ab, 0x5be0cd19};
  std::string msg = data;
  const uint64_t bits = static_cast<uint64_t>(data.size()) * 8;
  msg.push_back(static_cast<char>(0x80));
  while (msg.size() % 64 != 56) msg.push_back('\0');
  for (int i = 7; i >= 0; --i) msg.push_back(static_cast<char>((bits >> (8 * i)) & 0xff));
  for (size_t off = 0; off < msg.size(); off += 64) {
    uint32_t w[64];
    for (int t = 0; t < 16; ++t) {
      const auto* p = reinterpret_cast<const unsigned char*>(msg.data() + off + 4 * t);
      w[t] = (uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | p[3];
    }
    for (int t = 16; t < 64; ++t) {
      const uint32_t s0 = rotr(w[t - 15], 7) ^ rotr(w[t - 15], 18) ^ (w[t - 15] >> 3);
      const uint32_t s1 = rotr(w[t - 2], 17) ^ rotr(w[t - 2], 19) ^ (w[t - 2] >> 10);
      w[t] = w[t - 16] + s0 + w[t - 7] + s1;
    }
    uint32_t a = h[0], b = h[1], c = h[2], d = h[3], e = h[4], f = h[5], g = h[6], hh = h[7];
    for (int t = 0; t < 64; ++t) {
      const uint32_t t1 =
          hh + (rotr(e, 6) ^ rotr(e, 11) ^ rotr(e, 25)) + ((e & f) ^ (~e & g)) + kK[t] + w[t];
      const uint32_t t2 = (rotr(a, 2) ^ rotr(a, 13) ^ rotr(a, 22)) + ((a & b) ^ (a & c) ^ (b & c));
      hh = g;
      g = f;
      f = e;
      e = d + t1;
      d = c;
      c = b;
      b = a;
      a = t1 + t2;
    }
    h[0] += a;
    h[1] += b;
    h[2] += c;
    h[3] += d;
    h[4] += e;
    h[5] += f;
    h[6] += g;
    h[7] += hh;
  }
  char out[65];
  for (int i = 0; i < 8; ++i) std::snprintf(out + 8 * i, 9, "%08x", h[i]);
  return std::string(out, 64);
}

std::string image_bytes(const Image& img) {
  std::string out;
  out.reserve(img.data.size() * 4 + 8);
  const int32_t dims[2] = {img.width, img.height};
  out.append(reinterpret_cast<const char*>(dims), sizeof dims);
  for (double v : img.data) {
    const float f = static_cast<float>(v);
    out.append(reinterpret_cast<const char*>(&f), sizeof f);
  }
  return out;
}

namespace {

json input_json(const InputSpec& in) {
  json j = json::object();
  if (!in.stimulus.empty()) {
    j["stimulus"] = in.stimulus;
    j["width"] = in.width;
    j["height"] = in.height;
    json p = json::object();
    for (const auto& [k, v] : in.params) p[k] = v;
    j["params"] = p;
  } else if (!in.file.empty()) {
    std::ifstream f(in.file, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    j["file_sha256"] = sha256_hex(s.str());
  }
  return j;
}

std::string utc_now() {
  char buf[32];
  const std::time_t t = std::time(nullptr);
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

std::string quote_glob(const std::string& s) {
  return "'" + s + "'";
}

// Fixed probe cases of every stage whose outputs define the reference's fingerprint. Small, so
// the fingerprint costs a fraction of a second; they exercise each stage's code paths (SDR film
// and ACES devices, PQ and log shapers, both LUT layouts and a float format, bloom, the UI
// composite's PQ and scRGB encodings, VisualizeHDR).
std::vector<Case> probe_cases() {
  std::vector<Case> out;
  auto add = [&](const char* stage, std::vector<std::pair<const char*, double>> cvars,
                 std::vector<std::pair<const char*, double>> settings, const char* stimulus, int w,
                 int h) {
    Case c;
    c.id = "probe/" + std::to_string(out.size());
    c.stage = find_stage(stage);
    for (auto [k, v] : cvars) c.cvars.set(k, v);
    for (auto [k, v] : settings) c.settings.set(k, {v, 0, 0, 0}, 1);
    if (stimulus) {
      c.input.stimulus = stimulus;
      c.input.width = w;
      c.input.height = h;
    }
    out.push_back(c);
  };
  const char* hdr = "r.HDR.EnableHDROutput";
  const char* dev = "r.HDR.Display.OutputDevice";
  const char* gamut = "r.HDR.Display.ColorGamut";
  for (int d : {0, 3}) add("shaper", {{dev, d}}, {}, "special_ramp", 32, 4);
  for (int d : {7, 8})
    add("linear_device", {{hdr, 1}, {dev, d}, {gamut, 2}}, {}, "log_ramp", 32, 4);
  for (int d : {0, 1, 2, 3, 4, 5, 6, 7, 8, 9})
    add("combine_luts", {{hdr, 1}, {dev, d}, {gamut, d % 5}, {"r.LUT.Size", 16}}, {}, nullptr, 0,
        0);
  add("combine_luts", {{hdr, 1}, {dev, 3}, {"r.LUT.Size", 17}},
      {{"LUTFormat", 1}, {"LUTLayout", 1}, {"WhiteTemp", 4000}}, nullptr, 0, 0);
  add("tonemap", {{hdr, 1}, {dev, 0}, {"r.LUT.Size", 16}},
      {{"Sharpen", 1}, {"SceneFringeIntensity", 2}}, "hue_sweep", 36, 4);
  add("tonemap", {{hdr, 1}, {dev, 3}, {gamut, 2}, {"r.LUT.Size", 16}}, {}, "colorchecker", 24, 5);
  add("dither", {{hdr, 1}, {dev, 0}}, {{"FrameIndex", 5}}, "log_ramp", 16, 4);
  for (int d : {3, 5}) add("ui_composite", {{hdr, 1}, {dev, d}}, {}, "pq_codes", 32, 32);
  add("visualize_hdr", {{hdr, 1}, {dev, 3}, {"r.EyeAdaptation.VisualizeDebugType", 1}}, {},
      "log_ramp", 192, 168);
  return out;
}

// Within `ulps` float32 units in the last place, NaN = NaN, infinities by sign.
bool float_close(float a, float b, int ulps) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  if (a == b) return true;
  if (std::isinf(a) || std::isinf(b)) return false;
  int32_t ia, ib;
  std::memcpy(&ia, &a, 4);
  std::memcpy(&ib, &b, 4);
  // Map to a monotonic integer line (negative floats mirrored).
  if (ia < 0) ia = INT32_MIN - ia;
  if (ib < 0) ib = INT32_MIN - ib;
  return std::llabs(static_cast<long long>(ia) - ib) <= ulps;
}

// A golden sidecar (goldens update writes it): bounded like every JSON input, and a field of
// another type than the one written is an error naming it, so that the readers below may take
// .value() of any of them.
Result<json> read_json(const std::string& path) {
  auto doc = read_json_file<json>(path, "golden sidecar");
  if (!doc || !doc->is_object()) return doc;
  for (const char* key :
       {"case", "stage", "case_hash", "input_hash", "output_hash", "reference_version", "date"})
    if (auto it = doc->find(key); it != doc->end() && !it->is_string())
      return Error{path, std::string("/") + key,
                   std::string("expected a string, got ") + it->type_name() + " " + it->dump(),
                   "a string, as `hdrconform goldens update` writes it"};
  for (const char* key : {"width", "height"})
    if (auto it = doc->find(key); it != doc->end() && !it->is_number_integer())
      return Error{path, std::string("/") + key,
                   std::string("expected an integer, got ") + it->type_name() + " " + it->dump(),
                   "an integer, as `hdrconform goldens update` writes it"};
  if (auto it = doc->find("values"); it != doc->end()) {
    if (!it->is_object())
      return Error{path, "/values",
                   std::string("expected an object of name: number, got ") + it->type_name(),
                   "an object of name: number"};
    for (auto v = it->begin(); v != it->end(); ++v)
      if (!v->is_number())
        return Error{path, "/values/" + escape_pointer_token(v.key()),
                     std::string("expected a number, got ") + v->type_name() + " " + v->dump(),
                     "a number"};
  }
  return doc;
}

const char* kChannel = "RGBA";

}  // namespace

std::string case_hash(const Case& c) {
  json j = json::object();
  j["stage"] = std::string(c.stage ? c.stage->name : "");
  json cv = json::object();
  for (const auto& [k, v] : c.cvars.explicit_values()) cv[k] = v;
  j["cvars"] = cv;
  json st = json::object();
  for (const auto& [k, v] : c.settings.explicit_values()) st[k] = v;
  j["settings"] = st;
  j["input"] = input_json(c.input);
  j["bloom"] = input_json(c.bloom);
  j["bloom_dirt"] = input_json(c.bloom_dirt);
  if (!c.ui.stimulus.empty() || !c.ui.file.empty()) j["ui"] = input_json(c.ui);  // likewise
  if (c.lut) j["lut"] = c.lut->name;  // only when present: the hashes of LUT-free cases stay
  if (!c.lut_blend.empty()) {         // likewise
    json steps = json::array();
    for (const LutBlendStep& step : c.lut_blend)
      steps.push_back({{"lut", step.lut ? step.lut->name : ""}, {"weight", step.weight}});
    j["lut_blend"] = steps;
  }
  return sha256_hex(j.dump());
}

std::string input_hash(const ResolvedCase& r) {
  std::string bytes = image_bytes(r.input);
  for (const Image* img : {&r.bloom, &r.bloom_dirt, &r.ui}) bytes += image_bytes(*img);
  // Only when present: the hashes of LUT-free cases stay as they were.
  for (const Image& lut : r.user_luts)
    if (!lut.data.empty()) bytes += image_bytes(lut);
  return sha256_hex(bytes);
}

const std::string& reference_version() {
  static const std::string version = [] {
    ref::ReferenceEngine engine;
    std::string bytes;
    for (const Case& c : probe_cases()) {
      auto r = resolve_case(c);
      if (!r) {
        bytes += "resolve error: " + r.error().to_string();
        continue;
      }
      auto img = engine.run(*r);
      if (!img) {
        bytes += "run error: " + img.error().to_string();
        continue;
      }
      bytes += image_bytes(*img);
      for (const auto& [k, v] : img->values) {
        bytes += k;
        bytes.append(reinterpret_cast<const char*>(&v), sizeof v);
      }
    }
    return std::to_string(kReferenceVersion) + "/" + sha256_hex(bytes).substr(0, 12);
  }();
  return version;
}

GoldenPaths golden_paths(const std::string& goldens_dir, const std::string& case_id) {
  const std::string base = goldens_dir + "/" + case_id;
  return {base + ".exr", base + ".json"};
}

std::string golden_update_command(const std::string& case_id, const std::string& extra) {
  return "hdrconform goldens update --filter " + quote_glob(case_id) +
         (extra.empty() ? "" : " " + extra);
}

GoldenCheck check_golden(const std::string& goldens_dir, const Case& c,
                         const ResolvedCase& resolved, const Image& reference,
                         const std::string& update_extra) {
  GoldenCheck out;
  const GoldenPaths paths = golden_paths(goldens_dir, c.id);
  const std::string cmd = golden_update_command(c.id, update_extra);
  std::error_code ec;
  if (!fs::exists(paths.exr, ec) || !fs::exists(paths.sidecar, ec)) {
    out.outcome = GoldenCheck::kMissing;
    out.message = "no golden (" + (fs::exists(paths.exr, ec) ? paths.sidecar : paths.exr) +
                  " is missing); create it with: " + cmd;
    return out;
  }
  auto side = read_json(paths.sidecar);
  if (!side || !side->is_object()) {
    out.outcome = GoldenCheck::kStale;
    out.message = "unreadable golden sidecar " +
                  (side ? paths.sidecar + ": not a JSON object" : side.error().to_string()) +
                  "; recreate it with: " + cmd;
    return out;
  }
  const json& s = *side;
  const std::string made_by = s.value("reference_version", "?");
  if (s.value("case_hash", "") != case_hash(c)) {
    out.outcome = GoldenCheck::kStale;
    out.message = "stale golden: the case's definition changed since the golden was made (" +
                  s.value("date", "?") + "); update it with: " + cmd;
    return out;
  }
  if (s.value("input_hash", "") != input_hash(resolved)) {
    out.outcome = GoldenCheck::kStale;
    out.message = "stale golden: the case's input pixels changed since the golden was made (" +
                  s.value("date", "?") + "); update it with: " + cmd;
    return out;
  }
  auto golden = read_image(paths.exr);
  if (!golden) {
    out.outcome = GoldenCheck::kStale;
    out.message = "unreadable golden " + paths.exr + " (" + golden.error().message +
                  "); recreate it with: " + cmd;
    return out;
  }
  const std::string versions =
      " (golden made by reference " + made_by + ", this is " + reference_version() + ")";
  if (golden->width != reference.width || golden->height != reference.height) {
    out.outcome = GoldenCheck::kRegression;
    out.message = "golden regression: the reference's output is " +
                  std::to_string(reference.width) + "x" + std::to_string(reference.height) +
                  ", the golden " + std::to_string(golden->width) + "x" +
                  std::to_string(golden->height) + versions + "; if intended: " + cmd;
    return out;
  }
  // The bound: runner/golden_compare.h, docs/goldens.md.
  const GoldenDiff diff = compare_with_golden(*golden, reference);
  out.deviation = diff.largest;
  if (diff.differ) {
    const size_t first = diff.first, px = first / 4;
    char buf[320];
    std::snprintf(
        buf, sizeof buf,
        "(%zu, %zu) %c: golden %.9g, reference %.9g (%.3g times the bound; the largest "
        "is %.3g)",
        px % static_cast<size_t>(reference.width), px / static_cast<size_t>(reference.width),
        kChannel[first % 4], static_cast<float>(golden->data[first]),
        static_cast<float>(reference.data[first]),
        golden_deviation(
            static_cast<float>(golden->data[first]), static_cast<float>(reference.data[first]),
            first % 4 == 3 ? golden_scale(*golden).alpha : golden_scale(*golden).colour),
        diff.largest);
    out.outcome = GoldenCheck::kRegression;
    out.message = "golden regression: " + std::to_string(diff.differ) +
                  " value(s) differ, first at " + buf + versions +
                  "; if the change is intended: " + cmd;
    return out;
  }
  return out;
}

namespace {

// The values a stage printed, compared as float32 like the pixels.
bool values_equal(const json& a, const std::map<std::string, double>& b) {
  if (!a.is_object() || a.size() != b.size()) return false;
  for (const auto& [k, v] : b)
    if (!a.contains(k) || !a[k].is_number() ||
        !float_close(static_cast<float>(a[k].get<double>()), static_cast<float>(v), 2))
      return false;
  return true;
}

}  // namespace

namespace {

// Whether `path` (a golden about to be written) stays inside `goldens_dir` once symlinks in its
// existing parent folders are resolved.
bool inside_goldens(const std::string& goldens_dir, const std::string& path) {
  std::error_code ec;
  const fs::path root = fs::weakly_canonical(goldens_dir, ec);
  const fs::path p = fs::weakly_canonical(fs::path(path).parent_path(), ec);
  const fs::path rel = p.lexically_relative(root);
  return !ec && !rel.empty() && *rel.begin() != "..";
}

// A golden `goldens update` wrote: DIR/<id>.json, a regular file whose JSON names that same id
// as "case" and has the provenance fields a sidecar has; its image is DIR/<id>.exr.
bool is_our_sidecar(const fs::path& sidecar, const std::string& id) {
  auto j = read_json(sidecar.string());
  return j && j->is_object() && j->contains("case") && (*j)["case"].is_string() &&
         (*j)["case"].get<std::string>() == id && j->contains("case_hash") &&
         j->contains("reference_version");
}

// Goldens of degenerate cases, and with `prune` of cases no longer in the suite, go. Only pairs
// this command wrote (is_our_sidecar) are touched; nothing behind a symlink; every removed file
// is listed; only the folders those removals left empty are removed.
void prune_goldens(const std::vector<Case>& cases, const std::vector<char>& degenerate,
                   const std::string& goldens_dir, bool prune, GoldenUpdateReport* report) {
  std::set<std::string> keep, listed;
  for (size_t i = 0; i < cases.size(); ++i) {
    listed.insert(cases[i].id);
    if (!degenerate[i]) keep.insert(cases[i].id);
  }
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(goldens_dir, ec))) return;
  std::vector<fs::path> sidecars;
  size_t foreign = 0, visited = 0;
  for (fs::recursive_directory_iterator it(goldens_dir, ec), end; !ec && it != end;
       it.increment(ec)) {
    if (++visited > 1000000) break;
    const auto type = it->symlink_status(ec).type();
    if (type == fs::file_type::directory) continue;
    const fs::path& p = it->path();
    if (type == fs::file_type::regular && p.extension() == ".json")
      sidecars.push_back(p);
    else if (p.extension() != ".exr")
      ++foreign;
  }
  std::sort(sidecars.begin(), sidecars.end());
  std::set<fs::path> parents;
  for (const fs::path& side : sidecars) {
    const std::string id =
        side.lexically_relative(goldens_dir).replace_extension().generic_string();
    const bool in_run = listed.count(id) != 0;
    if (!((in_run && !keep.count(id)) || (prune && !in_run))) continue;
    if (!is_our_sidecar(side, id)) {
      ++foreign;
      continue;
    }
    fs::path exr = side;
    exr.replace_extension(".exr");
    const auto exr_type = fs::symlink_status(exr, ec).type();
    for (const fs::path& f : {exr, side}) {
      if (f == exr && exr_type != fs::file_type::regular) continue;
      if (fs::remove(f, ec))
        report->lines.push_back("removed " + valid_utf8(f.generic_string()));
      else if (ec)
        report->errors.push_back(
            Error{valid_utf8(f.generic_string()), "", "cannot remove: " + ec.message(), ""});
    }
    ++report->removed;
    parents.insert(side.parent_path());
  }
  // Folders the removals left empty, up to (not including) the goldens folder.
  const fs::path root = fs::path(goldens_dir).lexically_normal();
  for (fs::path dir : parents) {
    while (dir.lexically_normal() != root && !dir.empty() &&
           dir.lexically_normal().lexically_relative(root).native().rfind("..", 0) != 0 &&
           fs::is_directory(fs::symlink_status(dir, ec)) && fs::is_empty(dir, ec) &&
           fs::remove(dir, ec)) {
      report->lines.push_back("removed empty folder " + valid_utf8(dir.generic_string()));
      dir = dir.parent_path();
    }
  }
  if (foreign > 0)
    report->lines.push_back("left alone: " + std::to_string(foreign) + " file(s) under " +
                            valid_utf8(goldens_dir) + " that goldens update did not write");
}

}  // namespace

GoldenUpdateReport update_goldens(const std::vector<Case>& cases, const std::string& goldens_dir,
                                  bool prune, int jobs) {
  GoldenUpdateReport report;
  const std::string version = reference_version();
  const std::string date = utc_now();
  std::mutex mu;
  std::atomic<size_t> next{0};
  std::vector<char> degenerate(cases.size(), 0);
  auto work = [&] {
    ref::ReferenceEngine engine;
    for (size_t i; (i = next++) < cases.size();) {
      const Case& c = cases[i];
      auto resolved = resolve_case(c);
      if (!resolved) {
        std::lock_guard<std::mutex> lock(mu);
        report.errors.push_back(resolved.error());
        continue;
      }
      if (!resolved->degenerate.empty()) {
        degenerate[i] = 1;
        std::lock_guard<std::mutex> lock(mu);
        ++report.skipped_degenerate;
        continue;
      }
      auto img = engine.run(*resolved);
      if (!img) {
        std::lock_guard<std::mutex> lock(mu);
        report.errors.push_back(Error{c.file, c.id, "reference: " + img.error().to_string(), ""});
        continue;
      }
      const GoldenPaths paths = golden_paths(goldens_dir, c.id);
      json side = json::object();
      side["case"] = c.id;
      side["stage"] = std::string(c.stage->name);
      side["width"] = img->width;
      side["height"] = img->height;
      side["case_hash"] = case_hash(c);
      side["input_hash"] = input_hash(*resolved);
      side["output_hash"] = sha256_hex(image_bytes(*img));
      side["reference_version"] = version;
      json values = json::object();
      for (const auto& [k, v] : img->values) values[k] = v;
      side["values"] = values;
      // Unchanged: keep the files (their bytes and date) as they are. The reference version is
      // not compared: a change of the reference that leaves this case's output, hashes and named
      // values as they were leaves its golden as it was (the sidecar keeps the version that wrote
      // it), so that git shows only the goldens that moved.
      bool unchanged = false;
      std::optional<Image> before;  // the golden's pixels before this update, when readable
      if (std::error_code ec; fs::exists(paths.exr, ec))
        if (auto g = read_image(paths.exr)) before = std::move(*g);
      const bool same_image =
          before && sha256_hex(image_bytes(*before)) == side["output_hash"].get<std::string>();
      if (auto old = read_json(paths.sidecar); old && old->is_object() && same_image) {
        const json& o = *old;
        unchanged = o.value("case_hash", "") == side["case_hash"] &&
                    o.value("input_hash", "") == side["input_hash"] &&
                    o.value("output_hash", "") == side["output_hash"] &&
                    values_equal(o.value("values", json::object()), img->values);
      }
      if (unchanged) {
        std::lock_guard<std::mutex> lock(mu);
        ++report.unchanged;
        continue;
      }
      side["date"] = date;
      if (!inside_goldens(goldens_dir, paths.exr)) {
        std::lock_guard<std::mutex> lock(mu);
        report.errors.push_back(
            Error{valid_utf8(paths.exr), "",
                  "leaves the goldens folder (a symlinked folder?); not written",
                  "golden paths inside " + valid_utf8(goldens_dir)});
        continue;
      }
      // How far the golden moved (runner/goldens_diff.h: the run's metrics, old as the
      // reference), before it is overwritten.
      std::string line;
      GoldenMove move;
      if (!before) {
        line = "new " + c.id + ": wrote " + paths.exr;
      } else if (same_image) {
        line = "sidecar " + c.id + ": same pixels, wrote " + paths.sidecar;
      } else {
        move = golden_move(c, *resolved, *before, *img);
        line = "changed " + c.id + ": " + describe_move(move) + "; wrote " + paths.exr;
      }
      // The image only when its pixels changed: an EXR of the same pixels is left byte for byte.
      Status st = same_image ? Status{} : write_exr(paths.exr, *img);
      if (st) st = write_file_atomic(paths.sidecar, dump_json(side, 2) + "\n");
      std::lock_guard<std::mutex> lock(mu);
      if (!st) {
        report.errors.push_back(st.error());
        continue;
      }
      ++report.written;
      if (before && !same_image) {
        ++report.changed;
        if (move.resized || move.pq10_max > report.largest_pq10.first)
          report.largest_pq10 = {move.resized ? kNotJudged : move.pq10_max, c.id};
        if (!move.resized && move.itp_max > report.largest_itp.first)
          report.largest_itp = {move.itp_max, c.id};
      }
      report.lines.push_back(line);
    }
  };
  const int n = jobs > 0 ? jobs : std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (int t = 1; t < n; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();

  prune_goldens(cases, degenerate, goldens_dir, prune, &report);
  std::sort(report.lines.begin(), report.lines.end());
  return report;
}

GoldenRunSummary check_run_against_goldens(const std::vector<Case>& cases,
                                           const std::string& out_dir,
                                           const std::string& goldens_dir,
                                           const std::string& update_extra, int jobs) {
  GoldenRunSummary sum;
  const auto t0 = std::chrono::steady_clock::now();
  json report = json::object();
  report["goldens_dir"] = goldens_dir;
  report["reference_version"] = reference_version();
  json entries = json::array();
  std::pair<double, std::string> largest{0.0, ""};  // the largest deviation and its case
  auto results = read_results_json(out_dir + "/results.json");  // this run's
  std::map<std::string, const json*> by_id;
  if (results && results->contains("cases") && (*results)["cases"].is_array())
    for (const json& e : (*results)["cases"])
      if (e.contains("id") && e["id"].is_string()) by_id[e["id"].get<std::string>()] = &e;
  // The cases run, in order; their checks (two EXRs read, the input resolved, the named values
  // compared) on `jobs` threads; the lines, counts and goldens.json after, in order.
  std::vector<std::pair<const Case*, const json*>> run;
  for (const Case& c : cases) {
    auto it = by_id.find(c.id);
    if (it == by_id.end()) continue;
    const json& e = *it->second;
    if (!e.contains("images") || !e["images"].contains("reference")) continue;  // not run
    run.push_back({&c, &e});
  }
  std::vector<GoldenCheck> checks(run.size());
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t i; (i = next++) < run.size();) {
      const Case& c = *run[i].first;
      const json& e = *run[i].second;
      GoldenCheck check;
      auto ref_img = read_image(out_dir + "/" + e["images"]["reference"].get<std::string>());
      auto resolved = resolve_case(c);
      if (!ref_img || !resolved) {
        check.outcome = GoldenCheck::kRegression;
        check.message = "cannot check: " +
                        (!ref_img ? ref_img.error().to_string() : resolved.error().to_string());
      } else {
        check = check_golden(goldens_dir, c, *resolved, *ref_img, update_extra);
        if (check.outcome == GoldenCheck::kMatch) {
          // The named numbers (VisualizeHDR's text) against the sidecar's.
          auto side = read_json(golden_paths(goldens_dir, c.id).sidecar);
          std::map<std::string, double> values;
          if (e.contains("reference_values") && e["reference_values"].is_object())
            for (auto v = e["reference_values"].begin(); v != e["reference_values"].end(); ++v)
              if (v.value().is_number()) values[v.key()] = v.value().get<double>();
          if (!side || !values_equal(side->value("values", json::object()), values)) {
            check.outcome = GoldenCheck::kRegression;
            check.message =
                "golden regression: the stage's named values differ from the "
                "sidecar's (golden made by reference " +
                (side ? side->value("reference_version", "?") : std::string("?")) + ", this is " +
                reference_version() +
                "); if the change is intended: " + golden_update_command(c.id, update_extra);
          }
        }
      }
      checks[i] = std::move(check);
    }
  };
  const size_t n = std::min<size_t>(
      std::max<size_t>(1, run.size()),
      jobs > 0 ? static_cast<size_t>(jobs) : std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::thread> pool;
  for (size_t t = 1; t < n; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  for (size_t i = 0; i < run.size(); ++i) {
    const Case& c = *run[i].first;
    const GoldenCheck& check = checks[i];
    ++sum.checked;
    const char* outcome = "match";
    if (check.outcome == GoldenCheck::kMissing) {
      ++sum.missing;
      outcome = "missing";
    } else if (check.outcome == GoldenCheck::kStale) {
      ++sum.stale;
      outcome = "stale";
    } else if (check.outcome == GoldenCheck::kRegression) {
      ++sum.regressions;
      outcome = "regression";
    }
    if (check.outcome != GoldenCheck::kMatch)
      std::printf("GOLDEN %-10s %s  %s\n", outcome, c.id.c_str(), check.message.c_str());
    entries.push_back({{"id", c.id},
                       {"outcome", outcome},
                       {"message", check.message},
                       {"deviation", check.deviation}});
    if (check.deviation > largest.first) largest = {check.deviation, c.id};
  }
  report["cases"] = entries;
  report["checked"] = sum.checked;
  report["failed"] = sum.failed();
  report["largest_deviation"] = {{"deviation", largest.first}, {"id", largest.second}};
  report["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (Status st = write_file_atomic(out_dir + "/goldens.json", dump_json(report, 2) + "\n"); !st)
    std::fprintf(stderr, "error: %s\n", st.error().to_string().c_str());
  // The goldens hold the reference's outputs: the line says so, or "0 regressions" under a run
  // whose candidate failed cases reads as if the candidate had matched them.
  std::printf(
      "goldens: %d checked against %s: %d match, %d missing, %d stale, %d regressions (the "
      "reference's outputs; the candidate is judged by the cases above)\n",
      sum.checked, goldens_dir.c_str(), sum.checked - sum.failed(), sum.missing, sum.stale,
      sum.regressions);
  if (!largest.second.empty())
    std::printf("goldens: largest deviation %.3g of the bound (%s; docs/goldens.md)\n",
                largest.first, largest.second.c_str());
  std::fflush(stdout);
  return sum;
}

uintmax_t directory_bytes(const std::string& dir) {
  uintmax_t total = 0;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec);
       it != fs::recursive_directory_iterator(); ++it)
    if (it->is_regular_file()) total += it->file_size(ec);
  return total;
}

}  // namespace hdrc
