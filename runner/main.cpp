// hdrconform — golden-image conformance suite for Unreal Engine 5.5's HDR output pipeline.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "gpu/vulkan_engine.h"
#include "reference/reference_engine.h"
#include "runner/case_loader.h"
#include "runner/probe.h"
#include "runner/results.h"
#include "runner/run.h"

#ifndef HDRC_SOURCE_CASES_DIR
#error "HDRC_SOURCE_CASES_DIR must be defined by the build"
#endif

namespace {

constexpr const char* kExitCodes =
    "Exit codes:\n"
    "  0  pass: every case passed\n"
    "  1  fail: at least one case failed or errored\n"
    "  2  bad input: usage error or invalid case files (nothing was run or written)\n"
    "  3  engine unavailable: nothing failed, but the candidate engine could not start and its\n"
    "     cases were skipped (never counted as passed)\n"
    "Cases listed in cases/known_limits.json (KNOWN_LIMIT) and combinations for which UE computes\n"
    "degenerate parameters (DEGENERATE) are reported with their reason and do not change the "
    "code.\n";

void print_case_line(const hdrc::CaseResult& r, size_t index, size_t total) {
  std::printf("[%zu/%zu] %-5s %s  %s\n", index + 1, total, hdrc::verdict_name(r.verdict),
              r.spec.id.c_str(), r.reason.c_str());
  if (r.verdict == hdrc::CaseVerdict::kFail)
    std::printf("        tolerance from %s\n", r.spec.tolerance.source.c_str());
  std::fflush(stdout);
}

int load_or_report(const std::string& dir, const std::string& filter, std::vector<hdrc::Case>* out,
                   std::vector<hdrc::KnownLimit>* limits) {
  hdrc::LoadedCases loaded = hdrc::load_cases(dir);
  *limits = hdrc::load_known_limits(dir, &loaded.errors);
  if (!loaded.errors.empty()) {
    for (const auto& e : loaded.errors) std::fprintf(stderr, "error: %s\n", e.to_string().c_str());
    std::fprintf(stderr, "%zu error(s) in case files; nothing was run\n", loaded.errors.size());
    return hdrc::kExitBadInput;
  }
  for (auto& c : loaded.cases)
    if (hdrc::matches_filter(c.id, filter)) out->push_back(std::move(c));
  if (out->empty()) {
    std::fprintf(stderr, "error: no case matches --filter '%s' in %s\n", filter.c_str(),
                 dir.c_str());
    return hdrc::kExitBadInput;
  }
  return hdrc::kExitPass;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "hdrconform: conformance suite for Unreal Engine 5.5's HDR output pipeline.\n"
      "Runs a candidate engine (the GLSL/Vulkan port) and the double-precision reference on\n"
      "JSON cases and diffs them in linear and PQ space."};
  app.footer(kExitCodes);
  app.require_subcommand(1);

  std::string cases_dir = HDRC_SOURCE_CASES_DIR, filter, engine = "vulkan", out_dir = "out";
  hdrc::gpu::VulkanOptions vk;

  CLI::App* run = app.add_subcommand("run", "run cases on the reference and a candidate engine");
  run->footer(kExitCodes);
  run->add_option("--cases", cases_dir, "case directory")->capture_default_str();
  run->add_option("--filter", filter, "only cases whose id matches this glob");
  run->add_option("--engine", engine, "candidate engine")
      ->check(CLI::IsMember({"vulkan", "reference"}))
      ->capture_default_str();
  run->add_option("--out", out_dir, "output directory for results.json, junit.xml, report/")
      ->capture_default_str();
  run->add_option("--device", vk.device,
                  "Vulkan device: index or name substring (default: lavapipe)");
  run->add_option("--shader-dir", vk.shader_dir, "GLSL shader directory (default: gpu/shaders)");
  run->add_flag("--vk-validation", vk.validation, "enable the Khronos validation layer");

  CLI::App* list = app.add_subcommand("list", "list the expanded case ids");
  list->footer(kExitCodes);
  list->add_option("--cases", cases_dir, "case directory")->capture_default_str();
  list->add_option("--filter", filter, "only cases whose id matches this glob");

  CLI::App* devices = app.add_subcommand("devices", "list the Vulkan physical devices");
  devices->footer(kExitCodes);

  CLI::App* cvars = app.add_subcommand(
      "cvars", "list every supported cvar and post-process setting: type, default, range, use");
  cvars->footer(kExitCodes);

