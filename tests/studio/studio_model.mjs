// inhap studio's Model view in the system Chromium (puppeteer-core from web/node_modules). Run by
// ctest (studio.model):
//   node studio_model.mjs --inhap BIN --web WEB_DIR --out OUT_DIR
// lab:planar at --speed 20: the lab's explore operator records 65 simulated s (the training run of
// `inhap lab record --operator explore --coverage`), the coverage map shows visited cells; the
// recording and its truth land in the workspace; training (a process of its own, one thread,
// its CPU group at nice 19: the lab scene
// palpated as `sys palpate`, the proxy as `sys proxy`, then `model train`) writes the model, the
// yield surfaces, shape, proxied recording and coverage; the servo loop's statistics are printed for a stretch without
// and a stretch with training beside it; then a scripted mouse path is felt on the object and on
// the model, and the running RMSE per axis of model - object is checked against the planar
// target of `eval forces` (0.15 N); two blind answers land in the answers CSV; no console error.
// Screenshot: OUT_DIR/studio-model.png. Exit 77: skipped.
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

const arg = (k) => { const i = process.argv.indexOf(k); return i > 0 ? process.argv[i + 1] : undefined; };
const bin = arg('--inhap'), web = arg('--web'), out = arg('--out');
const slow = Math.max(1, +(arg('--slow') || 1)), T = (ms) => ms * slow;
let puppeteer;
try { puppeteer = createRequire(path.resolve(web, 'package.json'))('puppeteer-core'); }
catch { console.log('skipped: puppeteer-core is not installed (./run setup runs npm ci --prefix web)'); process.exit(77); }
if (!fs.existsSync('/usr/bin/chromium')) { console.log('skipped: no /usr/bin/chromium'); process.exit(77); }
fs.mkdirSync(out, { recursive: true });
const workspace = fs.mkdtempSync(path.join(os.tmpdir(), 'inhap-studio-model-'));
const t0 = Date.now();
const log = (...a) => console.log(`[${((Date.now() - t0) / 1000).toFixed(1)} s]`, ...a);
const failures = [];
const check = (ok, what) => { log((ok ? 'ok   ' : 'FAIL ') + what); if (!ok) failures.push(what); };
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

const server = spawn(bin, ['studio', '--device', 'lab:planar', '--workspace', workspace, '--port', '0',
  '--speed', '20', '--seed', '1', '--web-dir', web, '--seconds', String(T(400))], { stdio: ['ignore', 'pipe', 'pipe'] });
let stderr = '';
server.stderr.on('data', (d) => { stderr += d; });
const url = await new Promise((resolve, reject) => {
  let buf = '';
  server.stdout.on('data', (d) => { buf += d; const m = buf.match(/^(http:\/\/127\.0\.0\.1:\d+\/\?token=[0-9a-f]{32})$/m); if (m) resolve(m[1]); });
  server.on('exit', (c) => reject(new Error(`inhap studio exited (${c}): ${stderr}`)));
  setTimeout(() => reject(new Error(`no URL within ${T(30)} s: ` + stderr)), T(30000));
});

