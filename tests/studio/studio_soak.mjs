// inhap studio under load for a minute (docs/studio.md, "Limits"): 50 pages with the token
// (each receives the state stream and sends a request every 250 ms) and 12 slow-header
// connections (no token; a header line every second, the end of the headers never; reopened as
// soon as the server closes one) against `inhap studio --device lab:dome --realtime`. Meanwhile
// every 5 s a page load with the token (index.html, then its 8 files at once, as a browser
// does). Run by ctest (studio.soak):
//   node studio_soak.mjs --inhap BIN --web WEB_DIR [--seconds 60] [--slow F]
// Checks: every page load < 1 s; a normal page's state stream >= 50 Hz in every second; the
// servo loop's overruns (the "servo" request) during the soak no more than the same loop's rate
// in 8 s with the studio idle just before it predicts (plus 3 standard deviations and 3) or 1 %
// of the soak's ticks, whichever is more; the 50 pages still open. --no-realtime (diagnosis):
// the loop without SCHED_FIFO. --slow F (the sanitizer build): the times and rates F times looser, the
// overruns reported only. Exit 77: skipped.
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import fs from 'node:fs';
import http from 'node:http';
import net from 'node:net';
import os from 'node:os';
import path from 'node:path';

const arg = (k) => { const i = process.argv.indexOf(k); return i > 0 ? process.argv[i + 1] : undefined; };
const bin = arg('--inhap'), web = arg('--web');
const slow = Math.max(1, +(arg('--slow') || 1)), T = (ms) => ms * slow;
const soakS = +(arg('--seconds') || 60);
// --clients and --slow-headers (defaults 50 and 12) only for diagnosis (0 and 0: the baseline).
const kClients = +(arg('--clients') ?? 50), kSlow = +(arg('--slow-headers') ?? 12);
const kLoads = arg('--no-page-loads') === undefined && !process.argv.includes('--no-page-loads');
const kLoadMs = T(1000), kMinHz = 50 / slow;
let WebSocket;
try { WebSocket = createRequire(path.resolve(web, 'package.json'))('ws'); }
catch { console.log('skipped: the ws package is not installed (./run setup runs npm ci --prefix web)'); process.exit(77); }
const workspace = fs.mkdtempSync(path.join(os.tmpdir(), 'inhap-studio-soak-'));
const t0 = Date.now();
const log = (...a) => console.log(`[${((Date.now() - t0) / 1000).toFixed(1)} s]`, ...a);
const failures = [];
const check = (ok, what) => { log((ok ? 'ok   ' : 'FAIL ') + what); if (!ok) failures.push(what); };
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

const studio = spawn(bin, ['studio', '--device', 'lab:dome', '--workspace', workspace, '--port', '0',
  '--web-dir', web, '--seconds', String(soakS + T(60)), ...(process.argv.includes('--no-realtime') ? [] : ['--realtime'])],
  { stdio: ['ignore', 'pipe', 'pipe'] });
let stderr = '';
studio.stderr.on('data', (d) => { stderr += d; });

// A page: a WebSocket with the token; counts its state messages per second since `from`.
function openPage(base, token, { onReply } = {}) {
  return new Promise((resolve, reject) => {
    const ws = new WebSocket(`${base.replace('http', 'ws')}/ws?token=${token}`, { headers: { Origin: base } });
    const page = { ws, states: 0, perSecond: [], closed: false, replies: [] };
    ws.on('message', (data) => {
      const text = data.toString();
      if (text.includes('"type":"state"')) {
        ++page.states;
        const s = Math.floor((Date.now() - (page.from ?? Date.now())) / 1000);
        if (page.from !== undefined && s >= 0) page.perSecond[s] = (page.perSecond[s] || 0) + 1;
        return;
      }
      if (onReply) onReply(JSON.parse(text));
    });
    ws.on('close', () => { page.closed = true; });
    ws.on('open', () => resolve(page));
    ws.on('error', reject);
  });
}

