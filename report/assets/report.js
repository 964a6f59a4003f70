// hdrconform report: the script of every page (summary, matrix, case list, case pages).
// Static and offline: data arrives through <script> files written beside the pages (data.js)
// or JSON data blocks in the page (a case's #case-meta and #case-px, its float data), because
// file:// pages may not fetch. Text from the results is only ever set
// through textContent or attribute values, never parsed as HTML.
//
// The SDR preview mapping and the error metrics mirror report/images.cpp and runner/diff.cpp:
//   display = sRGB_OETF(clamp(nits / 100 · 2^EV, 0, 1)); NaN pixel magenta, infinite pixel cyan
//   pq10 = |PQ(nits(cand)) − PQ(nits(ref))| · 1023 (nits clamped to [0, 10000], NaN → 0)
//   ΔE_ITP (ITU-R BT.2124) of the BT.2020 colours, ICtCp per BT.2100.
'use strict';

const HDRC = (window.HDRC = window.HDRC || {});

// data.js writes each case's overall statistics as one array `m` in the order of `metric_keys`
// (the keys once, not once a case; null: the case has no such statistic); here each case gets
// them back as its `metrics` object ("pq_code10.max": value).
HDRC.data = (d) => {
  const keys = d.metric_keys || [];
  for (const c of d.cases) {
    if (!c.metrics) {
      c.metrics = {};
      (c.m || []).forEach((v, i) => {
        if (v !== null && i < keys.length) c.metrics[keys[i]] = v;
      });
    }
    delete c.m;
  }
  HDRC.cases = d.cases;
};
HDRC.pixels = (p) => {
  HDRC.px = p;
};

// ---------------------------------------------------------------------------------------------
// Small helpers.

function el(tag, attrs, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) {
    if (v === undefined || v === null || v === false) continue;
    if (k === 'class') e.className = v;
    else if (k === 'text') e.textContent = v;
    else if (k.startsWith('on')) e.addEventListener(k.slice(2), v);
    else e.setAttribute(k, v === true ? '' : String(v));
  }
  for (const c of children) {
    if (c === null || c === undefined) continue;
    e.append(c instanceof Node ? c : document.createTextNode(String(c)));
  }
  return e;
}
const $ = (sel, root) => (root || document).querySelector(sel);
const $$ = (sel, root) => Array.from((root || document).querySelectorAll(sel));

