#!/usr/bin/env python3
"""A port of docs/spec/film_tonemap.md, operators.md, pq_grading.md and ue55.md's device-3 path
(the ACES 1.3 PQ output at UE's default grading, its §15.1 worked pixels: the porter's exercise)
written from those pages alone (their formulas, constants, the matrices and the parameter block
they print), in plain Python float64, checked against the pages' own worked pixels (issue 28: a
port from the docs must be possible).

It shares nothing with the C++ reference: reference/spec_worked_pixels_test.cpp checks the pages
against the code, this checks that the pages say enough to reproduce them. Every value of every
worked pixel must agree to the 9 significant digits printed.

usage: spec_port_check.py [REPOSITORY_ROOT]   (exit status 1 on a mismatch)"""
import math, re, struct, sys

ROOT = sys.argv[1] if len(sys.argv) > 1 else '.'

def blocks(page):
    out, cur = [], None
    for line in open(f'{ROOT}/docs/spec/{page}'):
        if cur is not None:
            if line.startswith('```'):
                out.append(cur); cur = None; continue
            f = line.split()
            if f: cur['rows'][f[0]] = [float(x) for x in f[1:]]
        elif line.startswith('```worked-pixel') or line.startswith('```spec-constants'):
            info = line[3:].split()
            cur = {'kind': info[0], 'pipeline': info[1],
                   'opts': dict(o.split('=', 1) for o in info[2:]), 'rows': {}}
    return out

def mat_from_text(page, name):
    text = open(f'{ROOT}/docs/spec/{page}').read()
    i = text.index(name)
    nums = re.findall(r'-?\d+\.\d+', text[i:i + 400])[:9]
    return [[float(nums[3 * r + c]) for c in range(3)] for r in range(3)]

def mul(m, v): return [sum(m[r][c] * v[c] for c in range(3)) for r in range(3)]
def mm(a, b): return [[sum(a[r][k] * b[k][c] for k in range(3)) for c in range(3)] for r in range(3)]
def fmax(a, b):  # maxNum
    if math.isnan(a): return b
    if math.isnan(b): return a
    return max(a, b)
def fmin(a, b):
    if math.isnan(a): return b
    if math.isnan(b): return a
    return min(a, b)
def saturate(x): return 0.0 if math.isnan(x) else min(max(x, 0.0), 1.0)
def lerp(a, b, t): return a + t * (b - a)
def log10(x): return -math.inf if x == 0 else (math.log10(x) if x > 0 else math.nan)
def exp(x):
    try: return math.exp(x)
    except OverflowError: return math.inf
def sign(x): return float(x > 0) - float(x < 0)

# --- FilmToneMap (film_tonemap.md) ---
AP1_2_XYZ = mat_from_text('film_tonemap.md', 'AP1_2_XYZ_MAT  ')
XYZ_2_AP0 = mat_from_text('film_tonemap.md', 'XYZ_2_AP0_MAT  ')
AP0_2_AP1 = mat_from_text('film_tonemap.md', 'AP0_2_AP1_MAT  ')
AP1_RGB2Y = AP1_2_XYZ[1]
PRESETS = {'Default': (0.88, 0.55, 0.26, 0, 0.04), 'Legacy': (0.98, 0.3, 0.22, 0, 0.025),
           'ACES': (0.91, 0.53, 0.23, 0, 0.035), 'Uncharted': (0.63, 0.55, 0.47, 0, 0.01),
           'HP': (0.65, 0.63, 0.45, 0, 0)}

def rgb_2_saturation(c):
    mx = fmax(fmax(c[0], c[1]), c[2]); mn = fmin(fmin(c[0], c[1]), c[2])
    return (fmax(mx, 1e-10) - fmax(mn, 1e-10)) / fmax(mx, 0.01)
def rgb_2_yc(c):
    r, g, b = c
    return (b + g + r + 1.75 * math.sqrt(b * (b - g) + g * (g - r) + r * (r - b))) / 3
