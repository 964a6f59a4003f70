#!/usr/bin/env python3
"""Regenerates docs/performance.md: every figure in it measured on this machine, now.

    bench/performance.py --base BUILD_DIR [--rounds N] [--exhaustive] [--out FILE]

--base: a build of an older tree (for issue 17, a build of 64ebd63), measured side by side. Both
builds run the *same cases*: the base tree's own cases and goldens (found through the base build's
CMakeCache.txt, or --base-cases), so that the comparison is of the same work whatever cases the
new tree has added since. The runs alternate (base, new, base, new, ...) so that both see the same
load, and the tables give the ratio of their medians. CPU time (user + system of the whole process
tree) is the figure to compare on a shared machine; wall time is listed too.
Cold: MESA_SHADER_CACHE_DIR points to a fresh empty directory for that run; warm: the directory
the cold run filled. The runs are made with CI unset, so both builds keep every case's images and
write the whole report (the most work a run does).
--exhaustive: also runs `hdrconform run --suite exhaustive -j 2` once (minutes).

The engine figures come from bench/perf_bench (one process; thread CPU time for the reference and
OpenColorIO, wall time for lavapipe) and bench/tonemap4k_bench (built against both trees: it uses
only the engine interface every version has).
"""
import argparse
import json
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(cmd, env=None, cwd=None):
    """Runs cmd; returns (exit code, wall s, CPU s of the process tree, output)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    p = subprocess.run(cmd, env=env, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True)
    wall = time.monotonic() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return p.returncode, wall, cpu, p.stdout


def median(v):
    v = sorted(v)
    return v[len(v) // 2] if v else float("nan")


def clean_env(mesa_cache):
    env = {k: v for k, v in os.environ.items() if k != "CI"}
    env["MESA_SHADER_CACHE_DIR"] = mesa_cache
    return env


def source_dir_of(build):
    try:
        with open(os.path.join(build, "CMakeCache.txt")) as f:
            for line in f:
                if line.startswith("CMAKE_HOME_DIRECTORY:"):
                    return line.split("=", 1)[1].strip()
    except OSError:
        pass
    return None


def results_summary(out_dir):
    """Per-phase sums over the cases (results.json timers), the case loop's wall, case count."""
    with open(os.path.join(out_dir, "results.json")) as f:
        doc = json.load(f)
    total = {"reference": 0.0, "candidate": 0.0, "diff": 0.0}
    for c in doc.get("cases", []):
        s = c.get("seconds", {})
        for k in total:
            total[k] += s.get(k, 0.0)
    return total, doc.get("wall_seconds", float("nan")), len(doc.get("cases", []))


def suite(binary, tmp, label, mesa_cache, cold, args):
    if cold:
        shutil.rmtree(mesa_cache, ignore_errors=True)
    os.makedirs(mesa_cache, exist_ok=True)
    env = clean_env(mesa_cache)
    out = os.path.join(tmp, "run-" + label)
    shutil.rmtree(out, ignore_errors=True)
    code, wall, cpu, text = run([binary, "run", "-j", "2", "--out", out, *args], env=env)
    phases, loop_wall, n = results_summary(out)
    # The report alone, rebuilt from the same results (CPU), for its share of the run.
    _, report_wall, report_cpu, _ = run([binary, "report", out], env=env)
    shutil.rmtree(out, ignore_errors=True)
    lines = text.strip().splitlines()
    # The run's own figure for its report (builds that print it: "report: ... (CPU x s)"), the
    # CPU of the whole process while it built the report, images handed over in memory.
    in_run = None
    for l in lines:
        m = re.match(r"report: .* \(CPU ([0-9.]+) s\)$", l)
        if m:
            in_run = float(m.group(1))
    return {"code": code, "wall": wall, "cpu": cpu, "phases": phases, "loop_wall": loop_wall,
            "cases": n, "report_cpu": report_cpu, "report_wall": report_wall,
            "report_in_run": in_run,
            "summary": next((l for l in lines if l.startswith("hdrconform: ")), ""),
            "goldens": next((l for l in lines if l.startswith("goldens: ")), "")}