function verdictClass(v) {
  return v === 'PASS' ? 'pass' : v === 'FAIL' ? 'fail' : v === 'ERROR' ? 'error' : 'skip';
}
function badge(v) {
  return el('span', { class: 'badge v-' + verdictClass(v), text: v });
}
function toNumber(v) {
  if (typeof v === 'number') return v;
  if (v === 'NaN') return NaN;
  if (v === 'Infinity' || v === '+Inf') return Infinity;
  if (v === '-Infinity' || v === '−Inf') return -Infinity;
  return v === null || v === undefined || v === '' ? undefined : Number(v);
}
function fmt(v, digits) {
  v = toNumber(v);
  if (v === undefined) return '—';
  if (Number.isNaN(v)) return 'NaN';
  if (!Number.isFinite(v)) return v > 0 ? '+Inf' : '−Inf';
  if (v === 0) return '0';
  return Number(v.toPrecision(digits || 4)).toString();
}
// The shortest decimal that reads back as the same float32 (the EXRs hold float32).
function f32(v) {
  if (Number.isNaN(v)) return 'NaN';
  if (!Number.isFinite(v)) return v > 0 ? '+Inf' : '−Inf';
  if (v === 0) return Object.is(v, -0) ? '-0' : '0';
  for (let p = 1; p <= 9; p++) {
    const s = v.toPrecision(p);
    if (Math.fround(Number(s)) === v) return String(Number(s));
  }
  return v.toPrecision(9);
}
function pct(b) {
  b = toNumber(b);
  return b === undefined ? '—' : fmt(b * 100, 3) + ' %';
}
// UE's names of the device and gamut enums (HDRHelper.h: EDisplayOutputFormat,
// EDisplayColorGamut), shown beside the numbers everywhere a value is displayed.
const VALUE_NAMES = {
  'r.HDR.Display.OutputDevice': ['SDR sRGB', 'SDR Rec.709', 'SDR explicit gamma', 'HDR ACES 1000-nit ST 2084',
    'HDR ACES 2000-nit ST 2084', 'HDR ACES 1000-nit scRGB', 'HDR ACES 2000-nit scRGB', 'HDR LinearEXR',
    'HDR LinearNoToneCurve', 'HDR LinearWithToneCurve'],
  'r.HDR.Display.ColorGamut': ['Rec.709 / sRGB D65', 'DCI-P3 D65', 'Rec.2020 D65', 'ACES AP0 D60', 'ACEScg AP1 D60'],
};
function valueLabel(dim, v) {
  const names = VALUE_NAMES[dim];
  const n = names && /^\d+$/.test(String(v)) ? names[Number(v)] : undefined;
  return n ? v + ' (' + n + ')' : String(v);
}
function cvarValue(c, dim) {
  if (dim === 'stage') return c.stage;
  if (dim.startsWith('setting:')) {
    const v = c.settings[dim.slice(8)];
    return v === undefined ? '(default)' : String(v);
  }
  const v = c.cvars[dim];
  return v === undefined ? '(default)' : String(v);
}
function compareValues(a, b) {
  const na = Number(a), nb = Number(b);
  const fa = a !== '' && Number.isFinite(na), fb = b !== '' && Number.isFinite(nb);
  if (fa && fb) return na - nb;
  if (fa !== fb) return fa ? -1 : 1;
  return String(a).localeCompare(String(b));
}
function parseHash() {
  const out = { cv: [] };
  for (const part of location.hash.replace(/^#/, '').split('&')) {
    if (!part) continue;
    const i = part.indexOf('=');
    const k = decodeURIComponent(i < 0 ? part : part.slice(0, i));
    const v = i < 0 ? '' : decodeURIComponent(part.slice(i + 1));
    if (k === 'cv') out.cv.push(v);
    else out[k] = v;
  }
  return out;
}
function setHash(obj) {
  const parts = [];
  for (const [k, v] of Object.entries(obj)) {
    if (Array.isArray(v)) v.forEach((x) => parts.push(k + '=' + encodeURIComponent(x)));
    else if (v !== '' && v !== undefined) parts.push(k + '=' + encodeURIComponent(v));
  }
  history.replaceState(null, '', '#' + parts.join('&'));
}
function caseHref(c, fromRoot) {
  return (fromRoot ? 'c/' : '') + encodeURIComponent(c.slug) + '.html';
}
function ready() {
  HDRC.tti = performance.now();
  document.documentElement.dataset.ready = '1';
}

// Verdict rank for a group of cases: the worst verdict decides a matrix cell's colour.
function cellClass(cases) {
  if (cases.some((c) => c.verdict === 'FAIL')) return 'fail';
  if (cases.some((c) => c.verdict === 'ERROR')) return 'error';
  if (cases.some((c) => c.verdict === 'PASS' && c.warn)) return 'warn';
  if (cases.some((c) => c.verdict === 'PASS')) return 'pass';
  return 'skip';
}

// UE's Colorize(x) (PostProcessVisualizeHDR.usf): 0 blue, 0.5 green, 1 red (report/images.cpp).
function colorize(x) {
  x = Number.isNaN(x) ? 0 : Math.min(1, Math.max(0, x));
  const t = Math.abs(0.5 - x) * 2;
  return [Math.round(t * x * 255), Math.round((1 - t) * 255), Math.round(t * (1 - x) * 255)];
}
const HEAT = {
  pq10: { min: -4, max: 1, unit: 'PQ 10-bit code values', tol: 'pq_code10', panel: 'heat' },
  itp: { min: -3, max: 2, unit: 'ΔE_ITP', tol: 'delta_e_itp', panel: 'heat_itp' },
};
function heatColour(e, scale) {
  if (Number.isNaN(e)) return [255, 255, 255];
  if (!(e > 0)) return [0, 0, 0];
  return colorize((Math.log10(e) - scale.min) / (scale.max - scale.min));
}

// ---------------------------------------------------------------------------------------------
// Colour maths (mirrors report/images.cpp and runner/diff.cpp).

function srgbOetf(x) {
  // IEC 61966-2-1 encoding.
  if (!(x > 0)) return 0;
  if (x >= 1) return 1;
  return x <= 0.0031308 ? 12.92 * x : 1.055 * Math.pow(x, 1 / 2.4) - 0.055;
}
// SMPTE ST 2084 inverse EOTF (color/st2084.h: pq_from_nits), constants in the
// standard's fractional form.
const PQ_M1 = 2610 / 16384, PQ_M2 = (2523 / 4096) * 128;
const PQ_C1 = 3424 / 4096, PQ_C2 = (2413 / 4096) * 32, PQ_C3 = (2392 / 4096) * 32;
function pqFromNits(n) {
  const lm = Math.pow(n / 10000, PQ_M1);
  return Math.pow((PQ_C1 + PQ_C2 * lm) / (1 + PQ_C3 * lm), PQ_M2);
}
// ST 2084 EOTF: PQ signal → nits (color/st2084.h: nits_from_pq).
// The same expression (NaN below 0, extrapolated above 1), so the probe and the previews agree
// with the C++ decoding exactly.
function nitsFromPq(e) {
  const p = Math.pow(e, 1 / PQ_M2);
  return Math.pow(Math.max(p - PQ_C1, 0) / (PQ_C2 - PQ_C3 * p), 1 / PQ_M1) * 10000;
}
function pqSignal(n) {
  return pqFromNits(n > 0 ? Math.min(n, 10000) : 0);
}
// OutputEncoding::to_nits (core/output_encoding.cpp) from the parameters the report sends
// (html_report.cpp encoding_json): nits = transfer(pre_scale · v) · nits_scale. sRGB and Rec.709
// decode as color/gamma_correction.h srgb_to_linear / rec709_to_linear (UE's
// SrgbToLinear / Rec709ToLinear) after its min-normal clamp fmax(6.10352e-5, c); gamma:
// max(v, 0)^gamma.
const MIN_NORMAL = 6.10352e-5;
function toNits(e, v) {
  if (e.pre_scale !== 1) v *= e.pre_scale;
  const clamped = () => (Number.isNaN(v) ? MIN_NORMAL : Math.max(MIN_NORMAL, v));
  switch (e.transfer) {
    case 'pq':
      return nitsFromPq(v) * e.nits_scale;
    case 'srgb': {
      const c = clamped();
      return (c > 0.04045 ? Math.pow(c * (1 / 1.055) + 0.0521327, 2.4) : c * (1 / 12.92)) * e.nits_scale;
    }
    case 'rec709': {
      const c = clamped();
      return (c > 0.081 ? Math.pow((c + 0.099) / 1.099, 1 / 0.45) : c / 4.5) * e.nits_scale;
    }
    case 'gamma':
      return (v > 0 ? Math.pow(v, e.gamma) : 0) * e.nits_scale;
    default:
      return v * e.nits_scale;
  }
}
// ITU-R BT.2100-2 Table 7 (ICtCp, PQ) and BT.2124-0 eq. 1–2 (ΔE_ITP), as runner/diff.cpp.
function ictcp(rgb2020) {
  const l = (1688 * rgb2020[0] + 2146 * rgb2020[1] + 262 * rgb2020[2]) / 4096;
  const m = (683 * rgb2020[0] + 2951 * rgb2020[1] + 462 * rgb2020[2]) / 4096;
  const s = (99 * rgb2020[0] + 309 * rgb2020[1] + 3688 * rgb2020[2]) / 4096;
  const L = pqSignal(l), M = pqSignal(m), S = pqSignal(s);
  return [0.5 * L + 0.5 * M, (6610 * L - 13613 * M + 7003 * S) / 4096,
    (17933 * L - 17390 * M - 543 * S) / 4096];
}
function deltaEItp(a, b) {
  const di = a[0] - b[0], dt = 0.5 * (a[1] - b[1]), dp = a[2] - b[2];
  return 720 * Math.sqrt(di * di + dt * dt + dp * dp);
}
function mul3(m, v) {
  return [m[0] * v[0] + m[1] * v[1] + m[2] * v[2], m[3] * v[0] + m[4] * v[1] + m[5] * v[2],
    m[6] * v[0] + m[7] * v[1] + m[8] * v[2]];
}

// PNG chunks (ISO/IEC 15948: length, type, data, CRC-32 of type and data).
const CRC_TABLE = (() => {
  const t = new Uint32Array(256);
  for (let n = 0; n < 256; n++) {
    let c = n;
    for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
    t[n] = c >>> 0;
  }
  return t;
})();
function pngChunk(type, data) {
  const out = new Uint8Array(12 + data.length);
  const dv = new DataView(out.buffer);
  dv.setUint32(0, data.length);
  for (let i = 0; i < 4; i++) out[4 + i] = type.charCodeAt(i);
  out.set(data, 8);
  let c = 0xffffffff;
  for (let i = 4; i < 8 + data.length; i++) c = CRC_TABLE[(c ^ out[i]) & 255] ^ (c >>> 8);
  dv.setUint32(8 + data.length, (c ^ 0xffffffff) >>> 0);
  return out;
}

// Float data of one image: values (3 or 4 channels) and nits (3 channels, or values · scale).
function decodeF32(b64) {
  const bytes = bytesOf(b64);
  const dv = new DataView(bytes.buffer);
  const out = new Float32Array(bytes.length / 4);
  for (let i = 0; i < out.length; i++) out[i] = dv.getFloat32(i * 4, true);
  return out;
}
// Packed data (report/images.h: float32_packed_base64): base64 → inflate (the browser's own
// DecompressionStream) → byte planes → float32. Lossless, so the probe shows the EXR's values.
async function decodePacked(b64) {
  const z = bytesOf(b64);
  const stream = new Blob([z]).stream().pipeThrough(new DecompressionStream('deflate'));
  const planes = new Uint8Array(await new Response(stream).arrayBuffer());
  const n = planes.length / 4;
  const bytes = new Uint8Array(planes.length);
  for (let b = 0; b < 4; b++) {
    const plane = planes.subarray(b * n, (b + 1) * n);
    for (let i = 0; i < n; i++) bytes[i * 4 + b] = plane[i];
  }
  return new Float32Array(bytes.buffer); // little-endian hosts (every browser we target)
}
// An OpenEXR file (report/images.h exr_embeddable: one part, scan lines, compression NONE, ZIPS
// or ZIP, channels R, G, B and maybe A, HALF or FLOAT) → its RGBA values as float32, 4 per pixel
// (alpha 1 without an A channel, as the runner reads it). OpenEXR file layout: magic, version,
// header attributes (name, type, size, value) up to an empty name, the offset table (one uint64
// per chunk, by increasing y), chunks (int32 y, int32 size, data). A ZIP/ZIPS chunk is zlib data
// that inflates to the predictor-coded, interleaved bytes (OpenEXR's ImfZip.cpp: each byte is the
// previous plus it minus 128; then the first and second halves interleave), unless its size is
// the raw size (stored). A scan line holds each channel's `w` values in turn, channels sorted by
// name. Every read is bounded by the file; anything else is an error.
async function decodeExr(b64, w, h) {
  const b = bytesOf(b64);
  const dv = new DataView(b.buffer, b.byteOffset, b.byteLength);
  const fail = (why) => { throw new Error('OpenEXR data: ' + why); };
  const need = (at, n) => { if (at < 0 || at + n > b.length) fail('truncated'); };
  need(0, 8);
  if (dv.getUint32(0, true) !== 20000630 || (dv.getUint32(4, true) & 0x1aff) !== 2) fail('not a single-part scan-line file');
  let at = 8;
  const cstr = () => {
    const end = b.indexOf(0, at);
    if (end < 0 || end - at > 255) fail('bad string');
    const s = String.fromCharCode(...b.subarray(at, end));
    at = end + 1;
    return s;
  };
  const chans = [];
  let compression = -1, win = null;
  for (let n = 0; n < 1000; n++) {
    const name = cstr();
    if (!name) break;
    cstr(); // type
    need(at, 4);
    const size = dv.getInt32(at, true);
    at += 4;
    need(at, size);
    if (name === 'channels') {
      let p = at;
      while (p < at + size && b[p] !== 0 && chans.length < 16) {
        const end = b.indexOf(0, p);
        if (end < 0 || end + 17 > at + size) fail('bad channel list');
        chans.push({ name: String.fromCharCode(...b.subarray(p, end)), type: dv.getInt32(end + 1, true) });
        p = end + 17;
      }
    } else if (name === 'compression') compression = b[at];
    else if (name === 'dataWindow' && size === 16) win = [0, 4, 8, 12].map((o) => dv.getInt32(at + o, true));
    at += size;
  }
  if (!win || win[2] - win[0] + 1 !== w || win[3] - win[1] + 1 !== h) fail('data window is not ' + w + ' x ' + h);
  const lines = compression === 3 ? 16 : compression === 0 || compression === 2 ? 1 : fail('compression ' + compression);
  const slot = { R: 0, G: 1, B: 2, A: 3 };
  if (chans.some((c) => !(c.name in slot) || (c.type !== 1 && c.type !== 2))) fail('channels');
  const lineBytes = chans.reduce((n, c) => n + w * (c.type === 1 ? 2 : 4), 0);
  const out = new Float32Array(w * h * 4);
  if (!chans.some((c) => c.name === 'A')) for (let i = 3; i < out.length; i += 4) out[i] = 1;
  const chunks = Math.ceil(h / lines);
  need(at, chunks * 8);
  await Promise.all(Array.from({ length: chunks }, async (_, k) => {
    const off = Number(dv.getBigUint64(at + k * 8, true));
    need(off, 8);
    const y0 = dv.getInt32(off, true) - win[1], size = dv.getInt32(off + 4, true);
    const rows = Math.min(lines, h - y0);
    if (y0 !== k * lines || size <= 0) fail('chunk ' + k);
    need(off + 8, size);
    const raw = rows * lineBytes;
    let data = b.subarray(off + 8, off + 8 + size);
    if (compression !== 0 && size < raw) {
      const z = await inflateBounded(data, raw);
      for (let i = 1; i < z.length; i++) z[i] = (z[i - 1] + z[i] - 128) & 255;
      data = new Uint8Array(raw);
      const half = (raw + 1) >> 1;
      for (let i = 0; i < half; i++) data[2 * i] = z[i];
      for (let i = 0; 2 * i + 1 < raw; i++) data[2 * i + 1] = z[half + i];
    } else if (size !== raw) fail('chunk ' + k + ' size');
    // Each channel's row through a typed-array view where its bytes are aligned (OpenEXR is
    // little-endian, as every host we target: decodePacked assumes it too), else through the
    // DataView; halves through a table of all 65536 (a LUT-64³ page decodes 2 M values: the
    // DataView call per value was ~0.4 s of its time to interactive, issue 27).
    const cv = new DataView(data.buffer, data.byteOffset, data.byteLength);
    const table = chans.some((c) => c.type === 1) ? halfTable() : null;
    let p = 0;
    for (let r = 0; r < rows; r++) {
      const base = (y0 + r) * w * 4;
      for (const c of chans) {
        const s = slot[c.name], at = data.byteOffset + p;
        if (c.type === 2) {
          if (at % 4 === 0) {
            const src = new Float32Array(data.buffer, at, w);
            for (let x = 0; x < w; x++) out[base + x * 4 + s] = src[x];
          } else for (let x = 0; x < w; x++) out[base + x * 4 + s] = cv.getFloat32(p + x * 4, true);
          p += w * 4;
        } else {
          if (at % 2 === 0) {
            const src = new Uint16Array(data.buffer, at, w);
            for (let x = 0; x < w; x++) out[base + x * 4 + s] = table[src[x]];
          } else for (let x = 0; x < w; x++) out[base + x * 4 + s] = table[cv.getUint16(p + x * 2, true)];
          p += w * 2;
        }
      }
    }
  }));
  return out;
}
// Base64 → bytes: the engine's own decoder where it has one (Uint8Array.fromBase64, TC39's
// proposal-arraybuffer-base64, in Chromium since 140), else atob byte by byte.
function bytesOf(b64) {
  if (typeof Uint8Array.fromBase64 === 'function') return Uint8Array.fromBase64(b64);
  const bin = atob(b64);
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
  return bytes;
}
// zlib data → exactly `n` bytes, reading no more than that from the stream (a chunk declaring a
// small raw size cannot inflate into memory beyond it).
async function inflateBounded(z, n) {
  const reader = new Blob([z]).stream().pipeThrough(new DecompressionStream('deflate')).getReader();
  const out = new Uint8Array(n);
  let got = 0;
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    if (got + value.length > n) {
      reader.cancel();
      throw new Error('OpenEXR data: a chunk inflates past its size');
    }
    out.set(value, got);
    got += value.length;
  }
  if (got !== n) throw new Error('OpenEXR data: a chunk inflates to ' + got + ' bytes, not ' + n);
  return out;
}
// Every binary16 value as float32, made once.
let HALF_TABLE = null;
function halfTable() {
  if (!HALF_TABLE) {
    HALF_TABLE = new Float32Array(65536);
    for (let u = 0; u < 65536; u++) HALF_TABLE[u] = halfToFloat(u);
  }
  return HALF_TABLE;
}
// IEEE 754 binary16 → number.
function halfToFloat(u) {
  const sgn = u & 0x8000 ? -1 : 1, e = (u >> 10) & 31, m = u & 1023;
  return e === 0 ? sgn * m * Math.pow(2, -24) : e === 31 ? (m ? NaN : sgn * Infinity) : sgn * (1 + m / 1024) * Math.pow(2, e - 15);
}

