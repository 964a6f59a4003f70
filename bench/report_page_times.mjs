// Time to interactive of EVERY case page of a report (issue 27, item 6: "every case page of the
// default run is interactive within 2 s"). A one-off measurement, not a test: the browser test
// (report/browser_test, CTest's report.browser) times a sample that holds the heaviest kinds of
// page (the LUT-64³ page, a ue58 page, the failing page with its float data); this opens all of
// them, e.g. the 1655 of the default suite, which takes minutes.
//
//   node bench/report_page_times.mjs --report OUT/report [--tabs 4] [--chromium /usr/bin/chromium]
//                                    [--json FILE] [--limit-ms 2000]
//
// Time to interactive as the browser test defines it (report.test.mjs openPage): the page is
// loaded from file://, then the report's script marks it ready (<html data-ready="1">) and
// records performance.now() then in HDRC.tti (assets/report.js ready()), milliseconds from the
// navigation's start. --tabs pages load at once, each in a tab of its own (one browser): the
// figures include that contention, so they are an upper bound of a page opened alone; a page
// over the limit is opened again alone and both figures are printed. Prints the distribution
// (percentiles), the slowest 20 pages and every page with a script error; exits 1 when a page
// stays over the limit alone or has a script error. --json writes every page's time.
//
// playwright-core comes from the browser test's node_modules (scripts/setup.sh installs it);
// the browser is Debian's Chromium, started with the browser test's flags.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const { chromium } = await import(
  pathToFileURL(path.join(here, '..', 'report', 'browser_test', 'node_modules', 'playwright-core',
    'index.mjs')).href);

const args = process.argv.slice(2);
const opt = (name, dflt) => {
  const i = args.indexOf('--' + name);
  return i >= 0 ? args[i + 1] : dflt;
};
let report = opt('report');
if (!report) {
  console.error('usage: node bench/report_page_times.mjs --report OUT/report [--tabs N] ' +
    '[--chromium PATH] [--json FILE] [--limit-ms MS]');
  process.exit(2);
}
if (fs.existsSync(path.join(report, 'report', 'index.html'))) report = path.join(report, 'report');
const tabs = Math.max(1, Number(opt('tabs', '4')));
const limitMs = Number(opt('limit-ms', '2000'));
const executablePath = opt('chromium', '/usr/bin/chromium');
// report.test.mjs CHROME_ARGS: no background traffic on a closed network.
const CHROME_ARGS = ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync'];

const pages = fs.readdirSync(path.join(report, 'c')).filter((f) => f.endsWith('.html')).sort();
const browser = await chromium.launch({ executablePath, args: CHROME_ARGS });
const context = await browser.newContext({ viewport: { width: 1400, height: 1000 } });

// One page: load, wait for ready (or a script error), read HDRC.tti; as report.test.mjs openPage.
async function timePage(file) {
  const page = await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => {
    if (m.type() === 'error') errors.push(m.text());
  });
  try {
    await page.goto(pathToFileURL(path.join(report, 'c', file)).href, { waitUntil: 'load' });
    await page.waitForFunction(() => document.documentElement.dataset.ready === '1' ||
      document.documentElement.dataset.error, null, { timeout: 30000 });
    const tti = await page.evaluate(() => window.HDRC && window.HDRC.tti);
    const scriptError = await page.evaluate(() => document.documentElement.dataset.error || '');
    if (scriptError) errors.push(scriptError);
    return { file, tti, errors, bytes: fs.statSync(path.join(report, 'c', file)).size };
  } catch (e) {
    return { file, tti: Infinity, errors: errors.concat(String(e)), bytes: 0 };
  } finally {
    await page.close();
  }
}

const started = Date.now();
const load0 = os.loadavg()[0];
const results = [];
let next = 0;
await Promise.all(Array.from({ length: tabs }, async () => {
  while (next < pages.length) {
    const r = await timePage(pages[next++]);
    results.push(r);
    if (results.length % 200 === 0) console.error(`${results.length} of ${pages.length} pages`);
  }
}));
// A page over the limit under contention: again, alone.
for (const r of results)
  if (r.tti >= limitMs) r.alone = (await timePage(r.file)).tti;
const wallS = (Date.now() - started) / 1000;
await browser.close();

results.sort((a, b) => a.tti - b.tti);
const at = (q) => results[Math.min(results.length - 1, Math.floor(q * results.length))].tti;
const ms = (v) => (Number.isFinite(v) ? v.toFixed(0) : 'none');
console.log(`report: ${report}`);
console.log(`${results.length} case pages, ${tabs} tab(s) at once, ${wallS.toFixed(0)} s; load average ` +
  `${load0.toFixed(2)} at the start, ${os.loadavg()[0].toFixed(2)} at the end, ${os.cpus().length} CPUs; ` +
  new Date().toISOString());
console.log(`time to interactive (ms): min ${ms(results[0].tti)}, median ${ms(at(0.5))}, p90 ${ms(at(0.9))}, ` +
  `p99 ${ms(at(0.99))}, max ${ms(results[results.length - 1].tti)}`);
const buckets = [250, 500, 1000, 1500, 2000, Infinity];
let from = 0;
for (const b of buckets) {
  const n = results.filter((r) => r.tti >= from && r.tti < b).length;
  console.log(`  [${from}, ${Number.isFinite(b) ? b : '∞'}) ms: ${n}`);
  from = b;
}
console.log('slowest 20 (ms, page bytes, page):');
for (const r of results.slice(-20).reverse())
  console.log(`  ${ms(r.tti)}${r.alone !== undefined ? ` (alone ${ms(r.alone)})` : ''}  ${r.bytes}  ${r.file}`);
const broken = results.filter((r) => r.errors.length);
for (const r of broken) console.log(`script error: ${r.file}: ${r.errors.join(' | ')}`);
const over = results.filter((r) => (r.alone !== undefined ? r.alone : r.tti) >= limitMs);
console.log(`${over.length} page(s) over ${limitMs} ms alone, ${broken.length} with a script error`);
const json = opt('json');
if (json)
  fs.writeFileSync(json, JSON.stringify({ report, tabs, wall_s: wallS, load_start: load0,
    pages: results.map((r) => ({ file: r.file, tti_ms: r.tti, alone_ms: r.alone, bytes: r.bytes,
      errors: r.errors })) }, null, 1));
process.exit(over.length || broken.length ? 1 : 0);
