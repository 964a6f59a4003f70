#!/usr/bin/env python3
"""A port of UE 5.5's HDR output for output device 3 (ACES 1000 nits, ST 2084), from the docs alone.

Pure Python (no numpy), double precision. Formulas: docs/spec/ue55.md (section named at each
step), docs/spec/film_tonemap.md (the glow helpers the ACES sweeteners share), docs/spec/semantics.md
(D3D intrinsics); the contract: docs/candidate-protocol.md and docs/candidates/<stage>.md.
Nothing of hdrconform's source was read.

Stages: `shaper`, `combine_luts`, `tonemap` (device 3 only). Every other stage is declined with
exit 78, another device with exit 77, a tonemap feature this port lacks (colour fringe, the bloom
dirt mask) with exit 77.

Usage: ue55_dev3_candidate.py --params {params} --output {output}
"""
import argparse
import json
import math
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
from exr_io import read_exr, write_exr  # noqa: E402
from hlsl_math import (NAN, INF, hmax, hmin, sat, clamp, lerp, hpow, hlog10, exp2, mul,  # noqa: E402
                       to_half)

# --- D3D intrinsics (docs/spec/semantics.md) ---
def fdiv(a, b):
    """IEEE-754 division (Python raises on x / 0): x / 0 = ±Inf, 0 / 0 = NaN."""
    if b == 0.0:
        if a != a or a == 0.0:
            return NAN
        return math.copysign(INF, a) * math.copysign(1.0, b)
    return a / b


def smoothstep(e0, e1, x):
    t = sat((x - e0) / (e1 - e0))
    return t * t * (3.0 - 2.0 * t)


def rows(flat):
    """params.json matrices: 9 numbers, rows (or a list of 3 rows)."""
    if len(flat) == 3:
        return [list(r)[:3] for r in flat]
    return [flat[0:3], flat[3:6], flat[6:9]]


def num(v):
    if isinstance(v, str):
        return {"NaN": NAN, "Infinity": INF, "-Infinity": -INF}[v]
    return v


def nums(v):
    if isinstance(v, list):
        return [nums(x) for x in v]
    return num(v)


# --- Constants (ue55.md §2.1, §3.1, §4.5) ---
AP1_RGB2Y = (0.2722287168, 0.6740817658, 0.0536895174)
AP0_2_AP1 = [[1.4514393161, -0.2365107469, -0.2149285693],
             [-0.0765537734, 1.1762296998, -0.0996759264],
             [0.0083161484, -0.0060324498, 0.9977163014]]
AP1_2_XYZ = [[0.6624541811, 0.1340042065, 0.1561876870],
             [0.2722287168, 0.6740817658, 0.0536895174],
             [-0.0055746495, 0.0040607335, 1.0103391003]]
XYZ_2_AP1 = [[1.6410233797, -0.3248032942, -0.2364246952],
             [-0.6636628587, 1.6153315917, 0.0167563477],
             [0.0117218943, -0.0082844420, 0.9883948585]]
AP1_2_AP0 = [[0.6954522414, 0.1406786965, 0.1638690622],
             [0.0447945634, 0.8596711185, 0.0955343182],
             [-0.0055258826, 0.0040252103, 1.0015006723]]
EXPAND_MAT = [[1.3704123718, -0.3292921877, -0.0636831194],
              [-0.0834334917, 1.0970927480, -0.0108613795],
              [-0.0257933209, -0.0986257988, 1.2036949526]]
PQ_M1, PQ_M2 = 0.1593017578125, 78.84375
PQ_C1, PQ_C2, PQ_C3 = 0.8359375, 18.8515625, 18.6875


def linear_to_st2084(nits):  # §3.1, no clamp: negative nits give NaN
    lm = hpow(nits / 10000.0, PQ_M1)
    return hpow((PQ_C1 + PQ_C2 * lm) * (1.0 / (1.0 + PQ_C3 * lm)), PQ_M2)