class FloatImage {
  constructor(w, h, d, v, nits) {
    this.w = w;
    this.h = h;
    this.ch = d.exr ? 4 : d.ch;
    this.alpha = d.alpha;
    this.v = v;
    this.enc = d.enc || { transfer: 'linear', pre_scale: 1, nits_scale: 1, gamma: 1 };
  }
  static async load(w, h, d) {
    const packed = !!HDRC.px.packing;
    const dec = packed ? decodePacked : async (b) => decodeF32(b);
    return new FloatImage(w, h, d, d.exr ? await decodeExr(d.exr, w, h) : await dec(d.v), null);
  }
  value(i, c) {
    if (c === 3 && this.ch === 3) return this.alpha;
    return this.v[i * this.ch + c];
  }
  // Each value's nits, decoded once for the whole image (toNits is pow-bound: the previews, the
  // error pass and the plots read them many times over; a LUT-64³ page has 786 432 values).
  nits(i, c) {
    if (!this.n) {
      const n = new Float64Array(this.w * this.h * 3);
      for (let p = 0, q = 0; p < n.length; p += 3, q += this.ch) {
        n[p] = toNits(this.enc, this.v[q]);
        n[p + 1] = toNits(this.enc, this.v[q + 1]);
        n[p + 2] = toNits(this.enc, this.v[q + 2]);
      }
      this.n = n;
    }
    return this.n[i * 3 + c];
  }
}

// ---------------------------------------------------------------------------------------------
// Plots: SVG drawn here (no plotting library: a few hundred points per plot, axes on log scales,
// and the report must stay one offline folder with nothing to vendor or update).

const SVGNS = 'http://www.w3.org/2000/svg';
function svgEl(tag, attrs, ...children) {
  const e = document.createElementNS(SVGNS, tag);
  for (const [k, v] of Object.entries(attrs || {})) if (v !== undefined && v !== null) e.setAttribute(k, String(v));
  for (const c of children) e.append(c instanceof Node ? c : document.createTextNode(String(c)));
  return e;
}
// A plot frame: x/y scales (linear or log10), axes with decade or 5 linear ticks, labels.
function plotFrame(width, height, xr, yr, opts) {
  const m = { l: 58, r: 12, t: 8, b: 30 };
  const lx = opts.xlog, ly = opts.ylog;
  const tx = (v) => (lx ? Math.log10(v) : v), ty = (v) => (ly ? Math.log10(v) : v);
  const [x0, x1] = xr.map(tx), [y0, y1] = yr.map(ty);
  const X = (v) => m.l + ((tx(v) - x0) / (x1 - x0 || 1)) * (width - m.l - m.r);
  const Y = (v) => height - m.b - ((ty(v) - y0) / (y1 - y0 || 1)) * (height - m.t - m.b);
  const g = svgEl('svg', { width, height, viewBox: `0 0 ${width} ${height}`, role: 'img', id: opts.id });
  const ticks = (a, b, log) => {
    const out = [];
    if (log) for (let e = Math.ceil(a); e <= Math.floor(b); e++) out.push(Math.pow(10, e));
    else for (let i = 0; i <= 4; i++) out.push(a + ((b - a) * i) / 4);
    return out;
  };
  for (const v of ticks(x0, x1, lx)) {
    g.append(svgEl('line', { class: 'grid', x1: X(v), x2: X(v), y1: m.t, y2: height - m.b }));
    g.append(svgEl('text', { x: X(v), y: height - m.b + 12, 'text-anchor': 'middle' }, fmt(v, 3)));
  }
  for (const v of ticks(y0, y1, ly)) {
    g.append(svgEl('line', { class: 'grid', x1: m.l, x2: width - m.r, y1: Y(v), y2: Y(v) }));
    g.append(svgEl('text', { x: m.l - 4, y: Y(v) + 4, 'text-anchor': 'end' }, fmt(v, 3)));
  }
  g.append(svgEl('line', { class: 'axis', x1: m.l, x2: m.l, y1: m.t, y2: height - m.b }));
  g.append(svgEl('line', { class: 'axis', x1: m.l, x2: width - m.r, y1: height - m.b, y2: height - m.b }));
  g.append(svgEl('text', { x: (m.l + width - m.r) / 2, y: height - 4, 'text-anchor': 'middle' }, opts.xlabel));
  g.append(svgEl('text', { x: 12, y: (m.t + height - m.b) / 2, transform: `rotate(-90 12 ${(m.t + height - m.b) / 2})`, 'text-anchor': 'middle' }, opts.ylabel));
  return { g, X, Y };
}
function polyline(points, cls) {
  return svgEl('polyline', { class: cls, points: points.map(([x, y]) => x.toFixed(1) + ',' + y.toFixed(1)).join(' ') });
}
const LUMA709 = [0.2126, 0.7152, 0.0722], LUMA2020 = [0.2627, 0.678, 0.0593]; // BT.709, BT.2020 Y
// CIE 1931 2° spectral locus (x, y), 380–700 nm (CIE 15:2004 tables, rounded to 4 places).
const LOCUS = [[0.1741, 0.005], [0.1733, 0.0048], [0.1714, 0.0051], [0.1644, 0.0109], [0.1566, 0.0177],
  [0.144, 0.0297], [0.1241, 0.0578], [0.1096, 0.0868], [0.0913, 0.1327], [0.0687, 0.2007], [0.0454, 0.295],
  [0.0235, 0.4127], [0.0082, 0.5384], [0.0039, 0.6548], [0.0139, 0.7502], [0.0389, 0.812], [0.0743, 0.8338],
  [0.1142, 0.8262], [0.1547, 0.8059], [0.2296, 0.7543], [0.3016, 0.6923], [0.3731, 0.6245], [0.4441, 0.5547],
  [0.5125, 0.4866], [0.5752, 0.4242], [0.627, 0.3725], [0.6658, 0.334], [0.6915, 0.3083], [0.7079, 0.292],
  [0.719, 0.2809], [0.726, 0.274], [0.73, 0.27], [0.7334, 0.2666], [0.7347, 0.2653]];
// Primaries (x, y): BT.709, Display P3 (D65), BT.2020, ACES AP1.
const GAMUTS = [['Rec.709', [[0.64, 0.33], [0.3, 0.6], [0.15, 0.06]], '#2b8a3e'],
  ['P3-D65', [[0.68, 0.32], [0.265, 0.69], [0.15, 0.06]], '#1971c2'],
  ['Rec.2020', [[0.708, 0.292], [0.17, 0.797], [0.131, 0.046]], '#862e9c'],
  ['AP1', [[0.713, 0.293], [0.165, 0.83], [0.128, 0.044]], '#868e96']];
// BT.2020 RGB → CIE XYZ (D65), from its primaries (ITU-R BT.2020 Table 4).
const REC2020_TO_XYZ = [0.636958, 0.144617, 0.168881, 0.262700, 0.677998, 0.059302, 0, 0.028073, 1.060985];

// ---------------------------------------------------------------------------------------------
// Summary page: static; only marks itself ready.

function initSummary() {
  openReasons();
  ready();
}

// The case lists' reasons are cut to two lines (report.css div.reason); a click shows one whole.
function openReasons() {
  document.addEventListener('click', (e) => {
    const r = e.target.closest && e.target.closest('table.cases div.reason');
    if (r) r.classList.toggle('open');
  });
}

// ---------------------------------------------------------------------------------------------
// Case list: filter by stage, verdict, one cvar value and text; sort by any column or metric.

function initCases() {
  const cases = HDRC.cases || [];
  const byIndex = new Map(cases.map((c) => [String(c.i), c]));
  const tbody = $('#case-table tbody');
  const rows = $$('tr', tbody);
  const fill = (sel, values, keep) => {
    const s = $(sel);
    for (const v of values) s.append(el('option', { value: v, text: v }));
    if (keep) s.value = keep;
  };
  const uniq = (f) => Array.from(new Set(cases.map(f))).sort(compareValues);
  fill('#f-pipeline', uniq((c) => c.pipeline || ''));
  fill('#f-stage', uniq((c) => c.stage));
  fill('#f-verdict', uniq((c) => c.verdict).concat(['WARN', 'NEAR_MISS', 'TIGHTEN']));
  const cvarNames = Array.from(new Set(cases.flatMap((c) => Object.keys(c.cvars)))).sort();
  fill('#f-cvar', cvarNames);
  const metricNames = Array.from(new Set(cases.flatMap((c) => Object.keys(c.metrics)))).sort();
  fill('#f-metric', metricNames);
  const preferred = ['overall.pq_code10.max', 'pq_code10.max', 'max_pq10'].find((m) =>
    metricNames.includes(m));
  if (preferred) $('#f-metric').value = preferred;

  const fillCvarValues = () => {
    const s = $('#f-cvar-value');
    s.replaceChildren(el('option', { value: '', text: 'any' }));
    const name = $('#f-cvar').value;
    if (name) for (const v of uniq((c) => cvarValue(c, name))) s.append(el('option', { value: v, text: valueLabel(name, v) }));
  };
  const h = parseHash();
  if (h.pipeline) $('#f-pipeline').value = h.pipeline;
  if (h.stage) $('#f-stage').value = h.stage;
  if (h.verdict) $('#f-verdict').value = h.verdict;
  if (h.text) $('#f-text').value = h.text;
  if (h.metric && metricNames.includes(h.metric)) $('#f-metric').value = h.metric;
  const extra = []; // further cvar=value constraints from a matrix drill-down
  for (const cv of h.cv) {
    const i = cv.lastIndexOf(':');
    if (i > 0) extra.push([cv.slice(0, i), cv.slice(i + 1)]);
  }
  if (extra.length) {
    $('#f-cvar').value = extra[0][0];
    fillCvarValues();
    $('#f-cvar-value').value = extra[0][1];
  }
  let sortKey = h.sort || '', sortDir = h.dir === 'desc' ? -1 : 1;

  const apply = () => {
    const pipeline = $('#f-pipeline').value, stage = $('#f-stage').value, verdict = $('#f-verdict').value;
    const cvar = $('#f-cvar').value, cval = $('#f-cvar-value').value;
    const text = $('#f-text').value.trim().toLowerCase();
    const metric = $('#f-metric').value;
    $('#metric-head').textContent = metric || 'metric';
    const cons = extra.slice(1);
    if (cvar && cval) cons.unshift([cvar, cval]);
    let shown = 0;
    for (const r of rows) {
      const c = byIndex.get(r.dataset.i);
      const okVerdict = !verdict || c.verdict === verdict || (verdict === 'WARN' && c.warn) ||
        (verdict === 'NEAR_MISS' && c.near) || (verdict === 'TIGHTEN' && c.tighten);
      const ok = c && (!pipeline || c.pipeline === pipeline) && (!stage || c.stage === stage) && okVerdict &&
        cons.every(([k, v]) => cvarValue(c, k) === v) &&
        (!text || (c.id + ' ' + c.input + ' ' + c.reason).toLowerCase().includes(text));
      r.hidden = !ok;
      shown += ok;
      const m = c ? c.metrics[metric] : undefined;
      const cell = $('td.metric', r);
      cell.textContent = fmt(m);
      cell.dataset.v = m === undefined ? '' : String(toNumber(m));
    }
    $('#shown').textContent = shown + ' of ' + rows.length + ' cases';
    const key = (r) => {
      const c = byIndex.get(r.dataset.i);
      switch (sortKey) {
        case 'verdict': return c.verdict;
        case 'id': return c.id;
        case 'stage': return c.stage;
        case 'input': return c.input;
        case 'budget': return toNumber(c.budget);
        case 'metric': return toNumber(c.metrics[metric]);
        default: return c.i;
      }
    };
    const sorted = rows.slice().sort((a, b) => {
      const ka = key(a), kb = key(b);
      const ua = ka === undefined || Number.isNaN(ka), ub = kb === undefined || Number.isNaN(kb);
      if (ua || ub) return ua === ub ? 0 : ua ? 1 : -1; // missing values last either way
      const d = typeof ka === 'number' && typeof kb === 'number' ? ka - kb :
        String(ka).localeCompare(String(kb));
      return d * sortDir;
    });
    tbody.append(...sorted);
    for (const th of $$('th[data-sort]')) {
      th.classList.toggle('sorted-asc', th.dataset.sort === sortKey && sortDir > 0);
      th.classList.toggle('sorted-desc', th.dataset.sort === sortKey && sortDir < 0);
    }
    setHash({ pipeline, stage, verdict, text, metric, sort: sortKey, dir: sortDir < 0 ? 'desc' : '',
      cv: cons.map(([k, v]) => k + ':' + v) });
  };
  $('#f-cvar').addEventListener('change', () => {
    extra.length = 0;
    fillCvarValues();
    apply();
  });
  for (const id of ['#f-pipeline', '#f-stage', '#f-verdict', '#f-cvar-value', '#f-metric'])
    $(id).addEventListener('change', apply);
  $('#f-text').addEventListener('input', apply);
  $('#filters').addEventListener('submit', (e) => e.preventDefault());
  for (const th of $$('th[data-sort]'))
    th.addEventListener('click', () => {
      if (sortKey === th.dataset.sort) sortDir = -sortDir;
      else {
        sortKey = th.dataset.sort;
        sortDir = sortKey === 'budget' || sortKey === 'metric' ? -1 : 1;
      }
      apply();
    });
  openReasons();
  apply();
  ready();
}

