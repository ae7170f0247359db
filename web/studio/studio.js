// inhap studio page (docs/studio.md): one WebSocket to the server; three.js for the sampling,
// palpation and explore views, an SVG participant screen (thesis fig. 5.9b), canvas plots
// (plots.js) for the force and figs 4.7-4.8, plotly.js for figs 5.10-5.11 in the experimenter
// window (?view=experimenter). The live probe is drawn by elements over the 3-D view
// (markers.js): a state message does not re-render the WebGL scene.
// Units: mm, N, s. window.studio exposes counters for the browser test.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/OrbitControls.js';
import { drawFig47, drawFig48, drawLine } from '/plots.js';
import { Markers } from '/markers.js';
import { createModelView } from '/model.js';

const token = new URLSearchParams(location.search).get('token') || '';
const $ = (id) => document.getElementById(id);
const S = (window.studio = {
  ready: false, view: 'sampling', taps: 0, samples: new Map(), deleted: 0, mesh: null,
  lastReply: null, errors: [], state: null, contactSeen: false, maxForce: 0,
  frames: 0, fps: 0, latencies: [], latencyMs: [], latencyEventMs: [], trial: null, answered: 0, messages: 0,
});

// --- socket -------------------------------------------------------------------------------
const ws = new WebSocket(`ws://${location.host}/ws?token=${encodeURIComponent(token)}`);
const send = (m) => { if (ws.readyState === 1) ws.send(JSON.stringify(m)); };
ws.onopen = () => { $('status').textContent = 'connected'; send({ type: 'hello' }); };
ws.onclose = () => { $('status').textContent = 'disconnected'; };
let needRender = true;  // the scene changes only through messages, the camera and the mouse
let modelView = null;  // the Model view (model.js), made once the page's functions exist
ws.onmessage = (ev) => {
  const m = JSON.parse(ev.data);
  if (modelView && modelView.onMessage(m)) return;
  // states move the markers only (markers.js); cycles and progress go to plots and text
  if (m.type !== 'state' && m.type !== 'cycle' && m.type !== 'progress') needRender = true;
  S.messages++;
  switch (m.type) {
    case 'state': onState(m); break;
    case 'tap': addSample(m); S.taps = m.taps; updateCounts(); break;
    case 'samples': setSamples(m); clearPreview(); break;
    case 'preview': onPreview(m); break;
    case 'mesh': onMesh(m); break;
    case 'trial': onTrial(m); break;
    case 'hello': S.ready = true; S.hello = m; $('palpspeed').value = m.speed; $('palpspeedl').classList.toggle('hidden', !m.lab); break;
    case 'summary': onSummary(m); break;
    case 'progress': onProgress(m); break;
    case 'cycle': onCycle(m); break;
    case 'yield': onYield(m); break;
    case 'palpation': onPalpation(m); break;
    case 'error': S.errors.push(m); S.lastReply = m; $('status').textContent = 'error: ' + m.message; break;
    case 'ok': onOk(m); break;
    case 'dropped': S.dropped = m.count; break;  // this page fell behind: the server dropped states
    default: S.lastReply = m;
  }
  if (!['state', 'tap', 'cycle', 'progress'].includes(m.type)) S.lastReply = m;
};

// --- three.js stage ------------------------------------------------------------------------
const host = $('view3d');
const renderer = new THREE.WebGLRenderer({ antialias: false, powerPreference: "high-performance" });
renderer.setPixelRatio(1);
host.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0xf8f8f6);
const camera = new THREE.PerspectiveCamera(40, 1, 1, 5000);
camera.up.set(0, 0, 1);
const controls = new OrbitControls(camera, renderer.domElement);
controls.mouseButtons = { LEFT: null, MIDDLE: THREE.MOUSE.DOLLY, RIGHT: THREE.MOUSE.ROTATE };
scene.add(new THREE.HemisphereLight(0xffffff, 0x666666, 2.2));
const sun = new THREE.DirectionalLight(0xffffff, 1.2);
sun.position.set(100, -150, 300);
scene.add(sun);
const markers = new Markers(host);  // HIP, IHIP, CIHIP and the force arrow, over the WebGL canvas
const sampleGroup = new THREE.Group(), thresholdGroup = new THREE.Group();
scene.add(sampleGroup, thresholdGroup);
S.scene = scene; S.renderer = renderer;
const sampleGeo = new THREE.SphereGeometry(1.0, 10, 8), thrGeo = new THREE.SphereGeometry(0.5, 6, 4);
const sampleMat = new THREE.MeshLambertMaterial({ color: 0xc02828 }), outlierMat = new THREE.MeshLambertMaterial({ color: 0xff9900 }), thrMat = new THREE.MeshBasicMaterial({ color: 0x999999 });
let objectMesh = null, reconMesh = null, exploreMesh = null, palpMesh = null;