def st2084_to_linear(n):  # §3.1
    np_ = hpow(n, 1.0 / PQ_M2)
    l = hmax(np_ - PQ_C1, 0.0) / (PQ_C2 - PQ_C3 * np_)
    return hpow(l, 1.0 / PQ_M1) * 10000.0


# --- ACES 1.3 output transform (ue55.md §5.1, §5.2; helpers: film_tonemap.md) ---
def rgb_2_saturation(c):
    mx = hmax(hmax(c[0], c[1]), c[2])
    mn = hmin(hmin(c[0], c[1]), c[2])
    return (hmax(mx, 1e-10) - hmax(mn, 1e-10)) / hmax(mx, 0.01)


def rgb_2_yc(c):
    r, g, b = c
    return (b + g + r + 1.75 * math.sqrt(b * (b - g) + g * (g - r) + r * (r - b))) / 3.0


def sigmoid_shaper(x):
    t = hmax(1.0 - abs(x / 2.0), 0.0)
    s = float(x > 0.0) - float(x < 0.0)
    return 0.5 * (1.0 + s * (1.0 - t * t))


def glow_fwd(yc, gain, mid):
    if yc <= 2.0 / 3.0 * mid:
        return gain
    if yc >= 2.0 * mid:
        return 0.0
    return gain * (mid / yc - 0.5)


def rgb_2_hue(c):
    r, g, b = c
    if r == g and g == b:
        return 0.0
    h = math.degrees(math.atan2(math.sqrt(3.0) * (g - b), 2.0 * r - g - b))
    if h < 0.0:
        h += 360.0
    return clamp(h, 0.0, 360.0)


def center_hue(h, c):
    h = h - c
    if h < -180.0:
        h += 360.0
    elif h > 180.0:
        h -= 360.0
    return h


BASIS = [[-1 / 6, 3 / 6, -3 / 6, 1 / 6], [3 / 6, -6 / 6, 3 / 6, 0.0],
         [-3 / 6, 0.0, 3 / 6, 0.0], [1 / 6, 4 / 6, 1 / 6, 0.0]]


def cubic_basis_shaper(x, w):
    if not (-w / 2.0 < x < w / 2.0):
        return 0.0
    kc = (x + w / 2.0) * 4.0 / w
    j = int(math.floor(kc))
    t = kc - j
    m = (t * t * t, t * t, t, 1.0)
    return 1.5 * sum(m[k] * BASIS[k][3 - j] for k in range(4))


def rrt_sweeteners(aces):
    satv = rgb_2_saturation(aces)
    yc = rgb_2_yc(aces)
    s = sigmoid_shaper((satv - 0.4) / 0.2)
    glow = 1.0 + glow_fwd(yc, 0.05 * s, 0.08)
    aces = [v * glow for v in aces]
    hue = rgb_2_hue(aces)
    w = cubic_basis_shaper(center_hue(hue, 0.0), 135.0)
    aces[0] = aces[0] + w * satv * (0.03 - aces[0]) * (1.0 - 0.82)
    aces = [clamp(v, 0.0, 65535.0) for v in aces]
    pre = [clamp(v, 0.0, 65504.0) for v in mul(AP0_2_AP1, aces)]
    y = sum(AP1_RGB2Y[i] * pre[i] for i in range(3))
    return [lerp(y, v, 0.96) for v in pre]


def compress_color(aces):
    lin = mul(AP0_2_AP1, aces)
    ach = max(lin)
    if ach < 1e-10 or any(v < 0.0 for v in aces):
        return list(aces)
    lims, thrs = (1.147, 1.264, 1.312), (0.815, 0.803, 0.880)
    out = []
    for i in range(3):
        d = (ach - lin[i]) / abs(ach)
        lim, thr, p = lims[i], thrs[i], 1.2
        if d >= thr:
            scl = (lim - thr) / math.pow(math.pow((1.0 - thr) / (lim - thr), -p) - 1.0, 1.0 / p)
            nd = (d - thr) / scl
            d = thr + scl * nd / math.pow(1.0 + math.pow(nd, p), 1.0 / p)
        out.append(ach - d * abs(ach))
    return mul(AP1_2_AP0, out)


