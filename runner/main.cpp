// hdrconform — golden-image conformance suite for Unreal Engine 5.5's HDR output pipeline.
#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "core/install_paths.h"
#include "core/nearest.h"
#include "core/pipeline.h"
#include "core/utf8.h"
#include "gpu/vulkan_engine.h"
#include "reference/reference_engine.h"
#include "report/html_report.h"
#include "runner/budget.h"
#include "runner/case_loader.h"
#include "runner/coverage.h"
#include "runner/export.h"
#include "runner/goldens.h"
#include "runner/goldens_diff.h"
#include "runner/lut_cli.h"
#include "runner/merge.h"
#include "runner/output_set.h"
#include "runner/probe.h"
#include "runner/provenance.h"
#include "runner/results.h"
#include "runner/run.h"
#include "runner/selection.h"
#include "runner/verify.h"

#ifndef HDRC_SOURCE_CASES_DIR
#error "HDRC_SOURCE_CASES_DIR must be defined by the build"
#endif

namespace {

constexpr const char* kExitCodes =
    "Exit codes:\n"
    "  0  pass: every case passed\n"
    "  1  fail: at least one case failed or errored, or (run) a golden failed, or (verify) had\n"
    "     no candidate image, or (verify --require-all) was declined by the candidate\n"
    "     (UNSUPPORTED)\n"
    "  2  bad input: usage error or invalid case files (nothing was run or written)\n"
    "  3  engine unavailable: nothing failed, but the candidate engine could not start and its\n"
    "     cases were skipped (never counted as passed)\n"
    "  4  pass with warnings: every case passed, at least one over a tolerance's warn level\n"
    "  130  interrupted (Ctrl-C): finished cases are written, the rest are NOT_RUN\n"
    "Cases listed in cases/known_limits.json (KNOWN_LIMIT) and combinations for which UE computes\n"
    "degenerate parameters (DEGENERATE) are reported with their reason and do not change the "
    "code.\n";

std::vector<std::string> pipeline_list() {
  std::vector<std::string> names;
  for (const hdrc::Pipeline* p : hdrc::pipeline_table()) names.emplace_back(p->name);
  return names;
}

int load_or_report(const std::string& dir, const hdrc::CaseSelection& filter,
                   std::vector<hdrc::Case>* out, std::vector<hdrc::KnownLimit>* limits,
                   const std::string& suite = "quick") {
  hdrc::LoadedCases loaded = hdrc::load_cases(dir, suite);
  *limits = hdrc::load_known_limits(dir, &loaded.errors);
  if (!loaded.errors.empty()) {
    for (const auto& e : loaded.errors) std::fprintf(stderr, "error: %s\n", e.to_string().c_str());
    std::fprintf(stderr, "%zu error(s) in case files; nothing was run\n", loaded.errors.size());
    return hdrc::kExitBadInput;
  }
  for (const auto& c : loaded.cases)
    if (filter.matches(c)) out->push_back(c);
  if (out->empty()) {
    const std::string msg = hdrc::no_match_message(filter, loaded.cases, dir);
    if (filter.rerun_ids && filter.rerun_ids->empty()) {  // nothing failed: nothing to rerun
      std::printf("%s; nothing to rerun\n", msg.c_str());
      return -1;
    }
    std::fprintf(stderr, "error: %s\n", msg.c_str());
    return hdrc::kExitBadInput;
  }
  return hdrc::kExitPass;
}

// "Unreal Engine 5.5 HDR output, Unity URP colour grading, ...": every registered pipeline's
// title, so the top-level help names each one (a new pipeline touches no runner code).
std::string pipeline_titles() {
  std::string out;
  for (const hdrc::Pipeline* p : hdrc::pipeline_table())
    out += (out.empty() ? "" : ", ") + std::string(p->title);
  return out;
}

// -j/--jobs: a whole number 0..1024, with a message that says which (CLI11's Range says "Value
// two not in range" for a word).
CLI::Validator jobs_check() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        long v = 0;
        const char* end = text.data() + text.size();
        const auto [p, ec] = std::from_chars(text.data(), end, v);
        if (text.empty() || ec != std::errc() || p != end)
          return "'" + text +
                 "' is not a whole number: give the number of worker threads, 0 (every core) "
                 "to 1024";
        if (v < 0 || v > 1024)
          return "'" + text + "' is out of range: 0 (every core) to 1024 worker threads";
        return "";
      },
      "INT in [0 - 1024]");
}

// The subcommand the command line names, deepest first (`goldens update`), else the app.
const CLI::App* named_subcommand(const CLI::App& app, int argc, char** argv) {
  const CLI::App* at = &app;
  for (int i = 1; i < argc; ++i) {
    for (const CLI::App* sub : at->get_subcommands([](const CLI::App*) { return true; }))
      if (sub->get_name() == argv[i]) {
        at = sub;
        break;
      }
  }
  return at;
}

