#!/usr/bin/env python3
"""Shard balance of `hdrconform run --shard K/N`, and the stage costs the static plan uses.

    bench/shard_balance.py fit RESULTS_JSON
    bench/shard_balance.py plan [--build DIR] [--n 2,3,4] RESULTS_JSON...
    bench/shard_balance.py measure [--build DIR] [--shards 2,4] [--jobs 2] [--timings FILE]
                                   [--rounds 1] [--plans static,timings] [RUN ARGS...]

fit: the per-stage cost figures of core/pipeline.h (StageCost: us, us_per_pixel,
us_per_lut_texel), least squares of each evaluated case's recorded seconds (results.json
seconds.total: reference + candidate + diff) on its image's pixels (params.width x params.height,
a bake's N^2 x N lattice) and its LUT's N^3 texels (params.lut_size), per stage; a column that does
not vary over the stage's cases, or only with the pixels, is left out (its cost is in the others),
and so is one whose coefficient would be negative. Prints the figures to paste beside each
pipeline's stages (Pipeline::stage_costs), in microseconds of the measuring machine. The sizes
come from each case's resolved parameters, which a run keeps with its images: fit a run made with
`--images all` (the default outside CI).

plan: the balance of the static and the timings plans over each RESULTS_JSON's recorded seconds
(a whole run's): the slowest shard's summed seconds over the mean, for each N.

measure: runs every shard of each N, one after another, with the static model (no timings) and with
--timings FILE (default: a whole unsharded run made first, `run --out TMP`), each shard a separate
process as a CI job is: `hdrconform run --shard K/N --out TMP/... -j JOBS --images failing`. For
each plan and N it prints every shard's wall seconds and the sum of its cases' recorded seconds,
and the balance: the slowest shard over the mean of the shards (1.00 is perfect). The wall time
includes what every shard pays once (starting Vulkan, compiling its stages' shaders, loading the
cases, the report); the recorded seconds are the cases' own work, the part a plan can balance.
The machine's load counts in both: compare plans measured in the same invocation.
"""
import argparse
import collections
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def lstsq(rows, y):
    """Least squares by the normal equations (a few columns); None when singular."""
    k = len(rows[0])
    a = [[sum(r[i] * r[j] for r in rows) for j in range(k)] + [sum(r[i] * v for r, v in zip(rows, y))]
         for i in range(k)]
    for i in range(k):
        p = max(range(i, k), key=lambda r: abs(a[r][i]))
        a[i], a[p] = a[p], a[i]
        if abs(a[i][i]) < 1e-18:
            return None
        for r in range(k):
            if r != i:
                f = a[r][i] / a[i][i]
                a[r] = [x - f * z for x, z in zip(a[r], a[i])]
    return [a[i][k] / a[i][i] for i in range(k)]


def varies(xs):
    return max(xs) > min(xs)


def fit(results):
    with open(results) as f:
        doc = json.load(f)
    by = collections.defaultdict(list)
    pipeline_of = {}
    for c in doc["cases"]:
        if c.get("verdict") not in ("PASS", "FAIL", "KNOWN_LIMIT"):
            continue
        p = c.get("params") or {}
        pixels = p.get("width", 0) * p.get("height", 0) / 1e6
        texels = p.get("lut_size", 0) ** 3 / 1e6
        by[c["stage"]].append((c["seconds"]["total"], pixels, texels))
        pipeline_of[c["stage"]] = c["pipeline"]
    if not any(c.get("params") for c in doc["cases"]):
        sys.exit(f"{results}: no case has its resolved parameters (params), which give the sizes: "
                 "fit a run made with --images all")
    out = collections.defaultdict(list)
    for stage, v in sorted(by.items()):
        y = [s for s, _, _ in v]
        px, tx = [p for _, p, _ in v], [t for _, _, t in v]
        cols = ["us"]
        if varies(px):
            cols.append("us_per_pixel")
        if varies(tx) and (not varies(px) or any(abs(a - b) > 1e-12 for a, b in zip(px, tx))):
            cols.append("us_per_lut_texel")
        while True:
            x = {"us": [1.0] * len(v), "us_per_pixel": px, "us_per_lut_texel": tx}
            rows = [list(r) for r in zip(*(x[c] for c in cols))]
            coef = lstsq(rows, y)
            if coef is None or min(coef) >= 0 or len(cols) == 1:
                break
            cols.pop(min(range(1, len(cols)), key=lambda i: coef[i]))  # the most negative
        coef = coef or [sum(y) / len(y)]
        fig = dict(zip(cols, [max(0.0, c) * 1e6 for c in coef]))
        fig["us_per_pixel"] = fig.get("us_per_pixel", 0) / 1e6  # seconds per Mpx -> us per px
        fig["us_per_lut_texel"] = fig.get("us_per_lut_texel", 0) / 1e6
        resid = sum((sum(a * b for a, b in zip(r, coef)) - s) ** 2 for r, s in zip(rows, y))
        out[pipeline_of[stage]].append((stage, fig, len(v), sum(y) / len(y), (resid / len(v)) ** 0.5))
    for pipeline, stages in sorted(out.items()):
        print(f"{pipeline}:")
        for stage, fig, n, mean, rmse in stages:
            print(f'  {{"{stage}", {fig["us"]:.0f}, {fig["us_per_pixel"]:.3g}, '
                  f'{fig["us_per_lut_texel"]:.3g}}},  // {n} cases, mean {mean * 1e3:.2f} ms, '
                  f"rms residual {rmse * 1e3:.2f} ms")


