#!/usr/bin/env python3
"""The conformance check on a real GPU, in one command (docs/precision.md, "The default suite on a
real GPU").

  gpu-check.py --device NAME --out DIR [--hdrconform PATH] [--gpu-tests PATH] [--jobs N]
               [--filter GLOB]

Runs, on the Vulkan device NAME (index or name substring, as `hdrconform run --device`):
  1. the whole default suite with device allowances (DIR/suite/: results.json, report/);
  2. the same without them (`--no-device-allowance`, DIR/tight/): how many cases need one;
  3. every planted shader defect of planted_shader_defects.json, each on a copy of the shaders
     (DIR/planted/<k>/): its named case must FAIL on this device too;
  4. with --gpu-tests, the gpu_tests binary with HDRC_VK_DEVICE=NAME (DIR/gpu_tests.xml).
Writes DIR/summary.md (verdicts, allowance classes, failures, planted defects) and
DIR/summary.json. Exit status 0 when the suite has no FAIL or ERROR and every planted defect
fails; 1 otherwise; 2 on a usage error.

Works from a checkout (build/runner/hdrconform, gpu/shaders, runner/planted_shader_defects.json)
and from a bundle (scripts/bundle.sh puts this script at its top beside the launcher, and the
shaders and the defects file under share/hdrconform/). Needs Python 3.8 and nothing else.
"""
import argparse
import collections
import json
import os
import shutil
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.realpath(__file__))


def locate():
    """(hdrconform, shader dir, planted defects file) of the bundle or checkout holding this file."""
    share = os.path.join(HERE, "share", "hdrconform")
    if os.path.isdir(share):  # a bundle
        return (os.path.join(HERE, "hdrconform"), os.path.join(share, "shaders"),
                os.path.join(share, "planted_shader_defects.json"))
    root = os.path.dirname(HERE)  # scripts/ of a checkout
    build = os.environ.get("HDRC_BUILD_DIR", os.path.join(root, "build"))
    return (os.path.join(build, "runner", "hdrconform"), os.path.join(root, "gpu", "shaders"),
            os.path.join(root, "runner", "planted_shader_defects.json"))


def run(cmd, log, env=None, timeout=1800):
    t0 = time.time()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=timeout)
        code, out = p.returncode, p.stdout + p.stderr
    except subprocess.TimeoutExpired:
        code, out = 124, "timed out after %d s" % timeout
    log.write("$ %s\n%s\n[exit %d, %.1f s]\n\n" % (" ".join(cmd), out, code, time.time() - t0))
    log.flush()
    return code, out, time.time() - t0


def verdicts(results_path):
    with open(results_path, encoding="utf-8") as f:
        j = json.load(f)
    return j, {c["id"]: c for c in j["cases"]}