function fitCamera(box) {
  const c = box.getCenter(new THREE.Vector3()), s = box.getSize(new THREE.Vector3()).length() || 100;
  camera.position.set(c.x, c.y - 1.1 * s, c.z + 1.0 * s);
  controls.target.copy(c);
  controls.update();
}
function resize() {
  const w = host.clientWidth || 800, h = host.clientHeight || 600;
  renderer.setSize(w, h, false);
  renderer.domElement.style.width = w + 'px';
  renderer.domElement.style.height = h + 'px';
  markers.resize(w, h);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
  needRender = true;
}
window.addEventListener('resize', resize);
controls.addEventListener('change', () => { needRender = true; });
for (const e of ['pointerdown', 'pointerup', 'keydown']) window.addEventListener(e, () => { needRender = true; });

function colorMap(values) {
  let lo = Infinity, hi = -Infinity;
  for (const v of values) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
  const span = hi - lo > 1e-12 ? hi - lo : 1, col = new Float32Array(values.length * 3), c = new THREE.Color();
  values.forEach((v, i) => { c.setHSL(0.66 * (1 - (v - lo) / span), 0.8, 0.5); col.set([c.r, c.g, c.b], 3 * i); });
  return { col, lo, hi };
}
function buildMesh(m, opacity) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(m.vertices, 3));
  g.setIndex(m.faces);
  g.computeVertexNormals();
  const mat = new THREE.MeshLambertMaterial({ color: 0xbbbbbb, side: THREE.DoubleSide, transparent: opacity < 1, opacity });
  if (m.values) { g.setAttribute('color', new THREE.Float32BufferAttribute(colorMap(m.values).col, 3)); mat.vertexColors = true; mat.color.set(0xffffff); }
  return new THREE.Mesh(g, mat);
}
function onMesh(m) {
  const mesh = buildMesh(m, m.role === 'object' ? 0.35 : 1);
  if (m.role === 'object') { if (objectMesh) scene.remove(objectMesh); objectMesh = mesh; if (modelView) modelView.setObject(m); }
  if (m.role === 'reconstruction') {
    if (reconMesh) scene.remove(reconMesh);
    reconMesh = mesh; S.mesh = { vertices: m.vertices.length / 3, faces: m.faces.length / 3 };
    // the samples the pipeline's outlier filter dropped, in orange
    for (const [id, e] of S.samples) e.m.material = (m.outliers || []).includes(id) ? outlierMat : sampleMat;
    const r = colorMap(m.values || [0]);
    $('recinfo').textContent = `${S.mesh.faces} faces, alpha ${m.report.alpha.toFixed(2)} mm, ${m.report.outliers} outliers (orange), distance ${r.lo.toFixed(2)}-${r.hi.toFixed(2)} mm`;
  }
  if (m.role === 'explore') { if (exploreMesh) scene.remove(exploreMesh); exploreMesh = mesh; S.exploreMesh = m.faces.length / 3; }
  if (m.role === 'palpation') { if (palpMesh) scene.remove(palpMesh); palpMesh = mesh; S.palpMesh = m.faces.length / 3; }
  scene.add(mesh);
  showFor(S.view);
  if (m.role !== 'reconstruction') { mesh.geometry.computeBoundingBox(); fitCamera(mesh.geometry.boundingBox); }
}
function showFor(view) {
  const samp = view === 'sampling';
  sampleGroup.visible = thresholdGroup.visible = previewGroup.visible = samp;
  if (objectMesh) objectMesh.visible = samp;
  if (reconMesh) reconMesh.visible = samp;
  if (exploreMesh) exploreMesh.visible = view === 'explore';
  if (palpMesh) palpMesh.visible = view === 'palpation';
  palpGroup.visible = view === 'palpation';
}