def sigmoid_shaper(x):
    t = max(1 - abs(x / 2), 0.0)
    return 0.5 * (1 + sign(x) * (1 - t * t))
def glow_fwd(yc, gain, mid):
    if yc <= 2 / 3 * mid: return gain
    if yc >= 2 * mid: return 0.0
    return gain * (mid / yc - 0.5)
def rgb_2_hue(c):
    r, g, b = c
    if r == g == b: h = 0.0
    else:
        h = math.degrees(math.atan2(math.sqrt(3) * (g - b), 2 * r - g - b))
        if h < 0: h += 360
    return fmin(fmax(h, 0.0), 360.0)
def center_hue(h, c):
    d = h - c
    if d < -180: d += 360
    elif d > 180: d -= 360
    return d
def smoothstep01(x):
    t = saturate(x); return t * t * (3 - 2 * t)

def film(c, preset, tr):
    slope, toe_p, shoulder_p, black, white = PRESETS[preset]
    ts = 1 + black - toe_p; ss = 1 + white - shoulder_p
    if toe_p > 0.8: tm = (1 - toe_p - 0.18) / slope + math.log10(0.18)
    else:
        bt = (0.18 + black) / ts - 1
        tm = math.log10(0.18) - 0.5 * math.log((1 + bt) / (1 - bt)) * ts / slope
    sm_ = (1 - toe_p) / slope - tm
    shm = shoulder_p / slope - sm_
    tr.update(toe_scale=[ts], shoulder_scale=[ss], toe_match=[tm], straight_match=[sm_],
              shoulder_match=[shm])
    ap0 = mul(mm(XYZ_2_AP0, AP1_2_XYZ), c); tr['ap0'] = ap0
    sat = rgb_2_saturation(ap0); yc = rgb_2_yc(ap0); s = sigmoid_shaper((sat - 0.4) / 0.2)
    glow = 1 + glow_fwd(yc, 0.05 * s, 0.08)
    g = [x * glow for x in ap0]
    hue = rgb_2_hue(g); w = smoothstep01(1 - abs(2 * center_hue(hue, 0) / 135)) ** 2
    red = [g[0] + w * sat * (0.03 - g[0]) * (1 - 0.82), g[1], g[2]]
    cl = [fmax(0.0, x) for x in mul(AP0_2_AP1, red)]
    y = sum(a * b for a, b in zip(cl, AP1_RGB2Y)); de = [lerp(y, x, 0.96) for x in cl]
    tr.update(saturation=[sat], yc=[yc], sigmoid=[s], glow=[glow], ap0_glow=g, hue=[hue],
              hue_weight=[w], ap0_red=red, ap1_clamped=cl, ap1_desat=de)
    cols = {k: [] for k in ('log_color', 'toe', 'straight', 'shoulder', 'blend', 'tone')}
    for wv in de:
        lc = log10(wv)
        st = slope * (lc + sm_)
        to = -black + 2 * ts / (1 + exp((-2 * slope / ts) * (lc - tm)))
        sh = (1 + white) - 2 * ss / (1 + exp((2 * slope / ss) * (lc - shm)))
        tc = to if lc < tm else st
        sc = sh if lc > shm else st
        t = saturate((lc - tm) / (shm - tm))
        if shm < tm: t = 1 - t
        bl = (3 - 2 * t) * t * t
        tone = tc + bl * (sc - tc)  # lerp; 0 * -inf is NaN for black (film_tonemap.md)
        for k, v in zip(cols, (lc, to, st, sh, bl, tone)): cols[k].append(v)
    tr.update(cols)
    y = sum(a * b for a, b in zip(cols['tone'], AP1_RGB2Y))
    if math.isnan(y): post = [math.nan] * 3
    else: post = [lerp(y, x, 0.93) for x in cols['tone']]
    tr['post_desat'] = post
    return [fmax(0.0, x) for x in post]

