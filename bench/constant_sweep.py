#!/usr/bin/env python3
"""The planted-constant sweep (issue 28 item 5; docs/constant-sweep.md).

For every constant a porter types into a pipeline's GLSL port, make a copy of gpu/shaders with that
one constant rounded to the significant digits people commonly type (4 and 5), run the pipeline's
cases on it with the real CLI (`hdrconform run --shader-dir COPY`) and record the cases that FAIL
and the largest metrics against those of the unplanted shaders (float32 noise).

The constants are enumerated, not listed by hand, so that a new one cannot be missed:
  * every `const float NAME = <literal>;`, `const vec3 NAME = vec3(<literals>);` and
    `const mat3 NAME = mat3(<literals>);` in the files the pipeline's stage shaders include;
  * every constant and matrix of the generated include hdrc/interface.glsl
    (gpu/shader_constants.cpp, printed by build/bench/shader_constants_dump) that those files use,
    planted wherever it appears (encode and decode sharing it); ST 2084's m1, m2, c1, c2, c3 also
    in the encode (pq_from_nits) or the decode (nits_from_pq) alone;
  * the parameters a port types from the spec pages: the `spec-constants` blocks' matrices of
    docs/spec/<pipeline>.md and the published sets of docs/spec/operators.md and
    docs/spec/film_tonemap.md (PARAM_CONSTANTS below), planted where the shader reads P.<name>.
A constant whose published value already has at most d significant digits is typed exactly at d:
no plant, no run ("exact").

  bench/constant_sweep.py --list                    the enumerated constants (id, pipeline, value)
  bench/constant_sweep.py --pipeline pq_grading     sweep one pipeline (writes --json)
  bench/constant_sweep.py --only pq.m2              the constants whose id starts with pq.m2

Runs on this machine's lavapipe with -j 2 by default (the default suite's device).
"""

import argparse
import json
import math
import os
import re
import shutil
import signal
import struct
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHADERS = os.path.join(ROOT, "gpu", "shaders")

# Each pipeline's stage shaders (relative to gpu/shaders), in groups, and the cases a plant is
# judged on: a constant is run on the filters of the groups whose shaders include its file(s). Every
# pass of every stage a pipeline registers (`hdrconform pipelines`) is in a group (--check-table
# checks it). ue55's and ue58's suites are large: the groups name the case files that exercise the
# stage's paths (--filter); a constant they leave uncaught is then tried on more (--filter). The
# first group of each pipeline is what the sweep of its first stages ran on; the later groups
# (issue 28 item 5: every stage) hold the constants only their shaders include.
PIPELINES = {
    "pq_grading": [{"stages": ["pq_grading/stages/grade.comp"], "filter": "pq_grading/*"}],
    "operators": [{"stages": ["operators/stages/curve.comp"], "filter": "operators/*"}],
    "unity_urp": [{
        "stages": ["unity_urp/stages/lut_bake.comp", "unity_urp/stages/color_grading.comp"],
        "filter": "unity_urp/graded_look/*,unity_urp/lut_modes/*",
    }],
    "ue55": [
        {"stages": ["stages/combine_luts.comp", "stages/tonemap.comp"], "filter": "lut/devices/*"},
        # shaper (log and PQ) and linear_device (devices 7 and 8): 56 + 80 cases.
        {"stages": ["stages/shaper.comp", "stages/linear_device.comp"],
         "filter": "tonemap/shaper_pq/*,tonemap/linear_dev7/*,tonemap/linear_dev8/*"},
        # The grain: judged exactly on lavapipe (cases/defaults.json `dither`), 40 cases.
        {"stages": ["stages/dither.comp"], "filter": "tonemap/dither/*"},
        # Every UI mode and colour deficiency: 29 cases.
        {"stages": ["stages/ui_composite.comp"], "filter": "ui/composite/*,ui/color_deficiency/*"},
        {"stages": ["stages/visualize_histogram.comp", "stages/visualize_hdr.comp"],
         "filter": "visualize/visualize_hdr/*"},
    ],
    "ue58": [
        {"stages": ["ue58/stages/combine_luts.comp", "ue58/stages/combine_luts_inner.comp",
                    "ue58/stages/tonemap.comp", "ue58/stages/ui_composite.comp"],
         "filter": "ue58/hdr_display/*,ue58/shaper_eotf/*,ue58/grading/*,ue58/isolate/*"},
        # UE 5.5's dither and VisualizeHDR passes, run by ue58_dither and ue58_visualize_hdr.
        {"stages": ["stages/dither.comp"], "filter": "ue58/dither/*,ue58/dither_8bit/*"},
        # visualize_hdr_sdr: device 0's debug types 1 and 2, which isolate the eye-adaptation
        # luminance's floor and 1/3 (docs/constant-sweep.md "Every stage").
        {"stages": ["stages/visualize_histogram.comp", "stages/visualize_hdr.comp"],
         "filter": "ue58/visualize_hdr/*,ue58/visualize_hdr_devices/*,ue58/visualize_hdr_sdr/*"},
    ],
}