// --- sampling ------------------------------------------------------------------------------
function addSample(s) {
  if (S.samples.has(s.id)) return;
  const m = new THREE.Mesh(sampleGeo, sampleMat);
  m.position.set(...s.point);
  m.userData.id = s.id;
  const t = new THREE.Mesh(thrGeo, thrMat);
  t.position.set(...s.threshold);
  sampleGroup.add(m);
  thresholdGroup.add(t);
  S.samples.set(s.id, { s, m, t });
  if (S.samples.size === 1 && !objectMesh) fitCamera(new THREE.Box3().setFromCenterAndSize(m.position, new THREE.Vector3(120, 120, 60)));
}
function setSamples(msg) {
  const live = new Set(msg.samples.map((s) => s.id));
  for (const [id, e] of S.samples) if (!live.has(id)) { sampleGroup.remove(e.m); thresholdGroup.remove(e.t); S.samples.delete(id); }
  for (const s of msg.samples) { const e = S.samples.get(s.id); if (e) e.m.position.set(...s.point); else addSample(s); }
  S.deleted = msg.deleted;
  S.taps = msg.taps;
  updateCounts();
}
function updateCounts() {
  $('taps').textContent = S.taps; $('live').textContent = S.samples.size; $('deleted').textContent = S.deleted;
}
S.sampleScreenPos = (id) => {
  const e = S.samples.get(id); if (!e) return null;
  const v = e.m.position.clone().project(camera), r = renderer.domElement.getBoundingClientRect();
  return { x: r.left + (v.x + 1) / 2 * r.width, y: r.top + (1 - v.y) / 2 * r.height };
};
S.sampleIds = () => [...S.samples.keys()];

const ray = new THREE.Raycaster(), ndc = new THREE.Vector2();
function pick(ev, objects) {
  const r = renderer.domElement.getBoundingClientRect();
  ndc.set(((ev.clientX - r.left) / r.width) * 2 - 1, -((ev.clientY - r.top) / r.height) * 2 + 1);
  ray.setFromCamera(ndc, camera);
  return ray.intersectObjects(objects, false);
}
let boxStart = null, boxDiv = null;
renderer.domElement.addEventListener('pointerdown', (ev) => {
  if (ev.button !== 0) return;
  if (S.view === 'sampling') {
    if (ev.shiftKey) { boxStart = [ev.clientX, ev.clientY]; boxDiv = document.createElement('div'); boxDiv.id = 'selbox'; host.appendChild(boxDiv); return; }
    const hit = pick(ev, sampleGroup.children);
    if (hit.length) send({ type: 'delete', ids: [hit[0].object.userData.id] });
  } else if (S.view === 'explore') { pressing = true; dragFrom = [ev.clientX, ev.clientY]; exploreMove(ev); }
  else if (S.view === 'palpation' && palpMesh && !S.palpRunning) {
    const hit = pick(ev, [palpMesh]);
    if (hit.length) addPalpPoint(hit[0].point);
  }
});
window.addEventListener('pointermove', (ev) => {
  if (boxStart && boxDiv) {
    const r = host.getBoundingClientRect();
    Object.assign(boxDiv.style, { left: Math.min(ev.clientX, boxStart[0]) - r.left + 'px', top: Math.min(ev.clientY, boxStart[1]) - r.top + 'px',
      width: Math.abs(ev.clientX - boxStart[0]) + 'px', height: Math.abs(ev.clientY - boxStart[1]) + 'px' });
  }
  if (S.view === 'explore') exploreMove(ev);
});
window.addEventListener('pointerup', (ev) => {
  if (boxStart) {
    const [x0, x1] = [Math.min(ev.clientX, boxStart[0]), Math.max(ev.clientX, boxStart[0])];
    const [y0, y1] = [Math.min(ev.clientY, boxStart[1]), Math.max(ev.clientY, boxStart[1])];
    const ids = S.sampleIds().filter((id) => { const p = S.sampleScreenPos(id); return p.x >= x0 && p.x <= x1 && p.y >= y0 && p.y <= y1; });
    if (ids.length) send({ type: 'delete', ids });
    boxDiv.remove(); boxStart = boxDiv = null;
  }
  if (pressing) { pressing = false; exploreMove(ev); }
});
let tapping = true;
$('pause').onclick = () => { tapping = !tapping; send({ type: 'mode', mode: tapping ? 'sampling' : 'idle' }); $('pause').textContent = tapping ? 'Pause tapping' : 'Resume tapping'; };
$('undo').onclick = () => send({ type: 'undo' });
$('alpha').oninput = () => { const a = +$('alpha').value; $('alphav').textContent = a ? a + ' mm' : 'auto'; };
$('reconstruct').onclick = () => { $('recinfo').textContent = 'reconstructing…'; send({ type: 'reconstruct', alpha: +$('alpha').value, taubin: $('taubin').checked, sqrt3: $('sqrt3').checked }); };
// Outlier filter and jet (quadric) projection, previewed: orange = would be removed, purple
// segment = where the sample would move (x1). Apply deletes / moves them (one undo step).
const previewGroup = new THREE.Group();
scene.add(previewGroup);
function clearPreview() {
  for (const c of [...previewGroup.children]) { previewGroup.remove(c); c.geometry.dispose(); }
  if (S.preview) for (const [, e] of S.samples) e.m.material = sampleMat;
  S.preview = null; $('previnfo').textContent = '';
}
function onPreview(m) {
  clearPreview();
  S.preview = m;
  for (const id of m.outliers) { const e = S.samples.get(id); if (e) e.m.material = outlierMat; }
  const seg = [];
  for (const mv of m.moves) { const e = S.samples.get(mv.id); if (e) seg.push(e.m.position.clone(), new THREE.Vector3(...mv.to)); }
  if (seg.length) previewGroup.add(new THREE.LineSegments(new THREE.BufferGeometry().setFromPoints(seg), new THREE.LineBasicMaterial({ color: 0x8a2be2 })));
  $('previnfo').textContent = `${m.outliers.length} outlier(s) would be removed (orange); the projection would move ${m.moves.length} samples by ${m.median_move.toFixed(3)} mm median, ${m.max_move.toFixed(3)} mm at most (purple). Apply, then Undo reverts it.`;
}
$('preview').onclick = () => send({ type: 'preview' });
$('applyprev').onclick = () => send({ type: 'apply_preview' });
$('export').onclick = () => send({ type: 'export', points: $('ptsname').value, mesh: $('meshname').value });
$('savesess').onclick = () => send({ type: 'save_session', path: $('sessname').value });
$('opensess').onclick = () => send({ type: 'open_session', path: $('sessname').value });