function get(base, p, headers) {
  return new Promise((resolve) => {
    const req = http.get(`${base}${p}`, { headers, agent: false }, (res) => {
      let n = 0;
      res.on('data', (d) => { n += d.length; });
      res.on('end', () => resolve({ status: res.statusCode, bytes: n, cookie: res.headers['set-cookie'] }));
    });
    req.on('error', (e) => resolve({ status: 0, error: String(e) }));
    req.setTimeout(T(10000), () => req.destroy(new Error('timed out')));
  });
}

// What a browser loads: the page, then its scripts, style and libraries at once.
async function pageLoad(base, token) {
  const start = performance.now();
  const index = await get(base, `/?token=${token}`, {});
  const cookie = (index.cookie || [])[0]?.split(';')[0] || '';
  const files = ['/studio.js', '/studio.css', '/plots.js', '/markers.js', '/lib/three.module.js',
    '/lib/three.core.js', '/lib/OrbitControls.js', '/lib/plotly.min.js'];
  const rest = await Promise.all(files.map((f) => get(base, f, { Cookie: cookie })));
  const all = [index, ...rest];
  return { ms: performance.now() - start, ok: all.every((r) => r.status === 200),
    bytes: all.reduce((s, r) => s + (r.bytes || 0), 0), statuses: all.map((r) => r.status).join(',') };
}

// A slow-header connection: the request line and one header line a second, never the blank line.
function slowHeaders(port, stats, stop) {
  const open = () => {
    if (stop.now) return;
    const s = net.connect(port, '127.0.0.1');
    let timer = null;
    s.on('connect', () => {
      ++stats.opened;
      s.write(`GET / HTTP/1.1\r\nHost: 127.0.0.1:${port}\r\n`);
      timer = setInterval(() => s.write(`X-Slow-${stats.opened}: 1\r\n`), 1000);
    });
    s.on('error', () => {});
    s.on('close', () => {
      clearInterval(timer);
      if (!stop.now) { ++stats.closedByServer; setTimeout(open, 20); }
    });
    stats.sockets.add(s);
  };
  open();
}