class Ssts:
    def __init__(self, p):
        mm = p["aces_min_max"]
        self.min_x, self.min_y, self.max_x, self.max_y = mm[0], mm[1], mm[2], mm[3]
        self.mid_x = p["aces_mid"][0]
        lo, hi = p["aces_coefs_low_0"], p["aces_coefs_high_0"]
        self.low = list(lo[:4]) + [p["aces_coefs_low_4"]] * 2
        self.high = list(hi[:4]) + [p["aces_coefs_high_4"]] * 2

    def __call__(self, x):  # §5.2
        lx = hlog10(hmax(x, 1e-10))
        lmin, lmid, lmax = math.log10(self.min_x), math.log10(self.mid_x), math.log10(self.max_x)
        if lx <= lmin:
            ly = math.log10(self.min_y)
        elif lx < lmid:
            kc = 3.0 * (lx - lmin) / (lmid - lmin)
            j = int(kc)
            t = kc - j
            c0, c1, c2 = self.low[j:j + 3]
            ly = t * t * (0.5 * c0 - c1 + 0.5 * c2) + t * (c1 - c0) + 0.5 * (c0 + c1)
        elif lx < lmax:
            kc = 3.0 * (lx - lmid) / (lmax - lmid)
            j = int(kc)
            t = kc - j
            c0, c1, c2 = self.high[j:j + 3]
            ly = t * t * (0.5 * c0 - c1 + 0.5 * c2) + t * (c1 - c0) + 0.5 * (c0 + c1)
        else:
            ly = math.log10(self.max_y)
        return math.pow(10.0, ly)


class Ue55:
    def __init__(self, pj):
        p = {k: nums(v) for k, v in pj["params"].items()}
        self.p = p
        self.device = int(p["output_device"])
        self.to_ap1 = rows(p["wcs_to_ap1"])
        self.from_ap1 = rows(p["wcs_from_ap1"])
        self.to_ap0 = rows(p["wcs_to_ap0"])
        self.ap1_to_output = rows(p["ap1_to_output"])
        self.wb = rows(p["white_balance"]) if int(p["white_balance_enabled"]) else None
        self.ssts = Ssts(p)
        self.n = int(p["lut_size"])

    # §4.6
    def color_correct_all(self, c):
        p = self.p
        luma = sum(AP1_RGB2Y[i] * c[i] for i in range(3))

        def zone(suffix):
            g = lambda k: p["cc_" + k]  # noqa: E731
            z = lambda k: p["cc_" + k + suffix]  # noqa: E731
            s = [z("saturation")[i] * g("saturation")[i] for i in range(4)]
            k = [z("contrast")[i] * g("contrast")[i] for i in range(4)]
            gm = [z("gamma")[i] * g("gamma")[i] for i in range(4)]
            a = [z("gain")[i] * g("gain")[i] for i in range(4)]
            o = [z("offset")[i] + g("offset")[i] for i in range(4)]
            l = sum(AP1_RGB2Y[i] * c[i] for i in range(3))
            out = [hmax(0.0, lerp(l, c[i], s[i] * s[3])) for i in range(3)]
            out = [hpow(out[i] / 0.18, k[i] * k[3]) * 0.18 for i in range(3)]
            out = [hpow(out[i], 1.0 / (gm[i] * gm[3])) for i in range(3)]
            return [out[i] * (a[i] * a[3]) + (o[i] + o[3]) for i in range(3)]

        ws = 1.0 - smoothstep(0.0, p["cc_shadows_max"], luma)
        wh = smoothstep(p["cc_highlights_min"], p["cc_highlights_max"], luma)
        wm = 1.0 - ws - wh
        cs, cm, ch = zone("_shadows"), zone("_midtones"), zone("_highlights")
        return [cs[i] * ws + cm[i] * wm + ch[i] * wh for i in range(3)]

    def texel(self, coord):
        """§4: CombineLUTs for device 3 at a lattice coordinate; returns OutDeviceColor."""
        p = self.p
        lin = [st2084_to_linear(v) * (1.0 / 100.0) for v in coord]  # §4.3
        if self.wb is not None:  # §4.4
            lin = mul(self.wb, lin)
        ap1 = mul(self.to_ap1, lin)  # §4.5
        luma = sum(AP1_RGB2Y[i] * ap1[i] for i in range(3))
        if luma == 0.0:
            amount = 0.0  # D-NaN
        else:
            d2 = sum((ap1[i] / luma - 1.0) ** 2 for i in range(3))
            amount = (1.0 - exp2(-4.0 * d2)) * (1.0 - exp2(-4.0 * p["expand_gamut"] * luma * luma))
        ex = mul(EXPAND_MAT, ap1)
        ap1 = [lerp(ap1[i], ex[i], amount) for i in range(3)]
        ap1 = self.color_correct_all(ap1)
        graded = mul(self.from_ap1, ap1)  # §4.7
        cs, ov = p["color_scale"], p["overlay_color"]
        graded = [lerp(graded[i] * cs[i], ov[i], ov[3]) for i in range(3)]
        # §5.1 ACESOutputTransforms1000
        scm = p["aces_scene_color_multiplier"]
        aces = mul(self.to_ap0, [v * scm for v in graded])
        gc = p["aces_gamut_compression"]
        comp = compress_color(aces)
        aces = [lerp(aces[i], comp[i], gc) for i in range(3)]
        pre = rrt_sweeteners(aces)
        post = [self.ssts(v) for v in pre]
        ymin, ymax = self.ssts.min_y, self.ssts.max_y
        cv = [(v - ymin) / (ymax - ymin) for v in post]
        xyz = mul(AP1_2_XYZ, cv)
        xyz = mul(AP1_2_XYZ, [clamp(v, 0.0, 1.0) for v in mul(XYZ_2_AP1, xyz)])
        cv = [clamp(v, 0.0, 65535.0) for v in mul(XYZ_2_AP1, xyz)]
        nits = [clamp(v * ymax, 0.0, 65535.0) for v in cv]
        odt = mul(self.ap1_to_output, nits)  # §4.12, device 3
        return [linear_to_st2084(v) for v in odt]