// --- explore -------------------------------------------------------------------------------
let pressing = false, dragFrom = null, seq = 0, lastHit = null;
const pending = [];  // [seq, frame sent, mouse event time]
const arrived = [];  // [seq, time sent] not yet timed on arrival
function exploreMove(ev) {
  if (!exploreMesh || ev.target !== renderer.domElement && !pressing) return;
  const hit = pick(ev, [exploreMesh]);
  if (hit.length) lastHit = { p: hit[0].point, n: hit[0].face.normal };
  if (!lastHit) return;
  const drag = pressing && dragFrom ? Math.hypot(ev.clientX - dragFrom[0], ev.clientY - dragFrom[1]) : 0;
  const press = pressing ? Math.min(1, 0.35 + drag / 300) : 0;
  seq++;
  pending.push([seq, S.frames, ev.timeStamp]); arrived.push([seq, performance.now()]);
  send({ type: 'probe', x: lastHit.p.x, y: lastHit.p.y, z: lastHit.p.z, nx: lastHit.n.x, ny: lastHit.n.y, nz: lastHit.n.z, press, seq });
}
$('openmesh').onclick = () => {
  const src = $('meshsrc').value, v = $('meshpath').value || 'x.ply';
  if (src !== 'model') return send({ type: 'open_mesh', source: src, path: v });
  const [model, sys, shape] = v.split(',').map((x) => x.trim());
  send({ type: 'open_mesh', source: 'model', model, sys, shape });
};
$('algo').onchange = () => send({ type: 'algorithm', name: $('algo').value });
const fT = [], fY = [];
// plotly.js (3.5 MB) is loaded when the explore view first opens, not with the page.
let plotlyLoading = false;
function loadPlotly() {
  if (plotlyLoading) return;
  plotlyLoading = true;
  const s = document.createElement('script');
  s.src = '/lib/plotly.min.js';
  document.head.appendChild(s);
}
// The scrolling |f| plot: a plain canvas redrawn in the frame after new states arrived (a plotly
// relayout every 200 ms cost whole frames under software rendering).
let forceDirty = false;

