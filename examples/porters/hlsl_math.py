"""HLSL's arithmetic semantics in plain Python, shared by the porters' candidates.

Written from docs/spec/semantics.md (NaN rules of max/min/saturate, pow as exp2(y log2 x), the
float16 store), nothing else: maxNum returns the other operand for a NaN, saturate(NaN) is 0,
pow(x < 0, y) is NaN, pow(0, 0) is NaN, a half store overflows to infinity.
"""
import math
import struct

NAN = float("nan")
INF = float("inf")

def hmax(a, b):  # maxNum: a NaN operand gives the other operand
    if a != a:
        return b
    if b != b:
        return a
    return a if a > b else b


def hmin(a, b):
    if a != a:
        return b
    if b != b:
        return a
    return a if a < b else b


def sat(x):  # saturate(NaN) = 0
    if x != x:
        return 0.0
    return 0.0 if x < 0.0 else (1.0 if x > 1.0 else x)


def clamp(x, lo, hi):
    return hmin(hmax(x, lo), hi)


def lerp(a, b, t):
    return a + t * (b - a)


def hpow(x, y):  # pow = exp2(y log2 x): NaN for x < 0, pow(0, y > 0) = 0, pow(0, 0) = NaN
    if x != x or y != y or x < 0.0:
        return NAN
    if x == 0.0:
        return 0.0 if y > 0.0 else (NAN if y == 0.0 else INF)
    if x == INF:
        return INF if y > 0.0 else (0.0 if y < 0.0 else NAN)
    try:
        return math.pow(x, y)
    except OverflowError:
        return INF


def hlog10(x):
    if x != x or x < 0.0:
        return NAN
    if x == 0.0:
        return -INF
    if x == INF:
        return INF
    return math.log10(x)


def hlog2(x):
    if x != x or x < 0.0:
        return NAN
    if x == 0.0:
        return -INF
    if x == INF:
        return INF
    return math.log2(x)


def exp2(x):
    if x != x:
        return NAN
    try:
        return math.pow(2.0, x)
    except OverflowError:
        return INF


def mul(m, v):
    return [m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2] for i in range(3)]


def to_half(v):
    if v != v:
        return v
    try:
        return struct.unpack("<e", struct.pack("<e", v))[0]
    except OverflowError:
        return math.copysign(INF, v)