SRGB_2_XYZ = [[0.4123907993, 0.3575843394, 0.1804807884],
              [0.2126390059, 0.7151686788, 0.0721923154],
              [0.0193308187, 0.1191947798, 0.9505321522]]
XYZ_2_REC2020 = [[1.7166511880, -0.3556707838, -0.2533662814],
                 [-0.6666843518, 1.6164812366, 0.0157685458],
                 [0.0176398574, -0.0427706133, 0.9421031212]]
SRGB_TO_REC2020 = [[sum(XYZ_2_REC2020[i][k] * SRGB_2_XYZ[k][j] for k in range(3))
                    for j in range(3)] for i in range(3)]


def srgb_to_linear(c):  # ue55.md §3.3 with D3's clamp
    c = hmax(6.10352e-5, c)
    return hpow(c / 1.055 + 0.0521327, 2.4) if c > 0.04045 else c / 12.92


def f32(x):
    """Rounds to float32 (the dither's hash is specified in float32)."""
    if not math.isfinite(x):
        return x
    try:
        return struct.unpack("<f", struct.pack("<f", x))[0]
    except OverflowError:
        return math.copysign(INF, x)


def quantize(v, fmt):  # §4.12 storage (D-S1)
    if fmt == 0:
        return round(sat(v) * 1023.0) / 1023.0
    if fmt == 1:
        return to_half(v)
    return struct.unpack("<f", struct.pack("<f", v))[0] if math.isfinite(v) else v


def lattice_coord(r, g, b, n, layout):  # §4.2
    if layout == 1:
        return ((r + 1e-5) / (n - 1), (g + 1e-5) / (n - 1), b / (n - 1))
    return (r / (n - 1), g / (n - 1), b / (n - 1))


STAGES = ("shaper", "combine_luts", "tonemap", "dither", "ui_composite")


