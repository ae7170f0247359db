// inhap studio in the system Chromium, driven through the DevTools protocol (puppeteer-core
// from web/node_modules). Run by ctest (studio.browser):
//   node studio_browser.mjs --inhap BIN --web WEB_DIR --out OUT_DIR
// Checks: a request without the token -> 403; a sampling session on the lab with the simulated
// tapping operator (>= 50 taps) -> two samples deleted by clicking -> reconstruct -> export: the
// exported points number taps - 2 and the mesh has faces; in the explore view a mouse drag makes
// contact and a non-zero force; three experiment answers land in the participant's CSV; a
// palpation of one clicked reference point finishes, and sys.json lands in the workspace and
// reads back; no console error. Measures (reports, does not assert) the mouse-to-probe latency in frames and
// the page's frame rate. Screenshots of each view go to OUT_DIR/*.png. Exit 77: skipped.
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import fs from 'node:fs';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';

const arg = (k) => { const i = process.argv.indexOf(k); return i > 0 ? process.argv[i + 1] : undefined; };
const bin = arg('--inhap'), web = arg('--web'), out = arg('--out');
// --slow F: every wait and the server's lifetime F times longer (the sanitizer build: ASan and
// UBSan slow the lab and the server down).
const slow = Math.max(1, +(arg('--slow') || 1)), T = (ms) => ms * slow;
let puppeteer;
try { puppeteer = createRequire(path.resolve(web, 'package.json'))('puppeteer-core'); }
catch { console.log('skipped: puppeteer-core is not installed (./run setup runs npm ci --prefix web)'); process.exit(77); }
if (!fs.existsSync('/usr/bin/chromium')) { console.log('skipped: no /usr/bin/chromium'); process.exit(77); }
fs.mkdirSync(out, { recursive: true });
const workspace = fs.mkdtempSync(path.join(os.tmpdir(), 'inhap-studio-'));
const t0 = Date.now();
const log = (...a) => console.log(`[${((Date.now() - t0) / 1000).toFixed(1)} s]`, ...a);
const failures = [];
const check = (ok, what) => { log((ok ? 'ok   ' : 'FAIL ') + what); if (!ok) failures.push(what); };
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
// The page's JS time per frame (the render call and the whole rAF callback), median / p90 in ms,
// since the last call; with the machine's load average (the timings depend on it).
async function framePerf(page, what) {
  const p = await page.evaluate(() => {
    const q = (a, f) => { const v = a.slice().sort((x, y) => x - y); return v.length ? v[Math.min(v.length - 1, Math.floor(f * v.length))] : NaN; };
    const S = window.studio, r = { r50: q(S.perf.renderMs, 0.5), r90: q(S.perf.renderMs, 0.9), f50: q(S.perf.frameMs, 0.5), f90: q(S.perf.frameMs, 0.9), pr: S.pixelRatio };
    S.perf.renderMs.length = 0; S.perf.frameMs.length = 0;
    return r;
  });
  log(`MEASURED ${what}: render call ${p.r50.toFixed(2)} / ${p.r90.toFixed(2)} ms, frame callback ${p.f50.toFixed(2)} / ${p.f90.toFixed(2)} ms (median / p90), pixel ratio ${p.pr}, load average ${os.loadavg()[0].toFixed(1)}`);
}

// --- the server ----------------------------------------------------------------------------
const server = spawn(bin, ['studio', '--device', 'lab:dome', '--workspace', workspace, '--port', '0',
  '--speed', '4', '--seed', '3', '--web-dir', web, '--seconds', String(T(400))], { stdio: ['ignore', 'pipe', 'pipe'] });