// protocolTimeout: one DevTools call (a long waitForFunction included) may take as long as the
// longest wait below; puppeteer's default would end it after 180 s.
const browser = await puppeteer.launch({
  executablePath: '/usr/bin/chromium', headless: true, protocolTimeout: T(600000),
  args: ['--no-sandbox', '--disable-gpu', '--enable-unsafe-swiftshader', '--use-angle=swiftshader',
    '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync',
    '--disable-extensions', '--disable-background-timer-throttling', '--disable-renderer-backgrounding'],
});
const consoleErrors = [];
let exitCode = 1;
const statsLine = (s) => `ticks ${s.ticks}, step p50/p99/max ${s.step_p50_us.toFixed(2)}/${s.step_p99_us.toFixed(2)}/${s.step_max_us.toFixed(1)} us, ` +
  `period jitter p50/p99/max ${s.jitter_p50_us.toFixed(0)}/${s.jitter_p99_us.toFixed(0)}/${s.jitter_max_us.toFixed(0)} us, overruns ${s.overruns}`;
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1280, height: 760 });
  page.on('console', (m) => { if (m.type() === 'error') consoleErrors.push(m.text()); });
  page.on('pageerror', (e) => consoleErrors.push('page error: ' + e.message));
  page.on('requestfailed', (r) => consoleErrors.push('request failed: ' + r.url()));
  await page.goto(url, { waitUntil: 'load' });
  await page.waitForFunction(() => window.studio && window.studio.ready && window.studio.model.object, { timeout: T(20000) });
  await page.click('button[data-view="model"]');
  await page.waitForFunction(() => window.studio.lastReply && window.studio.lastReply.mode === 'model', { timeout: T(10000) });

  // 1. Record 65 simulated s with the lab's explore operator.
  await page.click('#mrec');
  await page.waitForFunction(() => window.studio.model.coverage && window.studio.model.coverage.cells.length > 0, { timeout: T(30000), polling: 100 });
  const early = await page.evaluate(() => ({ t: window.studio.model.coverage.t, cells: window.studio.model.coverage.cells.length }));
  log(`coverage while recording: ${early.cells} cells at ${early.t.toFixed(1)} simulated s`);
  await page.waitForFunction(() => window.studio.model.recorded, { timeout: T(120000), polling: 250 });
  const rec = await page.evaluate(() => window.studio.model.recorded);
  const cov = await page.evaluate(() => window.studio.model.coverage);
  log(`recorded ${rec.rows} rows (${rec.contact_rows} in contact), ${rec.seconds.toFixed(1)} simulated s in ${((Date.now() - t0) / 1000).toFixed(0)} s wall`);
  check(rec.seconds >= 60, `>= 60 simulated s recorded with the explore operator (${rec.seconds.toFixed(1)} s)`);
  check(cov.cells.length > 50 && cov.cells.length > early.cells, `the coverage map shows visited cells, growing (${early.cells} -> ${cov.cells.length}; ${cov.gaps.length} gaps marked)`);
  check(fs.existsSync(path.join(workspace, 'model-rec.csv')) && fs.existsSync(path.join(workspace, 'model-rec.truth.csv')), 'model-rec.csv and its truth in the workspace');

  // 2. Servo statistics without training (fresh loop, 8 s), then train with a fresh loop beside it.
  const stats = async () => {
    const n = await page.evaluate(() => { window.studio.send({ type: 'model_stats' }); return window.studio.model.stats.length; });
    await page.waitForFunction((k) => window.studio.model.stats.length > k, { timeout: T(30000) }, n);
    return page.evaluate(() => window.studio.model.stats[window.studio.model.stats.length - 1]);
  };
  await stats();  // restarts the loop: the next figures cover only the stretch after it
  await sleep(T(8000));
  const idle = await stats();
  log(`MEASURED servo loop, no training (8 s): ${statsLine(idle)}; load average ${os.loadavg()[0].toFixed(1)}`);
  // Cancel: a training started and cancelled at once ends as cancelled and writes no model.
  await page.click('#mtrain');
  await page.waitForFunction(() => window.studio.lastReply && window.studio.lastReply.request === 'model_train', { timeout: T(10000) });
  await page.click('#mcancel');
  // The training thread runs at nice 19: on a saturated machine (the sanitizer suite, load 7.7 on
  // two cores) it reached its next cancel point only after more than 180 s.
  await page.waitForFunction(() => window.studio.model.trained, { timeout: T(180000), polling: 100 });
  const cancelled = await page.evaluate(() => { const t = window.studio.model.trained; window.studio.model.trained = null; return t; });
  const leftovers = fs.readdirSync(workspace).filter((f) => f.startsWith('model.'));
  check(cancelled.status === 'cancelled' && leftovers.length === 0, `Cancel: the training ends as ${cancelled.status}, none of its files written (${leftovers.join(', ') || 'none'})`);
  await stats();  // a fresh loop for the figures beside the training
  const trainStart = Date.now();
  await page.click('#mtrain');
  await page.waitForFunction(() => window.studio.model.trained, { timeout: T(300000), polling: 250 });
  const trainWall = (Date.now() - trainStart) / 1000;
  const busy = await stats();
  const tr = await page.evaluate(() => window.studio.model.trained);
  log(`MEASURED servo loop while training (${trainWall.toFixed(1)} s): ${statsLine(busy)}; load average ${os.loadavg()[0].toFixed(1)}`);
  check(tr.status === 'done', `training finished (${tr.status}${tr.message ? ': ' + tr.message : ''})`);
  const rate = (s) => (100 * s.overruns / Math.max(1, s.ticks)).toFixed(2);
  log(`MEASURED servo beside training: without ${idle.overruns} overruns in ${idle.ticks} ticks (${rate(idle)} %, worst wake-up ${(idle.jitter_max_us / 1000).toFixed(1)} ms), ` +
    `with ${busy.overruns} in ${busy.ticks} (${rate(busy)} %, worst wake-up ${(busy.jitter_max_us / 1000).toFixed(1)} ms); ` +
    `training: its own process, ${tr.threads} thread, ${(tr.cpu_s || 0).toFixed(1)} s CPU in ${(tr.wall_s || 0).toFixed(1)} s wall = ${(tr.cores || 0).toFixed(2)} cores`);
  if (tr.status === 'done') log(`training printed:\n${tr.lines.join('\n')}`);
  // The machine's own overruns (other tests on two cores, the hypervisor) come and go between the
  // 8 s idle window and the training's: allowed are twice the idle rate plus 2 % of the ticks.
  // (A training thread in the studio's own scheduling group made the servo thread wait for the
  // group's share on every late wake-up: docs/studio.md, "Train".)
  const allowed = Math.max(2, 2 * idle.overruns * (busy.ticks / Math.max(1, idle.ticks)) + 0.02 * busy.ticks);
  check(busy.overruns <= allowed,
    `no overruns caused by training (${busy.overruns} in ${busy.ticks} ticks vs ${idle.overruns} in ${idle.ticks} without; allowed ${allowed.toFixed(0)})`);
  for (const f of ['model.json', 'model.coverage.csv', 'model.palpation.json', 'model.palpation.shape.ply', 'model.proxy.csv'])
    check(fs.existsSync(path.join(workspace, f)), `${f} in the workspace`);
  await sleep(500);
  await page.screenshot({ path: path.join(out, 'studio-model-coverage.png') });

  // 3. Feel: a scripted mouse path (press, slide, release) on the object, then on the model.
  const drive = async (seconds, shot) => {
    const t1 = Date.now() + seconds * 1000;
    const strokes = [[[-8, -4], [8, -4]], [[8, 2], [-8, 2]], [[-6, 6], [6, 6]], [[0, -8], [0, 8]]];
    let k = 0;
    while (Date.now() < t1) {
      const [[x0, y0], [x1, y1]] = strokes[k++ % strokes.length];
      const a = await page.evaluate((x, y) => window.studio.model.screenPos(x, y), x0, y0);
      const b = await page.evaluate((x, y) => window.studio.model.screenPos(x, y), x1, y1);
      await page.mouse.move(a.x, a.y, { steps: 5 });
      await sleep(300);
      await page.mouse.down();
      for (let i = 1; i <= 60; ++i) {
        await page.mouse.move(a.x + (b.x - a.x) * i / 60, a.y + (b.y - a.y) * i / 60); await sleep(25);
        if (shot && k === 2 && i === 40) await page.screenshot({ path: path.join(out, 'studio-model.png') });  // pressed, mid-slide
      }
      await page.mouse.up();
      await sleep(300);
    }
  };
  await page.click('#mobject');
  await drive(8);
  const onObject = await page.evaluate(() => ({ rmse: window.studio.model.rmse, n: window.studio.model.n, src: window.studio.model.source }));
  log(`felt: ${onObject.src}; RMSE model - object x/y/z ${onObject.rmse.map((v) => v.toFixed(3)).join(' / ')} N over ${onObject.n} ticks`);
  await page.keyboard.press('m');  // A/B: the model
  await page.waitForFunction(() => window.studio.model.source === 'model', { timeout: T(5000) });
  await drive(8, true);
  const both = await page.evaluate(() => ({ rmse: window.studio.model.rmse, n: window.studio.model.n }));
  log(`MEASURED model vs object along the scripted path: RMSE x/y/z ${both.rmse.map((v) => v.toFixed(3)).join(' / ')} N over ${both.n} ticks in contact`);
  check(both.n > 1000 && both.rmse.every((v) => v <= 0.15), `RMSE per axis <= 0.15 N (${both.rmse.map((v) => v.toFixed(3)).join(' / ')})`);

  // 4. Blind: two answers.
  await page.click('#mblind');
  await page.waitForFunction(() => window.studio.model.blind, { timeout: T(5000) });
  await page.keyboard.press('m');
  await sleep(300);
  await page.click('#mansb');
  await page.waitForFunction(() => window.studio.model.answers === 1, { timeout: T(5000) });
  await page.keyboard.press('m');
  await sleep(300);
  await page.click('#mansa');
  await page.waitForFunction(() => window.studio.model.answers === 2, { timeout: T(5000) });
  const hidden = await page.evaluate(() => document.getElementById('mcompare').classList.contains('hidden') && !/object|model/.test(document.getElementById('msource').textContent));
  check(hidden, 'blind: the label and the plot are hidden');
  let rows = [];
  try { rows = fs.readFileSync(path.join(workspace, 'model-ab.csv'), 'utf8').split('\n').filter((l) => /^\d/.test(l)); } catch { /* checked below */ }
  check(rows.length === 2, `two blind answers in model-ab.csv (${rows.join(' | ')})`);
  check(consoleErrors.length === 0, `no console errors (${consoleErrors.length}${consoleErrors.length ? ': ' + consoleErrors.slice(0, 3).join(' | ') : ''})`);
  exitCode = failures.length ? 1 : 0;
} catch (e) {
  failures.push(String(e));
  log('FAIL', e.stack || e);
  if (consoleErrors.length) log('console errors:', consoleErrors.slice(0, 5).join(' | '));
} finally {
  await browser.close();
  server.kill('SIGTERM');
  await new Promise((r) => { server.on('exit', r); setTimeout(r, 5000); });
  fs.rmSync(workspace, { recursive: true, force: true });
}
log(`${failures.length} failed; server log tail:\n${stderr.split('\n').slice(failures.length ? -40 : -6).join('\n')}`);
process.exit(exitCode);
