// inhap studio with --device udp: the virtual lab as a device client over the UDP bridge
// (`inhap lab device`, the same datagrams a real device sends), driven through the studio's
// WebSocket without a browser (the `ws` package puppeteer-core brings). Run by ctest
// (studio.udp):
//   node studio_udp.mjs --inhap BIN --web WEB_DIR
// Checks: the studio waits for the device and prints its URL once it joined; states stream with
// the device's time advancing; the tapping operator's taps are detected (>= 20); a reconstruction
// from them has faces; the samples export into the workspace; the palpation view then takes
// the reconstruction as its shape; the Model view records the device (no truth, the sensed
// force), trains with the recording's proxy and compares the model with the sensed force. Exit
// 77: skipped.
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

const arg = (k) => { const i = process.argv.indexOf(k); return i > 0 ? process.argv[i + 1] : undefined; };
const bin = arg('--inhap'), web = arg('--web');
// --slow F: every wait and the studio's lifetime F times longer (the sanitizer build).
const slow = Math.max(1, +(arg('--slow') || 1)), T = (ms) => ms * slow;
let WebSocket;
try { WebSocket = createRequire(path.resolve(web, 'package.json'))('ws'); }
catch { console.log('skipped: the ws package is not installed (./run setup runs npm ci --prefix web)'); process.exit(77); }
const workspace = fs.mkdtempSync(path.join(os.tmpdir(), 'inhap-studio-udp-'));
const t0 = Date.now();
const log = (...a) => console.log(`[${((Date.now() - t0) / 1000).toFixed(1)} s]`, ...a);
const failures = [];
const check = (ok, what) => { log((ok ? 'ok   ' : 'FAIL ') + what); if (!ok) failures.push(what); };

const udpPort = 20000 + Math.floor(Math.random() * 30000);
const studio = spawn(bin, ['studio', '--device', `udp:${udpPort}`, '--workspace', workspace, '--port', '0',
  '--web-dir', web, '--seconds', String(T(150)), '--connect-timeout', String(T(30)),
  '--tool-mass', '0.01'], { stdio: ['ignore', 'pipe', 'pipe'] });
let stderr = '';
studio.stderr.on('data', (d) => { stderr += d; });
// The lab as the device: the tapping operator with the sharp tip, in lockstep (as fast as the
// exchange allows, deterministic).
const device = spawn(bin, ['lab', 'device', '--port', String(udpPort), '--scene', 'dome', '--operator', 'tap',
  '--probe', 'tip', '--seconds', '600', '--seed', '3', '--lockstep'], { stdio: ['ignore', 'ignore', 'pipe'] });
let devErr = '';
device.stderr.on('data', (d) => { devErr += d; });

