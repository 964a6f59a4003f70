// hdrconform report: the script of every page (summary, matrix, case list, case pages).
// Static and offline: data arrives through <script> files written beside the pages (data.js,
// c/<case>/px.js), because file:// pages may not fetch. Text from the results is only ever set
// through textContent or attribute values, never parsed as HTML.
//
// The SDR preview mapping and the error metrics mirror report/images.cpp and runner/diff.cpp:
//   display = sRGB_OETF(clamp(nits / 100 · 2^EV, 0, 1)); NaN pixel magenta, infinite pixel cyan
//   pq10 = |PQ(nits(cand)) − PQ(nits(ref))| · 1023 (nits clamped to [0, 10000], NaN → 0)
//   ΔE_ITP (ITU-R BT.2124) of the BT.2020 colours, ICtCp per BT.2100.
'use strict';

const HDRC = (window.HDRC = window.HDRC || {});

HDRC.data = (d) => {
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
  pq10: { min: -4, max: 1, unit: 'PQ 10-bit code values', tol: 'pq_code10', png: 'heat.png' },
  itp: { min: -3, max: 2, unit: 'ΔE_ITP', tol: 'delta_e_itp', png: 'heat_itp.png' },
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
// SMPTE ST 2084 inverse EOTF (reference/color/st2084.h: pq_from_nits), constants in the
// standard's fractional form.
const PQ_M1 = 2610 / 16384, PQ_M2 = (2523 / 4096) * 128;
const PQ_C1 = 3424 / 4096, PQ_C2 = (2413 / 4096) * 32, PQ_C3 = (2392 / 4096) * 32;
function pqFromNits(n) {
  const lm = Math.pow(n / 10000, PQ_M1);
  return Math.pow((PQ_C1 + PQ_C2 * lm) / (1 + PQ_C3 * lm), PQ_M2);
}
function pqSignal(n) {
  return pqFromNits(n > 0 ? Math.min(n, 10000) : 0);
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

// Float data of one image: values (3 or 4 channels) and nits (3 channels, or values · scale).
function decodeF32(b64) {
  const bin = atob(b64);
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
  const dv = new DataView(bytes.buffer);
  const out = new Float32Array(bytes.length / 4);
  for (let i = 0; i < out.length; i++) out[i] = dv.getFloat32(i * 4, true);
  return out;
}
class FloatImage {
  constructor(w, h, d) {
    this.w = w;
    this.h = h;
    this.ch = d.ch;
    this.alpha = d.alpha;
    this.v = decodeF32(d.v);
    this.nitsArr = d.nits ? decodeF32(d.nits) : null;
    this.scale = d.scale;
  }
  value(i, c) {
    if (c === 3 && this.ch === 3) return this.alpha;
    return this.v[i * this.ch + c];
  }
  nits(i, c) {
    return this.nitsArr ? this.nitsArr[i * 3 + c] : this.v[i * this.ch + c] * this.scale;
  }
}

// ---------------------------------------------------------------------------------------------
// Summary page: static; only marks itself ready.

function initSummary() {
  ready();
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
    if (name) for (const v of uniq((c) => cvarValue(c, name))) s.append(el('option', { value: v, text: v }));
  };
  const h = parseHash();
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
    const stage = $('#f-stage').value, verdict = $('#f-verdict').value;
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
      const ok = c && (!stage || c.stage === stage) && okVerdict &&
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
    setHash({ stage, verdict, text, metric, sort: sortKey, dir: sortDir < 0 ? 'desc' : '',
      cv: cons.map(([k, v]) => k + ':' + v) });
  };
  $('#f-cvar').addEventListener('change', () => {
    extra.length = 0;
    fillCvarValues();
    apply();
  });
  for (const id of ['#f-stage', '#f-verdict', '#f-cvar-value', '#f-metric'])
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
  const metricNames = Array.from(new Set(all.flatMap((c) => Object.keys(c.metrics)))).sort();
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
    const vals = cs.map((c) => toNumber(show === 'budget' ? c.budget : c.metrics[show.slice(2)]))
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
    const table = el('table', { id: 'matrix-table' });
    const head = el('tr', {}, el('th', { class: 'corner', text: rd + ' ↓ / ' + (cd || '—') + ' →' }));
    for (const v of colsV) head.append(el('th', { text: v }));
    table.append(el('thead', {}, head));
    const body = el('tbody');
    for (const rv of rowsV) {
      const tr = el('tr', {}, el('th', { text: rv }));
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
          td.textContent = show === 'budget' ? pct(v) : fmt(v);
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
    let metricRange = null;
    function metricPosition(v) {
      if (!metricRange) {
        const vals = cases.map((c) => toNumber(c.metrics[show.slice(2)])).filter((x) => x > 0 && Number.isFinite(x));
        metricRange = [Math.log10(Math.min(...vals, 1)), Math.log10(Math.max(...vals, 1e-12))];
      }
      const [lo, hi] = metricRange;
      return hi > lo ? (Math.log10(Math.max(v, 1e-300)) - lo) / (hi - lo) : 1;
    }
    const legend = $('#matrix-legend');
    legend.replaceChildren();
    if (show === 'verdict') {
      for (const [cls, label] of [['pass', 'all passed'], ['warn', 'passed, with a warning'],
        ['fail', 'a case failed'], ['error', 'a case errored'], ['skip', 'not evaluated (skip, known limit, degenerate)']])
        legend.append(el('span', { class: 'badge cell-' + cls, text: label }), ' ');
    } else {
      legend.append(show === 'budget' ?
        'Colour: VisualizeHDR\'s Colorize ramp over log10(budget used), 0.1 % blue … 200 % red; black: exact.' :
        'Colour: Colorize ramp over log10 of the metric across the grid; black: exact.');
    }
    setHash({ stage: stageSel.value, rows: rd, cols: cd, show });
    if (selected) {
      const td = $$('td.cell').find((t) => t.dataset.row === selected[0] && t.dataset.col === selected[1]);
      if (td) td.click();
      else selected = null;
    }
  };

  const drill = (cs, rd, rv, cd, cv) => {
    $('#cell-title').textContent = rd + ' = ' + rv + (cd ? ', ' + cd + ' = ' + cv : '') +
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

function initCase() {
  const meta = JSON.parse($('#case-meta').textContent);
  HDRC.meta = meta;
  const w = meta.w, h = meta.h;
  const imgs = {};
  if (HDRC.px) {
    for (const [k, d] of Object.entries(HDRC.px.images)) imgs[k] = new FloatImage(HDRC.px.w, HDRC.px.h, d);
  }
  HDRC.images = imgs;
  const tol = meta.tol || {};
  const m2020 = meta.to_rec2020 || [1, 0, 0, 0, 1, 0, 0, 0, 1];
  let ev = 0, heatKey = 'pq10', pinned = null;

  if (!$('#panels')) {
    ready();
    return;
  }
  const keys = $$('figure.panel').map((f) => f.dataset.key);
  // The case's image folder, from the PNG the page was written with (c/<slug>/).
  const imgBase = $('figure.panel img').getAttribute('src').replace(/[^/]*$/, '');
  const labels = { input: 'input', reference: 'reference', candidate: 'candidate', heat: 'error heatmap', mask: 'over tolerance' };

  // Rendering of the float images at the current exposure (cached per exposure).
  const cache = new Map();
  function previewData(key) {
    const ck = key + '@' + ev;
    if (cache.has(ck)) return cache.get(ck);
    const im = imgs[key];
    const data = new ImageData(w, h);
    const k = Math.pow(2, ev) / 100;
    for (let i = 0; i < w * h; i++) {
      let nan = false, inf = false;
      for (let c = 0; c < 3; c++) {
        const v = im.value(i, c);
        nan = nan || Number.isNaN(v);
        inf = inf || (!Number.isFinite(v) && !Number.isNaN(v));
      }
      const o = i * 4;
      if (nan || inf) {
        data.data[o] = nan ? 255 : 0;
        data.data[o + 1] = nan ? 0 : 255;
        data.data[o + 2] = 255;
      } else {
        for (let c = 0; c < 3; c++) data.data[o + c] = Math.round(srgbOetf(im.nits(i, c) * k) * 255);
      }
      data.data[o + 3] = 255;
    }
    cache.set(ck, data);
    return data;
  }
  const floatKeys = new Set(['input', 'reference', 'candidate'].filter((k) => imgs[k]));

  // One displayable element for `key`: a canvas drawn from the float data (previews), or the
  // PNG (heatmaps, mask, and previews when there is no float data).
  function makeView(key) {
    let e;
    if (floatKeys.has(key)) {
      e = el('canvas', { width: w, height: h, 'data-key': key });
      e.getContext('2d').putImageData(previewData(key), 0, 0);
    } else {
      const file = key === 'heat' ? HEAT[heatKey].png : key + '.png';
      e = el('img', { alt: labels[key], 'data-key': key });
      e.src = imgBase + file;
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
    if (mode === 'flip') {
      const key = flipShowsB ? b : a;
      const v = makeView(key);
      const frame = el('div', { class: 'frame', id: 'flip-frame' }, v);
      frame.addEventListener('click', () => {
        if (pinned) return;
        flipShowsB = !flipShowsB;
        renderCompare();
      });
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
    }
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
  function pixelError(i) {
    const r = imgs.reference, c = imgs.candidate;
    // As report/images.cpp: a consistent non-finite channel is skipped (and leaves ΔE_ITP at 0),
    // an inconsistent one on any channel is a mismatch (NaN: drawn white).
    let worst = 0, finite = true;
    const rn = [0, 0, 0], cn = [0, 0, 0];
    for (let ch = 0; ch < 4; ch++) {
      const rv = r.value(i, ch), cv = c.value(i, ch);
      if (!Number.isFinite(rv) || !Number.isFinite(cv)) {
        if (!((Number.isNaN(rv) && Number.isNaN(cv)) || rv === cv)) return NaN;
        if (ch < 3) finite = false;
        continue;
      }
      if (ch === 3) continue;
      rn[ch] = r.nits(i, ch);
      cn[ch] = c.nits(i, ch);
      worst = Math.max(worst, Math.abs(pqSignal(cn[ch]) - pqSignal(rn[ch])) * 1023);
    }
    if (heatKey === 'pq10') return worst;
    return finite ? deltaEItp(ictcp(mul3(m2020, cn)), ictcp(mul3(m2020, rn))) : 0;
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

  redrawPanels();
  renderCompare();
  drawLegend();
  renderLut();
  ready();
}

document.addEventListener('DOMContentLoaded', () => {
  const page = document.body.dataset.page;
  try {
    if (page === 'summary') initSummary();
    else if (page === 'cases') initCases();
    else if (page === 'matrix') initMatrix();
    else if (page === 'case') initCase();
  } catch (e) {
    document.documentElement.dataset.error = String(e && e.stack ? e.stack : e);
    document.body.prepend(el('pre', { class: 'warning', text: 'report script error: ' + e }));
    throw e;
  }
});
