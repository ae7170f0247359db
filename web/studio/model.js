// inhap studio: the Model view (docs/studio.md): record a free exploration with a live coverage
// map, train in the background, feel the model against the object (A/B, blind answers), plot
// both forces on the same probe path. A 2-D canvas: the object from above.
// Units: mm, N, s.

const FMAX = 5;  // N, the top of the map's colour scale (the modelling range)

export function createModelView({ $, S, send }) {
  const canvas = $('modelmap');
  const M = (S.model = {
    coverage: null, trained: null, progress: null, compare: [], rmse: null, n: 0, source: 'object',
    blind: false, answers: 0, stats: [], recorded: null, recording: false, object: null,
  });
  let dirty = true, plotDirty = false, press = false, from = null, seq = 1e9;  // seq: above Explore's

  // --- the object's top (for z under the mouse) and the map's frame ---------------------------
  let box = { x0: -50, x1: 50, y0: -50, y1: 50 };
  function setObject(m) {
    M.object = m;
    const v = m.vertices;
    let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
    for (let i = 0; i < v.length; i += 3) { x0 = Math.min(x0, v[i]); x1 = Math.max(x1, v[i]); y0 = Math.min(y0, v[i + 1]); y1 = Math.max(y1, v[i + 1]); }
    box = { x0, x1, y0, y1 }; dirty = true;
  }
  function zAt(x, y) {
    const v = M.object ? M.object.vertices : null; if (!v) return 0;
    let best = Infinity, z = 0;
    for (let i = 0; i < v.length; i += 3) { const d = (v[i] - x) ** 2 + (v[i + 1] - y) ** 2; if (d < best) { best = d; z = v[i + 2]; } }
    return z;
  }
  function frame() {
    const w = canvas.clientWidth || 800, h = canvas.clientHeight || 600;
    if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
    const s = Math.min((w - 40) / (box.x1 - box.x0 || 1), (h - 40) / (box.y1 - box.y0 || 1));
    const ox = (w - s * (box.x1 - box.x0)) / 2, oy = (h - s * (box.y1 - box.y0)) / 2;
    return { s, px: (x) => ox + (x - box.x0) * s, py: (y) => h - oy - (y - box.y0) * s, mx: (u) => box.x0 + (u - ox) / s, my: (v) => box.y0 + (h - oy - v) / s };
  }
  M.screenPos = (x, y) => { const f = frame(), r = canvas.getBoundingClientRect(); return { x: r.left + f.px(x), y: r.top + f.py(y) }; };

  // --- drawing -------------------------------------------------------------------------------
  function colour(f) {  // 0 N: pale blue .. FMAX: red
    const u = Math.max(0, Math.min(1, f / FMAX));
    return `hsl(${(0.62 * (1 - u) * 360).toFixed(0)}, 75%, ${(70 - 20 * u).toFixed(0)}%)`;
  }
  function draw() {
    dirty = false;
    const g = canvas.getContext('2d'), f = frame();
    g.clearRect(0, 0, canvas.width, canvas.height);
    g.strokeStyle = '#bbb'; g.strokeRect(f.px(box.x0), f.py(box.y1), (box.x1 - box.x0) * f.s, (box.y1 - box.y0) * f.s);
    const c = M.coverage;
    if (c) {
      const cs = c.cell_mm * f.s;
      for (const [x, y, fm, mask] of c.cells) {
        g.fillStyle = colour(fm);
        g.fillRect(f.px(x) - cs / 2, f.py(y) - cs / 2, cs + 0.5, cs + 0.5);
        if (mask && cs > 6) {
          g.strokeStyle = 'rgba(0,0,0,0.55)'; g.lineWidth = 1; g.beginPath();
          for (let k = 0; k < 8; ++k) if (mask & (1 << k)) {
            const a = k * Math.PI / 4; g.moveTo(f.px(x), f.py(y)); g.lineTo(f.px(x) + 0.45 * cs * Math.cos(a), f.py(y) - 0.45 * cs * Math.sin(a));
          }
          g.stroke();
        }
      }
      g.strokeStyle = '#c00'; g.fillStyle = '#c00'; g.lineWidth = 2; g.font = '12px sans-serif';
      for (const [x, y] of c.gaps) {
        const X = f.px(x), Y = f.py(y);
        g.beginPath(); g.moveTo(X - 6, Y - 6); g.lineTo(X + 6, Y + 6); g.moveTo(X + 6, Y - 6); g.lineTo(X - 6, Y + 6); g.stroke();
        g.fillText('explore here', X + 8, Y - 6);
      }
    }
    // colour scale
    for (let i = 0; i <= 50; ++i) { g.fillStyle = colour(FMAX * i / 50); g.fillRect(10 + 3 * i, 10, 3, 10); }
    g.fillStyle = '#333'; g.font = '11px sans-serif'; g.fillText('0', 10, 32); g.fillText(`${FMAX} N`, 150, 32);
    g.fillText(c ? `${c.samples} contact samples, ${c.cells.length} cells` : 'no exploration yet', 180, 20);
    if (S.state) {  // the probe
      const [x, y] = S.state.p;
      g.fillStyle = S.state.contact ? '#ffffff' : '#20a020'; g.strokeStyle = '#000'; g.lineWidth = 2;
      g.beginPath(); g.arc(f.px(x), f.py(y), 7, 0, 2 * Math.PI); g.fill(); g.stroke();
    }
  }
  function drawPlot() {
    plotDirty = false;
    const cv = $('mplot'), g = cv.getContext('2d'), W = cv.width, H = cv.height;
    g.clearRect(0, 0, W, H);
    const pts = M.compare; if (!pts.length) return;
    const t1 = pts[pts.length - 1][0], t0 = t1 - 4;
    const rows = [['x', 1, 4], ['y', 2, 5], ['z', 3, 6]], h = H / 3;
    rows.forEach(([name, io, im], r) => {
      let lo = -0.5, hi = 0.5;
      for (const p of pts) { lo = Math.min(lo, p[io], p[im]); hi = Math.max(hi, p[io], p[im]); }
      const y = (v) => r * h + 4 + (h - 12) * (1 - (v - lo) / (hi - lo)), x = (t) => 28 + (W - 32) * (t - t0) / 4;
      g.strokeStyle = '#ddd'; g.beginPath(); g.moveTo(28, y(0)); g.lineTo(W - 4, y(0)); g.stroke();
      g.fillStyle = '#444'; g.font = '10px sans-serif'; g.fillText(`f${name}`, 2, r * h + h / 2); g.fillText(hi.toFixed(1), 2, r * h + 12);
      for (const [i, col] of [[io, '#1f77b4'], [im, '#ff7f0e']]) {
        g.strokeStyle = col; g.beginPath();
        pts.forEach((p, k) => (k ? g.lineTo(x(p[0]), y(p[i])) : g.moveTo(x(p[0]), y(p[i]))));
        g.stroke();
      }
    });
  }

  // --- messages ------------------------------------------------------------------------------
  function onMessage(m) {
    switch (m.type) {
      case 'coverage':
        M.coverage = m; dirty = true;
        if (!M.object && m.cells.length) {  // a bridged device: no object, the frame fits the cells
          const xs = m.cells.map((c) => c[0]), ys = m.cells.map((c) => c[1]), pad = 2 * m.cell_mm;
          box = { x0: Math.min(...xs) - pad, x1: Math.max(...xs) + pad, y0: Math.min(...ys) - pad, y1: Math.max(...ys) + pad };
        }
        $('mrecinfo').textContent = `${m.operator}: ${m.t.toFixed(1)} of ${m.seconds} s ${m.operator === 'device' ? 'device time' : 'simulated'}, ${m.samples} contact samples, ${m.cells.length} cells visited, ${m.gaps.length} gaps`;
        if (m.full && M.recording && (m.operator === 'explore' || m.operator === 'device')) send({ type: 'model_stop' });
        return true;
      case 'compare':
        M.rmse = m.rmse; M.n = m.n; M.hasModel = m.has_model;
        if (m.source) M.source = m.source;
        for (const p of m.points) M.compare.push(p);
        if (M.compare.length && M.compare[0][0] > M.compare[M.compare.length - 1][0]) M.compare = m.points.slice();  // a new loop
        while (M.compare.length && M.compare[0][0] < M.compare[M.compare.length - 1][0] - 4) M.compare.shift();
        plotDirty = true;
        return true;
      case 'train_progress':
        M.progress = m;
        if (m.note) $('msummary').textContent += m.note + '\n';
        else $('mtraininfo').textContent = `${m.stage} ${(100 * m.fraction).toFixed(0)} %` + (m.eta_s ? `, ${m.eta_s.toFixed(0)} s left` : '');
        return true;
      case 'trained':
        M.trained = m;
        if (m.status === 'done') {
          $('mtraininfo').textContent = `done in ${m.wall_s.toFixed(1)} s (one thread in a process of its own, ${m.cpu_s.toFixed(1)} s CPU: ${m.cores.toFixed(2)} cores)`;
          $('msummary').textContent = m.lines.join('\n') + '\nfiles: ' + m.files.join(', ');
          M.coverage = m.coverage; dirty = true;
        } else $('mtraininfo').textContent = m.status + (m.message ? ': ' + m.message : '');
        return true;
      case 'model_stats': M.stats.push(m); return true;
      case 'ok':
        if (m.request === 'model_record') { M.recording = true; M.coverage = null; dirty = true; }
        if (m.request === 'model_stop') {
          M.recording = false; M.recorded = m;
          $('mrecinfo').textContent = m.rows ? `wrote ${m.path}${m.truth ? ' and ' + m.truth : ' (no truth: a bridged device)'}: ${m.rows} rows (${m.contact_rows} in contact), ${m.seconds.toFixed(1)} s` : 'nothing recorded';
          if (m.rows) $('mtrainrec').value = m.path;
        }
        if (m.request === 'model_source' || m.request === 'model_blind' || m.request === 'model_answer') {
          M.source = m.source;
          if (m.request === 'model_answer') { M.answers = m.answers; $('mabinfo').textContent = `${m.answers} answer(s) in ${m.path}; trial ${m.trial}: A`; }
          if (m.request === 'model_blind') { M.blind = m.blind; $('mabinfo').textContent = m.blind ? `blind trial ${m.trial}: A (answers go to ${m.path})` : ''; }
        }
        if (m.request === 'model_train') { $('msummary').textContent = ''; $('mtraininfo').textContent = 'training…'; }
        return false;
      default: return false;
    }
  }

  // --- input ---------------------------------------------------------------------------------
  function move(ev) {
    const f = frame(), r = canvas.getBoundingClientRect();
    const x = f.mx(ev.clientX - r.left), y = f.my(ev.clientY - r.top);
    const drag = press && from ? Math.hypot(ev.clientX - from[0], ev.clientY - from[1]) : 0;
    send({ type: 'probe', x, y, z: zAt(x, y), nx: 0, ny: 0, nz: 1, press: press ? Math.min(1, 0.35 + drag / 300) : 0, seq: ++seq });
  }
  canvas.addEventListener('pointermove', move);
  canvas.addEventListener('pointerdown', (ev) => { if (ev.button !== 0) return; press = true; from = [ev.clientX, ev.clientY]; move(ev); });
  window.addEventListener('pointerup', (ev) => { if (press) { press = false; if (S.view === 'model') move(ev); } });
  window.addEventListener('keydown', (ev) => {
    if (S.view !== 'model' || ev.key !== 'm' || ev.target.tagName === 'INPUT') return;
    send({ type: 'model_source', source: M.blind ? (M.source === 'a' ? 'b' : 'a') : 'toggle' });
  });
  $('mrec').onclick = () => send({ type: 'model_record', operator: $('mrecop').value, seconds: +$('mrecsecs').value, path: $('mrecname').value });
  $('mrecstop').onclick = () => send({ type: 'model_stop' });
  $('mtrain').onclick = () => send({ type: 'model_train', recording: $('mtrainrec').value, out: $('mtrainout').value, proxy: $('mproxy').value });
  $('mcancel').onclick = () => send({ type: 'model_cancel' });
  $('mobject').onclick = () => send({ type: 'model_source', source: M.blind ? 'a' : 'object' });
  $('mmodel').onclick = () => send({ type: 'model_source', source: M.blind ? 'b' : 'model' });
  $('mblind').onchange = () => send({ type: 'model_blind', on: $('mblind').checked, path: $('mabname').value });
  $('mansa').onclick = () => send({ type: 'model_answer', model: 'a' });
  $('mansb').onclick = () => send({ type: 'model_answer', model: 'b' });

  let shownState = null;
  function tick() {  // once per animation frame while the view is shown
    if (shownState !== S.state) { shownState = S.state; dirty = true; }
    if (dirty) draw();
    if (plotDirty && !M.blind) drawPlot();
    $('mcompare').classList.toggle('hidden', M.blind);
    $('manswers').classList.toggle('hidden', !M.blind);
    $('msource').textContent = M.blind ? (M.source === 'b' ? 'B' : 'A') : M.source;
    $('mmodel').textContent = M.blind ? 'B' : 'Model'; $('mobject').textContent = M.blind ? 'A' : 'Object';
    if (S.state) $('mfmag').textContent = Math.hypot(...S.state.f).toFixed(2);
    if (M.rmse && !M.blind) $('mrmse').textContent = `RMSE x/y/z ${M.rmse.map((v) => v.toFixed(3)).join(' / ')} N over ${M.n} ticks in contact`;
  }
  function show(on) { canvas.classList.toggle('hidden', !on); dirty = true; }
  return { onMessage, setObject, tick, show };
}