def stage_files(pipeline):
    return [s for g in PIPELINES[pipeline] for s in g["stages"]]


def registered_passes(hdrconform):
    """{pipeline: [pass shader]} of every stage `hdrconform pipelines` lists."""
    text = subprocess.run([hdrconform, "pipelines"], check=True, capture_output=True,
                          text=True).stdout
    out, current = {}, None
    for line in text.splitlines():
        m = re.match(r"(\w+)\s", line)
        if m:
            current = m.group(1)
            out.setdefault(current, [])
        m = re.match(r"\s+passes:\s*(.*)", line)
        if m and current:
            out[current] += [p.strip() for p in m.group(1).split("->")]
    return out


# Parameters a port types from the spec pages rather than reading params.json: name, pipeline,
# the shader file and expression that reads it, and the published value(s). Matrices are the
# spec-constants blocks (docs/spec/operators.md, pq_grading.md); Hable's two published sets
# (docs/spec/operators.md "Hable"); FilmToneMap's Default preset (docs/spec/film_tonemap.md).
HABLE_SETS = {
    # J. Hable, "Uncharted 2: HDR Lighting", GDC 2010, slide 142.
    "gdc": {"a": 0.22, "b": 0.30, "c": 0.10, "d": 0.20, "e": 0.01, "f": 0.30, "w": 11.2},
    # J. Hable, "Filmic Tonemapping Operators" (filmicworlds.com, 2010).
    "blog": {"a": 0.15, "b": 0.50, "c": 0.10, "d": 0.20, "e": 0.02, "f": 0.30, "w": 11.2},
}
FILM_DEFAULT = {"slope": 0.88, "toe": 0.55, "shoulder": 0.26, "black_clip": 0.0, "white_clip": 0.04}


def spec_matrices(pipeline):
    """The 3x3 matrices of docs/spec/<pipeline>.md's spec-constants block: {name: [9 floats]}."""
    path = os.path.join(ROOT, "docs", "spec", pipeline + ".md")
    out = {}
    if not os.path.exists(path):
        return out
    text = open(path, encoding="utf-8").read()
    for block in re.findall(r"```spec-constants[^\n]*\n(.*?)```", text, re.S):
        for line in block.splitlines():
            parts = line.split()
            if len(parts) == 10:
                out[parts[0]] = [float(v) for v in parts[1:]]
    return out


def round_sig(x, digits):
    """x to `digits` significant digits, as the decimal a porter types."""
    if x == 0 or not math.isfinite(x):
        return x
    return float("%.*g" % (digits, x))


def f32(x):
    return struct.unpack("f", struct.pack("f", x))[0]


def glsl_float(x):
    s = "%.9g" % x
    if not re.search(r"[.eE]", s):
        s += ".0"
    return s


def resolve_include(including, name):
    for base in (os.path.dirname(including), SHADERS):
        p = os.path.normpath(os.path.join(base, name))
        if os.path.exists(p):
            return p
    return None


def closure(stages):
    """The files the stage shaders include, transitively (absolute paths, in discovery order)."""
    seen, order = set(), []
    todo = [os.path.join(SHADERS, s) for s in stages]
    while todo:
        f = todo.pop(0)
        if f in seen:
            continue
        seen.add(f)
        order.append(f)
        for inc in re.findall(r'#include\s+"([^"]+)"', open(f, encoding="utf-8").read()):
            if inc == "hdrc/interface.glsl":
                continue
            p = resolve_include(f, inc)
            if p:
                todo.append(p)
    return order


NUM = r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?"


def strip_comments(s):
    return re.sub(r"//[^\n]*", "", s)


def literal_decls(path):
    """const float/vec3/mat3 declarations whose initializer is numeric literals only."""
    text = open(path, encoding="utf-8").read()
    out = []
    for m in re.finditer(r"const\s+float\s+(\w+)\s*=\s*(" + NUM + r")\s*;", text):
        out.append((m.group(1), "float", [float(m.group(2))]))
    # A quotient of two literals (1.0 / 2.4): a port may type its value instead.
    for m in re.finditer(r"const\s+float\s+(\w+)\s*=\s*(" + NUM + r")\s*/\s*(" + NUM + r")\s*;",
                         text):
        out.append((m.group(1), "quotient", [float(m.group(2)) / float(m.group(3))]))
    for m in re.finditer(r"const\s+(vec3|mat3)\s+(\w+)\s*=\s*\1\s*\(", text):
        end = text.index(");", m.end())
        body = strip_comments(text[m.end():end])
        items = [i.strip() for i in body.split(",")]
        if items and all(re.fullmatch(NUM, i) for i in items):
            out.append((m.group(2), m.group(1), [float(i) for i in items]))
    return out