let exitCode = 1, ws = null;
try {
  const url = await new Promise((resolve, reject) => {
    let buf = '';
    studio.stdout.on('data', (d) => { buf += d; const m = buf.match(/^(http:\/\/127\.0\.0\.1:\d+\/\?token=[0-9a-f]{32})$/m); if (m) resolve(m[1]); });
    studio.on('exit', (c) => reject(new Error(`inhap studio exited (${c}): ${stderr}`)));
    setTimeout(() => reject(new Error(`no URL within ${T(40)} s: ` + stderr + devErr)), T(40000));
  });
  // stderr and stdout are separate pipes: the wait line, printed first, may arrive after the URL.
  for (let i = 0; i < 50 && !/waiting for a device on udp port/.test(stderr); ++i) await new Promise((r) => setTimeout(r, 100));
  check(/waiting for a device on udp port/.test(stderr), 'the studio waited for the device, then printed its URL');
  const base = url.replace(/\/\?token=.*/, ''), token = url.replace(/.*token=/, '');
  ws = new WebSocket(`${base.replace('http', 'ws')}/ws?token=${token}`, { headers: { Origin: base } });
  const inbox = [];
  let taps = 0, firstT = null, lastT = null, waiter = null;
  ws.on('message', (data) => {
    const m = JSON.parse(data.toString());
    if (m.type === 'state') { if (firstT === null) firstT = m.t; lastT = m.t; return; }
    if (m.type === 'tap') taps = m.taps;
    inbox.push(m);
    if (waiter) waiter();
  });
  await new Promise((resolve, reject) => { ws.on('open', resolve); ws.on('error', reject); });
  const send = (m) => ws.send(JSON.stringify(m));
  const reply = (pred, ms) => new Promise((resolve) => {
    const look = () => { const i = inbox.findIndex(pred); if (i >= 0) { waiter = null; resolve(inbox.splice(i, 1)[0]); return true; } return false; };
    if (look()) return;
    waiter = look;
    setTimeout(() => { if (waiter === look) waiter = null; resolve(null); }, T(ms));  // an answered wait's timer leaves the next wait alone
  });
  send({ type: 'hello' });
  const hello = await reply((m) => m.type === 'hello', 10000);
  check(hello && hello.lab === false && hello.device === `udp:${udpPort}`, `hello: device ${hello ? hello.device : '-'}, not the lab`);

  const want = 20;
  for (let i = 0; i < T(900) && taps < want; ++i) await new Promise((r) => setTimeout(r, 100));
  log(`taps detected over the bridge: ${taps}; device time ${firstT?.toFixed(2)} -> ${lastT?.toFixed(2)} s`);
  check(lastT > firstT, 'states stream with the device time advancing');
  check(taps >= want, `the operator's taps are detected over the bridge (${taps} >= ${want})`);

  send({ type: 'mode', mode: 'idle' });
  await reply((m) => m.request === 'mode', 10000);
  send({ type: 'reconstruct' });
  const mesh = await reply((m) => (m.type === 'mesh' && m.role === 'reconstruction') || m.type === 'error', 60000);
  check(mesh && mesh.type === 'mesh' && mesh.faces.length > 0, `reconstruction from the bridge's taps (${mesh && mesh.faces ? mesh.faces.length / 3 : 0} faces${mesh && mesh.type === 'error' ? ': ' + mesh.message : ''})`);
  send({ type: 'export', points: 'udp-samples.ply' });
  const ex = await reply((m) => m.request === 'export', 20000);
  check(ex && ex.type === 'ok' && ex.points === taps && fs.existsSync(path.join(workspace, 'udp-samples.ply')),
    `export: ${ex ? ex.points : '?'} points = ${taps} taps`);
  send({ type: 'mode', mode: 'palpation' });
  const pm = await reply((m) => (m.type === 'mesh' && m.role === 'palpation') || m.type === 'error', 20000);
  check(pm && pm.type === 'mesh' && pm.faces.length > 0, 'palpation view: the reconstruction is the shape to palpate');

  // The Model view with the bridged device: a recording of what the loop observes (no truth), a
  // training with the recording's proxy, the model's force against the sensed force.
  send({ type: 'mode', mode: 'model' });
  const mm = await reply((m) => m.request === 'mode' || m.type === 'error', 10000);
  check(mm && mm.type === 'ok', `model view on a bridged device${mm && mm.message ? ': ' + mm.message : ''}`);
  send({ type: 'model_record', operator: 'explore', seconds: 10, path: 'udp-rec.csv' });
  await reply((m) => m.request === 'model_record' || m.type === 'error', 10000);
  const full = await reply((m) => m.type === 'coverage' && m.full, 60000);
  send({ type: 'model_stop' });
  const ms = await reply((m) => m.request === 'model_stop' || m.type === 'error', 20000);
  check(full && ms && ms.rows > 9000 && ms.truth === '' && ms.operator === 'device' && fs.existsSync(path.join(workspace, 'udp-rec.csv')),
    `model recording over the bridge: ${ms ? ms.rows : '?'} rows, ${ms ? ms.contact_rows : '?'} in contact, ${ms ? ms.seconds : '?'} s, no truth`);
  const co = await reply((m) => m.type === 'compare' && m.source === 'object' && m.n > 200, 30000);
  check(co && co.rmse.every(Number.isFinite) && co.points.length > 0, `compare stream over the bridge (object = the sensed force): ${co ? co.n : 0} ticks`);
  send({ type: 'model_train', recording: 'udp-rec.csv', out: 'udp-m.json' });
  const tr = await reply((m) => m.type === 'trained' || m.type === 'error', 120000);
  check(tr && tr.status === 'done' && tr.proxy === 'recording' && fs.existsSync(path.join(workspace, 'udp-m.json')),
    `trained with the recording's proxy: ${tr ? tr.status + (tr.message ? ' ' + tr.message : '') : 'nothing'}`);
  send({ type: 'model_source', source: 'model' });
  const cm = await reply((m) => m.type === 'compare' && m.has_model && m.source === 'model' && m.n > 500, 30000);
  check(cm && cm.rmse.every(Number.isFinite), `the model against the sensed force: RMSE ${cm ? cm.rmse.map((v) => v.toFixed(3)).join(' / ') : '?'} N over ${cm ? cm.n : 0} ticks`);
  exitCode = failures.length ? 1 : 0;
} catch (e) {
  failures.push(String(e));
  log('FAIL', e.stack || e);
} finally {
  if (ws) ws.close();
  studio.kill('SIGTERM');
  device.kill('SIGTERM');
  await new Promise((r) => { studio.on('exit', r); setTimeout(r, 5000); });
  fs.rmSync(workspace, { recursive: true, force: true });
}
// On a failure the tail is long enough to hold a sanitizer report's first frames.
log(`${failures.length} failed; server log tail:\n${stderr.split('\n').slice(failures.length ? -60 : -5).join('\n')}`);
process.exit(exitCode);
