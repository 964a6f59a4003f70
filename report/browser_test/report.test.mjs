// End-to-end test of the HTML report (issue 7, acceptance 1) in headless Chromium.
//
//   node report.test.mjs --results DIR --artifacts DIR [--chromium PATH]
//       DIR holds the report fixture (report_fixture: results.json, expect.json, cases/, report/).
//       Asserts the summary counts, the matrix cell colours and drill-down, the case list filters
//       and sorting, the failing case page (heatmap, mask, worst pixel, probe numbers at the
//       planted pixel, exposure, flip and slider views), the LUT slices, the warned case's
//       markers and the escaping of a hostile case id; every page loads from file:// without
//       a request elsewhere, without a script error, and is interactive within 2 s. Screenshots
//       of the summary, the matrix and the failing case page go to the artifacts folder.
//
//   node report.test.mjs --measure DIR [--chromium PATH]
//       Opens every page of any report (e.g. the default suite's) and prints the time to
//       interactive of each kind of page; fails when one takes over 2 s.
//
// Expected numbers come from the fixture's own record of what it planted (expect.json: the
// planted pixel's float32 values read back from its EXRs) and from the documented formulas (PQ,
// ST 2084; the heatmap's Colorize ramp), not from the report's code.
import { chromium } from 'playwright-core';
import fs from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';

const args = process.argv.slice(2);
const opt = (name, dflt) => {
  const i = args.indexOf('--' + name);
  return i >= 0 ? args[i + 1] : dflt;
};
const executablePath = opt('chromium', '/usr/bin/chromium');
const TTI_LIMIT_MS = 2000;
// The flags Chromium needs on this closed network (see the machine notes): no background traffic.
const CHROME_ARGS = ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync'];

let failures = 0, checks = 0;
function check(cond, what, detail) {
  checks++;
  if (cond) {
    console.log('  ok   ' + what);
  } else {
    failures++;
    console.log('  FAIL ' + what + (detail !== undefined ? ': ' + JSON.stringify(detail) : ''));
  }
}
function close(a, b, rel) {
  return Math.abs(a - b) <= rel * Math.max(Math.abs(a), Math.abs(b));
}

// ST 2084 inverse EOTF (SMPTE ST 2084:2014 eq. 5.2), nits clamped to [0, 10000] as
// docs/diff-metrics.md states for the PQ metric.
function pq(nits) {
  const m1 = 2610 / 16384, m2 = (2523 / 4096) * 128;
  const c1 = 3424 / 4096, c2 = (2413 / 4096) * 32, c3 = (2392 / 4096) * 32;
  const y = Math.pow(Math.min(Math.max(nits, 0), 10000) / 10000, m1);
  return Math.pow((c1 + c2 * y) / (1 + c3 * y), m2);
}
// UE's Colorize (PostProcessVisualizeHDR.usf) on the heatmap's documented scale (log10 of the PQ
// error in 10-bit codes over [-4, 1]), 8-bit.
function heatRgb(pq10) {
  const x = Math.min(1, Math.max(0, (Math.log10(pq10) + 4) / 5));
  const t = Math.abs(0.5 - x) * 2;
  return [t * x, 1 - t, t * (1 - x)].map((v) => Math.round(v * 255));
}

async function openPage(context, url, log) {
  const page = await context.newPage();
  const errors = [], dialogs = [], foreign = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => {
    if (m.type() === 'error') errors.push(m.text());
  });
  page.on('dialog', async (d) => {
    dialogs.push(d.message());
    await d.dismiss();
  });
  page.on('request', (r) => {
    if (!r.url().startsWith('file:') && !r.url().startsWith('data:') && !r.url().startsWith('blob:'))
      foreign.push(r.url());
  });
  await page.goto(url, { waitUntil: 'load' });
  await page.waitForFunction(() => document.documentElement.dataset.ready === '1' ||
    document.documentElement.dataset.error, null, { timeout: 15000 });
  const tti = await page.evaluate(() => window.HDRC && window.HDRC.tti);
  const scriptError = await page.evaluate(() => document.documentElement.dataset.error || '');
  if (log) {
    check(!scriptError && errors.length === 0, `${log}: no script error`, scriptError || errors);
    check(foreign.length === 0, `${log}: no request leaves file://`, foreign);
    check(tti < TTI_LIMIT_MS, `${log}: interactive in ${tti.toFixed(0)} ms (< ${TTI_LIMIT_MS} ms)`, tti);
  }
  return { page, errors, dialogs, foreign, tti };
}