# --- operators (operators.md) ---
OPS = blocks('operators.md')
CONST = [b for b in OPS if b['kind'] == 'spec-constants'][0]['rows']
TO_AP1 = [CONST['op_rec709_to_ap1'][3 * r:3 * r + 3] for r in range(3)]
FROM_AP1 = [CONST['op_ap1_to_rec709'][3 * r:3 * r + 3] for r in range(3)]

def rational(y, A, B, C, D, E, F):
    return (y * (A * y + C * B) + D * E) / (y * (A * y + B) + D * F) - E / F

def operators(opts, inp):
    o = {'Operator': 'Reinhard', 'Key': 0.18, 'AdaptedLuminance': 0.18, 'WhitePoint': 11.2,
         'HableA': 0.22, 'HableB': 0.30, 'HableC': 0.10, 'HableD': 0.20, 'HableE': 0.01,
         'HableF': 0.30, 'HableW': 11.2, 'ExposureBias': 2.0, 'NarkowiczPreScale': 1.0,
         'FilmPreset': 'Default'}
    o.update(opts)
    num = lambda k: float(o[k])
    e = num('Key') / num('AdaptedLuminance')
    x = [e * v for v in inp]
    tr = {'input': inp, 'exposure': [e], 'x': x}
    op = o['Operator']
    if op == 'Reinhard': out = [v / (1 + v) for v in x]
    elif op == 'ReinhardWhite':
        lw = num('WhitePoint'); out = [v * (1 + v / lw ** 2) / (1 + v) for v in x]
    elif op == 'Hable':
        k = [num('Hable' + c) for c in 'ABCDEF']
        fb = [rational(num('ExposureBias') * v, *k) for v in x]; fw = rational(num('HableW'), *k)
        tr.update(f_bias_x=fb, f_w=[fw]); out = [v / fw for v in fb]
    elif op == 'AcesNarkowicz':
        ys = [num('NarkowiczPreScale') * v for v in x]
        out = [saturate(y * (2.51 * y + 0.03) / (y * (2.43 * y + 0.59) + 0.14)) for y in ys]
    elif op == 'UnityNeutral':
        k = (0.2, 0.29, 0.24, 0.272, 0.02, 0.3)
        ws = 1 / rational(5.3, *k); cur = [rational(fmax(v, 0.0) * ws, *k) for v in x]
        tr.update(white_scale=[ws], curve=cur); out = [v * ws / 1.0 for v in cur]
    elif op == 'UeFilmic':
        ap1 = mul(TO_AP1, x); ft = {}; tone = film(ap1, o['FilmPreset'], ft)
        rec = mul(FROM_AP1, tone)
        tr.update(ap1=ap1, tone_ap1=tone, rec709=rec); out = [fmax(0.0, v) for v in rec]
    tr['out'] = out
    return tr

# --- pq_grading (pq_grading.md) ---
m1, m2, c1, c2, c3 = 2610 / 16384, 2523 / 4096 * 128, 3424 / 4096, 2413 / 4096 * 32, 2392 / 4096 * 32
def pq(n):
    ym = (n / 10000) ** m1
    return ((c1 + c2 * ym) * (1 / (1 + c3 * ym))) ** m2
def pq_inv(e):
    p = e ** (1 / m2)
    return 10000 * (max(p - c1, 0) / (c2 - c3 * p)) ** (1 / m1)
def half(v):
    if math.isnan(v): return v
    v = min(max(v, -65504.0), 65504.0)
    return struct.unpack('<e', struct.pack('<e', struct.unpack('<f', struct.pack('<f', v))[0]))[0]
def read_cube(path):
    rows, size, dmin, dmax = [], 0, [0, 0, 0], [1, 1, 1]
    for line in open(path):
        f = line.split()
        if not f or f[0].startswith('#'): continue
        if f[0] == 'LUT_3D_SIZE': size = int(f[1])
        elif f[0] == 'DOMAIN_MIN': dmin = [float(x) for x in f[1:4]]
        elif f[0] == 'DOMAIN_MAX': dmax = [float(x) for x in f[1:4]]
        elif re.match(r'^[-0-9.]', f[0]):
            rows.append([struct.unpack('<f', struct.pack('<f', float(x)))[0] for x in f[:3]])
    return size, dmin, dmax, rows