# One case per pipeline for the memory and time per pixel (issue 29): the stage and settings
# of a typical case, the input a "random" stimulus of the size asked for.
CASE_KINDS = [
    ("ue55 tonemap", {"stage": "tonemap", "cvars": {"r.HDR.EnableHDROutput": 1,
                      "r.HDR.Display.OutputDevice": 3, "r.HDR.Display.ColorGamut": 2,
                      "r.HDR.Display.MaxLuminance": 1000}, "tolerance": "tonemap"}),
    ("unity_urp color_grading", {"pipeline": "unity_urp", "stage": "color_grading",
                                 "tolerance": "unity_urp_grading"}),
    ("operators tone_curve", {"pipeline": "operators", "stage": "tone_curve",
                              "settings": {"Operator": "Hable"}, "tolerance": "operators"}),
    ("pq_grading pq_grade", {"pipeline": "pq_grading", "stage": "pq_grade",
                             "lut": "lut/cube/pq_look_33.cube", "tolerance": "pq_grading"}),
]


def case_memory(binary, tmp, kind, case, side):
    """One case of side x side pixels run alone (-j 1, every image kept, the report written):
    (peak resident bytes, CPU s of user + system, wall s), by /usr/bin/time."""
    d = os.path.join(tmp, f"mem-{kind.split()[0]}-{side}")
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(os.path.join(d, "cases", "lut", "cube"))
    shutil.copy(os.path.join(ROOT, "cases", "defaults.json"), os.path.join(d, "cases"))
    shutil.copy(os.path.join(ROOT, "cases", "lut", "cube", "pq_look_33.cube"),
                os.path.join(d, "cases", "lut", "cube"))
    c = dict(case, description="memory per pixel (bench/performance.py)",
             input={"stimulus": "random", "width": side, "height": side})
    with open(os.path.join(d, "cases", "m.json"), "w") as f:
        json.dump(c, f)
    stats = os.path.join(d, "time.txt")
    p = subprocess.run(["/usr/bin/time", "-o", stats, "-f", "%M %U %S %e", binary, "run",
                        "--cases", os.path.join(d, "cases"), "--out", os.path.join(d, "out"),
                        "-j", "1"], env=clean_env(os.path.join(tmp, "mesa-mem")),
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    with open(stats) as f:
        kb, user, system, wall = f.read().split()[-4:]
    shutil.rmtree(d, ignore_errors=True)
    return int(kb) * 1024, float(user) + float(system), float(wall), p.returncode


def bench_values(text):
    values = {}
    for line in text.splitlines():
        parts = line.split()
        if len(parts) >= 2 and not line.startswith("#"):
            try:
                values[parts[0]] = float(parts[1])
            except ValueError:
                pass
    return values


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.environ.get("HDRC_BUILD_DIR", os.path.join(ROOT, "build")))
    ap.add_argument("--base", help="a build of an older tree, measured side by side")
    ap.add_argument("--base-cases", help="the cases both builds run (default: the base tree's)")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--exhaustive", action="store_true")
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "performance.md"))
    a = ap.parse_args()
    new_bin = os.path.join(a.build, "runner", "hdrconform")
    base_bin = os.path.join(a.base, "runner", "hdrconform") if a.base else None
    tmp = tempfile.mkdtemp(prefix="hdrc-perf-")
    head = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                          stdout=subprocess.PIPE, text=True).stdout.strip()
    base_src = source_dir_of(a.base) if a.base else None
    base_head = ""
    if base_src:
        base_head = subprocess.run(["git", "-C", base_src, "rev-parse", "--short", "HEAD"],
                                   stdout=subprocess.PIPE, text=True).stdout.strip()
    cases = a.base_cases or (os.path.join(base_src, "cases") if base_src else None)
    same_cases = []
    if base_bin and cases:
        same_cases = ["--cases", cases]
        goldens = os.path.join(os.path.dirname(cases), "goldens")
        if os.path.isdir(goldens):
            same_cases += ["--goldens", goldens]

    # 1. The default suite: per round, each build cold (a fresh Mesa cache) then warm (the
    # directory the cold run filled); the builds alternate at every step.
    runs = {}
    for r in range(a.rounds):
        for cold in (True, False):
            for label, binary in (("base", base_bin), ("new", new_bin)):
                if not binary:
                    continue
                runs.setdefault((label, cold), []).append(
                    suite(binary, tmp, f"{label}-{r}-{int(cold)}",
                          os.path.join(tmp, f"mesa-{label}-{r}"), cold, same_cases))
    # The new tree's own default suite (its golden check included), warm.
    own = suite(new_bin, tmp, "own", os.path.join(tmp, "mesa-own"), True, [])
    own_warm = suite(new_bin, tmp, "own-warm", os.path.join(tmp, "mesa-own"), False, [])

    # 2. Engines.
    _, _, _, text = run([os.path.join(a.build, "bench", "perf_bench"), "all", "5"])
    bench = bench_values(text)
    t4k = {"base": [], "new": []}
    t4k_first = {"base": [], "new": []}
    bench_bins = [("new", os.path.join(a.build, "bench", "tonemap4k_bench"))]
    if a.base and os.path.exists(os.path.join(a.base, "bench", "tonemap4k_bench")):
        bench_bins.insert(0, ("base", os.path.join(a.base, "bench", "tonemap4k_bench")))
    for _ in range(3):
        for label, b in bench_bins:
            _, _, _, out = run([b, "3"], cwd=os.path.dirname(os.path.dirname(b)))
            v = bench_values(out)
            if "tonemap4k_s" in v:
                t4k[label].append(v["tonemap4k_s"])
                t4k_first[label].append(v["tonemap4k_first_s"])

    # 3. Memory and time per case: each pipeline's case at 256² and 2048², the difference over
    # the pixels is the per-pixel figure (the 256² case: the process's fixed part).
    memory = []
    for kind, case in CASE_KINDS:
        for label, binary in (("base", base_bin), ("new", new_bin)):
            if not binary:
                continue
            small = case_memory(binary, tmp, kind, case, 256)
            big = case_memory(binary, tmp, kind, case, 2048)
            px = 2048 * 2048 - 256 * 256
            memory.append((kind, label, big, (big[0] - small[0]) / px, (big[1] - small[1]) / px))

    # 4. The exhaustive tier.
    exhaustive = None
    if a.exhaustive:
        exhaustive = suite(new_bin, tmp, "exhaustive", os.path.join(tmp, "mesa-own"), False,
                           ["--suite", "exhaustive", "--images", "failing"])
        _, _, _, listing = run([new_bin, "list", "--suite", "exhaustive"])
        exhaustive["size"] = len(listing.strip().splitlines())
        exhaustive["shards"] = []
        for k in range(1, 5):
            _, _, _, sh = run([new_bin, "list", "--suite", "exhaustive", "--shard", f"{k}/4"])
            exhaustive["shards"].append(len(sh.strip().splitlines()))

    def cpu(label, cold):
        return median([x["cpu"] for x in runs.get((label, cold), [])])

    def wall(label, cold):
        return median([x["wall"] for x in runs.get((label, cold), [])])

    def field(label, cold, k):
        return median([x[k] for x in runs.get((label, cold), [])])

    L = []
    L.append("# Performance")
    L.append("")
    L.append(f"Written by `bench/performance.py` on {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}"
             f" for tree {head}; every figure below was measured in that one run. Machine: "
             f"{os.cpu_count()} cores (load average {os.getloadavg()[0]:.1f} when written), lavapipe."
             " Comparisons are ratios of interleaved runs in one session; CPU time (user + system of"
             " the process tree) is the figure to compare, wall time is indicative. History and"
             " the reasons behind the figures: `docs/performance-notes.md`.")
    L.append("")
    L.append("## The default suite, side by side")
    L.append("")
    if base_bin:
        L.append(f"`hdrconform run -j 2` on the same {runs[('new', False)][0]['cases']} cases (the base"
                 f" tree's own cases and goldens, `{' '.join(same_cases) or 'default'}`), base = a build"
                 f" of {base_head or a.base}, new = this tree; median of {a.rounds} interleaved runs"
                 " each. Every case's images are kept and the whole report is written (CI unset)."
                 " Cold: `MESA_SHADER_CACHE_DIR` a fresh empty directory; warm: the one the cold"
                 " run filled.")
        L.append("")
        L.append("| Mesa cache | base CPU s | new CPU s | **new / base** | base wall s | new wall s |")
        L.append("|---|---|---|---|---|---|")
        for cold in (False, True):
            b, n = cpu("base", cold), cpu("new", cold)
            L.append(f"| {'cold' if cold else 'warm'} | {b:.1f} | {n:.1f} | **{n / b:.2f}** | "
                     f"{wall('base', cold):.1f} | {wall('new', cold):.1f} |")
        L.append("")
        L.append("Cold-cache penalty (cold − warm CPU): base "
                 f"{cpu('base', True) - cpu('base', False):.1f} s, new "
                 f"{cpu('new', True) - cpu('new', False):.1f} s.")
        L.append("")
        L.append("### Where the run's time goes (warm, medians)")
        L.append("")
        L.append("Per-case phases are the sums over cases of the run's own timers (results.json:"
                 " seconds.reference / candidate / diff, wall clock of each worker, two workers)."
                 " `case loop` is the loop's wall time; `after the loop` is the rest of the run's"
                 " wall (golden check, images, report). `report in the run` is the run's own"
                 " figure (builds that print it: the process's CPU while it built the report, the"
                 " run's images handed over in memory); `report alone` is `hdrconform report` run"
                 " again on the same results (a second process that reads every EXR back). The"
                 " share is the report's CPU in the run over the run's CPU (the base, which does not"
                 " print it: its report alone).")
        L.append("")
        L.append("| build | cases | reference s | candidate s | diff s | case loop wall s | after the loop wall s | run CPU s | report in the run CPU s | report alone CPU s | **report / run CPU** |")
        L.append("|---|---|---|---|---|---|---|---|---|---|---|")
        for label in ("base", "new"):
            xs = runs.get((label, False))
            if not xs:
                continue
            ph = {k: median([x["phases"][k] for x in xs]) for k in ("reference", "candidate", "diff")}
            loop = field(label, False, "loop_wall")
            rc = field(label, False, "report_cpu")
            ins = [x["report_in_run"] for x in xs if x["report_in_run"] is not None]
            ir = median(ins) if ins else None
            share = (ir if ir is not None else rc) / cpu(label, False) * 100
            L.append(f"| {label} | {xs[0]['cases']} | {ph['reference']:.2f} | {ph['candidate']:.2f} | "
                     f"{ph['diff']:.2f} | {loop:.1f} | {wall(label, False) - loop:.1f} | "
                     f"{cpu(label, False):.1f} | {'—' if ir is None else f'{ir:.2f}'} | {rc:.2f} | "
                     f"**{share:.1f} %** |")
        L.append("")
        L.append(f"Verdicts of the last runs: base `{runs[('base', False)][-1]['summary'][:160]}`;"
                 f" new `{runs[('new', False)][-1]['summary'][:160]}`. (The base tree's cases run"
                 " on the new build: a few of them differ in verdict or golden because the tree's"
                 " later fixes changed what they compute; the work is the same.)")
        L.append("")
    L.append("### This tree's own default suite")
    L.append("")
    L.append("| Mesa cache | cases | CPU s | wall s | CPU ms per case | report in the run CPU s | report alone CPU s | report / run CPU |")
    L.append("|---|---|---|---|---|---|---|---|")
    for name, x in (("cold", own), ("warm", own_warm)):
        ir = x["report_in_run"] if x["report_in_run"] is not None else x["report_cpu"]
        L.append(f"| {name} | {x['cases']} | {x['cpu']:.1f} | {x['wall']:.1f} | "
                 f"{x['cpu'] / max(x['cases'], 1) * 1000:.1f} | {ir:.2f} | {x['report_cpu']:.2f} | "
                 f"{ir / x['cpu'] * 100:.1f} % |")
    L.append("")
    L.append(f"`{own_warm['summary'][:200]}`; `{own_warm['goldens']}`; exit code {own_warm['code']}.")
    L.append("")
    L.append("## Engines")
    L.append("")
    L.append("`bench/perf_bench all 5` (one process, medians of 5 rounds; fast and plain paths"
             " interleaved). Reference and OpenColorIO figures are CPU time of the measuring thread"
             " (one core); Vulkan figures are wall time (lavapipe runs on its own threads). \"plain\""
             " is the same build with `set_fast_paths(false)`: the unoptimised evaluation,"
             " bit-identical results.")
    L.append("")
    L.append("| figure | value |")
    L.append("|---|---|")
    rows = [
        ("per-case fixed cost, reference engine (1x1 shaper case)", "fixed_cost_reference_us", "µs"),
        ("per-case fixed cost, Vulkan engine (1x1 shaper case)", "fixed_cost_vulkan_us", "µs"),
        ("reference CombineLUTs bake, device 0 (SDR film path), per texel", "bake_us_per_texel_fast_dev0", "µs"),
        ("  the same, plain evaluation", "bake_us_per_texel_plain_dev0", "µs"),
        ("reference CombineLUTs bake, device 3 (ACES 1000 nits), per texel", "bake_us_per_texel_fast_dev3", "µs"),
        ("  the same, plain evaluation", "bake_us_per_texel_plain_dev3", "µs"),
        ("reference LUT cache hit (32³)", "bake_cache_hit_us", "µs"),
        ("reference analytic Tonemap pass, device 0, per pixel (one core)", "analytic_tonemap_us_per_px_fast_dev0", "µs"),
        ("  the same, plain evaluation", "analytic_tonemap_us_per_px_plain_dev0", "µs"),
        ("reference analytic Tonemap pass, device 3, per pixel (one core)", "analytic_tonemap_us_per_px_fast_dev3", "µs"),
        ("  the same, plain evaluation", "analytic_tonemap_us_per_px_plain_dev3", "µs"),
        ("reference Tonemap pass with the baked 32³ LUT, device 0, per pixel", "baked_tonemap_us_per_px_dev0", "µs"),
        ("reference Tonemap pass with the baked 32³ LUT, device 3, per pixel", "baked_tonemap_us_per_px_dev3", "µs"),
        ("reference ACES 1000-nit output transform, per pixel", "aces_reference_us_per_px", "µs"),
        ("OpenColorIO CPU processor, HDR-VIDEO-1000nit built-in, same pixels", "aces_ocio_us_per_px", "µs"),
        ("**ACES: reference / OpenColorIO**", "aces_ratio_reference_over_ocio", "×"),
        ("**`probe`, 1e6 colours, device 3 (parse + evaluate + print)**", "probe_1e6_seconds_fast", "s"),
        ("  the same, plain evaluation", "probe_1e6_seconds_plain_evaluation", "s"),
        ("Vulkan LUT bake 32³, per texel (lavapipe)", "vulkan_bake_us_per_texel_32", "µs"),
        ("Vulkan LUT bake 64³, per texel (lavapipe)", "vulkan_bake_us_per_texel_64", "µs"),
        ("Vulkan tonemap stage at 3840x2160, reused engine (bake 32³ + pass)", "vulkan_tonemap_4k_s", "s"),
        ("  throughput", "vulkan_tonemap_4k_Mpx_per_s", "Mpx/s"),
        ("  first run of a fresh engine (pipelines, allocation)", "vulkan_tonemap_4k_first_run_s", "s"),
        ("memcpy bandwidth (read + write)", "memcpy_bandwidth_GBps", "GB/s"),
        ("  the tonemap pass's 32 B/px (input + output) at that throughput, as a fraction of it",
         "vulkan_tonemap_4k_fraction_of_memcpy_bandwidth", ""),
    ]
    for name, key, unit in rows:
        if key in bench:
            L.append(f"| {name} | {bench[key]:.4g} {unit} |")
    L.append("")
    L.append("### Vulkan tonemap at 3840×2160, side by side")
    L.append("")
    L.append("`bench/tonemap4k_bench 3` (the engine's interface only, so the same file builds against"
             " the base tree), the builds alternating, 3 processes each; per process the median of 3"
             " runs after the first; wall time.")
    L.append("")
    L.append("| build | first run s (median) | s per run (median) | Mpx/s |")
    L.append("|---|---|---|---|")
    for label in ("base", "new"):
        if t4k[label]:
            s = median(t4k[label])
            L.append(f"| {label} | {median(t4k_first[label]):.3f} | {s:.3f} | {3840 * 2160 / s / 1e6:.1f} |")
    if t4k["base"] and t4k["new"]:
        L.append("")
        L.append(f"**Throughput new / base: {median(t4k['base']) / median(t4k['new']):.2f} ×.**")
    L.append("")
    L.append("## Memory and time per case")
    L.append("")
    L.append("One case of each pipeline at 2048×2048 (a `random` stimulus), run alone:"
             " `/usr/bin/time` of `hdrconform run -j 1` (every image kept, the report written)."
             " Per pixel: the 2048² case's figure minus a 256² case's (the process's fixed part),"
             " over the pixels between them. runner/budget.cpp's estimate rests on these figures;"
             " the per-case budget is 1.5 GB and 60 s of CPU (history: `docs/performance-notes.md`,"
             " \"Memory and time per case\").")
    L.append("")
    L.append("| case | build | peak resident MB | CPU s | wall s | **bytes per pixel** | CPU µs per pixel |")
    L.append("|---|---|---|---|---|---|---|")
    for kind, label, big, bpp, cpp in memory:
        L.append(f"| {kind} | {label} | {big[0] / 1e6:.0f} | {big[1]:.1f} | {big[2]:.1f} | "
                 f"**{bpp:.0f}** | {cpp * 1e6:.2f} |")
    if exhaustive:
        L.append("")
        L.append("## The exhaustive tier")
        L.append("")
        L.append(f"`hdrconform list --suite exhaustive | wc -l`: {exhaustive['size']} cases;"
                 f" `--shard K/4`: {' / '.join(str(s) for s in exhaustive['shards'])}.")
        L.append("")
        L.append(f"`hdrconform run --suite exhaustive -j 2 --images failing` (warm cache): "
                 f"**{exhaustive['wall'] / 60:.1f} min wall**, {exhaustive['cpu']:.0f} s CPU, exit code "
                 f"{exhaustive['code']}.")
        L.append("")
        L.append(f"`{exhaustive['summary'][:300]}`")
        L.append(f"`{exhaustive['goldens']}`")
    L.append("")
    L.append("## What the figures rest on")
    L.append("")
    L.append("* Reference: `TexelEvaluator` (reference/ue/combine_luts.h) unpacks the parameters once per"
             " LUT and evaluates only the device's own path; colour-correction zones with identical"
             " parameters are evaluated once; pow(x, 1) returns x; the film curve's match points and"
             " the SSTS logarithms are computed once per parameter set. All bit-identical:"
             " reference/ue/fast_paths_test.cpp compares the fast and the plain path over 1e5 colours"
             " and every device × gamut.")
    L.append("* The reference's Tonemap pass on an image of fewer pixels than its LUT has texels / 8"
             " bakes only the texels it reads (`LazyBakedLut`, bit-identical:"
             " `Tonemap.LazyBakeIsBitIdenticalToTheWholeBake`); larger ones use the process-wide LUT"
             " cache (reference/ue/lut_cache.h), shared between cases and workers.")
    L.append("* Vulkan engine: buffers, the LUT image, descriptors, command buffer and fence are kept"
             " from case to case; SPIR-V is compiled once per process; pipelines once per device.")
    L.append("* Diff percentiles by selection (`std::nth_element`); `probe` parses with"
             " `std::from_chars` and prints with `std::to_chars`.")
    L.append("")
    with open(a.out, "w") as f:
        f.write("\n".join(L))
    print("\n".join(L))
    shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
