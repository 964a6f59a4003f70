#!/usr/bin/env python3
"""A port of the `unity_urp` pipeline (Unity URP colour grading) written from hdrconform's docs alone.

Pure Python (no numpy), double precision. Every formula comes from docs/spec/unity_urp.md (the
section is named at each step), the contract from docs/candidate-protocol.md,
docs/candidates/lut_bake.md and docs/candidates/color_grading.md, and the NaN/clamp intrinsics
from docs/spec/semantics.md. Nothing of hdrconform's source was read.

Usage (the candidate protocol's placeholders):
    urp_candidate.py --params {params} --output {output}
Exit 0 with the image written, 78 for a stage or pipeline this port does not implement.
"""
import argparse
import json
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from exr_io import read_exr, write_exr  # noqa: E402
from hlsl_math import (NAN, INF, hmax, hmin, sat, clamp, lerp, hpow, hlog10, exp2, mul,  # noqa: E402
                       to_half, hlog2)

# --- HLSL intrinsics with D3D's meaning (docs/spec/semantics.md, "The intrinsics") ---
def exp10(x):
    try:
        return math.pow(10.0, x)
    except OverflowError:
        return INF


def hsign(x):
    return float(x > 0.0) - float(x < 0.0)


def smoothstep(e0, e1, x):
    # spec/unity_urp.md §7 item 6: equal edges follow HLSL (x > e gives 1, otherwise 0).
    if e0 == e1:
        return 1.0 if x > e0 else 0.0
    t = sat((x - e0) / (e1 - e0))
    return t * t * (3.0 - 2.0 * t)


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def dot(a, v):
    return a[0] * v[0] + a[1] * v[1] + a[2] * v[2]


# --- Constants (spec/unity_urp.md §2.2, §2.3, §2.5) ---
LOGC_A, LOGC_B, LOGC_C, LOGC_D = 5.555556, 0.047996, 0.244161, 0.386036
ACESCC_MIDGRAY = 0.4135884
LUM_709 = (0.2126729, 0.7151522, 0.0721750)
AP1_RGB2Y = (0.272229, 0.674082, 0.0536895)
LIN2LMS = [[0.390405, 0.549941, 0.00892632], [0.0708416, 0.963172, 0.00135775],
           [0.0231082, 0.128021, 0.936245]]
LMS2LIN = [[2.85847, -1.62879, -0.0248910], [-0.210182, 1.15820, 0.000324281],
           [-0.0418120, -0.118169, 1.06867]]
SRGB_2_AP0 = [[0.4397010, 0.3829780, 0.1773350], [0.0897923, 0.8134230, 0.0967616],
              [0.0175440, 0.1115440, 0.8707040]]
AP0_2_AP1 = [[1.4514393161, -0.2365107469, -0.2149285693],
             [-0.0765537734, 1.1762296998, -0.0996759264],
             [0.0083161484, -0.0060324498, 0.9977163014]]
AP1_2_AP0 = [[0.6954522414, 0.1406786965, 0.1638690622],
             [0.0447945634, 0.8596711185, 0.0955343182],
             [-0.0055258826, 0.0040252103, 1.0015006723]]
AP1_2_XYZ = [[0.6624541811, 0.1340042065, 0.1561876870],
             [0.2722287168, 0.6740817658, 0.0536895174],
             [-0.0055746495, 0.0040607335, 1.0103391003]]
XYZ_2_AP1 = [[1.6410233797, -0.3248032942, -0.2364246952],
             [-0.6636628587, 1.6153315917, 0.0167563477],
             [0.0117218943, -0.0082844420, 0.9883948585]]
XYZ_2_REC709 = [[3.2409699419, -1.5373831776, -0.4986107603],
                [-0.9692436363, 1.8759675015, 0.0415550574],
                [0.0556300797, -0.2039769589, 1.0569715142]]
D60_2_D65 = [[0.98722400, -0.00611327, 0.0159533], [-0.00759836, 1.00186000, 0.0053302],
             [0.00307257, -0.00509595, 1.0816800]]