def pq_grading(opts, inp):
    size, dmin, dmax, rows = read_cube(f"{ROOT}/{opts['cube']}")
    N = size; W, H = N * N, N
    tex = lambda i, j: rows[(i % N) + N * (j + N * (i // N))]  # texel (r + N b, g) -> row (r, g, b)
    amp = float(opts.get('Amplify', 3)); hdr = opts.get('Display', 'HDR') == 'HDR'
    bb = opts.get('BackBuffer', 'R10G10B10A2'); peak = float(opts.get('PeakNits', 1000))
    ef = 1e-4 * amp; wn = peak if hdr else 100.0
    st = [half(v) for v in inp]; ex = [saturate(v * ef) for v in st]; q = [pq(v * 10000) for v in ex]
    t = [saturate((q[c] - dmin[c]) / (dmax[c] - dmin[c])) for c in range(3)]
    uvw = [v * (N - 1) / N + 0.5 / N for v in t]
    sw = uvw[2] * N - 0.5; si = math.floor(sw); sf = sw - si; u = (uvw[0] + si) / N
    def bil(u, v):
        a, b = u * W - 0.5, v * H - 0.5; i, j = math.floor(a), math.floor(b); al, be = a - i, b - j
        ci = lambda k: min(max(k, 0), W - 1); cj = lambda k: min(max(k, 0), H - 1)
        T = lambda x, y: tex(ci(x), cj(y))
        return [lerp(lerp(T(i, j)[c], T(i + 1, j)[c], al), lerp(T(i, j + 1)[c], T(i + 1, j + 1)[c], al), be)
                for c in range(3)]
    t0 = bil(u, uvw[1]); t1 = bil(u + 1 / N, uvw[1])
    gq = [t0[c] + sf * (t1[c] - t0[c]) for c in range(3)]
    g = [pq_inv(v) / 10000 / ef * amp for v in gq]
    tr = dict(input=inp, exposure_fract=[ef], white_nits=[wn], stored=st, exposed=ex, pq=q, lut_coord=t,
              uvw=uvw, slice_w=[sw], slice_i=[si], slice_f=[sf], u=[u], tap0=t0, tap1=t1, graded_pq=gq,
              graded=g)
    if hdr:
        ap1 = mul(TO_AP1, g); tone = film(ap1, 'Default', {}); rec = mul(FROM_AP1, tone)
        tr.update(ap1=ap1, tone_ap1=tone, rec709=rec); d = [fmax(0.0, v) for v in rec]
    else:
        d = [saturate(v * (2.51 * v + 0.03) / (v * (2.43 * v + 0.59) + 0.14)) for v in g]
    def enc(v):
        if bb == 'R10G10B10A2': return saturate(pq(v * wn))
        if bb == 'RGBA16F': return v * wn / 80
        if bb == 'SRGB8':
            e = saturate(v); return 12.92 * e if e <= 0.0031308 else 1.055 * e ** (1 / 2.4) - 0.055
        return saturate(v) ** (1 / 2.2)
    tr.update(display=d, out=[enc(v) for v in d])
    return tr

# --- UE 5.5, device 3/4 (ACES, ST 2084) at UE's default grading (ue55.md §15.1) ---
def ue_mat(label):  # a `[a, b, c; d, e, f; g, h, i]` matrix of ue55.md after "* LABEL"
    text = open(f'{ROOT}/docs/spec/ue55.md').read()
    i = text.index('* ' + label)
    nums = re.findall(r'-?\d+\.\d+', text[text.index('`[', i):text.index(']`', i)])
    return [[float(nums[3 * r + c]) for c in range(3)] for r in range(3)]
def f32(x): return struct.unpack('f', struct.pack('f', x))[0]  # the CPU's floats, printed with 9 digits
UE_AP1_2_XYZ, UE_XYZ_2_AP1 = ue_mat('AP1→XYZ:'), ue_mat('XYZ→AP1:')
UE_AP0_2_AP1 = ue_mat('AP0→AP1 (')
UE_AP1_Y = UE_AP1_2_XYZ[1]
UE_WIDE_2_XYZ = ue_mat('Wide→XYZ (')
UE_EXPAND = mm(mm(UE_XYZ_2_AP1, UE_WIDE_2_XYZ), ue_mat('AP1→sRGB ='))
UE_OUT = {2: ue_mat('AP1→Rec2020 ='), 0: ue_mat('AP1→sRGB ='), 1: ue_mat('AP1→P3-D65 =')}
def cubic_basis_shaper(x, w):
    M = [[-1 / 6, 3 / 6, -3 / 6, 1 / 6], [3 / 6, -6 / 6, 3 / 6, 0], [-3 / 6, 0, 3 / 6, 0],
         [1 / 6, 4 / 6, 1 / 6, 0]]
    if x <= -w / 2 or x >= w / 2: return 0.0
    kc = (x + w / 2) * 4 / w; j = math.floor(kc); t = kc - j; m = (t ** 3, t * t, t, 1.0)
    return 1.5 * sum(m[k] * M[k][3 - j] for k in range(4))
def ue55(opts, inp, const):
    if set(opts) - {'r.HDR.EnableHDROutput', 'r.HDR.Display.OutputDevice',
                    'r.HDR.Display.ColorGamut'} or opts.get('r.HDR.Display.OutputDevice') not in ('3', '4'):
        return None  # only the ACES PQ devices at UE's default settings are ported
    C = {k: [f32(x) for x in v] for k, v in const.items()}
    m3 = lambda k: [C[k][3 * r:3 * r + 3] for r in range(3)]
    mn_x, mn_y, mx_x, mx_y = C['aces_min_max']; md_x, md_y, md_s = C['aces_mid'][:3]
    lo = C['aces_coefs_low_0'] + C['aces_coefs_low_4'] * 2
    hi = C['aces_coefs_high_0'] + C['aces_coefs_high_4'] * 2
    def ssts(x):  # §5.2
        lx = math.log10(max(x, 1e-10))
        def seg(a, b, c):
            kc = 3 * (lx - math.log10(a)) / (math.log10(b) - math.log10(a)); j = int(kc); t = kc - j
            c0, c1, c2 = c[j:j + 3]
            return t * t * (0.5 * c0 - c1 + 0.5 * c2) + t * (c1 - c0) + 0.5 * (c0 + c1)
        if lx <= math.log10(mn_x): ly = math.log10(mn_y)
        elif lx < math.log10(md_x): ly = seg(mn_x, md_x, lo)
        elif lx < math.log10(mx_x): ly = seg(md_x, mx_x, hi)
        else: ly = math.log10(mx_y)
        return 10 ** ly
    tr = dict(input=inp, exposed=inp)  # the centre pixel, exposure 1 (§15)
    enc = [pq(x * 100) for x in inp]; dec = [pq_inv(e) / 100 for e in enc]  # §6.1 step 7, §4.3
    tr.update(encoded=enc, decoded=dec, white_balanced=dec)  # 6500 K / 0: skipped (§4.4)
    ap1 = mul(m3('wcs_to_ap1'), dec)
    luma = sum(a * b for a, b in zip(ap1, UE_AP1_Y))  # §4.5
    d2 = sum((c / luma - 1) ** 2 for c in ap1) if luma else 0.0
    amt = (1 - 2 ** (-4 * d2)) * (1 - 2 ** (-4 * 1.0 * luma * luma)) if luma else 0.0
    ex = [lerp(a, b, amt) for a, b in zip(ap1, mul(UE_EXPAND, ap1))]
    tr.update(ap1=ap1, expanded=ex, color_corrected=ex)  # ColorCorrectAll at its defaults (§4.6)
    graded = mul(m3('wcs_from_ap1'), ex)  # §4.7, no fade
    scm = C['aces_scene_color_multiplier'][0]
    aces = mul(m3('wcs_to_ap0'), [x * scm for x in graded])  # §5.1 (GamutCompression 0)
    sat = rgb_2_saturation(aces); yc = rgb_2_yc(aces)  # rrt_sweeteners: glow
    glow = 1 + glow_fwd(yc, 0.05 * sigmoid_shaper((sat - 0.4) / 0.2), 0.08)
    a = [x * glow for x in aces]
    w = cubic_basis_shaper(center_hue(rgb_2_hue(a), 0), 135)
    a[0] += w * sat * (0.03 - a[0]) * (1 - 0.82)
    a = [fmin(fmax(x, 0.0), 65535.0) for x in a]
    pre = [fmin(fmax(x, 0.0), 65504.0) for x in mul(UE_AP0_2_AP1, a)]
    y = sum(p * q for p, q in zip(pre, UE_AP1_Y)); pre = [lerp(y, x, 0.96) for x in pre]
    post = [ssts(x) for x in pre]
    lin = [(x - mn_y) / (mx_y - mn_y) for x in post]  # §5.1 steps 3-7
    xyz = mul(UE_AP1_2_XYZ, lin)
    xyz = mul(UE_AP1_2_XYZ, [fmin(fmax(x, 0.0), 1.0) for x in mul(UE_XYZ_2_AP1, xyz)])
    lin = [fmin(fmax(x, 0.0), 65535.0) for x in mul(UE_XYZ_2_AP1, xyz)]
    nits = [fmin(fmax(x * mx_y, 0.0), 65535.0) for x in lin]
    dev = [pq(x) for x in mul(UE_OUT[int(opts.get('r.HDR.Display.ColorGamut', '0'))], nits)]  # §4.12
    tr.update(graded=graded, aces=aces, rrt=pre, ssts=post, linear_cv=lin, aces_nits=nits,
              device=dev, stored=[x / 1.05 for x in dev], lut=dev, out=dev)
    return tr

worst, n, bad, where = 0.0, 0, 0, None
UE_CONST = [b for b in blocks('ue55.md') if b['kind'] == 'spec-constants'][0]
ported = 0
for page, fn in (('film_tonemap.md', None), ('operators.md', operators), ('pq_grading.md', pq_grading),
                 ('ue55.md', ue55)):
    for b in blocks(page):
        if b['kind'] != 'worked-pixel': continue
        inp = b['rows']['input']
        if fn is None:
            tr = {'input': inp}; tr['out'] = film(inp, b['opts'].get('FilmPreset', 'Default'), tr)
        elif fn is ue55:
            if b['opts'] != UE_CONST['opts']: continue  # another case than the constants' (§15.1)
            tr = ue55(b['opts'], inp, UE_CONST['rows'])
            if tr is None: continue
        else:
            tr = fn(b['opts'], inp)
        ported += 1
        for name, doc in b['rows'].items():
            got = tr.get(name)
            if got is None or len(got) != len(doc):
                print('NOT PORTED', page, b['opts'], name); bad += 1; continue
            for d, c in zip(doc, got):
                n += 1
                if math.isnan(d) or math.isnan(c):
                    if not (math.isnan(d) and math.isnan(c)):
                        print('MISMATCH', page, b['opts'], name, d, c); bad += 1
                    continue
                if d == c: continue
                rel = abs(d - c) / max(abs(c), 1e-300)
                if rel > worst: worst = rel; where = (page, b['opts'], name, d, c)
                if rel > 6e-9:
                    print('MISMATCH', page, b['opts'], name, d, c, rel); bad += 1
print(f'{ported} worked pixels, {n} values compared, {bad} mismatches; largest relative difference '
      f'{worst:.3g} at {where}')
sys.exit(1 if bad or n == 0 else 0)