// --- state ---------------------------------------------------------------------------------
function onState(m) {
  S.state = m;
  // round trip in ms: the target sent, applied by the servo thread, its state back on the page
  while (arrived.length && arrived[0][0] <= m.seq) { S.latencyMs.push(performance.now() - arrived[0][1]); arrived.shift(); }
  const f = Math.hypot(...m.f);
  if (m.contact) S.contactSeen = true;
  if (S.view === 'explore') { S.maxForce = Math.max(S.maxForce, f); fT.push(m.t); fY.push(f); if (fT.length > 600) { fT.shift(); fY.shift(); } forceDirty = true; }
}
// DOM text only when it changed (a write per frame restyles the sidebar every frame).
const shown = new Map();
function setText(id, t) { if (shown.get(id) !== t) { shown.set(id, t); $(id).textContent = t; } }
// `t`: this frame's rAF time. The markers themselves are drawn after the WebGL render (frame()).
function drawState(t) {
  const m = S.state; if (!m) return;
  if (S.view === 'explore') { setText('fmag', Math.hypot(...m.f).toFixed(2)); setText('contact', m.contact ? 'yes' : 'no'); }
  // mouse-to-probe latency: frames from the one the mouse event was handled in (counted from the
  // frame before it: Chrome hands a move to the page just before a frame's rAF) to the frame that
  // draws a state the servo applied it in; and ms from the event's time stamp to that frame
  while (pending.length && pending[0][0] <= m.seq) {
    S.latencies.push(S.frames - pending[0][1]); S.latencyEventMs.push(t - pending[0][2]); pending.shift();
  }
  if (S.view === 'experiment') drawHip(m);
  if (S.view === 'palpation') {
    if (S.palpRunning && m.palp_progress !== undefined) setText('palpinfo', `running: point ${m.palp_point}, ${(100 * m.palp_progress).toFixed(0)} %, ${S.cycles.length} cycles, t = ${m.t.toFixed(1)} s`);
    if (palpDirty) drawPalpation();
  }
}