AP1_TO_REC709_OUT = matmul(XYZ_2_REC709, matmul(D60_2_D65, AP1_2_XYZ))
CURVE_CAP = 127.0 / 128.0  # §4: the default YRGB curves are clamp(c, 0, 127/128)


# --- LogC, ACEScc (§2.2, §2.5) ---
def logc_to_linear(code):
    return (exp10((code - LOGC_D) / LOGC_C) - LOGC_B) / LOGC_A


def linear_to_logc(x):
    return LOGC_C * hlog10(hmax(LOGC_A * x + LOGC_B, 0.0)) + LOGC_D


def acescc(x):
    x = clamp(x, 0.0, 65504.0)
    if x < 0.00003051757:
        return (hlog2(0.00001525878 + x * 0.5) + 9.72) / 17.52
    return (hlog2(x) + 9.72) / 17.52


ACESCC_TOP = (math.log2(65504.0) + 9.72) / 17.52


def acescc_inv(y):
    if y < -0.3013698630:
        return (exp2(17.52 * y - 9.72) - 2.0 ** -16) * 2.0
    if y < ACESCC_TOP:
        return exp2(17.52 * y - 9.72)
    return 65504.0


# --- HSV (§2.4) ---
def rgb_to_hsv(c):
    r, g, b = c
    p = (g, b, 0.0, -1.0 / 3.0) if g >= b else (b, g, -1.0, 2.0 / 3.0)
    q = (r, p[1], p[2], p[0]) if r >= p[0] else (p[0], p[1], p[3], r)
    d = q[0] - hmin(q[3], q[1])
    e = 1.0e-4
    return (abs(q[2] + (q[3] - q[1]) / (6.0 * d + e)), d / (q[0] + e), q[0])


def frac(x):
    return x - math.floor(x)


def hsv_to_rgb(h, s, v):
    out = []
    for k in (1.0, 2.0 / 3.0, 1.0 / 3.0):
        p = abs(frac(h + k) * 6.0 - 3.0)
        out.append(v * lerp(1.0, sat(p - 1.0), s))
    return out


def soft_light(a, b):
    if b >= 0.5:
        return math.sqrt(a) * (2.0 * b - 1.0) + 2.0 * a * (1.0 - b)
    return 2.0 * a * b + a * a * (1.0 - 2.0 * b)


# --- Tone maps (§2.6) ---
def neutral_curve(x):
    a, b, c, d, e, f = 0.2, 0.29, 0.24, 0.272, 0.02, 0.3
    return (x * (a * x + c * b) + d * e) / (x * (a * x + b) + d * f) - e / f


NEUTRAL_WS = 1.0 / neutral_curve(5.3)


def neutral_tonemap(c):
    return [neutral_curve(hmax(x, 0.0) * NEUTRAL_WS) * NEUTRAL_WS / 1.0 for x in c]


def fast_sign(x):  # §7 item 5: +1 for +0 and -0
    return 1.0 if x >= 0.0 else -1.0