def decline(code, why):
    print(why)
    return code


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--params", required=True)
    ap.add_argument("--output", required=True)
    args = ap.parse_args()
    with open(args.params) as f:
        pj = json.load(f)
    if pj.get("format_version") != 3:
        return decline(78, f"params.json format_version {pj.get('format_version')} is not 3")
    stage = pj.get("stage")
    if pj.get("pipeline", "ue55") != "ue55" or stage not in STAGES:
        return decline(78, f"this port implements ue55 shaper/combine_luts/tonemap, not "
                           f"{pj.get('pipeline')}/{stage}")
    if pj.get("degenerate"):
        return decline(77, "degenerate case: not judged")
    ue = Ue55(pj)
    if ue.device != 3:
        return decline(77, f"output device {ue.device} is not implemented by this port (device 3 only)")
    base = os.path.dirname(os.path.abspath(args.params))
    out = pj["output"]
    w, h = int(out["width"]), int(out["height"])
    p = ue.p
    inp = pj["images"]["input"]
    inp_file = inp["file"] if isinstance(inp, dict) else inp

    if stage == "combine_luts":  # docs/candidates/combine_luts.md: rounded to storage.lut_format
        n, layout, fmt = ue.n, int(p["lut_layout"]), int(p["lut_format"])
        planes = {c: [0.0] * (w * h) for c in "RGBA"}
        for b in range(n):
            for g in range(n):
                for r in range(n):
                    v = ue.texel(lattice_coord(r, g, b, n, layout))
                    i = g * w + r + n * b
                    planes["R"][i], planes["G"][i], planes["B"][i] = [
                        quantize(x / 1.05, fmt) for x in v]
        write_exr(args.output, w, h, planes)
        return 0

    iw, ih, src = read_exr(os.path.join(base, inp_file))
    npx = iw * ih
    alpha = list(src.get("A", [0.0] * npx))
    if stage == "shaper":  # docs/candidates/shaper.md, devices 3-9
        planes = {"A": alpha}
        for c in "RGB":
            planes[c] = [st2084_to_linear(clamp_nan(linear_to_st2084(x * 100.0))) / 100.0
                         for x in src[c]]
        write_exr(args.output, iw, ih, planes)
        return 0

    if stage == "dither":  # docs/candidates/dither.md, ue55.md §6.1 step 10
        gr, amount = p["grain_random"], p["dither_amount"]
        planes = {"A": alpha}
        for c in "RGB":
            planes[c] = [0.0] * npx
        for y in range(ih):
            for x in range(iw):
                i = y * iw + x
                u = f32(f32(f32(x + 0.5) / iw) + gr[0])
                v = f32(f32(f32(y + 0.5) / ih) + gr[1])
                g = f32(math.sin(f32(u + f32(v * 543.31))))
                g = f32(g * 493013.0)
                g = f32(g - math.floor(g))
                nn = f32(2.0 * g - 1.0)
                sg = float(nn > 0.0) - float(nn < 0.0)
                t = f32(sg - f32(sg * f32(math.sqrt(sat(f32(1.0 - abs(nn)))))))
                for c in "RGB":
                    planes[c][i] = src[c][i] + t * amount
        write_exr(args.output, iw, ih, planes)
        return 0

    if stage == "ui_composite":  # ue55.md §8
        if int(p["cvd_type"]) != 0 and p["cvd_severity"] > 0:
            return decline(77, "colour-vision deficiency is not implemented by this port")
        ui_i = pj["images"]["ui"]
        uw, uh, ui = read_exr(os.path.join(base, ui_i["file"] if isinstance(ui_i, dict) else ui_i))
        level, lum = p["ui_level"], p["ui_luminance"]
        planes = {c: [0.0] * npx for c in "RGB"}
        planes["A"] = [1.0] * npx
        if int(p["ui_composite_mode"]) == 0:
            # CompositeMode 0: no shader composite; the UI is blended over the back buffer's codes
            # with premultiplied alpha (docs/spec/ue55.md §8, "CompositeMode 0").
            for i in range(npx):
                a = ui["A"][i]
                for c in "RGB":
                    planes[c][i] = src[c][i] * (1.0 - a) + ui[c][i]
            write_exr(args.output, iw, ih, planes)
            return 0
        for i in range(npx):
            u = [srgb_to_linear(ui[c][i]) for c in "RGB"]
            u = [v * lum for v in mul(SRGB_TO_REC2020, u)]
            a = ui["A"][i]
            scene = [st2084_to_linear(src[c][i]) for c in "RGB"]
            if 0.0 < a < 1.0:
                scene = [hmax(v, 0.0) for v in scene]
                l = fdiv(0.2627 * scene[0] + 0.678 * scene[1] + 0.0593 * scene[2], level)
                out_l = fdiv(1.0, l + 1.0)
                k = lerp(1.0, out_l * level, a)
                scene = [v * k for v in scene]
            rgb = [scene[c] * (1.0 - a) + u[c] * level for c in range(3)]
            for c in range(3):
                planes["RGB"[c]][i] = linear_to_st2084(rgb[c])
        write_exr(args.output, iw, ih, planes)
        return 0

    # tonemap (§6.1 steps 1-9)
    fringe = p.get("fringe", [0, 0, 0, 0])
    n, fmt = ue.n, int(p["lut_format"])
    lut = [None] * (n * n * n)
    layout = int(p["lut_layout"])
    for b in range(n):
        for g in range(n):
            for r in range(n):
                v = ue.texel(lattice_coord(r, g, b, n, layout))
                lut[(b * n + g) * n + r] = [quantize(x / 1.05, fmt) for x in v]
    bloom = None
    if "bloom" in pj["images"] and pj["images"]["bloom"]:
        bi = pj["images"]["bloom"]
        bw, bh, bp = read_exr(os.path.join(base, bi["file"] if isinstance(bi, dict) else bi))
        if (bw, bh) != (iw, ih):
            return decline(77, f"bloom {bw}x{bh} of another size than the input: not implemented")
        bloom = bp
    dirt = None
    if "bloom_dirt" in pj["images"] and pj["images"]["bloom_dirt"]:
        di = pj["images"]["bloom_dirt"]
        dw, dh, dirt = read_exr(os.path.join(base, di["file"] if isinstance(di, dict) else di))
        if (dw, dh) != (iw, ih):
            return decline(77, f"bloom dirt {dw}x{dh} of another size than the input: not implemented")
    dirt_tint = p.get("bloom_dirt_tint", [0.0, 0.0, 0.0, 0.0])
    exposure = p["exposure"]
    tint = p["scene_color_tint"]
    vig = p["vignette_intensity"]
    sharpen = p.get("sharpen_div6", 0.0)
    ar = ih / iw
    planes = {c: [0.0] * npx for c in "RGBA"}
    for y in range(ih):
        for x in range(iw):
            i = y * iw + x
            s = [src["R"][i], src["G"][i], src["B"][i]]
            # pixel centre in [-1, 1], y up (§6.1 steps 1 and 3)
            px = (x + 0.5) / iw * 2.0 - 1.0
            py = 1.0 - (y + 0.5) / ih * 2.0
            if fringe[3]:  # §6.1 step 1: R from a sample scaled by CAScaleR, G by CAScaleG
                def ca_sample(scale, ch):
                    def comp(l):
                        sg = float(l > 0.0) - float(l < 0.0)
                        return l - sg * sat(abs(l) - fringe[2]) * scale
                    u = comp(px) * 0.5 + 0.5
                    v = 0.5 - comp(py) * 0.5
                    return bilinear(src[ch], iw, ih, u * iw - 0.5, v * ih - 0.5)
                s = [ca_sample(fringe[0], "R"), ca_sample(fringe[1], "G"), s[2]]
            if sharpen > 0.0:  # §6.1 step 2; neighbours clamped to the image
                a0 = luminance(s)
                nb = [(min(x + 1, iw - 1), y), (max(x - 1, 0), y), (x, min(y + 1, ih - 1)),
                      (x, max(y - 1, 0))]
                cs = [[src[c][ny * iw + nx] for c in "RGB"] for nx, ny in nb]
                edge = exposure * max(abs(a0 - luminance(c)) for c in cs)
                edge_mask = sat(1.0 - edge)
                s = [s[c] + ((cs[0][c] + cs[1][c] + cs[2][c] + cs[3][c]) - 4.0 * s[c])
                     * (-edge_mask * sharpen) for c in range(3)]
            mask = 1.0
            if vig > 0.0:
                k = math.sqrt(2.0) / math.sqrt(1.0 + ar * ar)
                vx, vy = px * k * vig, py * ar * k * vig
                mask = (1.0 / (vx * vx + vy * vy + 1.0)) ** 2
            fl = [s[c] * tint[c] * (exposure * mask) for c in range(3)]
            if bloom is not None:
                raw = [bloom["RGB"[c]][i] for c in range(3)]
                if dirt is not None:  # §6.1 step 5: dirt at the pixel's own UV
                    raw = [raw[c] * (1.0 + dirt["RGB"[c]][i] * dirt_tint[c]) for c in range(3)]
                fl = [fl[c] + raw[c] * (exposure * mask) for c in range(3)]
            enc = [linear_to_st2084(v * 100.0) for v in fl]
            dev = [v * 1.05 for v in sample(lut, n, enc)]
            planes["R"][i], planes["G"][i], planes["B"][i] = dev
            planes["A"][i] = 0.299 * dev[0] + 0.587 * dev[1] + 0.114 * dev[2]
    write_exr(args.output, iw, ih, planes)
    return 0