def generated_constants(dump_exe):
    """{NAME: (kind, [values])} of hdrc/interface.glsl's generated constants and matrices."""
    text = subprocess.run([dump_exe], check=True, capture_output=True, text=True).stdout
    out = {}
    for m in re.finditer(r"const float (\w+) = (" + NUM + r");", text):
        out[m.group(1)] = ("float", [float(m.group(2))])
    for m in re.finditer(r"const mat3 (\w+) = mat3\(([^)]*)\);", text):
        out[m.group(1)] = ("mat3", [float(v) for v in m.group(2).split(",")])
    for m in re.finditer(r"const vec3 (\w+)\[3\] = vec3\[3\]\((.*)\);", text):
        vals = [float(v) for v in re.findall(NUM, m.group(2).replace("vec3", ""))]
        out[m.group(1)] = ("rows", vals)
    return out


def rel(path):
    return os.path.relpath(path, SHADERS)


def function_span(text, fn):
    """(start, end) of the body of GLSL function `fn` (first definition) in text."""
    m = re.search(r"\b\w+\s+" + fn + r"\s*\([^)]*\)\s*\{", text)
    if not m:
        return None
    depth, i = 1, m.end()
    while depth:
        depth += {"{": 1, "}": -1}.get(text[i], 0)
        i += 1
    return m.end(), i


def expr(kind, vals):
    if kind in ("float", "quotient"):
        return "(" + glsl_float(vals[0]) + ")"
    if kind == "vec3":
        return "vec3(" + ", ".join(glsl_float(v) for v in vals) + ")"
    if kind == "mat3":
        return "mat3(" + ", ".join(glsl_float(v) for v in vals) + ")"
    if kind == "rows":
        return "vec3[3](" + ", ".join(
            "vec3(" + ", ".join(glsl_float(v) for v in vals[3 * r:3 * r + 3]) + ")"
            for r in range(3)) + ")"
    if kind == "param_rows":  # P.<matrix>: vec4[3] rows
        return "vec4[3](" + ", ".join(
            "vec4(" + ", ".join(glsl_float(v) for v in vals[3 * r:3 * r + 3]) + ", 0.0)"
            for r in range(3)) + ")"
    raise ValueError(kind)


class Constant:
    """One constant of one pipeline and how to plant it.

    plants: [(file relative to gpu/shaders, mode, symbol, function or None)]; mode "decl" rewrites
    the declaration's literals, "symbol" replaces every whole-word use of symbol (within function,
    if given) by the rounded value's expression."""

    def __init__(self, cid, pipeline, name, kind, values, plants, where):
        self.id, self.pipeline, self.name = cid, pipeline, name
        self.kind, self.values, self.plants, self.where = kind, values, plants, where
        self.filter = None  # the cases it is judged on (enumerate_constants)

    def rounded(self, digits):
        return [round_sig(v, digits) for v in self.values]

    def exact_at(self, digits):
        """The typed value is the shader's float32 value: nothing to plant."""
        return all(f32(round_sig(v, digits)) == f32(v) for v in self.values)

    def typed(self, digits):
        r = self.rounded(digits)
        s = ", ".join("%.*g" % (digits, v) for v in r)
        return s if len(r) == 1 else "[" + s + "]"

    def plant(self, shader_dir, digits):
        vals = self.rounded(digits)
        for f, mode, symbol, fn in self.plants:
            path = os.path.join(shader_dir, f)
            text = open(path, encoding="utf-8").read()
            if mode == "decl":
                if self.kind in ("float", "quotient"):
                    quotient = r"\s*/\s*" + NUM if self.kind == "quotient" else ""
                    pat = r"(const\s+float\s+" + symbol + r"\s*=\s*)" + NUM + quotient + r"(\s*;)"
                    new, n = re.subn(pat, lambda m: m.group(1) + glsl_float(vals[0]) + m.group(2),
                                     text)
                else:
                    pat = r"const\s+" + self.kind + r"\s+" + symbol + r"\s*=\s*" + self.kind + \
                        r"\s*\((.*?)\);"
                    new, n = re.subn(pat, lambda m: "const " + self.kind + " " + symbol + " = " +
                                     expr(self.kind, vals) + ";", text, flags=re.S)
            else:
                kind = self.kind
                span = function_span(text, fn) if fn else (0, len(text))
                if span is None:
                    raise RuntimeError("%s: no function %s" % (f, fn))
                a, b = span
                body, n = re.subn(r"(?<![\w.])" + re.escape(symbol) + r"(?!\w)",
                                  expr(kind, vals), text[a:b])
                new = text[:a] + body + text[b:]
            if n == 0:
                raise RuntimeError("%s: %s not found in %s" % (self.id, symbol, f))
            open(path, "w", encoding="utf-8").write(new)


def group_files(pipeline):
    """The files the pipeline's stage shaders include, in discovery order (a group's closure after
    the earlier groups'), and, per file (relative), the indices of the groups that include it."""
    files, groups = [], {}
    for i, g in enumerate(PIPELINES[pipeline]):
        for f in closure(g["stages"]):
            if f not in files:
                files.append(f)
            groups.setdefault(rel(f), []).append(i)
    return files, groups