def aces_fit(a):
    """§2.6 "ACES", steps 1-7, on an ACES2065-1 (AP0) colour; returns linear Rec.709."""
    a = list(a)
    # 1. Glow
    mx, mn = max(a), min(a)
    satv = (hmax(mx, 1e-4) - hmax(mn, 1e-4)) / hmax(mx, 1e-2)
    r, g, b = a
    yc = (r + g + b + 1.75 * math.sqrt(hmax(b * (b - g) + g * (g - r) + r * (r - b), 0.0))) / 3.0
    x = (satv - 0.4) / 0.2
    t = hmax(1.0 - abs(x / 2.0), 0.0)
    sigma = (1.0 + fast_sign(x) * (1.0 - t * t)) / 2.0
    if yc <= (2.0 / 3.0) * 0.08:
        gain = 0.05 * sigma
    elif yc >= 0.16:
        gain = 0.0
    else:
        gain = 0.05 * sigma * (0.08 / yc - 0.5)
    a = [v * (1.0 + gain) for v in a]
    # 2. Red modifier
    r, g, b = a
    if r == g == b:
        hue = 0.0
    else:
        hue = math.degrees(math.atan2(math.sqrt(3.0) * (g - b), 2.0 * r - g - b))
        if hue < 0.0:
            hue += 360.0
    if hue > 180.0:
        hue -= 360.0
    w = smoothstep(0.0, 1.0, 1.0 - abs(2.0 * hue / 135.0)) ** 2
    a[0] = r + w * satv * (0.03 - r) * (1.0 - 0.82)
    # 3. To AP1, clamp, desaturate
    p = [hmax(v, 0.0) for v in mul(AP0_2_AP1, a)]
    y1 = dot(AP1_RGB2Y, p)
    p = [lerp(y1, v, 0.96) for v in p]
    # 4. Fitted tone curve
    q = [(v * (v + 0.0245786) - 0.000090537) / (v * (0.983729 * v + 0.4329510) + 0.238081)
         for v in p]
    # 5. Dim surround
    xyz = mul(AP1_2_XYZ, q)
    s = hmax(xyz[0] + xyz[1] + xyz[2], 1e-4)
    cx, cy = xyz[0] / s, xyz[1] / s
    yy = hpow(clamp(xyz[1], 0.0, 65504.0), 0.9811)
    xyz = [cx * yy / hmax(cy, 1e-4), yy, (1.0 - cx - cy) * yy / hmax(cy, 1e-4)]
    q = mul(XYZ_2_AP1, xyz)
    # 6. ODT desaturation
    y1 = dot(AP1_RGB2Y, q)
    q = [lerp(y1, v, 0.93) for v in q]
    # 7. Output
    return mul(AP1_TO_REC709_OUT, q)