// For CLI11's "arguments were not expected": the first --option that the named subcommand does
// not have, with the nearest one it has ("unknown option '--filtr' for 'run'; did you mean
// '--filter'?"). Empty where every --option is known (the extra is a positional argument).
std::string unknown_option_hint(const CLI::App& app, int argc, char** argv) {
  const CLI::App* sub = named_subcommand(app, argc, argv);
  std::vector<std::string> known;
  for (const CLI::App* a = sub; a; a = a->get_parent())
    for (const CLI::Option* o : a->get_options())
      for (const std::string& n : o->get_lnames()) known.push_back(n);
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.size() < 3 || arg.compare(0, 2, "--") != 0) continue;
    const size_t eq = arg.find('=');  // --name=value
    const std::string name = arg.substr(2, eq == std::string::npos ? eq : eq - 2);
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    const std::string where = sub == &app ? "hdrconform" : "'" + sub->get_name() + "'";
    // A prefix of one option, or within 2 edits (a typo, not another word: "--bogus" is 3 edits
    // from "--jobs").
    std::string near = hdrc::closest_command(name, known);
    if (!near.empty() && near.compare(0, name.size(), name) != 0 &&
        hdrc::edit_distance(name, near) > 2)
      near.clear();
    return "unknown option '--" + name + "' for " + where +
           (near.empty() ? "; --help lists its options" : "; did you mean '--" + near + "'?");
  }
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  hdrc::restore_library_path();  // a bundle's launcher: its lib/ is for this process only
  // A bundle (scripts/bundle.sh) replaces OpenImageIO's format libraries other than OpenEXR's and
  // PNG's by stubs that abort when called. OpenImageIO tries every other reader when the one its
  // extension names cannot open a file (a damaged PNG would reach libtiff's stub): there, only
  // that one reader (OpenImageIO imageio.h, attribute "try_all_readers").
  if (!hdrc::installed_data_dir().empty()) OIIO::attribute("try_all_readers", 0);
  CLI::App app{"hdrconform: conformance suite for HDR output pipelines (" + pipeline_titles() +
               ": hdrconform pipelines).\n"
               "Runs a candidate engine (the GLSL/Vulkan port) and the double-precision reference "
               "on\nJSON cases and diffs them in linear and PQ space."};
  app.footer(kExitCodes);
  app.require_subcommand(1);

  // The source tree's cases/, or a bundle's share/hdrconform/cases (core/install_paths.h).
  const std::string default_cases_dir = hdrc::data_dir(HDRC_SOURCE_CASES_DIR, "cases");
  std::string cases_dir = default_cases_dir, filter, engine = "vulkan", out_dir = "out";
  hdrc::gpu::VulkanOptions vk;

  // --filter: repeatable, comma-separated patterns (runner/selection.h); CLI11 joins repeats.
  const std::string filter_help =
      "only cases matching any pattern: a glob (* ? [) over the whole id, =ID exactly, else a "
      "substring of the id; repeatable, comma-separated";
  auto add_filter = [&](CLI::App* sub) {
    sub->add_option("--filter", filter, filter_help)
        ->multi_option_policy(CLI::MultiOptionPolicy::Join);
  };
  // CI systems set CI (GitHub Actions, GitLab, Jenkins' plugins: "true"); CI=0 / CI=false / CI=""
  // mean not CI.
  const char* ci = std::getenv("CI");
  const bool in_ci = ci && *ci && std::string(ci) != "0" && std::string(ci) != "false";
  std::string rerun_failed, images = in_ci ? "failing" : "all", timings;
  const std::string images_help =
      "case images kept in OUT/cases and shown in the report: failing (FAIL, ERROR, MISSING or a "
      "failed golden), all, none (default: failing when CI is set to other than \"\", 0 or false, "
      "else "
      "all)";
  const std::string timings_help =
      "a results.json whose per-case seconds balance --shard (default: OUT/results.json when "
      "present; without timings a static cost model); give every shard the same file";

  int jobs = 0;
  double memory_budget_gb = 0, time_budget_s = 0;
  std::string shard;
  const std::string jobs_help = "worker threads, each with its own engines (default: every core)";
  const std::string shard_help =
      "run shard K of N (1-based): the cases are split into N parts of about equal cost (the "
      "last run's seconds with --timings, else a static cost model), deterministically";
  // The options several subcommands share.
  std::string pipeline_filter;
  auto add_cases = [&](CLI::App* sub) {
    sub->add_option("--cases", cases_dir, "case directory")->capture_default_str();
    add_filter(sub);
    sub->add_option("--pipeline", pipeline_filter,
                    "only the cases of these pipelines (comma-separated; hdrconform pipelines): " +
                        hdrc::pipeline_names())
        ->multi_option_policy(CLI::MultiOptionPolicy::Join);
  };
  auto add_jobs = [&](CLI::App* sub) {
    sub->add_option("-j,--jobs", jobs, jobs_help)->check(jobs_check());
  };
  auto add_shard = [&](CLI::App* sub) {
    sub->add_option("--shard", shard, shard_help);
    sub->add_option("--timings", timings, timings_help);
  };
  // run and verify: which cases, in which order, and what their output folder keeps.
  hdrc::SuiteOptions suite;  // the options run_suite takes (runner/verify.h)
  auto add_run_outputs = [&](CLI::App* sub, const std::string& failed) {
    add_cases(sub);
    sub->add_option("--rerun-failed", rerun_failed,
                    "only the cases DIR/results.json lists as failed (" + failed + ")");
    sub->add_option(
        "--failed-first", suite.failed_first_dir,
        "the cases DIR/results.json lists as failed (" + failed + ") run first, then the others");
    sub->add_option("--maxfail", suite.max_fail,
                    "start no case after N cases failed (FAIL, ERROR, MISSING); the rest are "
                    "NOT_RUN, the output is complete, exit 1")
        ->check(CLI::Range(1, 1000000));
    sub->add_option("--images", images, images_help)
        ->check(CLI::IsMember({"failing", "all", "none"}));
    sub->add_option("--out", out_dir, "output directory for results.json, junit.xml, report/")
        ->capture_default_str();
    add_jobs(sub);
    add_shard(sub);
    sub->add_option("--memory-budget", memory_budget_gb,
                    "GB the run may hold (default: 1.5 per case, and the machine's available "
                    "memory and address-space limit for the run): a case estimated over it is "
                    "refused before any work, and -j runs fewer large cases at once "
                    "(runner/budget.h)")
        ->check(CLI::Range(0.001, 1e6));
    sub->add_option("--time-budget", time_budget_s,
                    "CPU seconds a case may take (default 60): a case estimated over it is refused "
                    "before any work")
        ->check(CLI::Range(0.001, 1e9));
  };

  CLI::App* run = app.add_subcommand("run", "run cases on the reference and a candidate engine");
  run->footer(kExitCodes);
  add_run_outputs(run, "FAIL, ERROR, MISSING, golden");
  run->add_option("--engine", engine, "candidate engine")
      ->check(CLI::IsMember({"vulkan", "reference"}))
      ->capture_default_str();
  run->add_option("--device", vk.device,
                  "Vulkan device: index or name substring (default: lavapipe)");
  run->add_option("--shader-dir", vk.shader_dir, "GLSL shader directory (default: gpu/shaders)");
  run->add_flag("--vk-validation", vk.validation, "enable the Khronos validation layer");
  run->add_option("--device-model", vk.device_model,
                  "none, or worst: the Vulkan device run as the worst-case conformant device "
                  "(docs/precision.md, \"The worst-case device\")")
      ->transform(CLI::CheckedTransformer(std::map<std::string, hdrc::DeviceModel>{
          {"none", hdrc::DeviceModel::kNone}, {"worst", hdrc::DeviceModel::kWorst}}))
      ->default_str("none");

  // Goldens (runner/goldens.h): `run` checks the reference against them; `goldens update` is the
  // only command that writes them. Default: goldens/ beside the default cases/ directory.
  std::string goldens_dir;
  bool no_goldens = false;
  run->add_option("--goldens", goldens_dir,
                  "golden directory the reference is checked against (default: the repository's "
                  "goldens/ with the default --cases; no check with another --cases)");
  run->add_flag("--no-goldens", no_goldens, "skip the golden check");
  std::string run_reference = "baked";
  run->add_option("--reference", run_reference,
                  "baked (UE's LUT) or analytic (per-pixel CombineLUTs: a port without a LUT; no "
                  "golden check)")
      ->check(CLI::IsMember({"baked", "analytic"}))
      ->capture_default_str();

  CLI::App* coverage = app.add_subcommand(
      "coverage",
      "print, per cvar and setting, every declared value (cases/coverage.json) and the cases that\n"
      "run with it, and the required combinations between them; fails if anything is uncovered");
  coverage->footer(kExitCodes);
  coverage->add_option("--cases", cases_dir, "case directory")->capture_default_str();
  std::string coverage_pipeline = "ue55";
  coverage
      ->add_option("--pipeline", coverage_pipeline,
                   "the pipeline whose declaration (coverage.json for ue55, "
                   "coverage_<pipeline>.json for the others) its cases are checked against")
      ->check(CLI::IsMember(pipeline_list()))
      ->capture_default_str();

  // The suite tier (docs/cases.md): quick (the default suite) or exhaustive (both tiers).
  std::string suite_name = "quick";
  const std::string suite_help = "quick (the default suite) or exhaustive (every tier)";
  for (CLI::App* sub : {run, coverage})
    sub->add_option("--suite", suite_name, suite_help)->capture_default_str();

  CLI::App* goldens = app.add_subcommand("goldens", "manage the reference goldens (goldens/)");
  goldens->footer(kExitCodes);
  goldens->require_subcommand(1);
  CLI::App* goldens_update = goldens->add_subcommand(
      "update",
      "run the reference on the cases and write their outputs to the golden directory (32-bit\n"
      "float EXR + a JSON sidecar each); goldens whose hashes and reference version are unchanged\n"
      "are left as they are; without --filter, goldens of cases no longer in the suite are "
      "removed");
  goldens_update->footer(kExitCodes);
  add_cases(goldens_update);
  goldens_update->add_option("--goldens", goldens_dir,
                             "golden directory (default: the repository's goldens/)");
  add_jobs(goldens_update);
  // goldens diff: the review page of a golden change (runner/goldens_diff.h).
  std::string goldens_since = "HEAD", goldens_old;
  CLI::App* goldens_diff = goldens->add_subcommand(
      "diff",
      "write a review page of the goldens that changed: the goldens of git revision --since\n"
      "(default HEAD) or of --old DIR against the working tree's, each changed one with the\n"
      "report's views (old as the reference, new as the candidate) and its ramp plot");
  goldens_diff->footer(kExitCodes);
  goldens_diff->add_option("--cases", cases_dir, "case directory (the goldens' cases)")
      ->capture_default_str();
  goldens_diff->add_option("--goldens", goldens_dir,
                           "the new goldens (default: the repository's goldens/)");
  goldens_diff->add_option("--since", goldens_since,
                           "git revision holding the old goldens (default HEAD)");
  goldens_diff->add_option("--old", goldens_old,
                           "a folder of old goldens instead of a git revision");
  goldens_diff->add_option("--out", out_dir, "output directory: review.html, report/, cases/")
      ->required();
  add_jobs(goldens_diff);

  CLI::App* list = app.add_subcommand("list", "list the expanded case ids");
  list->footer(kExitCodes);
  add_cases(list);
  add_shard(list);
  list->add_option("--suite", suite_name, suite_help)->capture_default_str();
  bool list_long = false;
  list->add_flag("--long", list_long, "each id with its stage and input");

  CLI::App* export_cmd = app.add_subcommand(
      "export",
      "write each case's input image(s) and resolved parameters (params.json: every value the\n"
      "shaders need) under DIR/cases/<case id>/, so another engine can render the same cases");
  export_cmd->footer(kExitCodes);
  add_cases(export_cmd);
  add_shard(export_cmd);
  export_cmd->add_option("--out", out_dir, "output directory")->required();

  std::string candidate_dir, candidate_cmd;
  double cmd_timeout = 120;
  CLI::App* verify = app.add_subcommand(
      "verify",
      "judge another engine's output images against the reference: found in a directory\n"
      "(DIR/<case id>.exr) or written by a command run once per case");
  verify->footer(
      std::string(
          "TEMPLATE is split into words like a shell would (quotes, backslash) but run without\n"
          "one; {input}, {params}, {output} and {id} are replaced inside each word. Example:\n"
          "  hdrconform verify --candidate-cmd 'my_port --params {params} --in {input} --out "
          "{output}'\n"
          "The command exits 0 after writing {output}, 77 to decline the case, 78 to decline its\n"
          "whole stage (UNSUPPORTED: never a pass; fails the run only with --require-all).\n"
          "Contract: docs/candidate-protocol.md, params.json schema: "
          "runner/params.schema.json.\n") +
      kExitCodes);
  add_run_outputs(verify, "FAIL, ERROR, MISSING");
  auto* dir_opt = verify->add_option("--candidate-dir", candidate_dir,
                                     "directory of candidate images DIR/<case id>.exr");
  auto* cmd_opt = verify->add_option("--candidate-cmd", candidate_cmd,
                                     "command TEMPLATE run per case (see below)");
  dir_opt->excludes(cmd_opt);
  verify->add_option("--timeout", cmd_timeout, "seconds a candidate command may take per case")
      ->check(CLI::Validator(hdrc::check_timeout_seconds, "SECONDS"))
      ->capture_default_str();
  verify->add_flag("--require-all", suite.require_all,
                   "fail the run when the candidate declines a case (UNSUPPORTED)");
  verify->add_option("--candidate-limits", suite.candidate_limits,
                     "the candidate's declared deviations (known_limits.json's form)");
  verify
      ->add_option("--reference", suite.reference,
                   "baked (UE's LUT) or analytic (per-pixel CombineLUTs, for ports without a "
                   "LUT)")
      ->check(CLI::IsMember({"baked", "analytic"}))
      ->capture_default_str();
  bool no_device_allowance = false;
  for (CLI::App* sub : {run, verify})
    sub->add_flag("--no-device-allowance", no_device_allowance,
                  "reference-grade results: a case outside the float32-exact bounds fails even "
                  "where a conformant device with the candidate's precision may produce its "
                  "values (docs/precision.md, \"Device allowances\")");
  bool sandbox = false;
  verify->add_flag("--sandbox", sandbox,
                   "run each candidate command under bubblewrap (bwrap): the system read-only, "
                   "no network, only its case folder writable");

  CLI::App* devices = app.add_subcommand("devices", "list the Vulkan physical devices");
  devices->footer(kExitCodes);

  CLI::App* cvars = app.add_subcommand(
      "cvars", "list every supported cvar and setting of a pipeline: type, default, range, use");
  cvars->footer(kExitCodes);
  std::string cvars_pipeline = "ue55";
  cvars->add_option("--pipeline", cvars_pipeline, "the pipeline (hdrconform pipelines)")
      ->check(CLI::IsMember(pipeline_list()))
      ->capture_default_str();

  CLI::App* pipelines_cmd =
      app.add_subcommand("pipelines", "list the pipelines: their stages, passes and sources");
  pipelines_cmd->footer(kExitCodes);

  hdrc::ProbeOptions probe_opts;
  CLI::App* probe = app.add_subcommand(
      "probe",
      "print what a pipeline's reference computes for colours read as \"R G B\" lines from\n"
      "standard input, one \"R G B\" line out per line in, 9 significant digits: --pipeline\n"
      "picks it (" +
          hdrc::pipeline_names() +
          "; default ue55: scene-linear, working colour space,\n"
          "at the centre of the screen: no vignette, bloom or dither)");
  probe->footer(
      std::string("Example:\n  printf '0.18 0.18 0.18\\n' | hdrconform probe --set "
                  "r.HDR.EnableHDROutput=1 \\\n    --set r.HDR.Display.OutputDevice=3 --set "
                  "r.HDR.Display.ColorGamut=2\n") +
      kExitCodes);
  probe->add_option("--set", probe_opts.set, "CVAR=VALUE (repeatable; ue55, ue58)");
  probe->add_option("--setting", probe_opts.setting,
                    "post-process setting NAME=VALUE or NAME=r,g,b,a (repeatable)");
  probe
      ->add_option("--lut", probe_opts.lut,
                   "analytic: evaluate CombineLUTs directly; baked: "
                   "bake the LUT (size and format from r.LUT.Size, LUTFormat) and sample it")
      ->capture_default_str();
  probe
      ->add_option("--pipeline", probe_opts.pipeline,
                   "the pipeline (hdrconform pipelines); for one other than ue55 the colours go "
                   "through its reference for --stage (default: its last stage that reads colours)")
      ->check(CLI::IsMember(pipeline_list()))
      ->capture_default_str();
  probe->add_option("--stage", probe_opts.stage, "value to print: " + hdrc::probe_stage_names())
      ->capture_default_str();
  probe
      ->add_option("--ui", probe_opts.ui,
                   "--stage ui_composite (ue58: ue58_ui_composite): the UI pixel over each "
                   "back-buffer line, premultiplied sRGB-encoded r,g,b,a")
      ->capture_default_str();
  probe->add_flag("--json", probe_opts.json,
                  "print a JSON document instead of lines (ue55: the --stage value; operators, "
                  "pq_grading, unity_urp: every named value of docs/spec/<pipeline>.md; ue58: "
                  "those of --stage ue58_ui_composite, with --set cvars and --ui)");
  probe->add_option("--cube", probe_opts.cube,
                    "a stage that takes a user LUT (docs/cases.md): the .cube file, sampled as the "
                    "engines sample a case's \"lut\"");

  std::string report_dir;
  CLI::App* report_cmd = app.add_subcommand(
      "report",
      "rebuild RESULTS_DIR/report/ (the HTML report) from RESULTS_DIR/results.json and the case\n"
      "images beside it");
  report_cmd->footer(kExitCodes);
  report_cmd->add_option("RESULTS_DIR", report_dir, "a directory written by `hdrconform run --out`")
      ->required();
  report_cmd->add_option("-j,--jobs", jobs, "threads building the case pages (default: every core)")
      ->check(jobs_check());

  std::string merge_out;
  std::vector<std::string> merge_dirs;
  CLI::App* merge_cmd = app.add_subcommand(
      "merge",
      "merge the outputs of `run --shard K/N` (every K of one N, same suite and build) into one\n"
      "results.json, junit.xml, case images and report in OUT, as one unsharded run writes them");
  merge_cmd->footer(kExitCodes);
  merge_cmd->add_option("OUT", merge_out, "output directory")->required();
  merge_cmd->add_option("DIR", merge_dirs, "the shards' output directories")->required();

  hdrc::lut::add_lut_command(app);  // `lut convert | info | apply`: runs and exits inside parse

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    std::vector<std::string> names;
    for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
      names.push_back(sub->get_name());
    if (const std::string near = argc > 1 ? hdrc::closest_command(argv[1], names) : "";
        !near.empty() && std::find(names.begin(), names.end(), argv[1]) == names.end()) {
      std::fprintf(stderr, "error: unknown command '%s'; did you mean '%s'?\n", argv[1],
                   near.c_str());
      return hdrc::kExitBadInput;
    }
    if (dynamic_cast<const CLI::ExtrasError*>(&e)) {
      if (const std::string hint = unknown_option_hint(app, argc, argv); !hint.empty()) {
        std::fprintf(stderr, "error: %s\n", hint.c_str());
        return hdrc::kExitBadInput;
      }
    }
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

  if (*pipelines_cmd) {
    for (const hdrc::Pipeline* p : hdrc::pipeline_table()) {
      std::printf("%s  %s%s\n  %s\n  sources: %s\n  %zu cvars, %zu settings\n",
                  std::string(p->name).c_str(), std::string(p->title).c_str(),
                  p == &hdrc::default_pipeline() ? " (the default pipeline of a case)" : "",
                  std::string(p->description).c_str(), std::string(p->sources).c_str(),
                  p->cvars().size(), p->settings().size());
      for (const hdrc::StageInfo& st : p->stages()) {
        std::string passes;
        for (const hdrc::StagePass& pass : st.passes)
          passes += (passes.empty() ? "" : " -> ") + std::string(pass.shader);
        std::printf("    %-16s %s\n    %-16s passes: %s\n", std::string(st.name).c_str(),
                    std::string(st.description).c_str(), "", passes.c_str());
      }
      std::printf("\n");
    }
    return hdrc::kExitPass;
  }

  if (*cvars) {
    const hdrc::Pipeline& pipeline = *hdrc::find_pipeline(cvars_pipeline);
    std::printf("%-44s %-6s %10s  %-22s %s\n", "cvar", "type", "default", "range", "feeds");
    for (const auto& c : pipeline.cvars()) {
      char range[64];
      std::snprintf(range, sizeof range, "%g .. %g", c.min_value, c.max_value);
      std::printf("%-44s %-6s %10g  %-22s %s\n", std::string(c.name).c_str(),
                  c.type == hdrc::CvarType::kInt ? "int" : "float", c.default_value, range,
                  std::string(c.feeds).c_str());
    }
    std::printf("\n%-44s %-6s %10s  %-22s %s\n", "setting", "kind", "default", "range", "feeds");
    const hdrc::SettingValues settings = pipeline.new_settings();
    for (const auto& s : pipeline.settings()) {
      char range[64], def[64];
      std::snprintf(range, sizeof range, "%g .. %g", s.min_value, s.max_value);
      if (s.components == 1)
        std::snprintf(def, sizeof def, "%g", s.default_value[0]);
      else
        std::snprintf(def, sizeof def, "%g,%g,%g,%g", s.default_value[0], s.default_value[1],
                      s.default_value[2], s.default_value[3]);
      const std::string named = settings.choices_text(s.name);
      std::printf("%-44s %-6s %10s  %-22s %s%s\n", std::string(s.name).c_str(),
                  s.components == 1 ? "scalar" : "vec4", def, range, std::string(s.feeds).c_str(),
                  named.empty() ? "" : (" [" + named + "]").c_str());
    }
    return hdrc::kExitPass;
  }

  if (*report_cmd) {
    // Nothing is written into a folder that holds no run's results (`report CASES` used to leave
    // CASES/.lock): its results.json is read before the lock is taken; the report is built from
    // the copy made under it.
    if (auto doc = hdrc::read_results_json(report_dir + "/results.json"); !doc) {
      std::fprintf(stderr, "error: %s\n", doc.error().to_string().c_str());
      return hdrc::kExitBadInput;
    }
    // Rebuilt like a run is published (runner/output_set.h): a copy of the folder without its
    // report (hard links), the new report written there, the copy swapped in whole; not while
    // a run publishes there (the lock).
    auto set = hdrc::OutputSet::open(report_dir, {}, "RESULTS_DIR", {"report"});
    if (!set) {
      std::fprintf(stderr, "error: %s\n", set.error().to_string().c_str());
      return hdrc::kExitBadInput;
    }
    auto info = hdrc::write_report((*set)->staging(), jobs);
    if (!info) {
      std::fprintf(stderr, "error: %s\n", info.error().to_string().c_str());
      return hdrc::kExitBadInput;
    }
    if (hdrc::Status st = (*set)->publish(); !st) {
      std::fprintf(stderr, "error: %s\n", st.error().to_string().c_str());
      return hdrc::kExitFail;
    }
    info->index_path = report_dir + "/report/index.html";
    std::error_code ec;
    std::printf("report: %zu cases, %zu files, %.1f MB in %.2f s (CPU %.2f s)\nreport: %s\n",
                info->cases, info->files, info->bytes / 1e6, info->seconds, info->cpu_seconds,
                std::filesystem::absolute(info->index_path, ec).lexically_normal().c_str());
    return hdrc::kExitPass;
  }

  if (*merge_cmd) {
    // OUT is checked as run's --out (runner/merge.h): the repository's cases and goldens folders
    // are protected here, the folders the shards ran on by merge itself.
    std::error_code ec;
    const std::string default_goldens =
        std::filesystem::weakly_canonical(
            std::filesystem::path(default_cases_dir) / ".." / "goldens", ec)
            .generic_string();
    return hdrc::merge_runs(merge_out, merge_dirs, {default_cases_dir, default_goldens});
  }

  if (*probe) {
    std::ios::sync_with_stdio(false);  // buffered std::cin/std::cout: 1e6 lines in about a second
    if (hdrc::Status st = hdrc::run_probe(probe_opts, std::cin, std::cout); !st) {
      std::fprintf(stderr, "error: %s\n", st.error().to_string().c_str());
      return hdrc::kExitBadInput;
    }
    return hdrc::kExitPass;
  }

  std::vector<hdrc::Case> cases;
  std::vector<hdrc::KnownLimit> limits;
  auto selection = hdrc::make_selection(filter, rerun_failed, pipeline_filter);
  if (!selection) {
    std::fprintf(stderr, "error: %s\n", selection.error().to_string().c_str());
    return hdrc::kExitBadInput;
  }
  if (!suite.failed_first_dir.empty()) {  // read like --rerun-failed's (bounded, schema-checked)
    auto ids = hdrc::failed_case_ids(suite.failed_first_dir);
    if (!ids) {
      std::fprintf(stderr, "error: --failed-first: %s\n", ids.error().to_string().c_str());
      return hdrc::kExitBadInput;
    }
    suite.failed_first = std::move(*ids);
  }
  // The per-case budget the loader checks every case against (runner/budget.h).
  if (memory_budget_gb > 0 || time_budget_s > 0)
    hdrc::set_case_budget(
        memory_budget_gb > 0 ? memory_budget_gb * 1e9 : hdrc::kCaseMemoryBudgetBytes,
        time_budget_s > 0 ? time_budget_s : hdrc::kCaseCpuBudgetSeconds);
  if (int code = load_or_report(cases_dir, *selection, &cases, &limits, suite_name);
      code != hdrc::kExitPass)
    return code < 0 ? hdrc::kExitPass : code;
  // --shard's cost model: --timings, else the last run's results in --out (runner/run.h).
  if (hdrc::Status st = hdrc::use_shard_timings(timings, out_dir); !st) {
    std::fprintf(stderr, "error: --timings: %s\n", st.error().to_string().c_str());
    return hdrc::kExitBadInput;
  }

  // The golden directory, and the options `goldens update` needs to find the same cases again.
  namespace fs = std::filesystem;
  std::error_code gec;
  const bool default_cases =
      fs::weakly_canonical(cases_dir, gec) == fs::weakly_canonical(default_cases_dir, gec);
  std::string golden_extra;
  if (!default_cases) golden_extra += "--cases " + cases_dir;
  if (!goldens_dir.empty())
    golden_extra += std::string(golden_extra.empty() ? "" : " ") + "--goldens " + goldens_dir;
  if (goldens_dir.empty() && default_cases)
    goldens_dir =
        fs::weakly_canonical(fs::path(default_cases_dir) / ".." / "goldens", gec).generic_string();

  // Folders this command writes are checked before any work (runner/output_set.h); run and
  // verify write a staging folder inside --out and publish it at the end (finish).
  std::unique_ptr<hdrc::OutputSet> outset;
  if (hdrc::Status st =
          hdrc::check_output_folders(*run || *verify, bool(*export_cmd), bool(*goldens_update),
                                     out_dir, cases_dir, goldens_dir, &outset);
      !st) {
    std::fprintf(stderr, "error: %s\n", st.error().to_string().c_str());
    return hdrc::kExitBadInput;
  }

  if (*coverage) {
    std::vector<hdrc::Error> errors;
    const hdrc::Pipeline& pipeline = *hdrc::find_pipeline(coverage_pipeline);
    const hdrc::CoverageSpec spec = hdrc::load_coverage_spec(
        cases_dir, &errors, hdrc::coverage_file_name(pipeline, suite_name), &pipeline);
    for (const auto& e : errors) std::fprintf(stderr, "error: %s\n", e.to_string().c_str());
    if (!errors.empty()) return hdrc::kExitBadInput;
    const hdrc::CoverageReport rep = hdrc::compute_coverage(spec, cases);
    const size_t own = std::count_if(cases.begin(), cases.end(), [&](const hdrc::Case& c) {
      return &hdrc::pipeline_of(*c.stage) == &pipeline;
    });
    std::printf("%zu cases of pipeline %s\n%s", own, coverage_pipeline.c_str(), rep.text().c_str());
    return rep.complete() ? hdrc::kExitPass : hdrc::kExitFail;
  }

  if (*goldens_update) {
    if (goldens_dir.empty()) {
      std::fprintf(stderr,
                   "error: --goldens DIR is required with --cases %s (the repository's goldens/ "
                   "belong to its cases/)\n",
                   cases_dir.c_str());
      return hdrc::kExitBadInput;
    }
    const hdrc::GoldenUpdateReport rep = hdrc::update_goldens(
        cases, goldens_dir, /*prune=*/filter.empty() && pipeline_filter.empty(), jobs);
    for (const auto& l : rep.lines) std::printf("%s\n", l.c_str());
    for (const auto& e : rep.errors) std::fprintf(stderr, "error: %s\n", e.to_string().c_str());
    std::printf(
        "goldens: %d written, %d unchanged, %d removed, %d degenerate cases (no golden); "
        "reference %s; %s holds %.1f MB\n",
        rep.written, rep.unchanged, rep.removed, rep.skipped_degenerate,
        hdrc::reference_version().c_str(), goldens_dir.c_str(),
        hdrc::directory_bytes(goldens_dir) / 1e6);
    if (rep.changed > 0) {
      // How far the changed goldens moved, and the page that shows it (runner/goldens_diff.h).
      std::printf(
          "goldens: %d changed; largest move PQ %.3g (10-bit codes, %s), ΔE_ITP %.3g (%s)\n",
          rep.changed, rep.largest_pq10.first, rep.largest_pq10.second.c_str(),
          rep.largest_itp.first, rep.largest_itp.second.c_str());
      std::printf(
          "goldens: review the change: hdrconform goldens diff%s --out DIR (DIR/review.html)\n",
          golden_extra.empty() ? "" : (" " + golden_extra).c_str());
    }
    return rep.errors.empty() ? hdrc::kExitPass : hdrc::kExitFail;
  }

  if (*goldens_diff) {
    if (goldens_dir.empty()) {
      std::fprintf(stderr,
                   "error: --goldens DIR is required with --cases %s (the repository's goldens/ "
                   "belong to its cases/)\n",
                   cases_dir.c_str());
      return hdrc::kExitBadInput;
    }
    if (!goldens_old.empty() && goldens_diff->count("--since")) {
      std::fprintf(stderr, "error: --since and --old: give one (the old goldens' source)\n");
      return hdrc::kExitBadInput;
    }
    // Published like a run's output (runner/output_set.h): the cases, the goldens and --old are
    // protected and must not change while the page is written.
    std::vector<std::string> watched = {cases_dir, goldens_dir};
    if (!goldens_old.empty()) watched.push_back(goldens_old);
    auto set = hdrc::OutputSet::open(out_dir, watched);
    if (!set) {
      std::fprintf(stderr, "error: %s\n", set.error().to_string().c_str());
      return hdrc::kExitBadInput;
    }
    hdrc::GoldensDiffOptions opt;
    opt.goldens_dir = goldens_dir;
    opt.old_dir = goldens_old;
    opt.since = goldens_since;
    opt.command_line = hdrc::command_line(argc, argv);
    opt.jobs = jobs;
    auto rep = hdrc::goldens_diff(cases, opt, (*set)->staging());
    if (!rep) {
      std::fprintf(stderr, "error: %s\n", rep.error().to_string().c_str());
      return hdrc::kExitBadInput;
    }
    if (hdrc::Status st = (*set)->publish(); !st) {
      std::fprintf(stderr, "error: %s\n", st.error().to_string().c_str());
      return hdrc::kExitFail;
    }
    for (const auto& l : rep->lines) std::printf("%s\n", l.c_str());
    std::error_code ec;
    std::printf(
        "goldens diff: %d changed, %d added, %d removed, %d with the same pixels, %d without a "
        "case (old: %s)\nreview: %s\n",
        rep->changed, rep->added, rep->removed, rep->bytes_only, rep->no_case,
        goldens_old.empty() ? goldens_since.c_str() : goldens_old.c_str(),
        std::filesystem::absolute(out_dir + "/" + rep->review_page, ec).lexically_normal().c_str());
    return hdrc::kExitPass;
  }

  if (!shard.empty() && !*run && !*verify) {
    auto sh = hdrc::parse_shard(shard);
    if (!sh) {
      std::fprintf(stderr, "error: %s\n", sh.error().to_string().c_str());
      return hdrc::kExitBadInput;
    }
    const size_t all = cases.size();
    cases = hdrc::select_shard(cases, *sh);
    if (cases.empty()) {
      std::fprintf(stderr, "error: --shard %s selects no case (there are %zu)\n", shard.c_str(),
                   all);
      return hdrc::kExitBadInput;
    }
  }

  if (*list) {
    for (const auto& c : cases)
      if (list_long)
        std::printf("%s  (%s, %s)\n", c.id.c_str(), std::string(c.stage->name).c_str(),
                    c.input.describe().c_str());
      else
        std::printf("%s\n", c.id.c_str());
    return hdrc::kExitPass;
  }

  if (*export_cmd) {
    const hdrc::ExportSummary sum = hdrc::export_cases(cases, out_dir);
    for (const auto& e : sum.errors) std::fprintf(stderr, "error: %s\n", e.to_string().c_str());
    std::error_code ec;
    std::printf("exported %zu cases (%zu degenerate) to %s\n", sum.cases, sum.degenerate,
                std::filesystem::absolute(out_dir, ec).lexically_normal().c_str());
    return sum.errors.empty() ? hdrc::kExitPass : hdrc::kExitFail;
  }

  suite.cases_dir = cases_dir;
  suite.out_dir = outset ? outset->staging() : out_dir;
  // The case images the run writes stay in memory, up to 384 MB, for the report built at its end
  // (core/image.h written_images; the default suite's are 120-300 MB).
  hdrc::written_images::set_capacity(hdrc::kKeptImagesBytes);
  // The run's last line names the report (README: the main job ends with the report's path).
  bool goldens_checked = false;
  auto finish = [&](int code) {
    // Golden outcomes into results.json and junit, --images applied, then the report, all in the
    // staging folder; then the run is published as a whole (runner/output_set.h).
    hdrc::report::ReportInfo report;
    code = hdrc::finish_run_outputs(suite.out_dir, code, goldens_checked, images, jobs, &report);
    hdrc::written_images::clear();
    code = hdrc::publish_run(outset.get(), code);
    if (report.cases > 0)
      std::printf("report: %zu cases, %zu files, %.1f MB in %.2f s (CPU %.2f s)\n", report.cases,
                  report.files, report.bytes / 1e6, report.seconds, report.cpu_seconds);
    std::error_code ec;
    if (code != hdrc::kExitBadInput &&
        fs::exists(out_dir + "/results.json"))  // bad input writes nothing
      std::printf(
          "report: %s\n",
          fs::absolute(out_dir + "/report/index.html", ec).lexically_normal().string().c_str());
    return code;
  };
  suite.jobs = jobs;
  suite.device_allowances = !no_device_allowance;
  suite.memory_budget = memory_budget_gb * 1e9;
  suite.shard = shard;
  if (*run && run_reference != "baked") suite.reference = run_reference;
  const std::string shader_dir = !*run || engine != "vulkan" ? ""
                                 : vk.shader_dir.empty()     ? hdrc::gpu::default_shader_dir()
                                                             : vk.shader_dir;
  suite.provenance = hdrc::run_provenance(argc, argv, cases, shader_dir, images);
  // A failing case's reproduce command (runner/verify.h: reproduce_command) repeats every option
  // of this command line but those choosing cases, outputs and parallelism: one list, made by
  // run_provenance.
  suite.reproduce_args = suite.provenance.reproduce_args;
  if (*verify) {
    suite.command = "verify";
    suite.candidate_engine = candidate_dir.empty() ? "candidate-cmd" : "candidate-dir";
    if (candidate_dir.empty() == candidate_cmd.empty()) {
      std::fprintf(stderr,
                   "error: verify needs exactly one of --candidate-dir or --candidate-cmd\n");
      return hdrc::kExitBadInput;
    }
    if (!candidate_dir.empty()) {
      hdrc::CandidateDirEngine dir(candidate_dir);
      if (hdrc::Status st = dir.init(); !st) {
        std::fprintf(stderr, "error: --candidate-dir: %s\n", st.error().to_string().c_str());
        return hdrc::kExitBadInput;
      }
      suite.candidate_dir = &dir;
      return finish(hdrc::run_suite(
          cases, limits, [&] { return std::make_unique<hdrc::CandidateDirEngine>(candidate_dir); },
          suite));
    }
    auto argv_template = hdrc::split_command_template(candidate_cmd);
    if (!argv_template) {
      std::fprintf(stderr, "error: %s\n", argv_template.error().to_string().c_str());
      return hdrc::kExitBadInput;
    }
    if (candidate_cmd.find("{output}") == std::string::npos) {
      std::fprintf(stderr,
                   "error: --candidate-cmd: the template has no {output}: the command must be "
                   "told where to write its image; valid placeholders: {input} {params} {output} "
                   "{id}\n");
      return hdrc::kExitBadInput;
    }
    if (const std::string bad = hdrc::unknown_placeholder(*argv_template); !bad.empty()) {
      std::fprintf(stderr,
                   "error: --candidate-cmd: unknown placeholder %s in '%s'; valid placeholders: "
                   "{input} {params} {output} {id}\n",
                   hdrc::valid_utf8(bad).c_str(), hdrc::valid_utf8(candidate_cmd).c_str());
      return hdrc::kExitBadInput;
    }
    auto declined = std::make_shared<hdrc::DeclinedStages>();  // shared by every worker
    return finish(hdrc::run_suite(
        cases, limits,
        [&] {
          return std::make_unique<hdrc::CandidateCommandEngine>(*argv_template, suite.out_dir,
                                                                cmd_timeout, declined, sandbox);
        },
        suite));
  }

  int code = hdrc::run_suite(
      cases, limits,
      [&]() -> std::unique_ptr<hdrc::Engine> {
        if (engine == "vulkan") return std::make_unique<hdrc::gpu::VulkanEngine>(vk);
        return std::make_unique<hdrc::ref::ReferenceEngine>();
      },
      suite);
  // The reference against the goldens: a regression of the reference, or a missing or stale
  // golden, fails the run (exit 1) unless the run already failed worse.
  if (code == hdrc::kExitBadInput || code == hdrc::kExitInterrupted) return finish(code);
  if (no_goldens || suite.reference != "baked") {
    std::printf("goldens: not checked (%s)\n",
                no_goldens ? "--no-goldens" : "the goldens hold the baked reference");
  } else if (goldens_dir.empty()) {
    std::printf("goldens: not checked (--cases %s has no golden directory; pass --goldens DIR)\n",
                cases_dir.c_str());
  } else {
    std::vector<hdrc::Case> checked = cases;
    if (!shard.empty())
      if (auto sh = hdrc::parse_shard(shard)) checked = hdrc::select_shard(checked, *sh);
    // Goldens exist for the quick tier only (docs/cases.md).
    std::erase_if(checked, [](const hdrc::Case& c) { return c.tier != "quick"; });
    const hdrc::GoldenRunSummary g =
        hdrc::check_run_against_goldens(checked, suite.out_dir, goldens_dir, golden_extra, jobs);
    if (g.failed() > 0 && code != hdrc::kExitFail) code = hdrc::kExitFail;
    goldens_checked = true;
  }
  return finish(code);
}
