// End-to-end test of the HTML report (issue 7, acceptance 1) in headless Chromium.
//
//   node report.test.mjs --results DIR --artifacts DIR [--chromium PATH]
//       DIR holds the report fixture (report_fixture: results.json, expect.json, cases/, report/).
//       Asserts the summary counts, the matrix cell colours and drill-down, the case list filters
//       and sorting, the failing case page (heatmap, mask, worst pixel, probe numbers at the
//       planted pixel, exposure, flip and slider views), the LUT slices, the warned case's
//       markers and the escaping of a hostile case id; the failing-case list and the summary's
//       worst cases (grouped by failure class) at 1400 and 1920 px: rows at most 120 px tall,
//       long ids shortened, reasons under the ids; the pipeline filter; the matrix's metric views
//       judged metrics only; the LUT-64³ page (issue 27). Every page loads from file:// without
//       a request elsewhere, without a script error, and is interactive within 2 s. Screenshots
//       of the summary, the matrix and the failing case page go to the artifacts folder. Also
//       the golden review page (`goldens diff`, run.sh) of a planted constant change, and its
//       case page (goldens-review*.png).
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
// Every control (select option, button, input, sortable header) the test drives, by page type.
const controls = new Set();
const drove = (page, what) => controls.add(page + ': ' + what);
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