class Grade:
    """The constants of one case (params.json `params`, spec §1)."""

    def __init__(self, p):
        self.hdr = int(p["urp_grading_mode"]) == 1
        self.tonemap = int(p["urp_tonemap_mode"])  # 0 None, 1 Neutral, 2 ACES
        self.aces = self.hdr and self.tonemap == 2  # mode A (§2.3)
        self.lum = AP1_RGB2Y if self.aces else LUM_709
        self.cb = p["urp_color_balance"][:3]
        self.filt = p["urp_color_filter"][:3]
        hsc = p["urp_hue_sat_con"]
        self.hue_shift, self.saturation, self.contrast = hsc[0], hsc[1], hsc[2]
        self.mixer = [p["urp_channel_mixer_red"][:3], p["urp_channel_mixer_green"][:3],
                      p["urp_channel_mixer_blue"][:3]]
        self.lift, self.gamma, self.gain = p["urp_lift"][:3], p["urp_gamma"][:3], p["urp_gain"][:3]
        self.sh, self.mid, self.hi = p["urp_shadows"][:3], p["urp_midtones"][:3], p["urp_highlights"][:3]
        self.limits = p["urp_sha_hi_limits"]
        self.split_s = p["urp_split_shadows"][:3]
        self.balance = p["urp_split_shadows"][3]
        self.split_h = p["urp_split_highlights"][:3]

    def lg(self, c):
        return dot(self.lum, c)

    def color_grade(self, code):
        """§2.3 (HDR) or §3 (LDR): a lattice code to the graded colour (before the tone map)."""
        # 1. Decode
        c = [logc_to_linear(v) for v in code] if self.hdr else list(code)
        # 2. White balance
        lms = mul(LIN2LMS, c)
        c = mul(LMS2LIN, [lms[i] * self.cb[i] for i in range(3)])
        # 3. Contrast
        k = self.contrast
        if self.aces:
            l = [acescc(v) for v in mul(SRGB_2_AP0, c)]
            l = [(v - ACESCC_MIDGRAY) * k + ACESCC_MIDGRAY for v in l]
            c = mul(AP0_2_AP1, [acescc_inv(v) for v in l])
        else:
            l = [linear_to_logc(v) for v in c]
            l = [(v - ACESCC_MIDGRAY) * k + ACESCC_MIDGRAY for v in l]
            c = [logc_to_linear(v) for v in l]
        # 4-5. Colour filter, clamp
        c = [hmax(c[i] * self.filt[i], 0.0) for i in range(3)]
        # 6. Split toning (gamma space)
        gm = [hpow(abs(v), 1.0 / 2.2) for v in c]
        lam = sat(self.lg([sat(v) for v in gm]) + self.balance)
        for i in range(3):
            sh = lerp(0.5, self.split_s[i], 1.0 - lam)
            hi = lerp(0.5, self.split_h[i], lam)
            gm[i] = soft_light(soft_light(gm[i], sh), hi)
        c = [hpow(abs(v), 2.2) for v in gm]
        # 7. Channel mixer
        c = [dot(self.mixer[0], c), dot(self.mixer[1], c), dot(self.mixer[2], c)]
        # 8. Shadows, midtones, highlights
        lam = self.lg(c)
        ws = 1.0 - smoothstep(self.limits[0], self.limits[1], lam)
        wh = smoothstep(self.limits[2], self.limits[3], lam)
        wm = 1.0 - ws - wh
        c = [c[i] * self.sh[i] * ws + c[i] * self.mid[i] * wm + c[i] * self.hi[i] * wh
             for i in range(3)]
        # 9. Lift, gain, gamma
        c = [c[i] * self.gain[i] + self.lift[i] for i in range(3)]
        c = [hsign(c[i]) * hpow(abs(c[i]), self.gamma[i]) for i in range(3)]
        # 10. HSV block; the default secondary curves give satMult 1 and no hue offset (§4)
        h, s, v = rgb_to_hsv(c)
        hue = h + self.hue_shift
        if hue < 0.0:
            hue += 1.0
        elif hue > 1.0:
            hue -= 1.0
        c = hsv_to_rgb(hue, s, v)
        sat_mult = 1.0
        # 11. Global saturation
        lam = self.lg(c)
        c = [lam + (self.saturation * sat_mult) * (v - lam) for v in c]
        # 12. YRGB curves at their defaults (§4), inside FastTonemap in HDR only (§3)
        if self.hdr:
            t = [v / (max(c) + 1.0) for v in c]
            t = [clamp(clamp(v, 0.0, CURVE_CAP), 0.0, CURVE_CAP) for v in t]
            c = [v / (1.0 - max(t)) for v in t]
        else:
            c = [clamp(clamp(v, 0.0, CURVE_CAP), 0.0, CURVE_CAP) for v in c]
        # 13. Clamp
        return [hmax(v, 0.0) for v in c]

    def bake_texel(self, code):
        c = self.color_grade(code)
        if not self.hdr:
            return [sat(v) for v in c]  # §3: LDR bake ends with sat, no tone map
        if self.tonemap == 1:
            return neutral_tonemap(c)
        if self.tonemap == 2:
            return aces_fit(mul(AP1_2_AP0, c))
        return c

    def uber_tonemap(self, x):
        """§5.2 step 3: the LDR grading's tone map before the LUT, saturated."""
        if self.tonemap == 1:
            x = neutral_tonemap(x)
        elif self.tonemap == 2:
            x = aces_fit(mul(SRGB_2_AP0, x))
        return [sat(v) for v in x]


def quantize(v, fmt):
    """docs/candidates/lut_bake.md: 1 RGBA16F nearest half, 3 RGBA8 UNORM, otherwise float32."""
    if fmt == 1:
        return to_half(v)
    if fmt == 3:
        return round(sat(v) * 255.0) / 255.0
    return v


def bake_lut(grade, size, fmt):
    """The strip as a flat list of texels [r, g, b], lattice (r, g, b) at index (g, r + H b)."""
    n1 = size - 1
    lut = [None] * (size * size * size)
    for b in range(size):
        for g in range(size):
            for r in range(size):
                out = grade.bake_texel((r / n1, g / n1, b / n1))
                lut[g * size * size + r + size * b] = [quantize(v, fmt) for v in out]
    return lut