def enumerate_constants(pipeline, dump_exe):
    files, groups = group_files(pipeline)
    out = enumerate_in(pipeline, files, dump_exe)
    for c in out:
        # the cases of every group whose shaders include a file the plant edits
        idx = sorted({i for f, _, _, _ in c.plants for i in groups.get(f, [0])} or {0})
        c.filter = ",".join(PIPELINES[pipeline][i]["filter"] for i in idx)
    return out


def enumerate_in(pipeline, files, dump_exe):
    out = []
    seen = set()
    for path in files:
        for name, kind, vals in literal_decls(path):
            if name in seen:
                continue
            seen.add(name)
            out.append(Constant("%s.%s" % (pipeline, name), pipeline, name, kind, vals,
                                [(rel(path), "decl", name, None)], rel(path)))
    gen = generated_constants(dump_exe)
    texts = {rel(p): open(p, encoding="utf-8").read() for p in files}
    for name, (kind, vals) in gen.items():
        users = [f for f, t in texts.items() if re.search(r"(?<![\w.])" + name + r"(?!\w)", t)]
        if not users:
            continue
        plants = [(f, "symbol", name, None) for f in users]
        out.append(Constant("%s.%s" % (pipeline, name), pipeline, name, kind, vals, plants,
                            ", ".join(users) + " (generated)"))
        if name in ("PQ_M1", "PQ_M2", "PQ_C1", "PQ_C2", "PQ_C3") and "lib/st2084.glsl" in users:
            for fn, side in (("pq_from_nits", "encode"), ("nits_from_pq", "decode")):
                out.append(Constant("%s.%s.%s" % (pipeline, name, side), pipeline,
                                    name + " (" + side + " only)", kind, vals,
                                    [("lib/st2084.glsl", "symbol", name, fn)],
                                    "lib/st2084.glsl " + fn + " (generated)"))
    # Parameters typed from the spec pages.
    prefix = {"pq_grading": "pq_", "operators": "op_"}.get(pipeline)
    if prefix:
        for name, vals in spec_matrices(pipeline).items():
            users = [f for f, t in texts.items() if ("P." + name) in t]
            out.append(Constant("%s.%s" % (pipeline, name), pipeline, name, "param_rows", vals,
                                [(f, "symbol", "P." + name, None) for f in users],
                                ", ".join(users) + " (P." + name + ")"))
    if pipeline == "operators":
        for set_name, k in HABLE_SETS.items():
            for letter, v in k.items():
                out.append(Constant("operators.hable_%s.%s" % (set_name, letter), pipeline,
                                    "Hable %s %s" % (set_name, letter.upper()), "float", [v],
                                    [("operators/lib/operators.glsl", "symbol",
                                      "P.op_hable_" + letter, None)],
                                    "operators/lib/operators.glsl (P.op_hable_%s)" % letter))
    if pipeline in ("operators", "pq_grading"):
        for field, v in FILM_DEFAULT.items():
            out.append(Constant("%s.film_%s" % (pipeline, field), pipeline,
                                "FilmToneMap Default " + field, "float", [v],
                                [("lib/film_tonemap.glsl", "symbol", "P.film_" + field, None)],
                                "lib/film_tonemap.glsl (P.film_%s)" % field))
    return out


def run_cases(hdrconform, shader_dir, filt, jobs, out_dir):
    cmd = [hdrconform, "run", "--shader-dir", shader_dir, "--filter", filt, "-j", str(jobs),
           "--out", out_dir, "--images", "none", "--no-goldens"]
    path = os.path.join(out_dir, "results.json")
    for _ in range(2):  # once more after a run that published nothing (cases/ edited meanwhile)
        p = subprocess.run(cmd, capture_output=True, text=True)
        if os.path.exists(path):
            break
    if not os.path.exists(path):
        raise RuntimeError("no results: %s\n%s" % (" ".join(cmd), p.stderr[-2000:]))
    return json.load(open(path, encoding="utf-8"))


METRICS = ("pq_code10", "delta_e_itp", "linear_rel")


def case_maxima(results):
    """{case id: (verdict, {metric: max})}"""
    out = {}
    for c in results["cases"]:
        overall = ((c.get("stats") or {}).get("overall") or {})
        m = {}
        for k in METRICS:
            v = (overall.get(k) or {}).get("max")
            m[k] = v if isinstance(v, (int, float)) else (float("inf") if v else None)
        out[c["id"]] = (c["verdict"], m)
    return out


def summarize(planted, baseline):
    """FAIL ids and, per metric, the largest planted max with its case and the baseline there."""
    fails = sorted(i for i, (v, _) in planted.items() if v in ("FAIL", "ERROR"))
    newly = [i for i in fails if baseline.get(i, ("PASS",))[0] not in ("FAIL", "ERROR")]
    largest = {}
    for k in METRICS:
        best = None
        for i, (_, m) in planted.items():
            v = m.get(k)
            if v is None:
                continue
            b = baseline.get(i, (None, {}))[1].get(k) or 0.0
            # the case where the plant moved the metric most above float32 noise
            gain = v - b
            if best is None or gain > best[0]:
                best = (gain, i, v, b)
        if best:
            largest[k] = {"case": best[1], "planted": best[2], "baseline": best[3]}
    return {"fail": newly, "fail_count": len(newly), "largest": largest}