// --- experiment (fig. 5.9b) ---------------------------------------------------------------
const svg = $('expsvg'), NS = 'http://www.w3.org/2000/svg';
let circles = [], hipDot = null;
const keyText = { shape: '0 flat · 1 bump · 2 hole', stiffness: '0 same · 1 harder · 2 softer' };
function onTrial(t) {
  S.trial = t;
  S.answered = t.answered.filter((a) => a >= 0).length;
  svg.setAttribute('viewBox', `0 0 ${t.size_mm} ${t.size_mm}`);
  svg.setAttribute('preserveAspectRatio', 'xMidYMid meet');
  if (circles.length !== t.centres.length) {
    svg.innerHTML = '';
    circles = t.centres.map(() => { const c = document.createElementNS(NS, 'circle'); svg.appendChild(c); return c; });
    hipDot = document.createElementNS(NS, 'circle'); hipDot.setAttribute('r', 1.6); hipDot.setAttribute('fill', '#2ee62e'); svg.appendChild(hipDot);
  }
  t.centres.forEach(([x, y], i) => {
    const c = circles[i];
    // SVG y down, the surface's y up: flip so the screen is the top view
    c.setAttribute('cx', x); c.setAttribute('cy', t.size_mm - y); c.setAttribute('r', t.cell_mm * 0.3);
    c.setAttribute('fill', t.answered[i] >= 0 ? '#4a6fd6' : 'none'); c.setAttribute('stroke', '#bbb'); c.setAttribute('stroke-width', 0.4);
  });
  $('expinfo').textContent = `participant ${t.participant} · ${t.task} · session ${t.session + 1} · trial ${t.trial + 1} (${t.index + 1}/${t.trials}) · answered ${S.answered}/25`;
  $('keys').textContent = 'Keys at a model: ' + keyText[t.task];
}
function drawHip(m) {
  if (!hipDot || !S.trial) return;
  hipDot.setAttribute('cx', m.hip[0]); hipDot.setAttribute('cy', S.trial.size_mm - m.hip[1]);
}
function svgToMm(ev) {
  const p = svg.createSVGPoint(); p.x = ev.clientX; p.y = ev.clientY;
  const q = p.matrixTransform(svg.getScreenCTM().inverse());
  return [q.x, S.trial.size_mm - q.y];
}
let expPress = false, expFrom = null;
function expMove(ev) {
  if (!S.trial) return;
  const [x, y] = svgToMm(ev);
  const drag = expPress && expFrom ? Math.hypot(ev.clientX - expFrom[0], ev.clientY - expFrom[1]) : 0;
  seq++; pending.push([seq, S.frames, ev.timeStamp]); arrived.push([seq, performance.now()]);
  send({ type: 'probe', x, y, z: 0, nx: 0, ny: 0, nz: 1, press: expPress ? Math.min(1, 0.35 + drag / 300) : 0, seq });
}
svg.addEventListener('pointermove', expMove);
svg.addEventListener('pointerdown', (ev) => { expPress = true; expFrom = [ev.clientX, ev.clientY]; expMove(ev); });
svg.addEventListener('pointerup', (ev) => { expPress = false; expMove(ev); });
S.cellScreenPos = (i) => {
  const [x, y] = S.trial.centres[i], p = svg.createSVGPoint(); p.x = x; p.y = S.trial.size_mm - y;
  const q = p.matrixTransform(svg.getScreenCTM()); return { x: q.x, y: q.y };
};
S.hipCell = () => {
  if (!S.trial || !S.state) return -1;
  const [hx, hy] = S.state.hip;
  return S.trial.centres.findIndex(([x, y]) => Math.hypot(hx - x, hy - y) <= S.trial.highlight_mm);
};
window.addEventListener('keydown', (ev) => {
  if (S.view !== 'experiment' || !['0', '1', '2'].includes(ev.key)) return;
  send({ type: 'answer', value: +ev.key });
});
$('expstart').onclick = () => send({ type: 'experiment', participant: +$('participant').value });
$('nexttrial').onclick = () => send({ type: 'next_trial' });
// Experimenter window (?view=experimenter): the controls, the progress and fig. 5.10 (mean
// correct of 25 per condition) and fig. 5.11 (per-model ratio), scored by the library from the
// participant CSVs in the workspace after every answer. The participant screen shows none of it.
const experimenter = new URLSearchParams(location.search).get('view') === 'experimenter';
$('openexp').onclick = () => window.open(`/?token=${encodeURIComponent(token)}&view=experimenter`, 'inhap-experimenter', 'width=900,height=760');
$('xstart').onclick = () => send({ type: 'experiment', participant: +$('xparticipant').value });
$('xnext').onclick = () => send({ type: 'next_trial' });
function onProgress(m) {
  S.progress = m;
  if (!experimenter) return;  // no cue on the participant screen
  $('progress').textContent = m.running
    ? `participant ${m.participant} · ${m.task} task, ${m.algorithm} · session ${m.session + 1}, trial ${m.trial + 1} (${m.index + 1}/${m.trials}) · this trial ${m.answered}/25 answered · ${m.answers} answers in all`
    : 'no experiment running';
  send({ type: 'summary' });
}
function onSummary(m) {
  S.summary = m;
  const rows = m.conditions.map((c) => `${c.algorithm} ${c.task}: ${c.mean.toFixed(1)} ± ${c.sd_trials.toFixed(1)} of 25 (${c.trials} trials); below 0.5: ${c.below_half.length ? 'M' + c.below_half.join(', M') : 'none'}`);
  $('summaryinfo').innerHTML = `${m.files.length} participant file(s), ${m.trials} trial(s)<br>` + rows.join('<br>');
  const draw = () => {
    if (typeof Plotly === 'undefined') return setTimeout(draw, 200);
    const name = (c) => `${c.algorithm} ${c.task}`;
    Plotly.react('fig510', [{ type: 'bar', x: m.conditions.map(name), y: m.conditions.map((c) => c.mean),
      error_y: { type: 'data', array: m.conditions.map((c) => c.sd_trials), visible: true } }],
    { title: { text: 'fig. 5.10: correct of 25', font: { size: 12 } }, margin: { l: 35, r: 5, t: 30, b: 40 }, height: 260, width: 300, yaxis: { range: [0, 25] } }, { staticPlot: true });
    const traces = m.conditions.map((c) => ({ type: 'bar', name: name(c), x: c.model_ratio.map((_, i) => 'M' + (i + 1)), y: c.model_ratio }));
    Plotly.react('ratioplot', traces, { title: { text: 'fig. 5.11: correct ratio per model', font: { size: 12 } }, margin: { l: 35, r: 5, t: 30, b: 30 }, height: 260, width: 520, yaxis: { range: [0, 1] }, showlegend: true, legend: { orientation: 'h' } }, { staticPlot: true });
  };
  draw();
}
if (experimenter) {
  document.body.classList.add('experimenter');
  S.view = 'experimenter';
  loadPlotly();
  for (const x of ['sampling', 'explore', 'experiment', 'palpation', 'model']) $('side-' + x).classList.add('hidden');
  $('side-experimenter').classList.remove('hidden');
  ws.addEventListener('open', () => { send({ type: 'progress' }); send({ type: 'summary' }); });
}