async function rgbAt(page, selector, x, y) {
  // Pixel (x, y) of an <img> or <canvas>, read back through a canvas (for <img> on file:// this
  // needs --allow-file-access-from-files: only the pixel-reading browser has it).
  return page.evaluate(({ selector, x, y }) => {
    const e = document.querySelector(selector);
    const c = document.createElement('canvas');
    const w = e.naturalWidth || e.width, h = e.naturalHeight || e.height;
    c.width = w;
    c.height = h;
    const ctx = c.getContext('2d');
    ctx.drawImage(e, 0, 0);
    return Array.from(ctx.getImageData(x, y, 1, 1).data.slice(0, 3));
  }, { selector, x, y });
}

async function fixtureTest(dir, artifacts) {
  const report = path.join(dir, 'report');
  const expect = JSON.parse(fs.readFileSync(path.join(dir, 'expect.json'), 'utf8'));
  const results = JSON.parse(fs.readFileSync(path.join(dir, 'results.json'), 'utf8'));
  const byId = new Map(results.cases.map((c) => [c.id, c]));
  const url = (p) => pathToFileURL(path.join(report, p)).href;
  fs.mkdirSync(artifacts, { recursive: true });
  const browser = await chromium.launch({ executablePath, args: CHROME_ARGS });
  const context = await browser.newContext({ viewport: { width: 1400, height: 1000 } });
  const dialogs = [];

  // ---- Summary.
  console.log('summary page');
  {
    const { page, dialogs: d } = await openPage(context, url('index.html'), 'summary');
    const count = async (id) => Number(await page.textContent('#count-' + id));
    check(await count('total') === results.cases.length, 'total count = cases in results.json');
    for (const [v, n] of Object.entries(expect.verdicts))
      check(await count(v) === n, `count ${v} = ${n} (fixture)`, await count(v));
    check(await count('PASS') === results.summary.pass && await count('FAIL') === results.summary.fail &&
      await count('SKIP') === results.summary.skipped, 'counts agree with results.json summary');
    check(await count('WARN') === expect.warned, 'warned count');
    const worst = await page.$$eval('#worst-cases tbody tr code', (e) => e.map((x) => x.textContent));
    check(worst[0] === expect.failing, 'worst cases list the failing case first', worst);
    const meta = await page.textContent('#run-meta');
    check(meta.includes(results.candidate.device), 'run metadata names the candidate device');
    check(await page.$('a[href="../results.json"]') && await page.$('a[href="../junit.xml"]'),
      'links to results.json and junit.xml');
    await page.screenshot({ path: path.join(artifacts, 'summary.png'), fullPage: true });
    dialogs.push(...d);
  }

  // ---- Matrix.
  console.log('matrix page');
  {
    const { page, dialogs: d } = await openPage(context, url('matrix.html'), 'matrix');
    await page.selectOption('#m-stage', 'linear_device');
    await page.selectOption('#m-rows', expect.matrix.rows);
    await page.selectOption('#m-cols', expect.matrix.cols);
    const cells = await page.$$eval('#matrix-table td.cell', (tds) => tds.map((td) => ({
      row: td.dataset.row, col: td.dataset.col, cls: td.className,
      bg: getComputedStyle(td).backgroundColor })));
    check(cells.length === 6, '2 × 3 grid of cells', cells.length);
    const [fr, fc] = expect.matrix.fail_cell, [wr, wc] = expect.matrix.warn_cell;
    for (const c of cells) {
      const want = c.row === fr && c.col === fc ? ['cell-fail', 'rgb(229, 86, 108)'] :
        c.row === wr && c.col === wc ? ['cell-warn', 'rgb(242, 215, 80)'] : ['cell-pass', 'rgb(127, 207, 147)'];
      check(c.cls.includes(want[0]) && c.bg === want[1], `cell (${c.row}, ${c.col}) is ${want[0]} ${want[1]}`, c);
    }
    await page.screenshot({ path: path.join(artifacts, 'matrix.png'), fullPage: true });
    await page.click(`#matrix-table td.cell[data-row="${fr}"][data-col="${fc}"]`);
    const drilled = await page.$$eval('#cell-table tbody tr code', (e) => e.map((x) => x.textContent));
    check(drilled.length === 1 && drilled[0] === expect.failing, 'drill-down lists the failing case', drilled);
    await page.selectOption('#m-show', 'budget');
    const txt = await page.textContent(`#matrix-table td.cell[data-row="${fr}"][data-col="${fc}"]`);
    check(/%$/.test(txt.trim()), 'metric toggle shows the budget used', txt);
    dialogs.push(...d);
  }

  // ---- Case list: filters and sorting.
  console.log('case list');
  {
    const { page, dialogs: d } = await openPage(context, url('cases.html'), 'case list');
    const visible = () => page.$$eval('#case-table tbody tr:not([hidden]) code', (e) => e.map((x) => x.textContent));
    check((await visible()).length === results.cases.length, 'all cases listed');
    await page.selectOption('#f-verdict', 'FAIL');
    let v = await visible();
    check(v.length === 1 && v[0] === expect.failing, 'verdict filter FAIL narrows to the failing case', v);
    await page.selectOption('#f-verdict', 'WARN');
    v = await visible();
    check(v.length === 1 && v[0] === expect.warned_case, 'WARN filter narrows to the warned case', v);
    await page.selectOption('#f-verdict', '');
    await page.fill('#f-text', 'dev7');
    v = await visible();
    check(v.length === 3 && v.every((x) => x.includes('dev7')), 'text filter "dev7" narrows to 3 cases', v);
    await page.fill('#f-text', '');
    await page.selectOption('#f-cvar', 'r.HDR.Display.ColorGamut');
    await page.selectOption('#f-cvar-value', '2');
    v = await visible();
    check(v.length === 2 && v.every((x) => x.includes('gamut2')), 'cvar filter ColorGamut = 2 narrows to 2 cases', v);
    await page.selectOption('#f-cvar', '');
    await page.click('th[data-sort="budget"]');
    v = await visible();
    check(v[0] === expect.failing, 'sorting by budget used (descending) puts the failing case first', v.slice(0, 3));
    const hostileText = await page.$$eval('#case-table tbody code', (e, id) => e.some((x) => x.textContent === id), expect.hostile);
    check(hostileText, 'hostile case id is listed as text');
    dialogs.push(...d);
  }

  // ---- Failing case page.
  console.log('failing case page');
  const failing = byId.get(expect.failing);
  const planted = expect.planted[expect.failing];
  {
    const slug = await caseSlug(context, url('cases.html'), expect.failing);
    const { page, dialogs: d } = await openPage(context, url('c/' + slug), 'failing case page');
    check((await page.textContent('#case-id')) === expect.failing, 'page names the case');
    check((await page.textContent('.verdict-line .badge')) === 'FAIL', 'verdict FAIL shown');
    const heat = await page.$eval('figure.panel[data-key="heat"] img', (i) => [i.complete, i.naturalWidth, i.naturalHeight]);
    check(heat[0] && heat[1] === 64 && heat[2] === 4, 'heatmap image loaded at the image size', heat);
    const legend = await page.textContent('#legend-tol');
    check(legend.includes(String(failing.tolerance.pq_code10.max ?? failing.tolerance.pq_code10)), 'legend marks the PQ tolerance', legend);
    // Worst pixel row: the planted pixel, with the values results.json has.
    const row = await page.$eval('#worst-pixel tbody tr', (tr) => Array.from(tr.children).map((c) => c.textContent));
    const wp = failing.worst_pixel;
    check(row[1] === '13' && row[2] === '2' && row[3] === 'G', 'worst pixel is the planted (13, 2) G', row);
    check(close(Number(row[6]), wp.reference, 1e-8) && close(Number(row[7]), wp.candidate, 1e-8),
      'worst pixel values = results.json', [row[6], row[7], wp.reference, wp.candidate]);
    check(close(Number(row[6]), planted.reference[1], 1e-7) && close(Number(row[7]), planted.candidate[1], 1e-7),
      'worst pixel values = the EXRs at the planted pixel', [row[6], row[7], planted.reference[1], planted.candidate[1]]);
    check(close(planted.candidate[1] / planted.reference[1], 1.01, 1e-6), 'planted defect is × 1.01 (fixture sanity)');
    // Pixel probe: hover the candidate canvas over pixel (13, 2).
    const box = await page.$eval('figure.panel[data-key="candidate"] canvas', (c) => {
      const r = c.getBoundingClientRect();
      return { x: r.left, y: r.top, w: r.width, h: r.height };
    });
    await page.mouse.move(box.x + ((13 + 0.5) * box.w) / 64, box.y + ((2 + 0.5) * box.h) / 4);
    check((await page.textContent('#probe-xy')) === 'x 13, y 2', 'probe shows x 13, y 2', await page.textContent('#probe-xy'));
    const probeRow = async (k) => page.$$eval(`#probe-table tr[data-row="${k}"] td`, (tds) => tds.map((t) => t.textContent));
    const ref = await probeRow('reference'), cand = await probeRow('candidate'), inp = await probeRow('input');
    for (let c = 0; c < 4; c++) {
      check(Math.fround(Number(ref[c])) === Math.fround(planted.reference[c]) &&
        Math.fround(Number(cand[c])) === Math.fround(planted.candidate[c]) &&
        Math.fround(Number(inp[c])) === Math.fround(planted.input[c]),
      `probe channel ${'RGBA'[c]}: input/reference/candidate = the EXRs' float32 values`, [inp[c], ref[c], cand[c]]);
    }
    // linear_device, device 8: scene-linear × 100 nits (docs/diff-metrics.md).
    const wantPq = Math.abs(pq(planted.candidate[1] * 100) - pq(planted.reference[1] * 100)) * 1023;
    const gotPq = Number((await probeRow('pq10'))[1]);
    check(close(gotPq, wantPq, 1e-4), `probe PQ error ${gotPq} = hand-computed ${wantPq.toPrecision(6)} codes`);
    const floor = failing.tolerance.rel_floor;
    const wantRel = Math.abs(planted.candidate[1] - planted.reference[1]) / Math.max(Math.abs(planted.reference[1]), floor);
    const gotRel = Number((await probeRow('rel'))[1]);
    check(close(gotRel, wantRel, 1e-4), `probe relative error ${gotRel} = hand-computed ${wantRel.toPrecision(6)}`);
    check(close(gotRel, failing.stats.overall.linear_rel.max, 1e-4), 'probe relative error = results.json max');
    // Exposure: +2 EV brightens the candidate canvas (read from the canvas the script drew).
    const mean = () => page.$eval('figure.panel[data-key="candidate"] canvas', (c) => {
      const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
      let s = 0;
      for (let i = 0; i < d.length; i += 4) s += d[i] + d[i + 1] + d[i + 2];
      return s / (d.length / 4);
    });
    const m0 = await mean();
    await page.fill('#exposure', '2');
    await page.dispatchEvent('#exposure', 'input');
    const m2 = await mean();
    check(m2 > m0, `exposure +2 EV brightens the preview (${m0.toFixed(1)} → ${m2.toFixed(1)})`);
    check((await page.textContent('#exposure-value')) === '+2 EV', 'exposure value shown');
    await page.click('#exposure-reset');
    // Views.
    await page.selectOption('#view-mode', 'flip');
    check(await page.isVisible('#flip-frame canvas'), 'A/B flip view shows one image');
    const before = await page.textContent('#flip-label b');
    await page.click('#flip-button');
    const after = await page.textContent('#flip-label b');
    check(before.startsWith('A: reference') && after.startsWith('B: candidate'), 'flip toggles A → B', [before, after]);
    await page.selectOption('#view-mode', 'slider');
    check((await page.$$('#slider-stack .layer')).length === 2 && await page.isVisible('#split'), 'slider view stacks A and B');
    await page.selectOption('#view-mode', 'side');
    await page.mouse.move(box.x + ((13 + 0.5) * box.w) / 64, box.y + ((2 + 0.5) * box.h) / 4);
    await page.screenshot({ path: path.join(artifacts, 'failing-case.png') });
    dialogs.push(...d);
  }

  // ---- Pixels of the PNGs (a second browser, allowed to read file:// images into a canvas).
  console.log('image pixels');
  {
    const pixBrowser = await chromium.launch({ executablePath, args: [...CHROME_ARGS, '--allow-file-access-from-files'] });
    const ctx = await pixBrowser.newContext();
    const slug = await caseSlug(ctx, url('cases.html'), expect.failing);
    const { page } = await openPage(ctx, url('c/' + slug), null);
    const wantPq = Math.abs(pq(planted.candidate[1] * 100) - pq(planted.reference[1] * 100)) * 1023;
    const heat = await rgbAt(page, 'figure.panel[data-key="heat"] img', 13, 2);
    const want = heatRgb(wantPq);
    check(heat.every((v, i) => Math.abs(v - want[i]) <= 2), `heatmap at (13, 2) is Colorize(${wantPq.toPrecision(3)} codes) = ${want}`, heat);
    const mask = await rgbAt(page, 'figure.panel[data-key="mask"] img', 13, 2);
    check(mask[0] === 255 && mask[1] === 0 && mask[2] === 0, 'over-tolerance mask marks (13, 2) red', mask);
    const maskOther = await rgbAt(page, 'figure.panel[data-key="mask"] img', 12, 2);
    check(!(maskOther[0] === 255 && maskOther[1] === 0), 'mask leaves (12, 2) unmarked', maskOther);
    // The script's rendering at 0 EV and the C++ PNG use the same documented mapping.
    let maxDiff = 0;
    for (const k of ['input', 'reference', 'candidate']) {
      const png = await page.evaluate((k) => new Promise((resolve) => {
        const i = new Image();
        i.onload = () => {
          const c = document.createElement('canvas');
          c.width = i.width;
          c.height = i.height;
          c.getContext('2d').drawImage(i, 0, 0);
          resolve(Array.from(c.getContext('2d').getImageData(0, 0, i.width, i.height).data));
        };
        i.src = document.querySelector(`figure.panel[data-key="${k}"] canvas`) ?
          location.href.replace(/\.html$/, '/') + k + '.png' : '';
      }), k);
      const js = await page.$eval(`figure.panel[data-key="${k}"] canvas`, (c) =>
        Array.from(c.getContext('2d').getImageData(0, 0, c.width, c.height).data));
      for (let i = 0; i < js.length; i++) if (i % 4 !== 3) maxDiff = Math.max(maxDiff, Math.abs(js[i] - png[i]));
    }
    check(maxDiff <= 1, `script's 0 EV previews match the PNG previews (max difference ${maxDiff} codes)`);
    await pixBrowser.close();
  }

  // ---- LUT page.
  console.log('LUT case page');
  {
    const slug = await caseSlug(context, url('cases.html'), expect.lut);
    const { page, dialogs: d } = await openPage(context, url('c/' + slug), 'LUT case page');
    check((await page.$$('#lut-panels canvas')).length === 3, 'reference, candidate and error slices');
    await page.click('#lut-goto-worst');
    check((await page.inputValue('#lut-slice')) === '7', 'worst lattice point is on blue slice 7 (planted)');
    const probe = await page.textContent('#lut-probe');
    check(probe.includes('r 5, g 9, b 7'), 'LUT probe names the planted lattice point (5, 9, 7)', probe);
    dialogs.push(...d);
  }

  // ---- Warned case page: warning and markers.
  console.log('warned case page');
  {
    const slug = await caseSlug(context, url('cases.html'), expect.warned_case);
    const { page, dialogs: d } = await openPage(context, url('c/' + slug), 'warned case page');
    check(await page.isVisible('.verdict-line .marker.warn'), 'WARN marker');
    check(await page.isVisible('.verdict-line .marker.near'), 'near-miss marker (budget over half)');
    check((await page.textContent('p.warning')).includes('linear_rel'), 'warning names the metric');
    dialogs.push(...d);
  }

  // ---- Hostile case id.
  console.log('hostile case id');
  {
    const slug = await caseSlug(context, url('cases.html'), expect.hostile);
    const { page, dialogs: d } = await openPage(context, url('c/' + slug), 'hostile case page');
    check((await page.textContent('#case-id')) === expect.hostile, 'hostile id rendered as text');
    const injected = await page.evaluate(() => Array.from(document.scripts).some((s) => s.textContent.includes('alert(1)') && s.type !== 'application/json'));
    check(!injected, 'no script element carries the hostile text');
    const html = fs.readFileSync(path.join(report, 'c', decodeURIComponent(slug)), 'utf8');
    check(!html.includes('<script>alert(1)') && html.includes('&lt;script&gt;alert(1)&lt;/script&gt;'), 'page source holds the id escaped');
    dialogs.push(...d);
  }
  check(dialogs.length === 0, 'no dialog (alert) opened on any page', dialogs);
  await browser.close();
}

