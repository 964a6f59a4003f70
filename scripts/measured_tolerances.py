#!/usr/bin/env python3
"""Per-case tolerances from a measured run (docs/tolerances.md, "Measured per-case tolerances").

Reads a results.json of `hdrconform run` on lavapipe and rewrites the measured overlays of
cases/tolerance_overlays.json: one overlay per passing case whose measured maxima, times MARGIN,
lie under its group tolerance. Each overlay selects the case by its id, the vulkan engine and the
llvmpipe device only (another GPU keeps the group sets of cases/defaults.json), sets each judged
metric's max to MARGIN x its measured maximum and records the measurement in its reason.
Hand-written overlays (whose reason does not start with PREFIX) are kept, in front. A run of part
of the suite (--filter) replaces the measured overlays of its own cases only: those of the cases it
did not run are kept.

Not touched: metrics measured at exactly 0 (bit-exact: a max of 0 would fail on any change of
rounding; the group set keeps judging them) and metrics with an allowed fraction where some value
is over max (LUT code flips, the dither grain: judged by the fraction and the hard cap). Where no
value is over max, the fraction is dropped and max = hard = MARGIN x measured.

--fractions: where a metric with an allowed fraction has values over max, the allowed fraction
becomes MARGIN x the measured fraction (max and hard kept): a LUT as stored judges its code flips
by their share, and a change that shifts every texel by a fraction of a code flips far more of them
than float32 noise does (docs/constant-sweep.md, ue58). --worst W: a results.json of the same
cases under `--device-model worst` (group sets): the fraction is MARGIN x the larger of the two
measured ones, so that the worst-case device model, whose allowances the overlay also meets,
passes.

Usage (the measurement must be made under the group sets, without measured overlays):
  scripts/measured_tolerances.py --strip [CASES_DIR]        # drop the measured overlays
  build/runner/hdrconform run --out OUT                       # measure on lavapipe
  scripts/measured_tolerances.py OUT/results.json [CASES_DIR] [--margin M]
"""
import argparse
import json
import math
import os
import sys

PREFIX = "measured per case on lavapipe"
METRICS = ["linear_abs", "linear_rel", "pq_code10", "pq_code12", "delta_e_itp"]


def sig(x):
    """x rounded up to 2 significant digits (a limit never falls below margin x measured)."""
    if x <= 0:
        return 0.0
    e = math.floor(math.log10(x)) - 1
    return float(f"{math.ceil(x / 10**e)}e{e}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--strip", action="store_true", help="only drop the measured overlays")
    ap.add_argument("results", nargs="?")
    ap.add_argument("cases", nargs="?", default=os.path.join(os.path.dirname(__file__), "..", "cases"))
    ap.add_argument("--margin", type=float, default=3.0)
    ap.add_argument("--fractions", action="store_true",
                    help="also tighten allowed fractions to MARGIN x the measured fraction "
                    "over max")
    ap.add_argument("--worst", help="with --fractions: results.json of the same cases under "
                    "--device-model worst; the larger fraction of the two is measured")
    a = ap.parse_args()
    if a.strip:
        a.cases = a.results or a.cases
        path = os.path.join(a.cases, "tolerance_overlays.json")
        doc = json.load(open(path))
        n = len(doc["overlays"])
        doc["overlays"] = [o for o in doc["overlays"]
                           if not o["tolerance"]["reason"].startswith(PREFIX)]
        with open(path, "w") as f:
            json.dump(doc, f, indent=2)
            f.write("\n")
        print(f"{path}: {n - len(doc['overlays'])} measured overlays dropped")
        return
    if not a.results:
        sys.exit("usage: measured_tolerances.py RESULTS_JSON [CASES_DIR] [--margin M] | --strip")
    results = json.load(open(a.results))
    # The run's candidate device (results.json "candidate"; older files also named it per case).
    device = results.get("candidate", {}).get("device", "") or (
        results["cases"][0].get("device", {}).get("device", "") if results["cases"] else "")
    if "llvmpipe" not in device:
        sys.exit(f"{a.results}: measured on '{device}', not lavapipe (llvmpipe)")
    path = os.path.join(a.cases, "tolerance_overlays.json")
    doc = json.load(open(path))
    worst = {}
    if a.worst:
        for c in json.load(open(a.worst))["cases"]:
            # A case the model does not pass (a known limit) keeps its set's fraction.
            if c["verdict"] == "PASS" and c.get("stats"):
                worst[c["id"]] = c["stats"]["overall"]
    ran = {c["id"] for c in results["cases"]}
    kept = [o for o in doc["overlays"] if not o["tolerance"]["reason"].startswith(PREFIX)]
    # The measured overlays of cases this run did not measure (a --filter run), in their order.
    others = [o for o in doc["overlays"]
              if o["tolerance"]["reason"].startswith(PREFIX) and o["cases"] not in ran]
    made = []
    for c in results["cases"]:
        if c["verdict"] != "PASS" or not c.get("stats"):
            continue
        if PREFIX in c["tolerance"].get("reason", ""):
            sys.exit(f"{a.results}: {c['id']} was judged with a measured overlay; measure under "
                     f"the group sets (--strip, run, then this)")
        tol, overall = c["tolerance"], c["stats"]["overall"]
        patch, said = {}, []
        for m in METRICS:
            t = tol.get(m)
            if not isinstance(t, dict) or not isinstance(t.get("max"), (int, float)):
                continue
            measured = overall[m]["max"]
            if not isinstance(measured, (int, float)) or measured <= 0:
                continue
            limit = sig(a.margin * measured)
            if t.get("allowed_fraction", 0) > 0:
                # An allowed fraction (LUT code flips, dither grain) is kept where any value is
                # over max; where none is, every value is within max: judge them all by one max.
                hard = t.get("hard")
                if overall[m]["over"] > 0:
                    if a.worst and c["id"] not in worst:
                        continue
                    measured_fraction = max(overall[m]["fraction_over"],
                                            (worst.get(c["id"], {}).get(m) or {})
                                            .get("fraction_over", 0.0))
                    fraction = sig(a.margin * measured_fraction)
                    if a.fractions and fraction < t["allowed_fraction"]:
                        patch[m] = {"max": t["max"], "allowed_fraction": fraction, "hard": hard,
                                    "warn": None}
                        said.append(f"{m}: {measured_fraction:.3g} of values over "
                                    f"{t['max']:g}" + (" (lavapipe or the worst-case model)"
                                                       if worst else ""))
                    continue
                if not isinstance(hard, (int, float)) or limit >= hard:
                    continue
                patch[m] = {"max": limit, "allowed_fraction": 0, "hard": limit, "warn": None}
            else:
                if limit >= t["max"]:
                    continue
                patch[m] = {"max": limit, "warn": None}
            said.append(f"{m} {measured:.3g}")
        if not patch:
            continue
        what = "max" if not any(" of values over " in x for x in said) else \
            "allowed fraction (where values are over max) or max"
        patch["reason"] = (f"{PREFIX} ({', '.join(said)}); {what} = {a.margin:g} x measured, "
                           f"rounded up to 2 digits: the margin covers rounding reshuffled by "
                           f"constant changes (docs/tolerances.md)")
        made.append({"engine": "vulkan", "device": "llvmpipe*", "cases": c["id"],
                     "tolerance": patch})
    doc["overlays"] = kept + others + made
    with open(path, "w") as f:
        json.dump(doc, f, indent=2)
        f.write("\n")
    print(f"{path}: {len(kept)} hand-written overlays kept, {len(others)} measured ones of cases "
          f"not in this run kept, {len(made)} measured per case (margin {a.margin:g})")


if __name__ == "__main__":
    main()