let stderr = '';
server.stderr.on('data', (d) => { stderr += d; });
const url = await new Promise((resolve, reject) => {
  let buf = '';
  server.stdout.on('data', (d) => { buf += d; const m = buf.match(/^(http:\/\/127\.0\.0\.1:\d+\/\?token=[0-9a-f]{32})$/m); if (m) resolve(m[1]); });
  server.on('exit', (c) => reject(new Error(`inhap studio exited (${c}): ${stderr}`)));
  setTimeout(() => reject(new Error(`no URL within ${T(30)} s: ` + stderr)), T(30000));
});
log('server at', url.replace(/token=.*/, 'token=…'));
const base = url.replace(/\/\?token=.*/, '');

function get(u, headers = {}) {
  return new Promise((resolve) => {
    http.get(u, { headers }, (res) => { res.resume(); res.on('end', () => resolve(res.statusCode)); })
      .on('error', () => resolve(-1));
  });
}
check(await get(base + '/') === 403, 'GET / without the token -> 403');
check(await get(base + '/lib/three.module.js') === 403, 'GET a library without the token -> 403');
check(await get(base + '/?token=0123456789abcdef0123456789abcdef') === 403, 'GET / with a wrong token -> 403');
check(await get(url, { Origin: 'http://evil.example' }) === 403, 'GET with a foreign Origin -> 403');
check(await get(url) === 200, 'GET / with the token -> 200');