let exitCode = 1;
const pages = [];
const stop = { now: false };
const slowStats = { opened: 0, closedByServer: 0, sockets: new Set() };
try {
  const url = await new Promise((resolve, reject) => {
    let buf = '';
    studio.stdout.on('data', (d) => { buf += d; const m = buf.match(/^(http:\/\/127\.0\.0\.1:\d+\/\?token=[0-9a-f]{32})$/m); if (m) resolve(m[1]); });
    studio.on('exit', (c) => reject(new Error(`inhap studio exited (${c}): ${stderr}`)));
    setTimeout(() => reject(new Error(`no URL within ${T(40)} s: ` + stderr)), T(40000));
  });
  const base = url.replace(/\/\?token=.*/, ''), token = url.replace(/.*token=/, '');
  const port = +base.replace(/.*:/, '');
  // The normal page: asks for the servo statistics, counts its stream.
  let servoWaiter = null;
  const normal = await openPage(base, token, { onReply: (m) => { if (m.type === 'servo' && servoWaiter) servoWaiter(m); } });
  const servo = () => new Promise((resolve) => {
    servoWaiter = (m) => { servoWaiter = null; resolve(m); };
    normal.ws.send(JSON.stringify({ type: 'servo' }));
    setTimeout(() => { if (servoWaiter) { servoWaiter = null; resolve(null); } }, T(5000));
  });
  await sleep(T(2000));  // the loop has started and settled
  // The machine's own rate of overruns (another process, the hypervisor), with the studio idle:
  // the soak must not add to it.
  const idle0 = await servo();
  const idleS = 8;
  await sleep(idleS * 1000);
  const before = await servo();
  check(before && before.running, `servo loop running (${before ? before.rt : '-'}); idle: ${before.overruns - idle0.overruns} overruns in ${idleS} s`);

  for (let i = 0; i < kClients; ++i) pages.push(await openPage(base, token));
  const timers = pages.map((p) => setInterval(() => { if (!p.closed) p.ws.send('{"type":"progress"}'); }, 250));
  for (let i = 0; i < kSlow; ++i) slowHeaders(port, slowStats, stop);
  log(`${kClients} pages and ${kSlow} slow-header connections open; soak for ${soakS} s`);
  normal.from = Date.now();
  const loads = [];
  const end = Date.now() + soakS * 1000;
  // A page load every 5 s on a fixed clock (a slow load does not push the next one back).
  for (let tick = 1; Date.now() < end; ++tick) {
    await sleep(Math.max(0, Math.min(normal.from + tick * 5000, end) - Date.now()));
    if (Date.now() >= end) break;
    if (!kLoads) continue;
    const l = await pageLoad(base, token);
    loads.push(l);
    if (!l.ok || l.ms >= kLoadMs) log(`page load ${l.ms.toFixed(0)} ms, statuses ${l.statuses}`);
  }
  const soakedS = Math.floor((Date.now() - normal.from) / 1000);
  const after = await servo();
  stop.now = true;
  timers.forEach(clearInterval);

  if (kLoads) {
    const worstLoad = Math.max(...loads.map((l) => l.ms));
    check(loads.length >= Math.floor(soakS / 5) - 1 && loads.every((l) => l.ok), `${loads.length} page loads with the token, all files 200 (${(loads[0]?.bytes / 1e6).toFixed(1)} MB each)`);
    check(worstLoad < kLoadMs, `page load during the soak: worst ${worstLoad.toFixed(0)} ms, median ${loads.map((l) => l.ms).sort((a, b) => a - b)[loads.length >> 1].toFixed(0)} ms (< ${kLoadMs} ms)`);
  }
  const hz = Array.from({ length: soakedS }, (_, s) => normal.perSecond[s] || 0);
  const minHz = Math.min(...hz), meanHz = hz.reduce((a, b) => a + b, 0) / hz.length;
  check(hz.length >= soakS - 1 && minHz >= kMinHz, `normal page's state stream: ${meanHz.toFixed(1)} Hz mean, ${minHz} Hz in its worst second of ${hz.length} (>= ${kMinHz})`);
  const others = pages.map((p) => p.states / soakedS).sort((a, b) => a - b);
  check(pages.every((p) => !p.closed), `the ${kClients} pages stayed open (their stream: ${others.length ? others[0].toFixed(1) : '-'} to ${others.length ? others[others.length - 1].toFixed(1) : '-'} Hz)`);
  log(`slow-header connections: ${slowStats.opened} opened, ${slowStats.closedByServer} closed by the server`);
  const moved = after && before ? after.overruns - before.overruns : NaN;
  const ok = after && after.running && after.ticks > before.ticks;
  // Allowed: the idle rate over the soak's length plus three Poisson standard deviations and 3,
  // or 1 % of the soak's ticks, whichever is more (this VM's idle rate swings between 1 and 7
  // per second from one minute to the next; a loop without real-time priority missed 2.6 % of
  // its deadlines under the soak).
  const expected = (before.overruns - idle0.overruns) * soakedS / idleS;
  const ticks = after ? after.ticks - before.ticks : 0;
  const allowed = Math.max(Math.floor(expected + 3 * Math.sqrt(expected) + 3), Math.floor(0.01 * ticks));
  const what = `servo overruns during the soak: ${moved} in ${soakedS} s (idle rate: ${expected.toFixed(1)}; allowed ${allowed}); ${after ? after.ticks - before.ticks : '?'} ticks; ${after?.rt}`;
  if (slow === 1) check(ok && moved <= allowed, what);
  else log(what + ' (not checked under --slow)');
  exitCode = failures.length ? 1 : 0;
} catch (e) {
  failures.push(String(e));
  log('FAIL', e.stack || e);
} finally {
  stop.now = true;
  for (const s of slowStats.sockets) s.destroy();
  for (const p of pages) p.ws.terminate();
  studio.kill('SIGTERM');
  await new Promise((r) => { studio.on('exit', r); setTimeout(r, 5000); });
  fs.rmSync(workspace, { recursive: true, force: true });
}
log(`${failures.length} failed; load average ${os.loadavg()[0].toFixed(1)}; server log tail:\n${stderr.split('\n').slice(failures.length ? -40 : -4).join('\n')}`);
process.exit(exitCode);