def bilinear(plane, w, h, fx, fy):
    """Bilinear sample at texel coordinate (fx, fy), clamped to the image (clamp addressing)."""
    fx = min(max(fx, 0.0), w - 1.0)
    fy = min(max(fy, 0.0), h - 1.0)
    x0, y0 = int(math.floor(fx)), int(math.floor(fy))
    x1, y1 = min(x0 + 1, w - 1), min(y0 + 1, h - 1)
    tx, ty = fx - x0, fy - y0
    a = lerp(plane[y0 * w + x0], plane[y0 * w + x1], tx)
    b = lerp(plane[y1 * w + x0], plane[y1 * w + x1], tx)
    return lerp(a, b, ty)


def luminance(c):  # §6.1 step 2: the sharpen's luminance
    return 0.3 * c[0] + 0.59 * c[1] + 0.11 * c[2]


def clamp_nan(x):
    """The LUT sampler's clamp to [0, 1]; NaN stays NaN (docs/candidates/shaper.md)."""
    if x != x:
        return x
    return 0.0 if x < 0.0 else (1.0 if x > 1.0 else x)


def sample(lut, n, enc):
    """§6.1 step 7: trilinear, clamp-to-edge, at texel coordinate enc * (N - 1); NaN propagates (D-NF)."""
    if any(v != v for v in enc):
        return [NAN, NAN, NAN]
    f = [clamp_nan(v) * (n - 1) for v in enc]
    i0 = [min(int(math.floor(v)), n - 1) for v in f]
    t = [f[k] - i0[k] for k in range(3)]
    i1 = [min(i0[k] + 1, n - 1) for k in range(3)]
    out = [0.0, 0.0, 0.0]
    for db in (0, 1):
        wb = t[2] if db else 1.0 - t[2]
        if wb == 0.0:
            continue
        bi = i1[2] if db else i0[2]
        for dg in (0, 1):
            wg = t[1] if dg else 1.0 - t[1]
            if wg == 0.0:
                continue
            gi = i1[1] if dg else i0[1]
            for dr in (0, 1):
                wr = t[0] if dr else 1.0 - t[0]
                if wr == 0.0:
                    continue
                ri = i1[0] if dr else i0[0]
                tex = lut[(bi * n + gi) * n + ri]
                wgt = wb * wg * wr
                for c in range(3):
                    out[c] += wgt * tex[c]
    return out


if __name__ == "__main__":
    sys.exit(main())