// The pixels of the image at `src` (a URL the page may load and read: the pixel-reading browser
// has --allow-file-access-from-files), read back through a canvas: { width, height, data RGBA }.
async function imagePixels(page, src) {
  return page.evaluate((src) => new Promise((resolve) => {
    const i = new Image();
    i.onload = () => {
      const c = document.createElement('canvas');
      c.width = i.width;
      c.height = i.height;
      c.getContext('2d').drawImage(i, 0, 0);
      resolve({ width: i.width, height: i.height, data: Array.from(c.getContext('2d').getImageData(0, 0, i.width, i.height).data) });
    };
    i.onerror = () => resolve(null);
    i.src = src;
  }), src);
}
function pixelOf(img, x, y) {
  return img.data.slice((y * img.width + x) * 4, (y * img.width + x) * 4 + 3);
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

// A case list's rows (issue 27, acceptance: rows at most 120 px tall at 1400 px): each row of
// `rows` at most ROW_LIMIT_PX tall; an id longer than its cell shown shortened, in one line, with
// the full id in its title; the reason on its own lines under the id, as wide as the id's cell
// (not squeezed into a column), cut to two lines but holding the full text.
const ROW_LIMIT_PX = 120;
async function listLayout(page, rows, what, count) {
  const got = await page.$$eval(rows, (trs, ids) => trs.map((tr) => {
    const a = tr.querySelector('a.case-link'), r = tr.querySelector('div.reason');
    const code = a && a.querySelector('code');
    return { id: tr.dataset.id || ids[Number(tr.dataset.i)], h: tr.getBoundingClientRect().height, shown: code && code.textContent, title: a && a.title,
      idFits: a ? a.scrollWidth <= a.clientWidth + 1 : false,
      reasonW: r ? r.getBoundingClientRect().width : 0,
      cellW: r ? r.parentElement.clientWidth - parseFloat(getComputedStyle(r.parentElement).paddingLeft) - parseFloat(getComputedStyle(r.parentElement).paddingRight) : 0,
      reasonBelow: r && a ? r.getBoundingClientRect().top >= a.getBoundingClientRect().bottom - 1 : true,
      reasonText: r ? r.textContent : null };
  }), RESULTS.cases.map((c) => c.id));
  if (count !== undefined) check(got.length === count, `${what}: ${count} rows`, got.length);
  const tallest = Math.max(...got.map((g) => g.h));
  check(got.length > 0 && got.every((g) => g.h <= ROW_LIMIT_PX), `${what}: every row at most ${ROW_LIMIT_PX} px tall (tallest ${tallest.toFixed(0)} px)`, got.filter((g) => g.h > ROW_LIMIT_PX));
  check(got.every((g) => g.title === g.id && g.idFits && (g.shown === g.id || g.shown.includes('…'))), `${what}: ids shown in one line, shortened with … where long, the full id in the title`, got.filter((g) => !(g.title === g.id && g.idFits)));
  const long = got.filter((g) => g.id.length > 64);
  check(long.length >= (count === undefined ? 1 : 2) && long.every((g) => g.shown !== g.id && g.shown.length <= 64), `${what}: the long ids (${long.length}) are shortened`, long.map((g) => g.shown));
  const byId = new Map(RESULTS.cases.map((c) => [c.id, c]));
  check(got.every((g) => g.reasonText === byId.get(g.id).reason && g.reasonBelow && g.reasonW >= g.cellW - 1 && g.reasonW >= 250),
    `${what}: each reason under its id, the width of the case's cell (narrowest ${Math.min(...got.map((g) => g.reasonW)).toFixed(0)} px), the full reason in it`,
    got.filter((g) => !(g.reasonText === byId.get(g.id).reason && g.reasonBelow && g.reasonW >= g.cellW - 1 && g.reasonW >= 250)).map((g) => [g.id, g.reasonW, g.cellW]));
}
let RESULTS = null;

async function fixtureTest(dir, artifacts) {
  const report = path.join(dir, 'report');
  const expect = JSON.parse(fs.readFileSync(path.join(dir, 'expect.json'), 'utf8'));
  const results = JSON.parse(fs.readFileSync(path.join(dir, 'results.json'), 'utf8'));
  RESULTS = results;
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
    const worst = await page.$$eval('#worst-cases tr.case', (e) => e.map((x) => [x.dataset.id, x.querySelector('.badge').textContent, x.children[2].textContent]));
    // Worst cases grouped by the class of their failure (the metric and the kind), the class
    // with most failures first: the classes the fixture planted (expect.classes).
    const groups = await page.$$eval('#worst-cases tbody.class-group', (g) => g.map((x) => [x.dataset.class, [...x.querySelectorAll('tr.case')].map((r) => r.dataset.id)]));
    const planted = Object.entries(expect.classes).sort((a, b) => b[1].length - a[1].length);
    check(groups.length === planted.length + 1 && planted.every(([cls, ids], k) => groups[k][0] === cls &&
      groups[k][1].length === ids.length && ids.every((id) => groups[k][1].includes(id))) &&
      groups[planted.length][0] === 'passed, most budget used',
    `worst cases grouped by class, most failures first (${planted.map(([c, i]) => c + ' ' + i.length).join(', ')}), then the passing cases`, groups);
    check(worst.filter((w) => w[1] === 'FAIL').length === expect.verdicts.FAIL, 'every failing case is listed under its class', worst);
    // Budget used is the runner's figure (results.json budget_used), never 1e+08 %.
    const budgets = worst.map((w) => [w[0], w[2]]);
    check(budgets.every(([id, t]) => t === '—' || Math.abs(Number(t.replace(' %', '')) - byId.get(id).budget_used * 100) <=
      0.01 * byId.get(id).budget_used * 100 + 1e-9), 'budget used = results.json budget_used for every listed case', budgets);
    check(worst.filter((w) => w[1] === 'PASS').every((w) => Number(w[2].replace(' %', '')) <= 100), 'passing cases use at most 100 % of their budget', worst);
    const meta = await page.textContent('#run-meta');
    check(meta.includes(results.candidate.device), 'run metadata names the candidate device');
    const hrefs = await page.$$eval('a[href], img[src], link[href], script[src]', (e) => e.map((x) => x.getAttribute('href') || x.getAttribute('src')));
    check(hrefs.every((h) => !h.startsWith('../') && !h.includes('://')), 'no link leaves report/ (self-contained)', hrefs.filter((h) => h.startsWith('../')));
    // Thumbnails are parts of atlas PNGs (t/<n>.png, the thumbnails of 64 cases stacked), offset
    // in a box of the thumbnail's size: the PNG loads, the box is at most 160 × [12, 40], and the
    // PNG covers the box (the pixels shown are checked with the failing case below).
    const thumbs = await page.$$eval('#worst-cases .thumb img', (e) => Promise.all(e.map((x) => (x.complete ? Promise.resolve() :
      new Promise((r) => { x.onload = x.onerror = r; })).then(() => {
      const box = x.parentElement.getBoundingClientRect(), im = x.getBoundingClientRect();
      return [x.naturalWidth, box.width - 2, box.height - 2, im.left <= box.left + 1 && im.top <= box.top + 1 && im.right >= box.right - 1 && im.bottom >= box.bottom - 1, x.getAttribute('src')];
    }))));
    check(thumbs.length > 0 && thumbs.every(([nw, w, h, covers]) => nw > 0 && w > 0 && w <= 160 && h >= 12 && h <= 40 && covers),
      'worst-case heatmap thumbnails load, at most 160 × [12, 40], the atlas covering the box', thumbs);
    const golden = await page.$$eval('#golden-failures tbody tr code', (e) => e.map((x) => x.textContent));
    check(golden.length === 1 && golden[0] === expect.golden_regression, 'golden regression listed in the report', golden);
    await page.screenshot({ path: path.join(artifacts, 'summary.png'), fullPage: true });
    await listLayout(page, '#worst-cases tr.case', 'summary worst cases');
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
    drove('matrix', '#m-show budget');
    const txt = await page.textContent(`#matrix-table td.cell[data-row="${fr}"][data-col="${fc}"]`);
    check(/%$/.test(txt.trim()), 'metric toggle shows the budget used', txt);
    const passTxt = await page.textContent(`#matrix-table td.cell[data-row="7"][data-col="0"]`);
    check(!/e\+/.test(passTxt) && Number(passTxt.replace(' %', '')) < 100, 'a passing cell\'s budget is under 100 % (not 1e+08 %)', passTxt);
    // Every view of the matrix: each metric, each stage, each row/column dimension.
    const shows = await page.$$eval('#m-show option', (o) => o.map((x) => x.value));
    let rendered = 0;
    for (const v of shows) {
      await page.selectOption('#m-show', v);
      drove('matrix', '#m-show ' + v);
      rendered += (await page.$$('#matrix-table td.cell')).length > 0;
    }
    check(rendered === shows.length, `every "show" view renders (${shows.length}: verdict, budget, each metric)`, rendered);
    for (const st of await page.$$eval('#m-stage option', (o) => o.map((x) => x.value))) {
      await page.selectOption('#m-stage', st);
      drove('matrix', '#m-stage ' + (st || 'all'));
      for (const sel of ['#m-rows', '#m-cols'])
        for (const v of await page.$$eval(sel + ' option', (o) => o.map((x) => x.value))) {
          await page.selectOption(sel, v);
          drove('matrix', sel + ' ' + v);
        }
      const cell = await page.$('#matrix-table td.cell');
      if (cell) {
        await cell.click();
        drove('matrix', 'cell click');
      }
    }
    // Metric views show a metric only for the cases whose tolerance judges it (results.json
    // tolerance: a metric entry not null): no option for a metric no case judges; a cell none of
    // whose cases judges the shown metric reads "not judged", uncoloured.
    const judgedBy = (c, m) => c.tolerance && c.tolerance[m] !== null && c.tolerance[m] !== undefined;
    await page.selectOption('#m-stage', '');
    const metricShows = (await page.$$eval('#m-show option', (o) => o.map((x) => x.value))).filter((v) => v.startsWith('m:'));
    const unjudged = metricShows.filter((v) => !results.cases.some((c) => judgedBy(c, v.slice(2).split('.')[0])));
    check(metricShows.length > 0 && unjudged.length === 0, `metric views offer judged metrics only (${metricShows.length})`, unjudged);
    const aces = byId.get(expect.aces);
    const notJudged = metricShows.find((v) => !judgedBy(aces, v.slice(2).split('.')[0]) && aces.stats.overall[v.slice(2).split('.')[0]]);
    await page.selectOption('#m-stage', 'tonemap');
    await page.selectOption('#m-show', notJudged || 'verdict');
    const acesCells = await page.$$eval('#matrix-table td.cell', (tds) => tds.map((td) => [td.textContent, td.className, td.style.background]));
    check(notJudged && acesCells.length > 0 && acesCells.every(([t, cls, bg]) => t === 'not judged' && cls.includes('not-judged') && !bg),
      `the tonemap stage's cells read "not judged" under ${notJudged} (its tolerance does not judge it)`, acesCells);
    check(d.length === 0 && (await page.evaluate(() => document.documentElement.dataset.error || '')) === '', 'every matrix view and control ran without a script error');
    dialogs.push(...d);
  }

  // ---- Case list: filters and sorting.
  console.log('case list');
  {
    const { page, dialogs: d } = await openPage(context, url('cases.html'), 'case list');
    const ids = results.cases.map((c) => c.id); // a row's data-i is its case's index in results.json
    const visible = () => page.$$eval('#case-table tbody tr:not([hidden])', (e, ids) => e.map((x) => ids[Number(x.dataset.i)]), ids);
    check((await visible()).length === results.cases.length, 'all cases listed');
    await page.selectOption('#f-verdict', 'FAIL');
    let v = await visible();
    const failIds = results.cases.filter((c) => c.verdict === 'FAIL').map((c) => c.id);
    check(v.length === expect.verdicts.FAIL && v.includes(expect.failing) && v.includes(expect.aces) && failIds.every((id) => v.includes(id)),
      'verdict filter FAIL narrows to the failing cases', v);
    for (const o of await page.$$eval('#f-verdict option', (x) => x.map((y) => y.value))) {
      await page.selectOption('#f-verdict', o);
      drove('cases', '#f-verdict ' + (o || 'all'));
    }
    for (const o of await page.$$eval('#f-stage option', (x) => x.map((y) => y.value))) {
      await page.selectOption('#f-stage', o);
      drove('cases', '#f-stage ' + (o || 'all'));
    }
    for (const o of await page.$$eval('#f-metric option', (x) => x.map((y) => y.value))) {
      await page.selectOption('#f-metric', o);
      drove('cases', '#f-metric ' + o);
    }
    for (const th of await page.$$eval('th[data-sort]', (x) => x.map((y) => y.dataset.sort))) {
      await page.click(`th[data-sort="${th}"]`);
      drove('cases', 'sort ' + th);
    }
    await page.selectOption('#f-stage', '');
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
    const gamut2 = results.cases.filter((c) => c.cvars['r.HDR.Display.ColorGamut'] === 2).map((c) => c.id);
    check(v.length === gamut2.length && v.length >= 2 && v.every((x) => gamut2.includes(x)), `cvar filter ColorGamut = 2 narrows to its ${gamut2.length} cases`, v);
    await page.selectOption('#f-cvar', '');
    await page.click('th[data-sort="id"]');
    await page.click('th[data-sort="budget"]');
    v = await visible();
    check(failIds.every((id) => v.slice(0, failIds.length).includes(id)), 'sorting by budget used (descending) puts the failing cases first', v.slice(0, failIds.length + 1));
    const hostileText = await page.$$eval('#case-table tbody code', (e, id) => e.some((x) => x.textContent === id), expect.hostile);
    check(hostileText, 'hostile case id is listed as text');
    // The pipeline filter: one option per pipeline of the run, each narrowing to its cases.
    await page.click('th[data-sort="id"]');
    const pipelines = await page.$$eval('#f-pipeline option', (o) => o.map((x) => x.value).filter((x) => x));
    const runPipelines = [...new Set(results.cases.map((c) => c.pipeline).filter((x) => x))].sort();
    check(JSON.stringify(pipelines.slice().sort()) === JSON.stringify(runPipelines) && runPipelines.length >= 2, 'pipeline filter offers the run\'s pipelines', pipelines);
    for (const p of pipelines) {
      await page.selectOption('#f-pipeline', p);
      drove('cases', '#f-pipeline ' + p);
      v = await visible();
      const want = results.cases.filter((c) => c.pipeline === p).map((c) => c.id);
      check(v.length === want.length && want.every((id) => v.includes(id)), `pipeline filter ${p} narrows to its ${want.length} cases`, v);
    }
    await page.selectOption('#f-pipeline', '');
    dialogs.push(...d);
  }
  // ---- The failing-case list at common widths (issue 27: at 1400 px a row was ~842 px tall).
  console.log('failing-case list at 1400 and 1920 px');
  for (const width of [1400, 1920]) {
    const ctx = await browser.newContext({ viewport: { width, height: 1000 } });
    const { page, dialogs: d } = await openPage(ctx, url('cases.html') + '#verdict=FAIL', `failing-case list at ${width} px`);
    await listLayout(page, '#case-table tbody tr:not([hidden])', `failing-case list at ${width} px`, expect.verdicts.FAIL);
    // A reason opens in full on a click (and closes on another).
    const long = await page.$eval(`#case-table tbody tr:has(a.case-link[title^="${expect.long_ids}"]) div.reason`, (r) => r.getBoundingClientRect().height);
    await page.click(`#case-table tbody tr:has(a.case-link[title^="${expect.long_ids}"]) div.reason`);
    const opened = await page.$eval(`#case-table tbody tr:has(a.case-link[title^="${expect.long_ids}"]) div.reason`, (r) => [r.getBoundingClientRect().height, r.scrollHeight]);
    check(opened[0] >= long && opened[0] >= opened[1] - 1, `a click shows a reason whole (${long.toFixed(0)} → ${opened[0].toFixed(0)} px)`, opened);
    drove('cases', 'reason click');
    await ctx.close();
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
    const heat = await page.$eval('figure.panel[data-key="heat"] canvas', (c) => [c.width, c.height]);
    check(heat[0] === 64 && heat[1] === 4, 'heatmap drawn at the image size', heat);
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
    // The float data: the reference and candidate EXRs are carried as they are (decoded by the
    // script), the PIZ-compressed input packed by the report (its fallback); the probe below shows
    // the EXRs' values for both.
    const pxKinds = await page.$eval('#case-px', (e) => Object.fromEntries(Object.entries(JSON.parse(e.textContent).images).map(([k, d]) => [k, d.exr ? 'exr' : d.v ? 'v' : '?'])));
    check(expect.piz_input === expect.failing && pxKinds.reference === 'exr' && pxKinds.candidate === 'exr' && pxKinds.input === 'v',
      'float data: reference and candidate as their EXR files, the PIZ input packed', pxKinds);
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
    await page.selectOption('#view-mode', 'diff');
    check(await page.isVisible('#diff-frame canvas'), 'diff view shows the difference');
    for (const v of ['side', 'flip', 'slider', 'diff']) drove('case', '#view-mode ' + v);
    drove('case', '#flip-button');
    await page.selectOption('#view-mode', 'slider');
    await page.fill('#split', '30');
    await page.dispatchEvent('#split', 'input');
    drove('case', '#split');
    check((await page.$eval('#slider-stack .layer:not(.base)', (e) => e.style.clipPath)).includes('30%'), 'slider moves the split');
    // Zoom: every level; zoomed in, the compare frame centres on the worst pixel.
    await page.selectOption('#view-mode', 'flip');
    for (const z of await page.$$eval('#zoom option', (o) => o.map((x) => x.value))) {
      await page.selectOption('#zoom', z);
      drove('case', '#zoom ' + z);
    }
    check((await page.getAttribute('#compare', 'data-centre')) === '13,2', 'zoom centres the compare frame on the worst pixel (13, 2)');
    await page.selectOption('#zoom', '0');
    // Display modes: each maps the same float data differently (read back from the canvas).
    await page.selectOption('#view-mode', 'side');
    const sig = () => page.$eval('figure.panel[data-key="candidate"] canvas', (c) => {
      const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
      let s = 0;
      for (let i = 0; i < d.length; i += 4) s += d[i] * 3 + d[i + 1] * 5 + d[i + 2] * 7;
      return s;
    });
    const sigs = {};
    for (const m of ['clip', 'tonemap', 'falsecolour', 'pq']) {
      await page.selectOption('#display-mode', m);
      drove('case', '#display-mode ' + m);
      sigs[m] = await sig();
    }
    check(new Set(Object.values(sigs)).size === 4, 'clip, tone map, false colour and PQ signal views differ', sigs);
    check(await page.$eval('#display-mode option[value="hdr"]', (o) => o.disabled), 'HDR view disabled on an SDR display');
    check((await page.textContent('#hdr-status')).includes('SDR display'), 'SDR fallback explained');
    await page.selectOption('#display-mode', 'clip');
    for (const m of ['itp', 'pq10']) {
      await page.selectOption('#heat-metric', m);
      drove('case', '#heat-metric ' + m);
    }
    check(await page.isVisible('#ramp-plot') && await page.isVisible('#ramp-error') && await page.isVisible('#itp-histogram'), 'ramp plot, its error and the ΔE_ITP histogram drawn');
    for (const r of await page.$$eval('#plot-row option', (o) => o.map((x) => x.value))) {
      await page.selectOption('#plot-row', r);
      drove('case', '#plot-row ' + r);
    }
    const hist = await page.$$eval('#itp-histogram rect.bar', (r) => r.reduce((a, x) => a + Number(x.dataset.count), 0));
    check(hist === 64 * 4, 'ΔE_ITP histogram counts every pixel (64 × 4)', hist);
    const repro = await page.textContent('#repro-cmd');
    check(repro.includes("--filter '=" + expect.failing + "'"), 'reproduce command selects exactly this case', repro);
    await page.click('#repro-copy');
    drove('case', '#repro-copy');
    for (const b of await page.$$('#worst-pixel button.goto')) {
      await b.click();
      drove('case', 'worst-pixel probe');
    }
    drove('case', '#exposure');
    drove('case', '#exposure-reset');
    drove('case', 'probe hover');
    await page.selectOption('#view-mode', 'side');
    await page.mouse.move(box.x + ((13 + 0.5) * box.w) / 64, box.y + ((2 + 0.5) * box.h) / 4);
    await page.screenshot({ path: path.join(artifacts, 'failing-case.png') });
    check((await page.evaluate(() => document.documentElement.dataset.error || '')) === '', 'every case-page control ran without a script error');
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
    const heat = await rgbAt(page, 'figure.panel[data-key="heat"] canvas', 13, 2);
    const want = heatRgb(wantPq);
    check(heat.every((v, i) => Math.abs(v - want[i]) <= 2), `heatmap at (13, 2) is Colorize(${wantPq.toPrecision(3)} codes) = ${want}`, heat);
    const mask = await rgbAt(page, 'figure.panel[data-key="mask"] canvas', 13, 2);
    check(mask[0] === 255 && mask[1] === 0 && mask[2] === 0, 'over-tolerance mask marks (13, 2) red', mask);
    const maskOther = await rgbAt(page, 'figure.panel[data-key="mask"] canvas', 12, 2);
    check(!(maskOther[0] === 255 && maskOther[1] === 0), 'mask leaves (12, 2) unmarked', maskOther);
    // The summary's heatmap thumbnail of this case shows its heatmap: the PNG pixel drawn at the
    // thumbnail's point for (13, 2) of the 64 × 4 image has the heat colour.
    const { page: summary } = await openPage(ctx, url('index.html'), null);
    const geo = await summary.evaluate((id) => {
      const row = [...document.querySelectorAll('#worst-cases tr.case')].find((tr) => tr.dataset.id === id);
      const im = row && row.querySelector('.thumb[data-key="heat"] img');
      if (!im) return null;
      const box = im.parentElement.getBoundingClientRect(), r = im.getBoundingClientRect();
      // The page point of (13.5, 2.5) in the 64 × 4 image, inside the box's 1-pixel border.
      const tx = box.left + 1 + (13.5 / 64) * (box.width - 2), ty = box.top + 1 + (2.5 / 4) * (box.height - 2);
      return { src: im.src, fx: (tx - r.left) / r.width, fy: (ty - r.top) / r.height };
    }, expect.failing);
    const atlas = geo && (await imagePixels(summary, geo.src));
    const thumbPx = atlas && pixelOf(atlas, Math.floor(geo.fx * atlas.width), Math.floor(geo.fy * atlas.height));
    check(thumbPx && thumbPx.every((v, i) => Math.abs(v - want[i]) <= 2), `the summary's heatmap thumbnail shows (13, 2) as ${want}`, thumbPx);
    // The script's previews at 0 EV and the C++ ones (the list pages' thumbnails, made by
    // report/images.cpp preview_of_nits) use the same documented mapping: each thumbnail pixel
    // equals the canvas pixel it samples (nearest neighbour, images.cpp nearest_source).
    {
      const js = await page.$eval('figure.panel[data-key="candidate"] canvas', (c) =>
        ({ w: c.width, h: c.height, d: Array.from(c.getContext('2d').getImageData(0, 0, c.width, c.height).data) }));
      const { page: list } = await openPage(ctx, url('cases.html'), null);
      const geo = await list.evaluate((id) => {
        const row = [...document.querySelectorAll('#case-table tbody tr')].find((tr) => tr.querySelector('a.case-link').title === id);
        const im = row && row.querySelector('.thumb[data-key="main"] img');
        if (!im) return null;
        const box = im.parentElement;
        return { src: im.src, tw: parseFloat(box.style.width), th: parseFloat(box.style.height), y0: -parseFloat(im.style.marginTop) };
      }, expect.failing);
      const atlas = geo && (await imagePixels(list, geo.src));
      const thumb = atlas && { tw: geo.tw, th: geo.th, d: atlas.data.slice(geo.y0 * atlas.width * 4, (geo.y0 + geo.th) * atlas.width * 4) };
      let maxDiff = thumb ? 0 : 999;
      const near = (x, t, n) => Math.min(n - 1, Math.floor(((x + 0.5) * n) / t));
      for (let y = 0; thumb && y < thumb.th; y++)
        for (let x = 0; x < thumb.tw; x++)
          for (let ch = 0; ch < 3; ch++)
            maxDiff = Math.max(maxDiff, Math.abs(thumb.d[(y * atlas.width + x) * 4 + ch] - js.d[(near(y, thumb.th, js.h) * js.w + near(x, thumb.tw, js.w)) * 4 + ch]));
      check(maxDiff <= 1, `script's 0 EV candidate preview matches the C++ thumbnail (max difference ${maxDiff} codes)`);
    }
    // The script's heatmaps and mask = report/images.cpp error_maps of the same images (the
    // fixture's expect.maps, made in C++): mask and its counts exact, heat within 2 codes.
    for (const [id, want] of Object.entries(expect.maps)) {
      const slugOf = await caseSlug(ctx, url('cases.html'), id);
      const { page: cp } = await openPage(ctx, url('c/' + slugOf), null);
      const canvas = (k) => cp.$eval(`figure.panel[data-key="${k}"] canvas`, (c) => Array.from(c.getContext('2d').getImageData(0, 0, c.width, c.height).data));
      const rgb = (b64) => Buffer.from(b64, 'base64');
      const cmp = (got, exp) => {
        let worst = 0, diff = 0;
        for (let i = 0; i < exp.length / 3; i++)
          for (let ch = 0; ch < 3; ch++) {
            const d = Math.abs(got[i * 4 + ch] - exp[i * 3 + ch]);
            worst = Math.max(worst, d);
            if (d) diff++;
          }
        return [worst, diff];
      };
      const [mw] = cmp(await canvas('mask'), rgb(want.mask));
      const counts = [await cp.textContent('#mask-over'), await cp.textContent('#mask-mismatch')];
      check(mw === 0 && counts[0] === String(want.over) && counts[1] === String(want.mismatch),
        `${id} (${want.encoding}): the script's mask = C++ error_maps (${want.over} over, ${want.mismatch} mismatched)`, [mw, counts]);
      const [hw] = cmp(await canvas('heat'), rgb(want.heat));
      await cp.selectOption('#heat-metric', 'itp');
      const [iw] = cmp(await canvas('heat'), rgb(want.heat_itp));
      check(hw <= 2 && iw <= 2, `${id}: the script's PQ and ΔE_ITP heatmaps = C++ error_maps within 2 codes`, [hw, iw]);
      await cp.close();
    }
    await pixBrowser.close();
  }

  // ---- The script's OpenEXR decoder (report.js decodeExr) on every form it reads: each value
  // equal to what OpenImageIO reads back from the same file (NaN as NaN, −0 as −0).
  console.log('EXR decoding');
  {
    const { page } = await openPage(context, url('index.html'), null);
    for (const f of expect.exr_forms) {
      const b64 = fs.readFileSync(path.join(dir, f.file)).toString('base64');
      const got = await page.evaluate(async ({ b64, w, h }) => Array.from(await decodeExr(b64, w, h)).map((v) => (Number.isNaN(v) ? 'NaN' : Object.is(v, -0) ? '-0' : v === Infinity ? 'Infinity' : v === -Infinity ? '-Infinity' : v)), { b64, w: f.w, h: f.h });
      const want = f.rgba.map((v) => (typeof v === 'string' ? v : Object.is(v, -0) ? '-0' : Math.fround(v)));
      const bad = want.findIndex((v, i) => v !== got[i]);
      check(got.length === want.length && bad < 0, `decodeExr(${f.file}) = OpenImageIO's values`, bad < 0 ? got.length : [bad, got[bad], want[bad]]);
    }
    const bad = await page.evaluate(async (b64) => {
      const out = [];
      const b = Uint8Array.from(atob(b64), (c) => c.charCodeAt(0));
      for (const n of [0, 7, 100, b.length >> 1, b.length - 1]) {
        try {
          await decodeExr(btoa(String.fromCharCode(...b.subarray(0, n))), 37, 19);
          out.push(n);
        } catch (e) { /* refused, as it must be */ }
      }
      try { await decodeExr(b64, 36, 19); out.push('size'); } catch (e) { /* refused */ }
      return out;
    }, fs.readFileSync(path.join(dir, expect.exr_forms[expect.exr_forms.length - 1].file)).toString('base64'));
    check(bad.length === 0, 'decodeExr refuses truncated files and a wrong size', bad);
    // toNits (how the script decodes values for its pictures and probe) = C++
    // OutputEncoding::to_nits for every transfer, to 1e-12 relative (Math.pow vs libm's pow).
    for (const t of expect.to_nits) {
      const got = await page.evaluate(({ e, v }) => v.map((x) => toNits(e, x)), { e: t.enc, v: t.v });
      const bad = t.nits.findIndex((n, i) => (n === 'NaN' ? !Number.isNaN(got[i]) : !(Math.abs(got[i] - n) <= 1e-12 * Math.abs(n))));
      check(bad < 0, `toNits(${t.enc.transfer}, pre_scale ${t.enc.pre_scale}) = C++ to_nits`, bad < 0 ? '' : [t.v[bad], got[bad], t.nits[bad]]);
    }
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

  // ---- The LUT-64³ page (4096 × 64 values a side, the heaviest case page of the default suite:
  // 4.1–4.4 s to interactive before issue 27): interactive within the limit, its views drawn.
  console.log('LUT-64³ case page');
  {
    const slug = await caseSlug(context, url('cases.html'), expect.lut64);
    const { page, dialogs: d, tti } = await openPage(context, url('c/' + slug), 'LUT-64³ case page');
    console.log(`  LUT-64³ case page: interactive in ${tti.toFixed(0)} ms`);
    check((await page.$$('#lut-panels canvas')).length === 3 && (await page.getAttribute('#lut-slice', 'max')) === '63', '64 blue slices; reference, candidate and error slices');
    const heat = await page.$eval('figure.panel[data-key="heat"] canvas', (c) => [c.width, c.height]);
    check(heat[0] === 4096 && heat[1] === 64, 'heatmap drawn at 4096 × 64', heat);
    const counts = [await page.textContent('#mask-over'), await page.textContent('#mask-mismatch')];
    check(counts[0] === '0' && counts[1] === '0', 'mask counts: nothing over the tolerance (passing case)', counts);
    check((await page.$$('#itp-histogram rect.bar')).length === 26, 'ΔE_ITP histogram drawn');
    dialogs.push(...d);
  }

  // ---- A ue58 case page (issue 27: the browser test's sample holds the heaviest kinds of case
  // page; bench/report_page_times.mjs times every page of a run): interactive within the limit,
  // its 16³ LUT's heatmap drawn (256 × 16), its resolved parameters listed.
  console.log('ue58 case page');
  {
    const slug = await caseSlug(context, url('cases.html'), expect.ue58);
    const { page, dialogs: d, tti } = await openPage(context, url('c/' + slug), 'ue58 case page');
    console.log(`  ue58 case page: interactive in ${tti.toFixed(0)} ms`);
    const heat = await page.$eval('figure.panel[data-key="heat"] canvas', (c) => [c.width, c.height]);
    check(heat[0] === 256 && heat[1] === 16, 'ue58: heatmap drawn at 256 × 16', heat);
    const resolved = await page.$$eval('#resolved tr', (rs) => rs.map((r) => r.children[0].textContent));
    check(resolved.length > 10, 'ue58: the resolved parameters are listed', resolved.length);
    const settings = await page.$$eval('#settings tr', (rs) => rs.map((r) => r.children[0].textContent));
    check(settings.includes('r.HDR.Aces.Version') && settings.includes('TonemappingMethod'), 'ue58: its settings are listed', settings);
    dialogs.push(...d);
  }

  // ---- The planted ACES regression (issue 14): the matrix, the case page's HDR views and the
  // ramp plot, as screenshots in the artifacts.
  console.log('ACES regression');
  {
    const mx = await openPage(context, url('matrix.html') + '#stage=tonemap&show=budget', 'matrix (tonemap budget)');
    await mx.page.screenshot({ path: path.join(artifacts, 'aces-matrix.png'), fullPage: true });
    const slug = await caseSlug(context, url('cases.html'), expect.aces);
    const { page, dialogs: d } = await openPage(context, url('c/' + slug), 'ACES case page');
    for (const m of ['clip', 'tonemap', 'falsecolour', 'pq']) {
      await page.selectOption('#display-mode', m);
      await page.selectOption('#view-mode', 'side');
      await page.locator('#images').screenshot({ path: path.join(artifacts, `aces-case-${m}.png`) });
    }
    await page.locator('#plots').screenshot({ path: path.join(artifacts, 'aces-ramp-plot.png') });
    // The ramp plot makes the regression visible: the candidate's curve leaves the reference's
    // over 200 nits, and the error line crosses the tolerance there.
    const errMax = await page.$eval('#ramp-error polyline.err', (p) => Math.min(...p.getAttribute('points').split(' ').map((q) => Number(q.split(',')[1]))));
    const tolY = await page.$eval('#ramp-error line.tol', (l) => Number(l.getAttribute('y1')));
    check(errMax < tolY, 'the ramp error rises above the tolerance line (planted regression visible)', [errMax, tolY]);
    await page.close();
    // The HDR path (#hdr=1 stands in for an HDR display): a 16-bit PQ PNG with cICP, decoded.
    const hdr = await openPage(context, url('c/' + slug) + '#hdr=1', 'ACES case page, HDR path');
    await hdr.page.waitForFunction(() => { const i = document.querySelector('figure.panel[data-key="candidate"] img.hdr'); return i && i.complete && i.naturalWidth > 0; }, null, { timeout: 10000 });
    const dims = await hdr.page.$eval('figure.panel[data-key="candidate"] img.hdr', (i) => [i.naturalWidth, i.naturalHeight, i.src.startsWith('blob:')]);
    check(dims[0] === 256 && dims[1] === 4 && dims[2], 'HDR view shows the PQ PNG (256 × 4)', dims);
    drove('case', '#display-mode hdr');
    await hdr.page.locator('#images').screenshot({ path: path.join(artifacts, 'aces-case-hdr.png') });
    dialogs.push(...d, ...hdr.dialogs, ...mx.dialogs);
  }

  // ---- Hue sweep: the CIE xy plot with the gamut triangles.
  console.log('hue sweep case page');
  {
    const slug = await caseSlug(context, url('cases.html'), expect.hue);
    const { page, dialogs: d } = await openPage(context, url('c/' + slug), 'hue case page');
    const gamuts = await page.$$eval('#xy-plot polygon[data-gamut]', (p) => p.map((x) => x.dataset.gamut));
    check(gamuts.join() === 'Rec.709,P3-D65,Rec.2020,AP1', 'xy plot with the Rec.709, P3, Rec.2020 and AP1 triangles', gamuts);
    const dots = await page.$$eval('#xy-plot circle', (c) => c.length);
    check(dots > 10, `xy plot shows the reference's chromaticities (${dots} points)`);
    await page.locator('#plots').screenshot({ path: path.join(artifacts, 'hue-xy-plot.png') });
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
  // ---- The golden review (`hdrconform goldens diff`, run.sh wrote goldens-review/out): a planted
  // change of one reference constant. review.html lists the changed golden with its largest PQ
  // move (expect.json: computed by the fixture from the two EXRs); its case page shows the old
  // golden as the reference and the new as the candidate, with both ramp curves.
  console.log('golden review');
  {
    const reviewDir = path.join(dir, 'goldens-review', 'out');
    const page = await context.newPage();
    const errors = [], foreign = [];
    page.on('pageerror', (e) => errors.push(String(e)));
    page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
    page.on('request', (r) => { if (!/^(file|data|blob):/.test(r.url())) foreign.push(r.url()); });
    await page.goto(pathToFileURL(path.join(reviewDir, 'review.html')).href, { waitUntil: 'load' });
    const rows = await page.$$eval('#changes tbody tr', (trs) => trs.map((tr) => [...tr.cells].map((c) => c.textContent)));
    check(rows.length === 1 && rows[0][0] === expect.review.id && rows[0][1] === 'changed',
      'review page lists the one changed golden', rows);
    const pqMax = rows.length ? Number(rows[0][3]) : NaN;
    check(close(pqMax, expect.review.pq10_max, 0.006),
      `review page: PQ max ${pqMax} codes = the fixture's |new − old| · 1023 (${expect.review.pq10_max.toPrecision(4)})`);
    check(errors.length === 0 && foreign.length === 0, 'review page: 0 console errors, no request leaves file://', [errors, foreign]);
    await page.screenshot({ path: path.join(artifacts, 'goldens-review.png'), fullPage: true });
    const href = await page.$eval('#changes tbody a', (a) => a.href);
    await page.close();
    const cp = await openPage(context, href, 'golden review: case page');
    const curves = await cp.page.$$eval('#ramp-plot polyline', (ps) => ps.map((p) => p.getAttribute('class')));
    check(curves.includes('ref') && curves.includes('cand'), 'golden review: the ramp plot has the old (reference) and the new (candidate) curve', curves);
    const bars = await cp.page.$$eval('#itp-histogram rect.bar', (r) => r.length);
    check(bars > 0, 'golden review: the ΔE_ITP histogram is drawn', bars);
    await cp.page.locator('#plots').screenshot({ path: path.join(artifacts, 'goldens-review-ramp-plot.png') });
    await cp.page.screenshot({ path: path.join(artifacts, 'goldens-review-case.png'), fullPage: true });
    dialogs.push(...cp.dialogs);
    await cp.page.close();
  }

  check(dialogs.length === 0, 'no dialog (alert) opened on any page', dialogs);
  drove('LUT', '#lut-slice');
  drove('LUT', '#lut-goto-worst');
  const pages = new Set([...controls].map((c) => c.split(':')[0]));
  console.log(`controls driven: ${controls.size} (${[...pages].map((p) => p + ' ' + [...controls].filter((c) => c.startsWith(p + ':')).length).join(', ')})`);
  await browser.close();
}

async function caseSlug(context, listUrl, id) {
  const { page } = await openPage(context, listUrl, null);
  const href = await page.$$eval('#case-table tbody tr', (trs, id) => {
    const tr = trs.find((x) => x.querySelector('a.case-link').title === id);
    return tr ? tr.querySelector('a').getAttribute('href') : null;
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