// ---------------------------------------------------------------------------------------------
// Cvar matrix: verdict or a metric pivoted over two dimensions, drill-down into a cell.

function initMatrix() {
  const all = HDRC.cases || [];
  const h = parseHash();
  const stageSel = $('#m-stage'), rowSel = $('#m-rows'), colSel = $('#m-cols'), showSel = $('#m-show');
  for (const s of Array.from(new Set(all.map((c) => c.stage))).sort())
    stageSel.append(el('option', { value: s, text: s }));
  // A metric's value counts only for the cases whose tolerance judges it (data.js judged: from the
  // tolerance each case ran with, results.json); a metric no case judges is not offered.
  const judges = (c, m) => !c.judged || c.judged.includes(m.split('.')[0]);
  const metricNames = Array.from(new Set(all.flatMap((c) => Object.keys(c.metrics).filter((m) => judges(c, m))))).sort();
  showSel.append(el('option', { value: 'budget', text: 'budget used (max)' }));
  for (const m of metricNames) showSel.append(el('option', { value: 'm:' + m, text: m + ' (max)' }));
  if (h.stage) stageSel.value = h.stage;
  if (h.show) showSel.value = h.show;
  let selected = null;

  const dims = (cases) => {
    // Dimensions that vary within the cases: cvars, settings, the stage.
    const d = [];
    const consider = (name) => {
      const vals = new Set(cases.map((c) => cvarValue(c, name)));
      if (vals.size > 1) d.push(name);
    };
    for (const n of Array.from(new Set(cases.flatMap((c) => Object.keys(c.cvars)))).sort()) consider(n);
    for (const n of Array.from(new Set(cases.flatMap((c) => Object.keys(c.settings)))).sort())
      consider('setting:' + n);
    consider('stage');
    return d;
  };
  const fillDims = () => {
    const cases = all.filter((c) => !stageSel.value || c.stage === stageSel.value);
    const d = dims(cases);
    const prevR = rowSel.value || h.rows, prevC = colSel.value || h.cols;
    rowSel.replaceChildren(...d.map((n) => el('option', { value: n, text: n })));
    colSel.replaceChildren(el('option', { value: '', text: '(none)' }),
      ...d.map((n) => el('option', { value: n, text: n })));
    const pick = (want, fallback) => (d.includes(want) ? want : fallback);
    rowSel.value = pick(prevR, pick('r.HDR.Display.OutputDevice', d[0] || ''));
    colSel.value = pick(prevC, pick('r.HDR.Display.ColorGamut', d.find((x) => x !== rowSel.value) || ''));
  };

  const cellValue = (cs) => {
    const show = showSel.value;
    if (show === 'verdict') return undefined;
    const vals = cs.filter((c) => show === 'budget' || judges(c, show.slice(2)))
      .map((c) => toNumber(show === 'budget' ? c.budget : c.metrics[show.slice(2)]))
      .filter((v) => v !== undefined);
    if (!vals.length) return undefined;
    return vals.reduce((a, b) => (Number.isNaN(b) || b > a ? b : a));
  };

  const render = () => {
    const cases = all.filter((c) => !stageSel.value || c.stage === stageSel.value);
    const rd = rowSel.value, cd = colSel.value;
    const rowsV = Array.from(new Set(cases.map((c) => cvarValue(c, rd)))).sort(compareValues);
    const colsV = cd ? Array.from(new Set(cases.map((c) => cvarValue(c, cd)))).sort(compareValues) : [''];
    const grid = new Map();
    for (const c of cases) {
      const k = cvarValue(c, rd) + '\u0000' + (cd ? cvarValue(c, cd) : '');
      if (!grid.has(k)) grid.set(k, []);
      grid.get(k).push(c);
    }
    const show = showSel.value;
    // The metric's range over the grid's cases (log10), for the colour of each cell; declared
    // before the cells are drawn (it was used before its declaration: a ReferenceError).
    let metricRange = null;
    const metricPosition = (v) => {
      if (!metricRange) {
        const vals = cases.filter((c) => judges(c, show.slice(2))).map((c) => toNumber(c.metrics[show.slice(2)])).filter((x) => x > 0 && Number.isFinite(x));
        metricRange = vals.length ? [Math.log10(Math.min(...vals)), Math.log10(Math.max(...vals))] : [0, 0];
      }
      const [lo, hi] = metricRange;
      return hi > lo ? (Math.log10(Math.max(v, 1e-300)) - lo) / (hi - lo) : 1;
    };
    const table = el('table', { id: 'matrix-table' });
    const head = el('tr', {}, el('th', { class: 'corner', text: rd + ' ↓ / ' + (cd || '—') + ' →' }));
    for (const v of colsV) head.append(el('th', { text: valueLabel(cd, v) }));
    table.append(el('thead', {}, head));
    const body = el('tbody');
    for (const rv of rowsV) {
      const tr = el('tr', {}, el('th', { text: valueLabel(rd, rv) }));
      for (const cv of colsV) {
        const cs = grid.get(rv + '\u0000' + cv) || [];
        if (!cs.length) {
          tr.append(el('td', { class: 'empty' }));
          continue;
        }
        const counts = {};
        for (const c of cs) counts[c.verdict] = (counts[c.verdict] || 0) + 1;
        const td = el('td', {
          class: 'cell',
          'data-row': rv,
          'data-col': cv,
          title: Object.entries(counts).map(([k, n]) => n + ' ' + k).join(', '),
        });
        if (show === 'verdict') {
          td.classList.add('cell-' + cellClass(cs));
          td.textContent = Object.entries(counts).map(([k, n]) => (cs.length > 1 ? n + ' ' : '') + k).join(' · ');
        } else {
          const v = cellValue(cs);
          const unjudged = show !== 'budget' && !cs.some((c) => judges(c, show.slice(2)));
          td.textContent = show === 'budget' ? pct(v) : unjudged ? 'not judged' : fmt(v);
          if (unjudged) td.classList.add('cell-skip', 'not-judged');
          if (v !== undefined) {
            // Budget: Colorize over log10 from 0.1 % to 200 %; other metrics over their range.
            const x = show === 'budget' ? (Math.log10(Math.max(v, 1e-12)) + 3) / (3 + Math.log10(2)) :
              metricPosition(v);
            const [r, g, b] = Number.isNaN(v) ? [255, 255, 255] : v === 0 ? [0, 0, 0] : colorize(x);
            td.style.background = `rgb(${r}, ${g}, ${b})`;
            td.style.color = v === 0 || (g > 150 && r < 100) || (r > 200 && g > 200) ? '#000' : '#fff';
          }
        }
        td.addEventListener('click', () => {
          selected = [rv, cv];
          drill(cs, rd, rv, cd, cv);
          for (const x of $$('td.cell.selected')) x.classList.remove('selected');
          td.classList.add('selected');
        });
        tr.append(td);
      }
      body.append(tr);
    }
    table.append(body);
    $('#matrix').replaceChildren(table);
    const legend = $('#matrix-legend');
    legend.replaceChildren();
    if (show === 'verdict') {
      for (const [cls, label] of [['pass', 'all passed'], ['warn', 'passed, with a warning'],
        ['fail', 'a case failed'], ['error', 'a case errored'], ['skip', 'not evaluated (skip, known limit, degenerate)']])
        legend.append(el('span', { class: 'badge cell-' + cls, text: label }), ' ');
    } else {
      legend.append(show === 'budget' ?
        'Colour: VisualizeHDR\'s Colorize ramp over log10(budget used), 0.1 % blue … 200 % red; black: exact.' :
        'Colour: Colorize ramp over log10 of the metric across the grid, over the cases whose tolerance judges it; black: exact; grey: no case of the cell is judged on it.');
    }
    setHash({ stage: stageSel.value, rows: rd, cols: cd, show });
    if (selected) {
      const td = $$('td.cell').find((t) => t.dataset.row === selected[0] && t.dataset.col === selected[1]);
      if (td) td.click();
      else selected = null;
    }
  };

  const drill = (cs, rd, rv, cd, cv) => {
    $('#cell-title').textContent = rd + ' = ' + valueLabel(rd, rv) + (cd ? ', ' + cd + ' = ' + valueLabel(cd, cv) : '') +
      ': ' + cs.length + ' case' + (cs.length === 1 ? '' : 's');
    const hash = [];
    if (stageSel.value) hash.push('stage=' + encodeURIComponent(stageSel.value));
    if (rd !== 'stage' && !rd.startsWith('setting:')) hash.push('cv=' + encodeURIComponent(rd + ':' + rv));
    if (cd && cd !== 'stage' && !cd.startsWith('setting:')) hash.push('cv=' + encodeURIComponent(cd + ':' + cv));
    const t = el('table', { class: 'cases', id: 'cell-table' });
    t.append(el('thead', {}, el('tr', {}, el('th', { text: 'verdict' }), el('th', { text: 'case' }),
      el('th', { text: 'budget used' }), el('th', { text: 'reason' }))));
    const b = el('tbody');
    for (const c of cs) {
      const v = el('td', {}, badge(c.verdict));
      if (c.warn) v.append(' ', el('span', { class: 'marker warn', text: 'WARN' }));
      if (c.near) v.append(' ', el('span', { class: 'marker near', text: 'near miss' }));
      if (c.tighten) v.append(' ', el('span', { class: 'marker tighten', text: 'could be tightened' }));
      b.append(el('tr', {}, v, el('td', {}, el('a', { href: caseHref(c, true) }, el('code', { text: c.id }))),
        el('td', { class: 'num', text: pct(c.budget) }), el('td', { class: 'reason', text: c.reason })));
    }
    t.append(b);
    $('#cell-cases').replaceChildren(t, el('p', {}, el('a', { href: 'cases.html#' + hash.join('&'), text: 'these cases in the case list' })));
  };

  stageSel.addEventListener('change', () => {
    selected = null;
    fillDims();
    render();
  });
  for (const s of [rowSel, colSel, showSel]) s.addEventListener('change', render);
  fillDims();
  if (h.rows && $$('option', rowSel).some((o) => o.value === h.rows)) rowSel.value = h.rows;
  if (h.cols !== undefined && $$('option', colSel).some((o) => o.value === h.cols)) colSel.value = h.cols;
  render();
  ready();
}