// --- palpation (thesis 4.3, figs 4.7-4.8) --------------------------------------------------
const palpGroup = new THREE.Group(), palpMarkers = new THREE.Group(), yieldLines = new THREE.Group();
palpGroup.add(palpMarkers, yieldLines);
scene.add(palpGroup);
const markerGeo = new THREE.SphereGeometry(1.6, 12, 8), markerMat = new THREE.MeshLambertMaterial({ color: 0xf0c000 });
Object.assign(S, { palpPoints: [], cycles: [], yield: null, palpRunning: false, palpError: null, sysSaved: null });
let palpDirty = false, palpPlateaus = [0.1, 0.6];
function addPalpPoint(p) {
  S.palpPoints.push([p.x, p.y, p.z]);
  const m = new THREE.Mesh(markerGeo, markerMat); m.position.copy(p); palpMarkers.add(m);
  $('palpn').textContent = S.palpPoints.length;
}
function clearYield() { for (const c of [...yieldLines.children]) { yieldLines.remove(c); c.geometry.dispose(); } }
$('palpclear').onclick = () => { if (S.palpRunning) return; S.palpPoints = []; palpMarkers.clear(); clearYield(); $('palpn').textContent = 0; };
$('palprun').onclick = () => {
  if (!S.palpPoints.length) { $('palpinfo').textContent = 'click the surface to add a point first'; return; }
  send({ type: 'palpate', points: S.palpPoints, quick: $('palpquick').checked, speed: +$('palpspeed').value });
};
$('palpstop').onclick = () => { S.palpRunning = false; send({ type: 'mode', mode: 'palpation' }); $('palpinfo').textContent = 'stopped'; };
$('savesys').onclick = () => send({ type: 'save_sys', path: $('sysname').value });
function onPalpation(m) {
  if (m.status === 'running') {
    Object.assign(S, { palpRunning: true, cycles: [], yield: null, palpError: null, sysSaved: null });
    palpPlateaus = m.plateaus; clearYield(); palpDirty = true;
    // the points as the server projected them onto the shape
    m.points.forEach((r, i) => palpMarkers.children[i] && palpMarkers.children[i].position.set(...r.position));
    $('palpinfo').textContent = `running: ${m.points.length} point(s), f_N ${m.levels.join(', ')} N, ${m.directions} directions`;
  } else if (m.status === 'failed') {
    S.palpRunning = false; S.palpError = m.message; $('palpinfo').textContent = m.message;
  }
}
function onCycle(m) { S.cycles.push(m); palpDirty = true; }
function drawPalpation() {
  palpDirty = false;
  const last = S.cycles[S.cycles.length - 1];
  const sel = last ? S.cycles.filter((c) => c.point === last.point && c.fn === last.fn) : [];
  drawFig47($('palpplot'), sel, palpPlateaus, last ? `point ${last.point}, f_N ${last.fn} N, ${S.cycles.length} cycles` : 'no cycles yet');
}
function onYield(m) {
  S.yield = m; S.palpRunning = false; clearYield();
  const p0 = m.points[0];
  drawFig48($('yieldplot'), m.levels, m.angles, p0.limits, `point ${p0.id}: creep ${p0.creep_viscosity.toFixed(3)} N s/mm`);
  // on the surface: the tangential elastic displacement limit per direction (x5), one loop per f_N
  for (const p of m.points) {
    const c = new THREE.Vector3(...p.position);
    m.levels.forEach((_, j) => {
      const pts = p.tdirs.map((t, k) => c.clone().addScaledVector(new THREE.Vector3(...t), 5 * (p.limits[j][k].r || 0)));
      const line = new THREE.LineLoop(new THREE.BufferGeometry().setFromPoints(pts), new THREE.LineBasicMaterial({ color: j ? 0x2020c0 : 0x8080ff }));
      yieldLines.add(line);
    });
  }
  $('palpinfo').textContent = `done: ${m.cycles} cycles, ${m.points.length} point(s) fitted`;
}
function onOk(m) {
  if (m.request === 'save_sys') { S.sysSaved = m; $('sysinfo').textContent = `wrote ${m.path} (read back: ${m.points} point(s), ${m.levels} f_N levels × ${m.directions} directions) and its ${m.cycles} cycles (.cycles.csv)`; }
}
S.palpTopScreenPos = () => {  // the highest vertex of the shape on the screen (the browser test)
  if (!palpMesh) return null;
  const a = palpMesh.geometry.attributes.position; let best = 0;
  for (let i = 1; i < a.count; ++i) if (a.getZ(i) > a.getZ(best)) best = i;
  const v = new THREE.Vector3(a.getX(best), a.getY(best), a.getZ(best)).project(camera), r = renderer.domElement.getBoundingClientRect();
  return { x: r.left + (v.x + 1) / 2 * r.width, y: r.top + (1 - v.y) / 2 * r.height };
};