async function caseSlug(context, listUrl, id) {
  const { page } = await openPage(context, listUrl, null);
  const href = await page.$$eval('#case-table tbody a', (as, id) => {
    const a = as.find((x) => x.textContent === id);
    return a ? a.getAttribute('href') : null;
  }, id);
  await page.close();
  if (!href) throw new Error('case not in the list: ' + id);
  return href.replace(/^c\//, '');
}

async function measure(dir) {
  const report = path.join(dir, 'report');
  const url = (p) => pathToFileURL(path.join(report, p)).href;
  const browser = await chromium.launch({ executablePath, args: CHROME_ARGS });
  const context = await browser.newContext({ viewport: { width: 1400, height: 1000 } });
  const times = {};
  const add = (kind, t, name) => (times[kind] = times[kind] || []).push([t, name]);
  for (const p of ['index.html', 'matrix.html', 'cases.html']) {
    const { page, tti } = await openPage(context, url(p), p);
    add(p, tti, p);
    await page.close();
  }
  const pages = fs.readdirSync(path.join(report, 'c')).filter((f) => f.endsWith('.html'));
  for (const f of pages) {
    const { page, tti, errors } = await openPage(context, url('c/' + f), null);
    const scriptError = await page.evaluate(() => document.documentElement.dataset.error || '');
    add('case pages', tti, f);
    check(tti < TTI_LIMIT_MS && !scriptError && errors.length === 0,
      `c/${f}: ${tti.toFixed(0)} ms, no script error`, [tti, scriptError, errors]);
    await page.close();
  }
  for (const [k, v] of Object.entries(times)) {
    v.sort((a, b) => a[0] - b[0]);
    const med = v[Math.floor(v.length / 2)][0];
    console.log(`time to interactive, ${k}: ${v.length} page(s), median ${med.toFixed(0)} ms, max ${v[v.length - 1][0].toFixed(0)} ms (${v[v.length - 1][1]})`);
  }
  await browser.close();
}

try {
  if (opt('measure')) await measure(opt('measure'));
  else await fixtureTest(opt('results'), opt('artifacts'));
} catch (e) {
  console.log('FAIL ' + (e && e.stack ? e.stack : e));
  failures++;
}
console.log(`${checks - failures} of ${checks} checks passed` + (failures ? `, ${failures} failed` : ''));
process.exit(failures ? 1 : 0);