// ---------------------------------------------------------------------------------------------
// Case page: images with exposure, heatmaps, mask, side-by-side / flip / slider, pixel probe,
// LUT slices.

async function initCase() {
  const meta = JSON.parse($('#case-meta').textContent);
  HDRC.meta = meta;
  const w = meta.w, h = meta.h;
  const imgs = {};
  const pxData = $('#case-px');
  if (!HDRC.px && pxData) HDRC.px = JSON.parse(pxData.textContent);
  if (HDRC.px) {
    for (const [k, d] of Object.entries(HDRC.px.images)) imgs[k] = await FloatImage.load(HDRC.px.w, HDRC.px.h, d);
  }
  const copy = $('#repro-copy');
  if (copy)
    copy.addEventListener('click', async () => {
      const text = $('#repro-cmd').textContent;
      try {
        await navigator.clipboard.writeText(text);
        copy.textContent = 'copied';
      } catch (e) {
        // file:// pages may not write the clipboard: select the text for Ctrl-C instead.
        const r = document.createRange();
        r.selectNodeContents($('#repro-cmd'));
        getSelection().removeAllRanges();
        getSelection().addRange(r);
        copy.textContent = 'selected: press Ctrl-C';
      }
    });
  HDRC.images = imgs;
  const tol = meta.tol || {};
  const m2020 = meta.to_rec2020 || [1, 0, 0, 0, 1, 0, 0, 0, 1];
  let ev = 0, heatKey = 'pq10', pinned = null;

  if (!$('#panels')) {
    ready();
    return;
  }
  const keys = $$('figure.panel').map((f) => f.dataset.key);
  // The case's pictures: one PNG, the panels' background image (a data: URL in the page's
  // #case-sprite style), each picture at meta.sprite.panels[key] = [x, y, w, h] in it
  // (report/html_report.cpp case_images). Loaded once; a picture is drawn from it onto a canvas.
  // null if it does not load (the panels then stay empty).
  const spriteUrl = $('#images .sprite') && /^url\("?(.*?)"?\)$/.exec(getComputedStyle($('#images .sprite')).backgroundImage);
  const sprite = meta.sprite && spriteUrl ? await new Promise((resolve) => {
    const i = new Image();
    i.onload = () => resolve(i);
    i.onerror = () => resolve(null);
    i.src = spriteUrl[1];
  }) : null;
  HDRC.spriteUrl = spriteUrl && spriteUrl[1];
  const labels = { input: 'input', reference: 'reference', candidate: 'candidate', heat: 'error heatmap', mask: 'over tolerance', diff: 'difference (heatmap)' };

  // Rendering of the float images (cached per display mode and exposure). Each pixel's nits are
  // converted from the output gamut to the display's (meta.to_display: sRGB primaries; the input,
  // in the working colour space, as it is), scaled by 2^EV, then mapped by the display mode:
  //   clip        sRGB(clamp(nits / 100 · 2^EV, 0, 1)) per channel (the PNGs' mapping)
  //   tonemap     sRGB(x / (1 + x)) per channel, x = nits / 100 · 2^EV (Reinhard: nothing clips)
  //   falsecolour VisualizeHDR's Colorize(histogram position of log2(max(mean RGB / 100 · 2^EV,
  //               LuminanceMin))), default eye adaptation (meta.false_colour)
  //   pq          the PQ signal of each channel (ST 2084 of the Rec.2020 nits), shown as grey codes
  //   hdr         (HDR displays) a 16-bit PQ / BT.2020 PNG (cICP) the browser shows in true HDR
  const toDisplay = meta.to_display || [1, 0, 0, 0, 1, 0, 0, 0, 1];
  const fc = meta.false_colour || { scale: 1 / 30, bias: 0.5, luminance_min: 1e-4 };
  const cache = new Map();
  function displayMode() {
    return $('#display-mode') ? $('#display-mode').value : 'clip';
  }
  function previewData(key, atEv = ev, atMode = undefined) {
    const mode = atMode || (displayMode() === 'hdr' ? 'clip' : displayMode());
    const ck = key + '@' + atEv + '@' + mode;
    if (cache.has(ck)) return cache.get(ck);
    const im = imgs[key];
    const data = new ImageData(w, h);
    const k = Math.pow(2, atEv) / 100;
    const m = key === 'input' ? [1, 0, 0, 0, 1, 0, 0, 0, 1] : toDisplay;
    const m2 = key === 'input' ? [1, 0, 0, 0, 1, 0, 0, 0, 1] : m2020;
    for (let i = 0; i < w * h; i++) {
      let nan = false, inf = false;
      for (let c = 0; c < 3; c++) {
        const v = im.value(i, c);
        nan = nan || Number.isNaN(v);
        inf = inf || (!Number.isFinite(v) && !Number.isNaN(v));
      }
      const o = i * 4;
      data.data[o + 3] = 255;
      if (nan || inf) {
        data.data[o] = nan ? 255 : 0;
        data.data[o + 1] = nan ? 0 : 255;
        data.data[o + 2] = 255;
        continue;
      }
      const n = [im.nits(i, 0), im.nits(i, 1), im.nits(i, 2)];
      if (mode === 'pq') {
        const n2020 = mul3(m2, n);
        for (let c = 0; c < 3; c++) data.data[o + c] = Math.round(pqSignal(n2020[c]) * 255);
        continue;
      }
      const d = mul3(m, n);
      if (mode === 'falsecolour') {
        const lum = Math.max(((d[0] + d[1] + d[2]) / 3) * k, fc.luminance_min);
        const rgb = colorize(Math.log2(lum) * fc.scale + fc.bias);
        for (let c = 0; c < 3; c++) data.data[o + c] = rgb[c];
        continue;
      }
      for (let c = 0; c < 3; c++) {
        const x = d[c] * k;
        data.data[o + c] = Math.round(srgbOetf(mode === 'tonemap' ? (x > 0 ? x / (1 + x) : 0) : x) * 255);
      }
    }
    cache.set(ck, data);
    return data;
  }
  // The HDR path: a 16-bit RGB PNG of the BT.2020 PQ signal with a cICP chunk (primaries 9
  // BT.2020, transfer 16 PQ, matrix 0, full range), which Chromium shows in HDR on an HDR display.
  const hdrCache = new Map();
  async function hdrUrl(key) {
    const ck = key + '@' + ev;
    if (hdrCache.has(ck)) return hdrCache.get(ck);
    const im = imgs[key];
    const k = Math.pow(2, ev);
    const raw = new Uint8Array(h * (1 + w * 6));
    const m2 = key === 'input' ? [0.6274, 0.3293, 0.0433, 0.0691, 0.9195, 0.0114, 0.0164, 0.0880, 0.8956] : m2020;
    for (let y = 0; y < h; y++) {
      raw[y * (1 + w * 6)] = 0; // filter: none
      for (let x = 0; x < w; x++) {
        const i = y * w + x;
        const n = mul3(m2, [im.nits(i, 0), im.nits(i, 1), im.nits(i, 2)]);
        for (let c = 0; c < 3; c++) {
          const v = Number.isFinite(n[c]) ? Math.round(pqSignal(n[c] * k) * 65535) : 0;
          const o = y * (1 + w * 6) + 1 + x * 6 + c * 2;
          raw[o] = v >> 8;
          raw[o + 1] = v & 255;
        }
      }
    }
    const z = new Uint8Array(await new Response(new Blob([raw]).stream().pipeThrough(new CompressionStream('deflate'))).arrayBuffer());
    const ihdr = new Uint8Array(13);
    new DataView(ihdr.buffer).setUint32(0, w);
    new DataView(ihdr.buffer).setUint32(4, h);
    ihdr.set([16, 2, 0, 0, 0], 8); // 16-bit, RGB
    const png = new Blob([new Uint8Array([137, 80, 78, 71, 13, 10, 26, 10]), pngChunk('IHDR', ihdr),
      pngChunk('cICP', new Uint8Array([9, 16, 0, 1])), pngChunk('IDAT', z), pngChunk('IEND', new Uint8Array(0))],
    { type: 'image/png' });
    const url = URL.createObjectURL(png);
    hdrCache.set(ck, url);
    return url;
  }
  // The error heatmap of the chosen metric (report/images.cpp error_maps: Colorize of log10 of
  // the pixel's error; black exact, white a non-finite mismatch).
  const heatCache = new Map();
  function heatData() {
    if (heatCache.has(heatKey)) return heatCache.get(heatKey);
    const d = new ImageData(w, h);
    const e = errorPass(heatKey === 'itp')[heatKey];
    for (let i = 0; i < w * h; i++) {
      const [r, g, b] = heatColour(e[i], HEAT[heatKey]);
      d.data.set([r, g, b, 255], i * 4);
    }
    heatCache.set(heatKey, d);
    return d;
  }
  // The over-tolerance mask and its counts, as report/images.cpp error_maps: a pixel pairing a
  // non-finite value inconsistently (alpha too) is a mismatch (magenta); one with a colour value
  // over the max of a judged metric (linear_abs, linear_rel, pq_code10, pq_code12; ΔE_ITP per
  // pixel) is over (red); the rest show the reference's 0 EV preview as dim grey. A metric with
  // no max in the tolerance is not judged; a NaN error is over (!(v <= max)).
  // One pass over the pixels gives every per-pixel error the page shows (the heatmaps, the mask
  // and its counts, the LUT's worst lattice point, the ΔE_ITP histogram), each pixel's PQ signals
  // and ICtCp computed once (a LUT-64³ page computed them four times over: 4.1–4.4 s to
  // interactive, issue 27). Per pixel, as report/images.cpp error_maps:
  //   pq10  the largest |PQ(nits(cand)) − PQ(nits(ref))| · 1023 of its colour channels; NaN for a
  //         non-finite mismatch (drawn white)
  //   itp   ΔE_ITP of the BT.2020 colours; 0 when a colour channel is non-finite on both sides
  //         consistently, NaN for a mismatch
  //   flag  the mask: 2 a non-finite value paired inconsistently (alpha too; magenta), 1 a colour
  //         value over the max of a judged metric (linear_abs, linear_rel, pq_code10, pq_code12;
  //         ΔE_ITP per pixel; red), 0 within tolerance. A metric with no max is not judged; a NaN
  //         error is over (!(v <= max)).
  //   hist  1 where all six nits are finite: the pixels the ΔE_ITP histogram counts
  // ΔE_ITP (two ICtCp conversions, twelve pow a pixel) is computed in this pass only when the
  // tolerance judges it (the mask needs it); else on first use (errorPass(true): the ΔE_ITP
  // heatmap, the histogram), so a page whose case does not judge it (every LUT case) does not
  // pay for it before it is interactive.
  let errorCache = null;
  const LAZY_PIXELS = 1 << 16; // larger images draw their ΔE_ITP histogram when it is shown
  function errorPass(wantItp) {
    if (errorCache && (errorCache.itp || !wantItp)) return errorCache;
    const r = imgs.reference, c = imgs.candidate, n = w * h;
    const pq10 = new Float64Array(n), itp = new Float64Array(n);
    const flag = new Uint8Array(n), hist = new Uint8Array(n);
    const max = (k) => (typeof tol[k] === 'number' ? tol[k] : Infinity);
    const mAbs = max('linear_abs'), mRel = max('linear_rel'), m10 = max('pq_code10'), m12 = max('pq_code12'), mItp = max('delta_e_itp');
    const floor = tol.rel_floor || 0;
    const withItp = !!wantItp || mItp < Infinity;
    const rn = [0, 0, 0], cn = [0, 0, 0];
    for (let i = 0; i < n; i++) {
      let mis = false, ov = false, finite = true, worst = 0;
      for (let ch = 0; ch < 4; ch++) {
        const rv = r.value(i, ch), cv = c.value(i, ch);
        const rf = Number.isFinite(rv), cf = Number.isFinite(cv);
        if (!rf || !cf) {
          mis = mis || !(!rf && !cf && ((Number.isNaN(rv) && Number.isNaN(cv)) || rv === cv));
          if (ch < 3) finite = false;
          continue;
        }
        if (ch === 3) continue;
        rn[ch] = r.nits(i, ch);
        cn[ch] = c.nits(i, ch);
        const abs = Math.abs(cv - rv);
        const rel = abs === 0 ? 0 : abs / Math.max(Math.abs(rv), floor);
        const dq = Object.is(rv, cv) ? 0 : Math.abs(pqSignal(cn[ch]) - pqSignal(rn[ch]));
        worst = Math.max(worst, dq * 1023);
        ov = ov || !(abs <= mAbs) || !(rel <= mRel) || !(dq * 1023 <= m10) || !(dq * 4095 <= m12);
      }
      let e = 0;
      if (finite && withItp) {
        const same = Object.is(r.value(i, 0), c.value(i, 0)) && Object.is(r.value(i, 1), c.value(i, 1)) && Object.is(r.value(i, 2), c.value(i, 2));
        e = same ? 0 : deltaEItp(ictcp(mul3(m2020, cn)), ictcp(mul3(m2020, rn)));
        ov = ov || !(e <= mItp);
      }
      pq10[i] = mis ? NaN : worst;
      itp[i] = mis ? NaN : e;
      flag[i] = mis ? 2 : ov ? 1 : 0;
      hist[i] = finite && Number.isFinite(rn[0] + rn[1] + rn[2] + cn[0] + cn[1] + cn[2]) ? 1 : 0;
    }
    errorCache = { pq10, itp: withItp ? itp : null, flag, hist };
    return errorCache;
  }
  // The over-tolerance mask and its counts (errorPass flag); within tolerance, the reference's
  // 0 EV preview as dim grey.
  let maskCache = null;
  function maskData() {
    if (maskCache) return maskCache;
    const refPrev = previewData('reference', 0, 'clip').data;
    const { flag } = errorPass();
    const d = new ImageData(w, h);
    let over = 0, mismatch = 0;
    for (let i = 0; i < w * h; i++) {
      const o = i * 4;
      d.data[o + 3] = 255;
      if (flag[i] === 2) {
        d.data.set([255, 0, 255], o);
        mismatch++;
      } else if (flag[i] === 1) {
        d.data.set([255, 0, 0], o);
        over++;
      } else {
        const g = Math.floor((refPrev[o] * 3 + refPrev[o + 1] * 6 + refPrev[o + 2]) / 40);
        d.data.set([g, g, g], o);
      }
    }
    maskCache = { data: d, over, mismatch };
    return maskCache;
  }
  if (imgs.reference && imgs.candidate && $('#mask-over')) {
    const m = maskData();
    $('#mask-over').textContent = String(m.over);
    $('#mask-mismatch').textContent = String(m.mismatch);
  }
  const floatKeys = new Set(['input', 'reference', 'candidate'].filter((k) => imgs[k]));

  // One displayable element for `key`: a canvas drawn from the float data (previews), or the
  // PNG (heatmaps, mask, and previews when there is no float data).
  function makeView(key) {
    let e;
    if (floatKeys.has(key) && displayMode() === 'hdr') {
      e = el('img', { alt: labels[key] + ' (HDR)', 'data-key': key, class: 'hdr' });
      hdrUrl(key).then((u) => {
        e.src = u;
      });
    } else if (floatKeys.has(key)) {
      e = el('canvas', { width: w, height: h, 'data-key': key });
      e.getContext('2d').putImageData(previewData(key), 0, 0);
    } else if (key === 'diff' || ((key === 'heat' || key === 'mask') && imgs.reference && imgs.candidate)) {
      // The heatmap of the chosen metric (also the 'diff' view), or the mask, from the float data.
      e = el('canvas', { width: w, height: h, 'data-key': key });
      if (imgs.reference && imgs.candidate) e.getContext('2d').putImageData(key === 'mask' ? maskData().data : heatData(), 0, 0);
    } else {
      // A picture of the case's PNG: the heatmap of the chosen metric, the mask, or a preview
      // when there is no float data.
      const r = meta.sprite && meta.sprite.panels[key === 'heat' ? HEAT[heatKey].panel : key];
      e = el('canvas', { width: r ? r[2] : w, height: r ? r[3] : h, 'data-key': key, 'aria-label': labels[key], role: 'img' });
      if (r && sprite) e.getContext('2d').drawImage(sprite, r[0], r[1], r[2], r[3], 0, 0, r[2], r[3]);
    }
    sizeView(e);
    attachProbe(e);
    return e;
  }
  function scales() {
    const z = Number($('#zoom').value);
    const mode = $('#view-mode').value;
    let sx;
    if (z > 0) sx = z;
    else {
      const avail = mode === 'side' ? Math.max(240, Math.min(560, (document.body.clientWidth - 80) / Math.min(keys.length, 3))) :
        Math.max(320, Math.min(1100, document.body.clientWidth - 80));
      sx = Math.min(avail / w, 16);
      if (sx >= 1) sx = Math.floor(sx);
    }
    // Very flat images (ramps 8 pixels high) are stretched to at least 48 pixels in height.
    const sy = h * sx < 48 ? 48 / h : sx;
    return [sx, sy];
  }
  function sizeView(e) {
    const [sx, sy] = scales();
    e.style.width = w * sx + 'px';
    e.style.height = h * sy + 'px';
  }
  function redrawPanels() {
    for (const f of $$('figure.panel')) {
      const key = f.dataset.key;
      const frame = $('.frame', f);
      frame.replaceChildren(makeView(key));
    }
  }

  // Views: side by side, A/B flip, slider.
  const selA = $('#view-a'), selB = $('#view-b');
  for (const k of keys) {
    selA.append(el('option', { value: k, text: labels[k] }));
    selB.append(el('option', { value: k, text: labels[k] }));
  }
  selA.value = keys.includes('reference') ? 'reference' : keys[0];
  selB.value = keys.includes('candidate') ? 'candidate' : keys[keys.length - 1];
  let flipShowsB = false;
  function renderCompare() {
    const mode = $('#view-mode').value;
    const cmp = $('#compare');
    $('#panels').hidden = mode !== 'side';
    cmp.hidden = mode === 'side';
    if (mode === 'side') return;
    const a = selA.value, b = selB.value;
    if (mode === 'diff') {
      cmp.replaceChildren(el('p', { class: 'caption', id: 'diff-label' }, 'difference of A and B: per pixel the heatmap of ' + HEAT[heatKey].unit),
        el('div', { class: 'frame', id: 'diff-frame' }, makeView('diff')));
      centreOnWorst(cmp);
      return;
    }
    if (mode === 'flip') {
      const key = flipShowsB ? b : a;
      const v = makeView(key);
      const frame = el('div', { class: 'frame', id: 'flip-frame' }, v);
      frame.addEventListener('click', () => {
        if (pinned) return;
        flipShowsB = !flipShowsB;
        renderCompare();
      });
      queueMicrotask(() => centreOnWorst(cmp));
      cmp.replaceChildren(el('p', { class: 'caption', id: 'flip-label' },
        'showing ', el('b', { text: (flipShowsB ? 'B: ' : 'A: ') + labels[key] }),
        ' — click the image, press F or ', el('button', { type: 'button', id: 'flip-button', onclick: () => {
          flipShowsB = !flipShowsB;
          renderCompare();
        } }, 'flip')), frame);
    } else {
      const base = makeView(a), top = makeView(b);
      base.classList.add('layer', 'base');
      top.classList.add('layer');
      const pos = Number(cmp.dataset.split || 50);
      top.style.clipPath = `inset(0 0 0 ${pos}%)`;
      const split = el('div', { class: 'split' });
      split.style.left = pos + '%';
      const stack = el('div', { class: 'stack frame', id: 'slider-stack' }, base, top, split);
      const range = el('input', { type: 'range', id: 'split', min: 0, max: 100, step: 0.5, value: pos });
      const set = (p) => {
        cmp.dataset.split = p;
        top.style.clipPath = `inset(0 0 0 ${p}%)`;
        split.style.left = p + '%';
        range.value = p;
      };
      range.addEventListener('input', () => set(Number(range.value)));
      stack.addEventListener('mousemove', (e) => {
        if (e.buttons & 1) set((100 * e.offsetX) / stack.clientWidth);
      });
      cmp.replaceChildren(el('p', { class: 'caption' }, 'left: A (' + labels[a] + '), right: B (' + labels[b] + ') — drag, or ', range), stack);
      centreOnWorst(cmp);
    }
  }
  // Zoomed in, the compare frame scrolls so that the worst pixel (results.json) is at its centre.
  function centreOnWorst(cmp) {
    const z = Number($('#zoom').value);
    cmp.classList.toggle('zoomed', z > 0);
    if (!(z > 0) || !meta.worst) return;
    const [sx, sy] = scales();
    cmp.scrollLeft = Math.max(0, (meta.worst.x + 0.5) * sx - cmp.clientWidth / 2);
    cmp.scrollTop = Math.max(0, (meta.worst.y + 0.5) * sy - cmp.clientHeight / 2);
    cmp.dataset.centre = meta.worst.x + ',' + meta.worst.y;
  }
  document.addEventListener('keydown', (e) => {
    if ((e.key === 'f' || e.key === 'F') && $('#view-mode').value === 'flip' && !/INPUT|SELECT/.test(e.target.tagName)) {
      flipShowsB = !flipShowsB;
      renderCompare();
    }
  });
  for (const s of [$('#view-mode'), selA, selB]) s.addEventListener('change', () => {
    flipShowsB = false;
    renderCompare();
  });
  $('#zoom').addEventListener('change', () => {
    redrawPanels();
    renderCompare();
    renderLut();
  });
  const expo = $('#exposure');
  const setEv = (v) => {
    ev = v;
    expo.value = v;
    $('#exposure-value').textContent = (v > 0 ? '+' : '') + v + ' EV';
    redrawPanels();
    renderCompare();
  };
  expo.addEventListener('input', () => setEv(Number(expo.value)));
  $('#exposure-reset').addEventListener('click', () => setEv(0));
  // HDR display: the browser says so (or #hdr=1 forces the path, for tests); else SDR views only.
  const hdrOk = matchMedia('(dynamic-range: high)').matches || parseHash().hdr === '1';
  const hdrOpt = $('#display-mode option[value="hdr"]');
  if (hdrOpt) {
    hdrOpt.disabled = !hdrOk || !floatKeys.size;
    $('#hdr-status').textContent = hdrOk ? 'HDR display found: "HDR (PQ)" shows the true HDR image' :
      'SDR display (matchMedia dynamic-range: high is false): the SDR views are shown';
    if (hdrOk && floatKeys.size && parseHash().hdr === '1') $('#display-mode').value = 'hdr';
  }
  if ($('#display-mode'))
    $('#display-mode').addEventListener('change', () => {
      redrawPanels();
      renderCompare();
      renderLut();
    });
  if (!floatKeys.size) {
    expo.disabled = true;
    $('#exposure-value').textContent = 'needs the float data';
  }

  // Heatmap legend.
  function drawLegend() {
    const bar = $('#legend-bar');
    if (!bar) return;
    const s = HEAT[heatKey];
    const ctx = bar.getContext('2d');
    for (let x = 0; x < bar.width; x++) {
      const [r, g, b] = colorize(x / (bar.width - 1));
      ctx.fillStyle = `rgb(${r},${g},${b})`;
      ctx.fillRect(x, 0, 1, bar.height);
    }
    const ticks = $('#legend-ticks');
    ticks.replaceChildren();
    for (let e = s.min; e <= s.max; e++)
      ticks.append(el('span', { style: `left:${((e - s.min) / (s.max - s.min)) * 100}%`, text: fmt(Math.pow(10, e)) }));
    const t = tol[s.tol];
    if (t > 0) {
      const x = Math.min(1, Math.max(0, (Math.log10(t) - s.min) / (s.max - s.min)));
      ticks.append(el('span', { class: 'tol', id: 'legend-tol', style: `left:${x * 100}%`, text: '▲ tolerance ' + fmt(t) }));
    }
    $('#legend-unit').textContent = s.unit;
  }
  $('#heat-metric').addEventListener('change', () => {
    heatKey = $('#heat-metric').value;
    drawLegend();
    redrawPanels();
    renderCompare();
    renderLut();
  });

  // Pixel probe.
  const probe = $('#probe'), probeTable = $('#probe-table');
  function probeAt(x, y) {
    if (!floatKeys.size || x < 0 || y < 0 || x >= w || y >= h) return;
    const i = y * w + x;
    const tb = $('tbody', probeTable);
    tb.replaceChildren();
    $('#probe-xy').textContent = 'x ' + x + ', y ' + y;
    probe.dataset.x = x;
    probe.dataset.y = y;
    for (const k of ['input', 'reference', 'candidate']) {
      if (!imgs[k]) continue;
      const tr = el('tr', { 'data-row': k }, el('th', { text: k }));
      for (let c = 0; c < 4; c++) tr.append(el('td', { text: f32(imgs[k].value(i, c)) }));
      tb.append(tr);
    }
    const r = imgs.reference, c = imgs.candidate;
    if (r && c) {
      const rows = { abs: [], rel: [], pq10: [] };
      for (let ch = 0; ch < 3; ch++) {
        const rv = r.value(i, ch), cv = c.value(i, ch);
        if (!Number.isFinite(rv) || !Number.isFinite(cv)) {
          const ok = (Number.isNaN(rv) && Number.isNaN(cv)) || rv === cv;
          for (const k in rows) rows[k].push(ok ? 'consistent' : 'MISMATCH');
          continue;
        }
        const abs = Math.abs(cv - rv);
        rows.abs.push(fmt(abs, 6));
        rows.rel.push(fmt(abs === 0 ? 0 : abs / Math.max(Math.abs(rv), tol.rel_floor || 0), 6));
        rows.pq10.push(fmt(Math.abs(pqSignal(c.nits(i, ch)) - pqSignal(r.nits(i, ch))) * 1023, 6));
      }
      const names = { abs: '|cand − ref|', rel: 'relative', pq10: 'PQ 10-bit codes' };
      for (const k of ['abs', 'rel', 'pq10']) {
        const tr = el('tr', { class: 'err', 'data-row': k }, el('th', { text: names[k] }));
        for (const v of rows[k]) tr.append(el('td', { text: v }));
        tr.append(el('td', { text: '' }));
        tb.append(tr);
      }
      const rn = [0, 1, 2].map((ch) => (Number.isFinite(r.value(i, ch)) ? r.nits(i, ch) : NaN));
      const cn = [0, 1, 2].map((ch) => (Number.isFinite(c.value(i, ch)) ? c.nits(i, ch) : NaN));
      const itp = rn.concat(cn).some(Number.isNaN) ? NaN : deltaEItp(ictcp(mul3(m2020, cn)), ictcp(mul3(m2020, rn)));
      tb.append(el('tr', { class: 'err', 'data-row': 'itp' }, el('th', { text: 'ΔE_ITP (pixel)' }),
        el('td', { text: fmt(itp, 6) }), el('td'), el('td'), el('td')));
      tb.append(el('tr', { 'data-row': 'nits' }, el('th', { text: 'reference nits' }),
        ...rn.map((v) => el('td', { text: fmt(v, 6) })), el('td')));
      tb.append(el('tr', { 'data-row': 'cand-nits' }, el('th', { text: 'candidate nits' }),
        ...cn.map((v) => el('td', { text: fmt(v, 6) })), el('td')));
      // PQ code values (10-bit, of the Rec.2020 nits), the full RGB triplet of each side.
      const pq10 = (n) => mul3(m2020, n).map((v) => (Number.isFinite(v) ? fmt(pqSignal(v) * 1023, 6) : 'NaN'));
      tb.append(el('tr', { 'data-row': 'ref-pq' }, el('th', { text: 'reference PQ (10-bit codes)' }),
        ...pq10(rn).map((v) => el('td', { text: v })), el('td')));
      tb.append(el('tr', { 'data-row': 'cand-pq' }, el('th', { text: 'candidate PQ (10-bit codes)' }),
        ...pq10(cn).map((v) => el('td', { text: v })), el('td')));
    }
    probeTable.hidden = false;
    $('#probe-hint').hidden = true;
  }
  HDRC.probeAt = probeAt;
  function attachProbe(e) {
    const pos = (ev2) => {
      const r = e.getBoundingClientRect();
      return [Math.floor(((ev2.clientX - r.left) / r.width) * w), Math.floor(((ev2.clientY - r.top) / r.height) * h)];
    };
    e.addEventListener('mousemove', (ev2) => {
      if (!pinned) probeAt(...pos(ev2));
    });
    e.addEventListener('click', (ev2) => {
      if ($('#view-mode').value === 'flip' && !pinned) return; // a click flips there
      const p = pos(ev2);
      pinned = pinned && pinned[0] === p[0] && pinned[1] === p[1] ? null : p;
      probe.classList.toggle('pinned', !!pinned);
      probeAt(...p);
    });
  }
  for (const b of $$('#worst-pixel button.goto')) {
    const tr = b.closest('tr');
    const x = Number(tr.dataset.x), y = Number(tr.dataset.y);
    if (!floatKeys.size || !Number.isInteger(x) || !Number.isInteger(y)) b.disabled = true;
    b.addEventListener('click', () => {
      pinned = [x, y];
      probe.classList.add('pinned');
      probeAt(x, y);
      probe.scrollIntoView({ block: 'nearest' });
    });
  }

  // LUT slices (CombineLUTs: the N² × N image holds blue slice b at x ∈ [bN, bN + N)).
  function renderLut() {
    const n = meta.lut_size;
    if (!n || !$('#lut')) return;
    const b = Number($('#lut-slice').value);
    $('#lut-slice-value').textContent = b + ' (blue = ' + fmt(b / (n - 1), 4) + ')';
    const scale = Math.max(4, Math.floor(256 / n)) * (Number($('#zoom').value) > 2 ? 2 : 1);
    const panels = [];
    const mk = (label, fill) => {
      const cv = el('canvas', { width: n, height: n });
      cv.style.width = cv.style.height = n * scale + 'px';
      const d = new ImageData(n, n);
      for (let g = 0; g < n; g++)
        for (let r = 0; r < n; r++) {
          const [R, G, B] = fill(b * n + r + g * w);
          const o = (g * n + r) * 4;
          d.data[o] = R;
          d.data[o + 1] = G;
          d.data[o + 2] = B;
          d.data[o + 3] = 255;
        }
      cv.getContext('2d').putImageData(d, 0, 0);
      cv.addEventListener('mousemove', (e) => {
        const rr = Math.floor((e.offsetX / cv.clientWidth) * n), gg = Math.floor((e.offsetY / cv.clientHeight) * n);
        lutProbe(rr, gg, b);
      });
      panels.push(el('figure', { class: 'panel' }, el('figcaption', { text: label }), cv));
    };
    const prev = (key) => (i) => {
      const d = previewData(key).data;
      return [d[i * 4], d[i * 4 + 1], d[i * 4 + 2]];
    };
    if (imgs.reference) mk('reference, slice b = ' + b, prev('reference'));
    if (imgs.candidate) mk('candidate, slice b = ' + b, prev('candidate'));
    if (imgs.reference && imgs.candidate) mk('error per lattice point (' + HEAT[heatKey].unit + ')', (i) => heatColour(pixelError(i), HEAT[heatKey]));
    $('#lut-panels').replaceChildren(...panels);
  }
  // The heatmap's error of pixel i in the chosen metric (errorPass).
  function pixelError(i) {
    return errorPass(heatKey === 'itp')[heatKey][i];
  }
  function lutProbe(r, g, b) {
    const n = meta.lut_size;
    if (r < 0 || g < 0 || r >= n || g >= n) return;
    const i = b * n + r + g * w;
    const v = (k) => (imgs[k] ? [0, 1, 2].map((c) => f32(imgs[k].value(i, c))).join(', ') : '—');
    $('#lut-probe').textContent = `lattice (r ${r}, g ${g}, b ${b}) = image (${b * n + r}, ${g}): reference ${v('reference')}; candidate ${v('candidate')}` +
      (imgs.reference && imgs.candidate ? `; error ${fmt(pixelError(i), 4)} ${HEAT[heatKey].unit}` : '');
  }
  if (meta.lut_size && $('#lut')) {
    $('#lut-slice').addEventListener('input', renderLut);
    if (imgs.reference && imgs.candidate) {
      // The worst lattice point, to jump to its slice.
      const n = meta.lut_size;
      let best = -1, at = 0;
      for (let i = 0; i < w * h; i++) {
        const e = pixelError(i);
        if (Number.isNaN(e) || e > best) {
          best = Number.isNaN(e) ? Infinity : e;
          at = i;
        }
      }
      const x = at % w, y = Math.floor(at / w);
      const lb = Math.floor(x / n), lr = x % n;
      $('#lut-worst').replaceChildren(el('p', {}, 'Largest error: lattice (r ' + lr + ', g ' + y + ', b ' + lb + '), ' + fmt(best) + ' ' + HEAT[heatKey].unit + ' ',
        el('button', { type: 'button', id: 'lut-goto-worst', onclick: () => {
          $('#lut-slice').value = lb;
          renderLut();
          lutProbe(lr, y, lb);
        } }, 'show')));
    }
    if (!floatKeys.size) $('#lut').append(el('p', { class: 'muted', text: 'The LUT view needs the float data.' }));
  }

  // Plots (section #plots): the ramp's nits in vs out with the error beneath, the ΔE_ITP
  // histogram, the CIE xy chromaticities of colour stimuli.
  function renderPlots() {
    const box = $('#plots-body');
    if (!box) return;
    box.replaceChildren();
    const r = imgs.reference, c = imgs.candidate, inp = imgs.input;
    const input = String(meta.input || '');
    const lumOut = (im, i) => { const n = mul3(m2020, [im.nits(i, 0), im.nits(i, 1), im.nits(i, 2)]); return n[0] * LUMA2020[0] + n[1] * LUMA2020[1] + n[2] * LUMA2020[2]; };
    const lumIn = (i) => inp.nits(i, 0) * LUMA709[0] + inp.nits(i, 1) * LUMA709[1] + inp.nits(i, 2) * LUMA709[2];
    if (inp && r && /ramp|pq_codes|near_black|above_peak/.test(input)) {
      const row = Number($('#plot-row').value);
      const pts = [];
      for (let x = 0; x < w; x++) {
        const i = row * w + x;
        const xin = lumIn(i), yr = lumOut(r, i), yc = c ? lumOut(c, i) : NaN;
        if (xin > 0 && Number.isFinite(xin)) pts.push([xin, yr, yc, c ? pixelErrorPq(i) : NaN]);
      }
      const pos = pts.flatMap((p) => [p[1], p[2]]).filter((v) => v > 0 && Number.isFinite(v));
      if (pts.length > 1 && pos.length) {
        const xr = [Math.min(...pts.map((p) => p[0])), Math.max(...pts.map((p) => p[0]))];
        const yr = [Math.max(Math.min(...pos), 1e-6), Math.max(...pos)];
        const { g, X, Y } = plotFrame(760, 280, xr, yr, { xlog: true, ylog: true, id: 'ramp-plot', xlabel: 'input luminance (nits, row ' + row + ')', ylabel: 'output luminance (nits)' });
        const ok = (v) => v > 0 && Number.isFinite(v);
        g.append(polyline(pts.filter((p) => ok(p[1])).map((p) => [X(p[0]), Y(Math.max(p[1], yr[0]))]), 'ref'));
        if (c) g.append(polyline(pts.filter((p) => ok(p[2])).map((p) => [X(p[0]), Y(Math.max(p[2], yr[0]))]), 'cand'));
        g.append(svgEl('text', { x: 70, y: 20, fill: '#1f5fbf' }, '— reference'), svgEl('text', { x: 170, y: 20, fill: '#d9480f' }, '- - candidate'));
        box.append(el('figure', { class: 'plot' }, el('figcaption', { text: 'Nits in vs nits out along the ramp (BT.2020 luminance of the output, BT.709 of the input)' }), g));
        if (c) {
          const errs = pts.map((p) => p[3]).filter((v) => Number.isFinite(v));
          const emax = Math.max(...errs, tol.pq_code10 || 0, 1e-3);
          const { g: ge, X: Xe, Y: Ye } = plotFrame(760, 160, xr, [0, emax * 1.05], { xlog: true, ylog: false, id: 'ramp-error', xlabel: 'input luminance (nits)', ylabel: 'PQ error (10-bit codes)' });
          ge.append(polyline(pts.filter((p) => Number.isFinite(p[3])).map((p) => [Xe(p[0]), Ye(p[3])]), 'err'));
          if (tol.pq_code10 > 0) ge.append(svgEl('line', { class: 'tol', x1: Xe(xr[0]), x2: Xe(xr[1]), y1: Ye(tol.pq_code10), y2: Ye(tol.pq_code10) }));
          box.append(el('figure', { class: 'plot' }, el('figcaption', { text: 'Error beneath: the largest PQ error of the pixel\'s channels; dashed: the tolerance' }), ge));
        }
      }
    }
    // ΔE_ITP per pixel: exact 0 in the first bar, then log10 bins of 0.25 from 1e-4 to 100.
    const histogram = () => {
      const bins = new Array(26).fill(0);
      const { itp, hist } = errorPass(true);
      let n = 0;
      for (let i = 0; i < w * h; i++) {
        if (!hist[i]) continue;
        const e = itp[i];
        n++;
        if (!(e > 0)) bins[0]++;
        else bins[Math.min(25, Math.max(1, 1 + Math.floor((Math.log10(e) + 4) * 4)))]++;
      }
      const maxc = Math.max(...bins, 1);
      const { g, X, Y } = plotFrame(760, 200, [0, 26], [0, maxc], { xlog: false, ylog: false, id: 'itp-histogram', xlabel: 'ΔE_ITP (bar 0: exact; then 4 bars per decade from 1e-4)', ylabel: 'pixels' });
      const t = tol.delta_e_itp;
      bins.forEach((cnt, b) => {
        const lo = b === 0 ? 0 : Math.pow(10, (b - 1) / 4 - 4);
        g.append(svgEl('rect', { class: 'bar' + (t > 0 && lo >= t ? ' over' : ''), x: X(b) + 1, y: Y(cnt), width: Math.max(1, X(b + 1) - X(b) - 2), height: Y(0) - Y(cnt), 'data-count': cnt },
          svgEl('title', {}, (b === 0 ? 'exact' : '≥ ' + fmt(lo, 3)) + ': ' + cnt + ' pixels')));
      });
      return el('figure', { class: 'plot' }, el('figcaption', { text: 'ΔE_ITP histogram (' + n + ' finite pixels' + (t > 0 ? '; red: at or over the tolerance ' + fmt(t) : '') + ')' }), g);
    };
    if (r && c) {
      if (w * h <= LAZY_PIXELS || (errorCache && errorCache.itp)) box.append(histogram());
      else {
        // A large image whose ΔE_ITP is not computed yet: drawn when the plot scrolls into view.
        const slot = el('figure', { class: 'plot', id: 'itp-histogram-slot' }, el('figcaption', { text: 'ΔE_ITP histogram: drawn when shown' }));
        box.append(slot);
        const seen = new IntersectionObserver((es) => {
          if (!es.some((e) => e.isIntersecting)) return;
          seen.disconnect();
          if (slot.isConnected) slot.replaceWith(histogram());
        }, { rootMargin: '200px' });
        seen.observe(slot);
      }
    }
    if (r && /hue_sweep|colorchecker|primaries/.test(input)) {
      const { g, X, Y } = plotFrame(420, 420, [0, 0.8], [0, 0.9], { xlog: false, ylog: false, id: 'xy-plot', xlabel: 'CIE x', ylabel: 'CIE y' });
      g.append(svgEl('polygon', { points: LOCUS.map(([x, y]) => X(x) + ',' + Y(y)).join(' '), fill: 'none', stroke: '#333' }));
      GAMUTS.forEach(([name, p, col], gi) => {
        g.append(svgEl('polygon', { points: p.map(([x, y]) => X(x) + ',' + Y(y)).join(' '), fill: 'none', stroke: col, 'data-gamut': name }));
        g.append(svgEl('text', { x: 300, y: 20 + gi * 14, fill: col }, name));
      });
      const seen = new Set();
      const dot = (im, i, cls) => {
        const n = mul3(REC2020_TO_XYZ, mul3(m2020, [im.nits(i, 0), im.nits(i, 1), im.nits(i, 2)]));
        const sum = n[0] + n[1] + n[2];
        if (!(sum > 0) || !Number.isFinite(sum)) return;
        const x = n[0] / sum, y = n[1] / sum;
        const k = cls + Math.round(x * 2000) + ',' + Math.round(y * 2000);
        if (seen.has(k) || seen.size > 3000) return;
        seen.add(k);
        g.append(cls === 'r' ? svgEl('circle', { cx: X(x), cy: Y(y), r: 2.5, fill: 'none', stroke: '#1f5fbf' }) :
          svgEl('path', { d: `M${X(x) - 2},${Y(y) - 2}l4,4m0,-4l-4,4`, stroke: '#d9480f' }));
      };
      for (let i = 0; i < w * h; i++) {
        dot(r, i, 'r');
        if (c) dot(c, i, 'c');
      }
      box.append(el('figure', { class: 'plot' }, el('figcaption', { text: 'CIE 1931 xy of the output (○ reference, × candidate) with the spectral locus and gamut triangles' }), g));
    }
    if (!box.children.length) box.append(el('p', { class: 'muted', text: 'No plot applies to this case (ramps, colour stimuli, or a reference and a candidate).' }));
  }
  function pixelErrorPq(i) {
    const r = imgs.reference, c = imgs.candidate;
    let worst = 0;
    for (let ch = 0; ch < 3; ch++) {
      const rv = r.nits(i, ch), cv = c.nits(i, ch);
      if (!Number.isFinite(rv) || !Number.isFinite(cv)) return NaN;
      worst = Math.max(worst, Math.abs(pqSignal(cv) - pqSignal(rv)) * 1023);
    }
    return worst;
  }
  if ($('#plot-row')) {
    const sel = $('#plot-row');
    for (let y = 0; y < h; y++) sel.append(el('option', { value: y, text: 'row ' + y }));
    sel.value = meta.worst ? meta.worst.y : 0;
    sel.addEventListener('change', renderPlots);
  }

  redrawPanels();
  renderCompare();
  drawLegend();
  renderLut();
  renderPlots();
  ready();
}

document.addEventListener('DOMContentLoaded', async () => {
  const page = document.body.dataset.page;
  try {
    if (page === 'summary') initSummary();
    else if (page === 'cases') initCases();
    else if (page === 'matrix') initMatrix();
    else if (page === 'case') await initCase();
  } catch (e) {
    document.documentElement.dataset.error = String(e && e.stack ? e.stack : e);
    document.body.prepend(el('pre', { class: 'warning', text: 'report script error: ' + e }));
    throw e;
  }
});