TABLE = os.path.join(ROOT, "docs", "constant-sweep.md")

# Representative rows of docs/constant-sweep.md that CTest pins (constant_sweep.pinned): the
# constant planted at the digits, the named case FAILs (and passes unplanted), and the table's row
# for the constant names that case.
PINNED = [
    ("pq_grading.PQ_M2", 4, "pq_grading/isolate/pq_m1_m2_roundtrip/near_black_decode"),
    ("pq_grading.PQ_M1", 4, "pq_grading/isolate/pq_m1_m2_roundtrip/near_black_decode"),
    ("pq_grading.PQG_SRGB_EXPONENT", 4, "pq_grading/isolate/srgb_exponent/near_black_srgb"),
    # Caught by a case's measured lavapipe overlay (cases/tolerance_overlays.json), not its set.
    ("pq_grading.AP1_RGB2Y", 4, "pq_grading/luts/display1_backbuffer0_lutpq_clip_33_hues"),
    ("unity_urp.URP_ACES_FIT_E", 4,
     "unity_urp/graded_look/gradingmode1_mode2_postexposure-2_colorchecker"),
    ("ue55.PQ_M2.encode", 4, "tonemap/display/hdr0_dev7_gamut1_lut16_fmt0_layout0_log_ramp"),
    # UE 5.8: a Tonemap case's measured overlay; 5.8's sRGB decode's isolating case.
    ("ue58.ACES_RAD_TO_DEG", 4, "ue58/tonemap_effects/dev0_shaper0_log_ramp"),
    ("ue58.UE58_SRGB_OFFSET", 4, "ue58/isolate/ui_srgb_offset/opaque_srgb_codes"),
    # The eye-adaptation luminance's 1/3 on its isolating VisualizeHDR case's measured overlay
    # (the floor, EA_LUMINANCE_MIN, is caught the same way on dev0_debug1, with more margin).
    ("ue58.EA_ONE_THIRD", 4, "ue58/visualize_hdr_sdr/dev0_debug2_log_ramp"),
]


DITHER_NOTE = (
    "caught on lavapipe by the exact grain pattern (cases/defaults.json `dither`: the reference's "
    "grain, where the device's sin is the host's); another GPU is judged by the grain's "
    "properties, which 543.3 and 493000 pass on all 52 dither cases (measured with "
    "`exact_pattern` never): a hash's constant cannot be told from a device's sin one ulp off, "
    "which the hash amplifies ~5e5-fold (runner/dither_test.cpp, DitherPlanted)")
VIS_PI_NOTE = (
    "no effect on any image: pi scales the illuminance meter's number (E = pi x mean), which UE "
    "prints as text; the port draws the meter's ring only, and the printed numbers a run records "
    "are the reference's (results.json reference_values): no case can see it")
HISTOGRAM_ONE_NOTE = (
    "no effect: the histogram packs each weight as trunc(w x 2^19) and unpacks the sum / 2^19 "
    "(PackFloatToUINT32, HistogramConvertCS) with the same constant, so 524300 scales and divides "
    "back, leaving the truncation's 2^-19 of a weight: no bar moves by a pixel")
EA_MAX_NOTE = (
    "no effect: 188700 for 188743.688 moves the histogram's maximum-brightness marker by "
    "log2(1.000231) / 30 = 1.1e-5 of the panel's width, far under a pixel")