// --- the browser ---------------------------------------------------------------------------
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
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1280, height: 760 });
  page.on('console', (m) => { if (m.type() === 'error') consoleErrors.push(m.text()); });
  page.on('pageerror', (e) => consoleErrors.push('page error: ' + e.message));
  page.on('requestfailed', (r) => consoleErrors.push('request failed: ' + r.url()));
  await page.goto(url, { waitUntil: 'load' });
  await page.waitForFunction(() => window.studio && window.studio.ready, { timeout: T(20000) });
  log('page ready');

  // Sampling: wait for >= 50 taps, pause the operator, delete two samples by clicking.
  const wantTaps = 50;
  await page.waitForFunction((n) => window.studio.taps >= n, { timeout: T(90000), polling: 250 }, wantTaps);
  await framePerf(page, 'warm-up');
  const f0 = await page.evaluate(() => window.studio.frames), ts0 = Date.now();
  await sleep(2000);
  const fpsSampling = (await page.evaluate(() => window.studio.frames) - f0) / ((Date.now() - ts0) / 1000);
  log(`MEASURED page frame rate in the sampling view (operator tapping): ${fpsSampling.toFixed(1)} fps, load average ${os.loadavg()[0].toFixed(1)}`);
  await framePerf(page, 'sampling view');
  await page.click('#pause');
  await page.waitForFunction(() => window.studio.lastReply && window.studio.lastReply.mode === 'idle', { timeout: T(10000) });
  await sleep(300);
  const taps = await page.evaluate(() => window.studio.taps);
  log(`taps detected: ${taps} (simulated ${await page.evaluate(() => window.studio.state.t.toFixed(1))} s)`);
  check(taps >= wantTaps, `sampling session with >= ${wantTaps} taps (${taps})`);
  await page.screenshot({ path: path.join(out, 'studio-sampling.png') });
  // Two samples far (in pixels) from every other sample, so the click hits only that one.
  const targets = await page.evaluate(() => {
    const S = window.studio, pos = S.sampleIds().map((id) => [id, S.sampleScreenPos(id)]);
    const clear = pos.filter(([id, p]) => pos.every(([j, q]) => j === id || Math.hypot(p.x - q.x, p.y - q.y) > 14));
    return clear.slice(0, 2);
  });
  check(targets.length === 2, 'two isolated samples to click');
  for (const [id, p] of targets) {
    const before = await page.evaluate(() => window.studio.samples.size);
    await page.mouse.click(p.x, p.y);
    await page.waitForFunction((b) => window.studio.samples.size === b - 1, { timeout: T(5000) }, before)
      .catch(() => check(false, `click deletes sample ${id}`));
  }
  const live = await page.evaluate(() => window.studio.samples.size);
  check(live === taps - 2, `live samples after two clicks = taps - 2 (${live} = ${taps} - 2)`);
  await page.click('#reconstruct');
  await page.waitForFunction(() => window.studio.mesh || (window.studio.lastReply && window.studio.lastReply.type === 'error'), { timeout: T(60000) });
  const mesh = await page.evaluate(() => window.studio.mesh);
  check(mesh && mesh.faces > 0, `reconstruction has faces (${mesh ? mesh.faces : 0})`);
  await page.click('#export');
  await page.waitForFunction(() => window.studio.lastReply && window.studio.lastReply.request === 'export', { timeout: T(20000) });
  const plyCount = (f, what) => { const h = fs.readFileSync(path.join(workspace, f)).subarray(0, 600).toString('latin1');
    const m = h.match(new RegExp(`element ${what} (\\d+)`)); return m ? +m[1] : -1; };
  const exported = plyCount('samples.ply', 'vertex'), faces = plyCount('mesh.ply', 'face');
  check(exported === taps - 2, `exported points = taps - 2 (${exported} = ${taps} - 2)`);
  check(faces > 0, `exported mesh is non-empty (${faces} faces)`);
  await page.screenshot({ path: path.join(out, 'studio-reconstruction.png') });
  // The outlier filter and the jet projection, previewed (not applied: the export above stands).
  await page.click('#preview');
  await page.waitForFunction(() => window.studio.preview || (window.studio.lastReply && window.studio.lastReply.type === 'error'), { timeout: T(20000) });
  const pv = await page.evaluate(() => window.studio.preview && { o: window.studio.preview.outliers.length, m: window.studio.preview.moves.length, med: window.studio.preview.median_move, live: window.studio.samples.size });
  check(pv && pv.o + pv.m === pv.live, `preview: ${pv ? pv.o : '?'} outlier(s) + ${pv ? pv.m : '?'} projected = ${pv ? pv.live : '?'} live samples (median move ${pv ? pv.med.toFixed(3) : '?'} mm)`);
  await page.screenshot({ path: path.join(out, 'studio-preview.png') });

  // Explore: the 25-model surface; a mouse drag presses the lab probe onto it.
  await page.click('button[data-view=explore]');
  await page.waitForFunction(() => window.studio.exploreMesh > 0, { timeout: T(20000) });
  await sleep(800);
  const box = await (await page.$('#view3d canvas')).boundingBox();
  const cx = box.x + box.width * 0.5, cy = box.y + box.height * 0.5;
  await page.mouse.move(cx, cy);
  for (let i = 0; i < 20; ++i) { await page.mouse.move(cx + i, cy); await sleep(30); }
  await framePerf(page, 'explore, mouse moving');
  const fps0 = await page.evaluate(() => window.studio.frames);
  const tf0 = Date.now();
  const r0 = await page.evaluate(() => { const S = window.studio; S.latencies.length = 0; S.latencyMs.length = 0; S.latencyEventMs.length = 0; S.contactSeen = false; S.maxForce = 0; return S.renders; });
  await page.mouse.down();
  for (let i = 0; i < 60; ++i) { await page.mouse.move(cx + 20 - i, cy + i * 1.5); await sleep(33); }
  await sleep(300);
  const ex = await page.evaluate(() => ({ contact: window.studio.contactSeen, f: window.studio.maxForce, lat: window.studio.latencies.slice(), ms: window.studio.latencyMs.slice(), ev: window.studio.latencyEventMs.slice(), fps: window.studio.fps, renders: window.studio.renders }));
  const fpsMeasured = (await page.evaluate(() => window.studio.frames) - fps0) / ((Date.now() - tf0) / 1000);
  const webglPerS = (ex.renders - r0) / ((Date.now() - tf0) / 1000);
  await framePerf(page, 'explore view while dragging');
  await page.screenshot({ path: path.join(out, 'studio-explore.png') });
  await page.mouse.up();
  check(ex.contact, 'explore: the drag made contact');
  check(ex.f > 0, `explore: non-zero force (max ${ex.f.toFixed(2)} N)`);
  const lat = ex.lat.slice().sort((a, b) => a - b);
  const q = (p) => (lat.length ? lat[Math.min(lat.length - 1, Math.floor(p * lat.length))] : NaN);
  const ms = ex.ms.slice().sort((a, b) => a - b);
  log(`MEASURED round trip (target sent -> applied by the servo thread -> state on the page): median ${ms[Math.floor(ms.length / 2)].toFixed(1)} ms, p90 ${ms[Math.floor(0.9 * ms.length)].toFixed(1)} ms`);
  const evms = ex.ev.slice().sort((a, b) => a - b);
  log(`MEASURED mouse event time stamp -> start of the frame that draws the probe: median ${evms[Math.floor(evms.length / 2)].toFixed(1)} ms, p90 ${evms[Math.floor(0.9 * evms.length)].toFixed(1)} ms`);
  log(`MEASURED mouse-to-probe latency: median ${q(0.5)} frames, p90 ${q(0.9)}, max ${lat[lat.length - 1]} (${lat.length} moves); page ${fpsMeasured.toFixed(1)} fps while dragging (rAF counter ${ex.fps.toFixed(1)}; WebGL renders ${webglPerS.toFixed(1)}/s), load average ${os.loadavg()[0].toFixed(1)}`);

  // Experiment: participant 7, three answers at three models.
  await page.click('button[data-view=experiment]');
  await page.$eval('#participant', (e) => { e.value = '7'; });
  await page.click('#expstart');
  await page.waitForFunction(() => window.studio.trial && window.studio.trial.participant === 7, { timeout: T(20000) });
  // The experimenter's own window (?view=experimenter): progress and scores, live.
  const xpage = await browser.newPage();
  await xpage.setViewport({ width: 900, height: 700 });
  xpage.on('console', (m) => { if (m.type() === 'error') consoleErrors.push('experimenter: ' + m.text()); });
  xpage.on('pageerror', (e) => consoleErrors.push('experimenter page error: ' + e.message));
  await xpage.goto(url + '&view=experimenter', { waitUntil: 'load' });
  await xpage.waitForFunction(() => window.studio && window.studio.progress && window.studio.progress.running, { timeout: T(20000) });
  await page.bringToFront();
  for (const cell of [0, 12, 24]) {
    const p = await page.evaluate((c) => window.studio.cellScreenPos(c), cell);
    await page.mouse.move(p.x - 30, p.y - 30);
    await page.mouse.move(p.x, p.y, { steps: 5 });
    await page.waitForFunction((c) => window.studio.hipCell() === c, { timeout: T(15000), polling: 50 }, cell)
      .catch(() => check(false, `the HIP reaches model cell ${cell}`));
    const before = await page.evaluate(() => window.studio.answered);
    await page.keyboard.press(String(cell % 3));
    await page.waitForFunction((b) => window.studio.answered === b + 1, { timeout: T(5000) }, before)
      .catch(() => check(false, `answer at cell ${cell} accepted`));
  }
  await page.screenshot({ path: path.join(out, 'studio-experiment.png') });
  const csvPath = path.join(workspace, 'participant-007.csv');
  const rows = fs.existsSync(csvPath) ? fs.readFileSync(csvPath, 'utf8').split('\n').filter((l) => /^\d/.test(l)) : [];
  check(rows.length === 3, `three answers in participant-007.csv (${rows.length})`);
  check(rows.map((r) => r.split(',')[6]).join(' ') === '0 12 24', `answers at cells 0, 12, 24 (${rows.map((r) => r.split(',')[6]).join(' ')})`);

  await xpage.waitForFunction(() => window.studio.progress.answers === 3 && window.studio.summary && window.studio.summary.trials === 1, { timeout: T(15000), polling: 100 }).catch(() => {});
  const xs = await xpage.evaluate(() => ({ p: window.studio.progress, s: window.studio.summary, text: document.getElementById('progress').textContent }));
  check(xs.p.answers === 3 && /3 answers/.test(xs.text), `experimenter window: progress live (${xs.text})`);
  check(xs.s && xs.s.trials === 1 && xs.s.conditions.length === 1,
    `experimenter window scores the saved answers (${xs.s ? xs.s.trials : 0} trial)`);
  const cue = await page.evaluate(() => !document.getElementById('side-experimenter').classList.contains('hidden') || /answers in all/.test(document.body.innerText));
  check(!cue, 'the participant page shows no progress or scores');
  await xpage.waitForFunction(() => document.querySelector('#ratioplot .main-svg'), { timeout: T(20000) }).catch(() => {});
  await xpage.screenshot({ path: path.join(out, 'studio-experimenter.png') });
  await xpage.close();
  // Palpation: one reference point clicked at the top of the dome, the library's quick protocol
  // (f_N 1 and 3 N, 4 directions) at 20 simulated seconds per second, sys.json saved and read back.
  await page.click('button[data-view=palpation]');
  await page.waitForFunction(() => window.studio.palpMesh > 0, { timeout: T(20000) });
  await sleep(500);
  const top = await page.evaluate(() => window.studio.palpTopScreenPos());
  await page.mouse.click(top.x, top.y);
  await page.waitForFunction(() => window.studio.palpPoints.length > 0, { timeout: T(15000), polling: 100 }).catch(() => {});
  const nPoints = await page.evaluate(() => window.studio.palpPoints.length);
  check(nPoints === 1, `a click on the shape adds one reference point (${nPoints})`);
  await page.$eval('#palpspeed', (e) => { e.value = '20'; });
  const tp0 = Date.now();
  await page.click('#palprun');
  await page.waitForFunction(() => window.studio.cycles.length > 0 || window.studio.palpError, { timeout: T(60000), polling: 100 });
  await sleep(1500);
  await page.screenshot({ path: path.join(out, 'studio-palpation-live.png') });
  await page.waitForFunction(() => window.studio.yield || window.studio.palpError, { timeout: T(150000), polling: 250 });
  const palp = await page.evaluate(() => ({ y: window.studio.yield, err: window.studio.palpError, cycles: window.studio.cycles.length }));
  log(`palpation: ${palp.cycles} cycles streamed, ${((Date.now() - tp0) / 1000).toFixed(1)} s wall${palp.err ? ', error ' + palp.err : ''}`);
  check(!palp.err && palp.y && palp.y.points.length === 1, `palpation of one point finished and fitted (${palp.err || 'ok'})`);
  check(palp.cycles > 0 && palp.y && palp.cycles === palp.y.cycles, `every cycle streamed live (${palp.cycles} of ${palp.y ? palp.y.cycles : '?'})`);
  await sleep(300);
  await page.screenshot({ path: path.join(out, 'studio-palpation.png') });
  await page.click('#savesys');
  await page.waitForFunction(() => window.studio.sysSaved || (window.studio.lastReply && window.studio.lastReply.request === 'save_sys'), { timeout: T(20000) });
  const saved = await page.evaluate(() => window.studio.sysSaved);
  check(saved && saved.points === 1, `save_sys: the server read sys.json back (${saved ? saved.points : 0} point)`);
  const sysPath = path.join(workspace, 'sys.json');
  let sys = null;
  try { sys = JSON.parse(fs.readFileSync(sysPath, 'utf8')); } catch { /* checked below */ }
  check(sys && sys.format === 'inhap-sys' && Array.isArray(sys.points) && sys.points.length === 1,
    `sys.json in the workspace: format ${sys ? sys.format : '-'}, ${sys && sys.points ? sys.points.length : 0} point`);
  check(fs.existsSync(path.join(workspace, 'sys.cycles.csv')), 'sys.cycles.csv beside it');
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
// On a failure the tail is long enough to hold a sanitizer report's first frames.
log(`${failures.length} failed; server log tail:\n${stderr.split('\n').slice(failures.length ? -60 : -6).join('\n')}`);
process.exit(exitCode);