def plan(a):
    """Each plan's balance over the recorded seconds of whole runs: the shards `list --shard K/N`
    names, each summed in seconds of the same run (one load for every case, so the machine's
    load changes the figure far less than shard walls run one after another)."""
    binary = os.path.join(a.build, "runner", "hdrconform")
    print("| seconds of | plan | " + " | ".join(f"N = {n}" for n in a.n) + " |")
    print("|---|---|" + "---|" * len(a.n))
    for results in a.results:
        with open(results) as f:
            sec = {c["id"]: c["seconds"]["total"] for c in json.load(f)["cases"]}
        for name, extra in (("static", []), ("timings", ["--timings", results])):
            cells = []
            for n in a.n:
                loads = []
                for k in range(1, n + 1):
                    ids = subprocess.run([binary, "list", "--shard", f"{k}/{n}"] + extra,
                                         capture_output=True, text=True, check=True).stdout.split()
                    loads.append(sum(sec.get(i, 0) for i in ids))
                cells.append(f"{balance(loads):.3f}")
            print(f"| {results} | {name} | " + " | ".join(cells) + " |")


def run_shards(binary, n, timings, jobs, args, tmp):
    walls, recorded = [], []
    for k in range(1, n + 1):
        out = os.path.join(tmp, f"shard-{k}-of-{n}")
        shutil.rmtree(out, ignore_errors=True)
        cmd = [binary, "run", "--shard", f"{k}/{n}", "--out", out, "-j", str(jobs),
               "--images", "failing"] + (["--timings", timings] if timings else []) + args
        t0 = time.monotonic()
        p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        walls.append(time.monotonic() - t0)
        if p.returncode not in (0, 1, 3, 4):
            sys.exit(f"{' '.join(cmd)}: exit {p.returncode}\n{p.stderr}")
        with open(os.path.join(out, "results.json")) as f:
            recorded.append(sum(c["seconds"]["total"] for c in json.load(f)["cases"]))
        shutil.rmtree(out, ignore_errors=True)
    return walls, recorded


def balance(v):
    return max(v) / (sum(v) / len(v))


def measure(a, args):
    binary = os.path.join(a.build, "runner", "hdrconform")
    tmp = tempfile.mkdtemp(prefix="shard_balance.")
    try:
        timings = a.timings
        if not timings and "timings" in a.plans.split(","):
            whole = os.path.join(tmp, "whole")
            t0 = time.monotonic()
            p = subprocess.run([binary, "run", "--out", whole, "-j", str(a.jobs), "--images",
                                "failing"] + args, stdout=subprocess.DEVNULL)
            print(f"whole run (the timings): {time.monotonic() - t0:.1f} s wall, exit {p.returncode}")
            timings = os.path.join(tmp, "timings.json")
            shutil.copy(os.path.join(whole, "results.json"), timings)
            shutil.rmtree(whole, ignore_errors=True)
        print("| plan | N | round | shard walls s | wall max/mean | shard case seconds | "
              "case s max/mean |")
        print("|---|---|---|---|---|---|---|")
        for rnd in range(1, a.rounds + 1):
            for n in [int(x) for x in a.shards.split(",")]:
                for plan, t in (("static", None), ("timings", timings)):
                    if plan not in a.plans.split(","):
                        continue
                    walls, rec = run_shards(binary, n, t, a.jobs, args, tmp)
                    print(f"| {plan} | {n} | {rnd} | {', '.join(f'{w:.1f}' for w in walls)} | "
                          f"{balance(walls):.2f} | {', '.join(f'{r:.1f}' for r in rec)} | "
                          f"{balance(rec):.2f} |", flush=True)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    f = sub.add_parser("fit")
    f.add_argument("results")
    m = sub.add_parser("measure")
    m.add_argument("--build", default=os.path.join(ROOT, "build"))
    m.add_argument("--shards", default="2,4")
    m.add_argument("--jobs", type=int, default=2)
    m.add_argument("--timings", default="")
    m.add_argument("--rounds", type=int, default=1)
    m.add_argument("--plans", default="static,timings", help="which plans to run")
    pl = sub.add_parser("plan")
    pl.add_argument("results", nargs="+")
    pl.add_argument("--build", default=os.path.join(ROOT, "build"))
    pl.add_argument("--n", type=lambda t: [int(x) for x in t.split(",")], default=[2, 3, 4])
    a, rest = ap.parse_known_args()
    if a.cmd == "fit":
        fit(a.results)
    elif a.cmd == "plan":
        plan(a)
    else:
        measure(a, rest)


if __name__ == "__main__":
    main()