# Verdicts the JSON lines alone cannot give: a constant no case catches, measured against what
# bounds it (float32 noise, a storage step), with the numbers (docs/constant-sweep.md "Findings");
# and how a few are caught (an isolating case, lavapipe's measured limits only).
# "within float32 noise" or "**uncaught**" in the text sets the counts table's column.
NOTES = {
    "ue58.AP1_TO_SRGB":
        "no effect: included with lib/post_device.glsl but not evaluated, UE 5.8's Tonemap writes "
        "devices 5/6 as the LUT holds them (no ST2084ToScRGB; docs/ue58-differences.md T1-T3)",
    "ue58.ACES2_AP0_2_AP1_2":
        "caught on lavapipe only, by the Tonemap cases' measured limits: the row typed (0.008316, "
        "-0.006032, 0.9977) moves AP1 blue by at most 1.6e-5 of itself, within ACES 2.0's float32 "
        "error (OCIO's criterion 3e-5, docs/ue58-decisions.md D), but tips stored texels to the "
        "neighbouring code (ue58/tonemap_stimuli/dev3_above_peak 0.00016 -> 1.0 PQ codes), past "
        "3 x the case's lavapipe maximum; another GPU is judged by the ue58_tonemap set's 2 codes, "
        "which it passes",
    "ue58.UE58_SRGB_OFFSET":
        "caught by its isolating case (docs/constant-sweep.md, UE 5.8's sRGB decode); on the UI "
        "and SDR-EOTF cases it moved the largest delta_e_itp 42 x (2.1e-5 -> 8.8e-4) within "
        "their tolerance",
    # UE 5.5's dither, VisualizeHDR and UI composite stages (and 5.8's runs of the first two).
    "ue55.DITHER_GRAIN_V_SCALE": DITHER_NOTE,
    "ue55.DITHER_GRAIN_SIN_SCALE": DITHER_NOTE,
    "ue58.DITHER_GRAIN_V_SCALE": DITHER_NOTE,
    "ue58.DITHER_GRAIN_SIN_SCALE": DITHER_NOTE,
    "ue55.VIS_PI": VIS_PI_NOTE,
    "ue58.VIS_PI": VIS_PI_NOTE,
    "ue55.HISTOGRAM_FIXED_POINT_ONE": HISTOGRAM_ONE_NOTE,
    "ue58.HISTOGRAM_FIXED_POINT_ONE": HISTOGRAM_ONE_NOTE,
    "ue55.EA_MAX_AVERAGE_LUMINANCE": EA_MAX_NOTE,
    "ue58.EA_MAX_AVERAGE_LUMINANCE": EA_MAX_NOTE,
    "ue58.EA_LUMINANCE_MIN":
        "caught on lavapipe only, by its isolating case's measured limits "
        "(ue58/visualize_hdr_sdr/dev0_debug1: 3 x 0.00288 PQ codes, 3 x 0.000703 delta_e_itp); "
        "on ue58's 7 other VisualizeHDR cases (devices 3/5/7) no case's largest error moved, the "
        "tonemapped scene's error being the largest; another GPU is judged by the "
        "ue58_visualize_hdr set (2 codes), which it passes. UE 5.5's copy fails 5 ue55 cases",
    "ue58.EA_ONE_THIRD":
        "caught on lavapipe only, by its isolating case's measured limits "
        "(ue58/visualize_hdr_sdr/dev0_debug2: 3 x 0.00288 PQ codes, 3 x 0.000703 delta_e_itp); "
        "on ue58's 7 other VisualizeHDR cases it moved dev3_debug2's delta_e_itp 0.0681 -> 0.0703 "
        "(+3 %, the tonemapped scene's error), under the set; another GPU is judged by the set, "
        "which it passes. UE 5.5's copy fails 3 ue55 cases",
    "ue58.UE58_SRGB_LINEAR_SCALE":
        "caught by its isolating case ue58/isolate/ui_srgb_linear_segment: 1/12.92 typed 0.0774 is "
        "8.0e-6 too large, on sRGB codes at or below 0.04045 only (no other case's error moved)",
}


def table_rows():
    """{constant id: the table's row text} of docs/constant-sweep.md (rows start with | `id`)."""
    rows = {}
    text = open(TABLE, encoding="utf-8").read()
    for line in text[text.index("\n## The table\n"):].splitlines():
        m = re.match(r"\|\s*`([^`]+)`", line)
        if m:
            rows[m.group(1)] = line
    return rows


def check_stages(hdrconform):
    """Every pass of every stage a pipeline registers is in its PIPELINES groups."""
    bad = 0
    for pipeline, passes in registered_passes(hdrconform).items():
        listed = set(stage_files(pipeline)) if pipeline in PIPELINES else set()
        for shader in sorted(set(passes) - listed):
            print("bench/constant_sweep.py: %s's pass %s is in no group of PIPELINES (its "
                  "constants are not swept)" % (pipeline, shader))
            bad += 1
    return bad


def check_table(constants, hdrconform):
    rows = table_rows()
    missing = [c.id for c in constants if c.id not in rows]
    known = {c.id for c in constants}
    stale = [i for i in rows if i not in known]
    for i in missing:
        print("docs/constant-sweep.md: no row for %s (bench/constant_sweep.py --list enumerates it)"
              % i)
    for i in stale:
        print("docs/constant-sweep.md: row %s is no constant the sweep enumerates" % i)
    print("%d constants, %d rows" % (len(constants), len(rows)))
    unlisted = check_stages(hdrconform)
    return 1 if missing or stale or unlisted else 0


def check_pinned(constants, hdrconform, jobs):
    by_id = {c.id: c for c in constants}
    rows = table_rows()
    work = tempfile.mkdtemp(prefix="constant-sweep-pinned-")
    bad = 0
    try:
        for cid, digits, case in PINNED:
            c = by_id.get(cid)
            if c is None:
                print("FAIL %s: not enumerated" % cid)
                bad += 1
                continue
            if case not in rows.get(cid, ""):
                print("FAIL %s: the table's row does not name %s" % (cid, case))
                bad += 1
            base = case_maxima(run_cases(hdrconform, SHADERS, "=" + case, jobs,
                                         os.path.join(work, "base")))
            copy = os.path.join(work, "shaders")
            shutil.rmtree(copy, ignore_errors=True)
            shutil.copytree(SHADERS, copy)
            c.plant(copy, digits)
            planted = case_maxima(run_cases(hdrconform, copy, "=" + case, jobs,
                                            os.path.join(work, "out")))
            ok = base.get(case, ("?",))[0] == "PASS" and planted.get(case, ("?",))[0] == "FAIL"
            print("%s %s typed %s: %s unplanted %s, planted %s" % (
                "ok  " if ok else "FAIL", cid, c.typed(digits), case, base.get(case, ("?",))[0],
                planted.get(case, ("?",))[0]))
            bad += 0 if ok else 1
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return 1 if bad else 0