def main():
    hdrconform, shaders, planted_file = locate()
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--device", required=True, help="Vulkan device: index or name substring")
    ap.add_argument("--out", required=True, help="output folder (created; must be empty or new)")
    ap.add_argument("--hdrconform", default=hdrconform, help="hdrconform binary or launcher (default: %(default)s)")
    ap.add_argument("--shaders", default=shaders, help="the suite's shader folder, copied for each planted defect (default: %(default)s)")
    ap.add_argument("--planted", default=planted_file, help="the planted defects (default: %(default)s)")
    ap.add_argument("--gpu-tests", help="gpu_tests binary to run on the device as well")
    ap.add_argument("--jobs", "-j", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--filter", help="only these cases of the suite (as run --filter); the planted "
                    "defects run their own cases")
    a = ap.parse_args()
    for what, path in (("--hdrconform", a.hdrconform), ("--planted", a.planted)):
        if not os.path.isfile(path):
            ap.error("%s %s: no such file" % (what, path))
    if not os.path.isdir(a.shaders):
        ap.error("--shaders %s: no such folder" % a.shaders)
    if os.path.exists(a.out) and os.listdir(a.out):
        ap.error("--out %s exists and is not empty; choose an empty or new folder" % a.out)
    os.makedirs(a.out, exist_ok=True)
    log = open(os.path.join(a.out, "log.txt"), "w", encoding="utf-8")
    hc = [a.hdrconform]
    selection = ["--filter", a.filter] if a.filter else []
    summary = {"device": a.device}

    code, out, _ = run(hc + ["devices"], log)
    if code != 0:
        print(out, file=sys.stderr)
        return 1
    summary["devices"] = out.strip()

    # 1, 2: the suite with and without device allowances.
    suite = os.path.join(a.out, "suite")
    code, out, secs = run(hc + ["run", "--device", a.device, "-j", str(a.jobs), "--images",
                                "failing", "--out", suite] + selection, log)
    if not os.path.isfile(os.path.join(suite, "results.json")):
        print(out[-4000:], file=sys.stderr)
        return 1
    j, cases = verdicts(os.path.join(suite, "results.json"))
    summary["candidate"] = j.get("candidate")
    summary["suite_seconds"] = round(secs, 1)
    summary["verdicts"] = dict(collections.Counter(c["verdict"] for c in cases.values()))
    summary["goldens"] = j.get("goldens")
    allow = collections.Counter()
    for c in cases.values():
        if c.get("device_allowance"):
            for cls in c["device_allowance"].get("classes", []):
                allow[cls] += 1
    summary["allowance_classes"] = dict(allow)
    summary["allowance_cases"] = sum(1 for c in cases.values() if c.get("device_allowance"))
    failing = {i: c.get("reason", "") for i, c in cases.items() if c["verdict"] in ("FAIL", "ERROR")}
    summary["failing"] = failing
    tight = os.path.join(a.out, "tight")
    run(hc + ["run", "--device", a.device, "-j", str(a.jobs), "--images", "none", "--no-goldens",
              "--no-device-allowance", "--out", tight] + selection, log)
    if os.path.isfile(os.path.join(tight, "results.json")):
        _, tcases = verdicts(os.path.join(tight, "results.json"))
        summary["verdicts_without_allowances"] = dict(
            collections.Counter(c["verdict"] for c in tcases.values()))

    # 3: planted defects.
    with open(a.planted, encoding="utf-8") as f:
        defects = json.load(f)["defects"]
    planted = []
    for k, d in enumerate(defects):
        work = os.path.join(a.out, "planted", str(k))
        copy = os.path.join(work, "shaders")
        shutil.copytree(a.shaders, copy)
        path = os.path.join(copy, d["shader"])
        with open(path, encoding="utf-8") as f:
            text = f.read()
        row = {"what": d["what"], "shader": d["shader"], "must_fail": d["must_fail"]}
        if text.count(d["from"]) != 1:
            row["result"] = "the text to replace is not in %s exactly once" % d["shader"]
            row["caught"] = False
            planted.append(row)
            continue
        with open(path, "w", encoding="utf-8") as f:
            f.write(text.replace(d["from"], d["to"]))
        run(hc + ["run", "--device", a.device, "-j", str(a.jobs), "--images", "none",
                  "--no-goldens", "--shader-dir", copy, "--filter", d["cases"], "--out",
                  os.path.join(work, "out")], log)
        _, pc = verdicts(os.path.join(work, "out", "results.json"))
        fails = sorted(i for i, c in pc.items() if c["verdict"] == "FAIL")
        row["failed"] = "%d of %d" % (len(fails), len(pc))
        row["caught"] = bool(fails) if d["must_fail"] == "*" else d["must_fail"] in fails
        if not row["caught"] and d.get("shows_only"):
            row["caught"] = None  # not visible on every device: reported, not a miss
            row["result"] = "not shown on this device; it shows only " + d["shows_only"]
        if row["caught"] is False and d["must_fail"] in pc:
            c = pc[d["must_fail"]]
            row["result"] = c["verdict"] + (" with a device allowance" if c.get("device_allowance")
                                             else "")
        planted.append(row)
        shutil.rmtree(copy)
    summary["planted"] = planted

    # 4: gpu_tests.
    if a.gpu_tests:
        env = dict(os.environ, HDRC_VK_DEVICE=a.device)
        xml = os.path.join(a.out, "gpu_tests.xml")
        code, out, _ = run([a.gpu_tests, "--gtest_output=xml:" + xml], log, env=env)
        failed, skipped, passed = [], [], 0
        if os.path.isfile(xml):
            for t in ET.parse(xml).getroot().iter("testcase"):
                name = "%s.%s" % (t.get("classname"), t.get("name"))
                if t.find("failure") is not None:
                    failed.append(name)
                elif t.find("skipped") is not None or t.get("result") == "skipped":
                    skipped.append(name)
                else:
                    passed += 1
        summary["gpu_tests"] = {"exit": code, "passed": passed, "failed": failed,
                                "skipped": skipped}

    with open(os.path.join(a.out, "summary.json"), "w", encoding="utf-8") as f:
        json.dump(summary, f, indent=2)
    cand = summary.get("candidate") or {}
    md = ["# hdrconform on %s" % cand.get("device", a.device), "",
          "driver %s, Vulkan %s, precision %s" % (cand.get("driver"), cand.get("api_version"),
                                                  json.dumps(cand.get("precision"))), "",
          "| | count |", "|---|---|"]
    md += ["| %s | %d |" % kv for kv in sorted(summary["verdicts"].items())]
    md += ["| of the PASS, with a device allowance | %d |" % summary["allowance_cases"]]
    for v, n in sorted(summary.get("verdicts_without_allowances", {}).items()):
        md.append("| without allowances: %s | %d |" % (v, n))
    md += ["", "| allowance class | cases |", "|---|---|"]
    md += ["| %s | %d |" % kv for kv in sorted(allow.items(), key=lambda kv: -kv[1])]
    md += ["", "## Failing cases (%d)" % len(failing), ""]
    md += ["- `%s`: %s" % (i, r[:300]) for i, r in sorted(failing.items())]
    md += ["", "## Planted shader defects", "", "| defect | must fail | failed | caught |",
           "|---|---|---|---|"]
    md += ["| %s | `%s` | %s | %s |" % (p["what"][:160], p["must_fail"], p.get("failed", "-"),
                                         "yes" if p["caught"] else
                                         p.get("result", "") if p["caught"] is None else
                                         "**no**: " + p.get("result", ""))
           for p in planted]
    if "gpu_tests" in summary:
        g = summary["gpu_tests"]
        md += ["", "## gpu_tests", "", "exit %d: %d passed, %d failed, %d skipped" %
               (g["exit"], g["passed"], len(g["failed"]), len(g["skipped"]))]
        md += ["- FAILED %s" % t for t in g["failed"]] + ["- skipped %s" % t for t in g["skipped"]]
    with open(os.path.join(a.out, "summary.md"), "w", encoding="utf-8") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md))
    ok = not failing and all(p["caught"] is not False for p in planted)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