  hdrc::ProbeOptions probe_opts;
  CLI::App* probe = app.add_subcommand(
      "probe",
      "print what UE 5.5 computes for colours read as \"R G B\" lines from standard input\n"
      "(scene-linear, working colour space, at the centre of the screen: no vignette, bloom or\n"
      "dither); one \"R G B\" line out per line in, 9 significant digits");
  probe->footer(
      std::string("Example:\n  printf '0.18 0.18 0.18\\n' | hdrconform probe --set "
                  "r.HDR.EnableHDROutput=1 \\\n    --set r.HDR.Display.OutputDevice=3 --set "
                  "r.HDR.Display.ColorGamut=2\n") +
      kExitCodes);
  probe->add_option("--set", probe_opts.set, "CVAR=VALUE (repeatable)");
  probe->add_option("--setting", probe_opts.setting,
                    "post-process setting NAME=VALUE or NAME=r,g,b,a (repeatable)");
  probe
      ->add_option("--lut", probe_opts.lut,
                   "analytic: evaluate CombineLUTs directly; baked: "
                   "bake the LUT (size and format from r.LUT.Size, LUTFormat) and sample it")
      ->capture_default_str();
  probe->add_option("--stage", probe_opts.stage, "value to print: " + hdrc::probe_stage_names())
      ->capture_default_str();
  probe
      ->add_option("--ui", probe_opts.ui,
                   "--stage ui_composite: the UI pixel over each back-buffer line, premultiplied "
                   "sRGB-encoded r,g,b,a")
      ->capture_default_str();
  probe->add_flag("--json", probe_opts.json, "print a JSON document instead of lines");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? hdrc::kExitPass : hdrc::kExitBadInput;
  }

  if (*devices) {
    auto text = hdrc::gpu::list_devices();
    if (!text) {
      std::fprintf(stderr, "error: %s\n", text.error().to_string().c_str());
      return hdrc::kExitEngineUnavailable;
    }
    std::fputs(text->c_str(), stdout);
    return hdrc::kExitPass;
  }

  if (*cvars) {
    std::printf("%-44s %-6s %10s  %-22s %s\n", "cvar", "type", "default", "range", "feeds");
    for (const auto& c : hdrc::cvar_table()) {
      char range[64];
      std::snprintf(range, sizeof range, "%g .. %g", c.min_value, c.max_value);
      std::printf("%-44s %-6s %10g  %-22s %s\n", std::string(c.name).c_str(),
                  c.type == hdrc::CvarType::kInt ? "int" : "float", c.default_value, range,
                  std::string(c.feeds).c_str());
    }
    std::printf("\n%-44s %-6s %10s  %-22s %s\n", "setting", "kind", "default", "range", "feeds");
    for (const auto& s : hdrc::setting_table()) {
      char range[64], def[64];
      std::snprintf(range, sizeof range, "%g .. %g", s.min_value, s.max_value);
      if (s.components == 1)
        std::snprintf(def, sizeof def, "%g", s.default_value[0]);
      else
        std::snprintf(def, sizeof def, "%g,%g,%g,%g", s.default_value[0], s.default_value[1],
                      s.default_value[2], s.default_value[3]);
      std::printf("%-44s %-6s %10s  %-22s %s\n", std::string(s.name).c_str(),
                  s.components == 1 ? "scalar" : "vec4", def, range, std::string(s.feeds).c_str());
    }
    return hdrc::kExitPass;
  }

  if (*probe) {
    if (hdrc::Status st = hdrc::run_probe(probe_opts, std::cin, std::cout); !st) {
      std::fprintf(stderr, "error: %s\n", st.error().to_string().c_str());
      return hdrc::kExitBadInput;
    }
    return hdrc::kExitPass;
  }

  std::vector<hdrc::Case> cases;
  std::vector<hdrc::KnownLimit> limits;
  if (int code = load_or_report(cases_dir, filter, &cases, &limits); code != hdrc::kExitPass)
    return code;

  if (*list) {
    for (const auto& c : cases)
      std::printf("%s  (%s, %s)\n", c.id.c_str(), std::string(c.stage->name).c_str(),
                  c.input.describe().c_str());
    return hdrc::kExitPass;
  }

  hdrc::ref::ReferenceEngine reference;
  std::unique_ptr<hdrc::Engine> candidate;
  if (engine == "vulkan")
    candidate = std::make_unique<hdrc::gpu::VulkanEngine>(vk);
  else
    candidate = std::make_unique<hdrc::ref::ReferenceEngine>();

  hdrc::RunReport report = hdrc::run_cases(cases, reference, *candidate, limits, print_case_line);
  if (!report.candidate_unavailable.empty())
    std::printf("candidate unavailable: %s\n", report.candidate_unavailable.c_str());
  if (hdrc::Status st = hdrc::write_run_outputs(report, out_dir); !st) {
    std::fprintf(stderr, "error: %s\n", st.error().to_string().c_str());
    return hdrc::kExitFail;
  }
  std::error_code ec;
  const std::string report_path =
      std::filesystem::absolute(out_dir + "/report/index.html", ec).lexically_normal().string();
  std::printf(
      "hdrconform: %zu cases: %d passed, %d failed, %d errors, %d skipped, %d known limits, %d "
      "degenerate in %.1f s on %s (%s)\n",
      report.cases.size(), report.count(hdrc::CaseVerdict::kPass),
      report.count(hdrc::CaseVerdict::kFail), report.count(hdrc::CaseVerdict::kError),
      report.count(hdrc::CaseVerdict::kSkipped), report.count(hdrc::CaseVerdict::kKnownLimit),
      report.count(hdrc::CaseVerdict::kDegenerate), report.wall_seconds,
      report.candidate_device.device.c_str(), report.candidate_device.driver.c_str());
  std::printf("report: %s\n", report_path.c_str());
  return report.exit_code();
}