def fmt(v):
    return "%.3g" % v


def effect_text(row):
    """'pq_code10 +8.02 (0.554 → 8.57), ...' over the metrics the plant moved."""
    parts = []
    for k in METRICS:
        e = row.get("largest", {}).get(k)
        if not e:
            continue
        gain = e["planted"] - e["baseline"]
        if gain > 0:
            parts.append("%s %s → %s" % (k, fmt(e["baseline"]), fmt(e["planted"])))
    return "; ".join(parts) if parts else "no metric moved"


def verdict_note(row):
    """Why a plant that failed nothing is not a hole: what it moved, against float32 noise."""
    if row.get("exact") or row.get("fail_count"):
        return ""
    ratio = 0.0
    for k in METRICS:
        e = row.get("largest", {}).get(k)
        if e and e["baseline"] > 0:
            ratio = max(ratio, e["planted"] / e["baseline"] - 1.0)
        elif e and e["planted"] > 0:
            ratio = float("inf")
    if ratio <= 0:
        return "no case's largest error moved: below float32 resolution on every stimulus"
    if ratio < 0.5:
        return "largest error up by %.0f %% at most: within float32 noise" % (100 * ratio)
    if math.isinf(ratio):
        return ("**uncaught** in the selection: a case matched exactly unplanted and moves, "
                "within its tolerance")
    return "**uncaught** in the selection: the largest error grows %.3g x, within every " \
        "case's tolerance" % (1 + ratio)


def merge_runs(a, b):
    """One constant's runs at the same digits on two case selections (--filter: a selection that
    left it uncaught tried on more of the suite) as one: the FAILs of both, per metric the case
    whose largest error the plant moved most. A rerun on the same selection replaces the first."""
    if a.get("exact") or b.get("exact") or a.get("filter") == b.get("filter"):
        return b
    out = dict(a)
    out["filter"] = a["filter"] + "," + b["filter"]
    out["fail"] = a["fail"] + [i for i in b["fail"] if i not in a["fail"]]
    out["fail_count"] = len(out["fail"])
    largest = dict(a.get("largest", {}))
    for k, e in b.get("largest", {}).items():
        if k not in largest or \
                e["planted"] - e["baseline"] > largest[k]["planted"] - largest[k]["baseline"]:
            largest[k] = e
    out["largest"] = largest
    return out


def counts(constants, results):
    """Per pipeline, the number of constants per verdict of the table's 4-digit column."""
    rows = markdown_rows(constants, results, NOTES)
    kinds = ("exact", "caught", "none", "noise", "uncaught", "not")
    out = {}
    for line in rows:
        cells = [c.strip() for c in line.split("|")]
        c4, note = cells[4], cells[6]
        if c4.startswith("exact"):
            k = "exact"
        elif c4 == "not swept":
            k = "not"
        elif "FAIL**" in c4:
            k = "caught"
        elif "**uncaught**" in note:
            k = "uncaught"
        elif "no metric moved" in c4:
            k = "none"
        else:
            k = "noise"
        out.setdefault(cells[1].strip("`").split(".")[0], dict.fromkeys(kinds, 0))[k] += 1
    return ["| `%s` | %d | %s |" % (p, sum(c.values()), " | ".join(str(c[k]) for k in kinds))
            for p, c in out.items()]