// --- views ---------------------------------------------------------------------------------
function setView(v) {
  S.view = v;
  document.querySelectorAll('.tab').forEach((b) => b.classList.toggle('active', b.dataset.view === v));
  for (const s of ['sampling', 'explore', 'experiment', 'palpation', 'model']) $('side-' + s).classList.toggle('hidden', s !== v);
  host.classList.toggle('hidden', v === 'experiment' || v === 'model');
  modelView.show(v === 'model');
  svg.classList.toggle('hidden', v !== 'experiment');
  showFor(v);
  if (v === 'sampling') send({ type: 'mode', mode: tapping ? 'sampling' : 'idle' });
  if (v === 'explore') { send({ type: 'mode', mode: 'explore' }); if (!exploreMesh) send({ type: 'open_mesh', source: 'study25' }); }
  if (v === 'experiment' && S.trial) send({ type: 'mode', mode: 'experiment' });
  if (v === 'palpation' && !S.palpRunning) send({ type: 'mode', mode: 'palpation' });
  if (v === 'model') send({ type: 'mode', mode: 'model' });
  resize();
}
document.querySelectorAll('.tab').forEach((b) => (b.onclick = () => setView(b.dataset.view)));

// --- frame loop ----------------------------------------------------------------------------
modelView = createModelView({ $, S, send });
S.send = send;  // the browser test sends a few messages of its own (model_stats)
let fpsT = performance.now(), fpsN = 0;
const forceCanvas = $('fplot');
// Timings for the browser test: JS time of the render call and of the whole frame callback, ms.
S.perf = { renderMs: [], frameMs: [] }; S.renders = 0;
function perfPush(a, v) { a.push(v); if (a.length > 2000) a.shift(); }
let markedState = null;
function frame(t) {
  S.frames++; fpsN++;
  const now = performance.now();
  if (now - fpsT >= 1000) { S.fps = (fpsN * 1000) / (now - fpsT); fpsT = now; fpsN = 0;
    // (No adaptive pixel ratio any more: the scene renders only when it changes, so a slow
    // frame is not the WebGL's, and a resize re-rendered it.)
    S.pixelRatio = renderer.getPixelRatio();
    $('status').textContent = `${S.view} · ${S.fps.toFixed(0)} fps · ${S.state ? S.state.t.toFixed(1) : '-'} s` +
      (S.dropped ? ` · ${S.dropped} dropped` : ''); }
  drawState(t);
  if (S.view === 'model') modelView.tick();
  if (S.view === 'explore' && forceDirty) { forceDirty = false; drawLine(forceCanvas, fT, fY, 4, '|f| (N)', '#e07000'); }
  if (['sampling', 'explore', 'palpation'].includes(S.view) && (needRender || markedState !== S.state)) {
    const r0 = performance.now();
    if (needRender) { needRender = false; S.renders++; renderer.render(scene, camera); }
    markers.draw(camera, S.state, S.view === 'explore');  // after render: the camera's matrices
    markedState = S.state;
    perfPush(S.perf.renderMs, performance.now() - r0);
  }
  perfPush(S.perf.frameMs, performance.now() - now);
  requestAnimationFrame(frame);
}
resize();
fitCamera(new THREE.Box3(new THREE.Vector3(-60, -60, 0), new THREE.Vector3(60, 60, 40)));
requestAnimationFrame(frame);