def apply_lut(lut, size, rgb):
    """§5.3 ApplyLut2D as trilinear interpolation of the stored lattice."""
    n1 = size - 1
    w = size * size

    def texel(ri, gi, bi):
        return lut[gi * w + ri + size * bi]

    z = rgb[2] * n1
    s = int(math.floor(z))
    phi = z - s
    fr, fg = rgb[0] * n1, rgb[1] * n1
    r0, g0 = int(math.floor(fr)), int(math.floor(fg))
    ar, ag = fr - r0, fg - g0
    r1, g1 = min(r0 + 1, n1), min(g0 + 1, n1)
    s1 = min(s + 1, n1)
    out = []
    for ch in range(3):
        def bil(si):
            t00, t10 = texel(r0, g0, si)[ch], texel(r1, g0, si)[ch]
            t01, t11 = texel(r0, g1, si)[ch], texel(r1, g1, si)[ch]
            return lerp(lerp(t00, t10, ar), lerp(t01, t11, ar), ag)
        tap0 = bil(s)
        tap1 = bil(s1) if phi != 0.0 else 0.0
        out.append(lerp(tap0, tap1, phi) if phi != 0.0 else tap0)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--params", required=True)
    ap.add_argument("--output", required=True)
    args = ap.parse_args()
    with open(args.params) as f:
        pj = json.load(f)
    if pj.get("format_version") != 3:
        print(f"params.json format_version {pj.get('format_version')} is not 3")
        return 78
    if pj.get("pipeline") != "unity_urp" or pj.get("stage") not in ("lut_bake", "color_grading"):
        print(f"this port implements unity_urp's lut_bake and color_grading, not "
              f"{pj.get('pipeline')}/{pj.get('stage')}")
        return 78
    if pj.get("degenerate"):
        print("degenerate case: not judged")
        return 77
    p = pj["params"]
    storage = pj.get("storage") or {}
    size = int(p.get("lut_size", storage.get("lut_size", 32)))
    fmt = p.get("lut_format", storage.get("lut_format"))
    if isinstance(fmt, dict):
        fmt = fmt["value"]
    fmt = int(fmt)
    grade = Grade(p)
    lut = bake_lut(grade, size, fmt)
    out_w, out_h = int(pj["output"]["width"]), int(pj["output"]["height"])
    base = os.path.dirname(os.path.abspath(args.params))
    if pj["stage"] == "lut_bake":
        if (out_w, out_h) != (size * size, size):
            print(f"output {out_w}x{out_h} is not the {size * size}x{size} strip")
            return 1
        planes = {"R": [], "G": [], "B": [], "A": [1.0] * (out_w * out_h)}
        for t in lut:
            planes["R"].append(t[0])
            planes["G"].append(t[1])
            planes["B"].append(t[2])
        write_exr(args.output, out_w, out_h, planes)
        return 0
    inp = pj["images"]["input"]
    w, h, src = read_exr(os.path.join(base, inp["file"] if isinstance(inp, dict) else inp))
    exposure = p["urp_post_exposure"]
    planes = {"R": [0.0] * (w * h), "G": [0.0] * (w * h), "B": [0.0] * (w * h),
              "A": list(src.get("A", [1.0] * (w * h)))}
    for i in range(w * h):
        x = [src["R"][i] * exposure, src["G"][i] * exposure, src["B"][i] * exposure]
        if grade.hdr:
            uvw = [sat(linear_to_logc(v)) for v in x]
        else:
            uvw = grade.uber_tonemap(x)
        out = apply_lut(lut, size, uvw)
        planes["R"][i], planes["G"][i], planes["B"][i] = out
    write_exr(args.output, w, h, planes)
    return 0


if __name__ == "__main__":
    sys.exit(main())