def markdown_rows(constants, results, notes):
    """One table row per enumerated constant, from the sweep's JSON lines (both digit counts); a
    constant typed exactly needs no run, one without results is "not swept"."""
    by_id = {}
    for r in results:
        per = by_id.setdefault(r["id"], {})
        d = r["digits"]
        per[d] = merge_runs(per[d], r) if d in per else r
    lines = []
    for c in constants:
        cid = c.id
        per = by_id.get(cid, {})
        for d in (4, 5):
            if d not in per and c.exact_at(d):
                per[d] = {"id": cid, "where": c.where, "value": c.values, "digits": d,
                          "typed": c.typed(d), "exact": True}
        if not per:
            value = ", ".join("%.10g" % v for v in c.values) if len(c.values) == 1 else \
                "%d entries" % len(c.values)
            lines.append("| `%s` | %s | %s | not swept | — | %s |" % (
                cid, c.where, value, notes.get(cid, "not swept in this measurement (time)")))
            continue
        any_row = next(iter(per.values()))
        value = ", ".join("%.10g" % v for v in any_row["value"])
        if len(any_row["value"]) > 1:
            value = "%d entries" % len(any_row["value"])
        cells = []
        for d in (4, 5):
            r = per.get(d)
            if r is None and d == 4:
                cells.append("not swept")
            elif r is None:
                moved = per.get(4) and not per[4].get("exact") and \
                    effect_text(per[4]) != "no metric moved"
                cells.append("not run" if moved else "—")
            elif r.get("exact"):
                cells.append("exact (%s)" % r["typed"] if len(r["value"]) == 1 else "exact")
            else:
                typed = r["typed"] if len(r["value"]) == 1 else "each entry"
                if r["fail_count"]:
                    # the isolating case where one catches it, else the first
                    named = next((i for i in r["fail"] if "/isolate/" in i), r["fail"][0])
                    cells.append("%s: **%d FAIL**, e.g. `%s`; %s" % (
                        typed, r["fail_count"], named, effect_text(r)))
                else:
                    cells.append("%s: 0 FAIL; %s" % (typed, effect_text(r)))
        note = notes.get(cid) or (verdict_note(per[4]) if 4 in per else
                                  "not swept in this measurement (time)")
        lines.append("| `%s` | %s | %s | %s | %s | %s |" % (
            cid, any_row["where"], value, cells[0], cells[1], note))
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--list", action="store_true", help="print the enumerated constants and exit")
    ap.add_argument("--pipeline", action="append", help="pipeline(s) to sweep (default: all)")
    ap.add_argument("--only", action="append", help="constant id prefix(es)")
    ap.add_argument("--digits", default="4,5", help="significant digits typed (default 4,5)")
    ap.add_argument("--filter", help="override the pipeline's case filter")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"), help="build folder")
    ap.add_argument("--hdrconform", help="the hdrconform binary (default: BUILD/runner/hdrconform; "
                    "a copy keeps a long sweep off a rebuild)")
    ap.add_argument("-j", "--jobs", type=int, default=2)
    ap.add_argument("--json", help="append the results (JSON lines) to this file; the constants "
                    "and digits it holds already are not run again")
    ap.add_argument("--markdown", metavar="JSONL[,JSONL...]",
                    help="print the table rows of the enumerated constants from sweeps' --json "
                    "output and exit")
    ap.add_argument("--counts", action="store_true",
                    help="with --markdown: print the counts table's rows (constants per pipeline "
                    "and verdict) instead")
    ap.add_argument("--check-table", action="store_true",
                    help="exit 1 unless docs/constant-sweep.md has a row for every constant")
    ap.add_argument("--pinned", action="store_true",
                    help="plant the table's pinned rows (PINNED): each named case must FAIL")
    args = ap.parse_args()

    dump = os.path.join(args.build, "bench", "shader_constants_dump")
    hdrconform = args.hdrconform or os.path.join(args.build, "runner", "hdrconform")
    pipelines = args.pipeline or list(PIPELINES)
    constants = [c for p in pipelines for c in enumerate_constants(p, dump)]
    if args.only:
        constants = [c for c in constants if any(c.id.startswith(o) for o in args.only)]
    digits = [int(d) for d in args.digits.split(",")]

    if args.markdown:
        results = [json.loads(l) for f in args.markdown.split(",")
                   for l in open(f, encoding="utf-8") if l.strip()]
        print("\n".join(counts(constants, results) if args.counts else
                        markdown_rows(constants, results, NOTES)))
        return 0
    if args.check_table:
        return check_table(constants, hdrconform)
    if args.pinned:
        return check_pinned(constants, hdrconform, args.jobs)
    if args.list:
        for c in constants:
            print("%s\t%s\t%s\t%s" % (c.id, c.pipeline, c.where,
                                      ", ".join("%.10g" % v for v in c.values)))
        return 0

    done = set()
    if args.json and os.path.exists(args.json):
        for line in open(args.json, encoding="utf-8"):
            if line.strip():
                r = json.loads(line)
                done.add((r["id"], r["digits"]))
    # SIGTERM as an exception, so that the finally below removes the work folder.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    work = tempfile.mkdtemp(prefix="constant-sweep-")
    baselines = {}
    sink = open(args.json, "a", encoding="utf-8") if args.json else None
    try:
        for c in constants:
            filt = args.filter or c.filter
            for d in digits:
                if (c.id, d) in done:
                    continue
                row = {"id": c.id, "pipeline": c.pipeline, "name": c.name, "where": c.where,
                       "value": c.values, "digits": d, "typed": c.typed(d), "filter": filt}
                if c.exact_at(d):
                    row["exact"] = True
                else:
                    if filt not in baselines:
                        baselines[filt] = case_maxima(run_cases(
                            hdrconform, SHADERS, filt, args.jobs,
                            os.path.join(work, "baseline-%d" % len(baselines))))
                    copy = os.path.join(work, "shaders")
                    shutil.rmtree(copy, ignore_errors=True)
                    shutil.copytree(SHADERS, copy)
                    c.plant(copy, d)
                    out = os.path.join(work, "out")
                    shutil.rmtree(out, ignore_errors=True)
                    row.update(summarize(case_maxima(run_cases(hdrconform, copy, filt, args.jobs,
                                                               out)), baselines[filt]))
                line = json.dumps(row)
                print(line, flush=True)
                if sink:
                    sink.write(line + "\n")
                    sink.flush()
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
