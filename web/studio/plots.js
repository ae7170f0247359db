// inhap studio: light canvas 2-D plots (no plotting library: each is redrawn only when its data
// changed, or at most once per animation frame for the scrolling force plot).
// Units: mm, N, s.

export const dirColors = ['#d62728', '#1f77b4', '#2ca02c', '#9467bd', '#ff7f0e', '#17becf', '#8c564b', '#e377c2',
  '#7f7f7f', '#bcbd22', '#393b79', '#637939', '#8c6d31', '#843c39', '#7b4173', '#3182bd'];

function niceMax(v) {
  if (!(v > 0)) return 1;
  const e = Math.pow(10, Math.floor(Math.log10(v))), m = v / e;
  return (m <= 1 ? 1 : m <= 2 ? 2 : m <= 5 ? 5 : 10) * e;
}

// Axes in a box; returns the data -> pixel maps.
function axes(g, box, xmin, xmax, ymax, xlabel, ylabel) {
  const { x, y, w, h } = box;
  g.strokeStyle = '#888'; g.lineWidth = 1; g.fillStyle = '#444'; g.font = '10px sans-serif';
  g.beginPath(); g.moveTo(x, y); g.lineTo(x, y + h); g.lineTo(x + w, y + h); g.stroke();
  g.textAlign = 'right'; g.fillText(ymax.toPrecision(2), x - 2, y + 8); g.fillText('0', x - 2, y + h);
  g.textAlign = 'center'; g.fillText(xmax.toPrecision(2), x + w - 8, y + h + 11); g.fillText(xmin.toPrecision(2), x, y + h + 11);
  g.fillText(xlabel, x + w / 2, y + h + 11);
  g.save(); g.translate(x - 24, y + h / 2); g.rotate(-Math.PI / 2); g.fillText(ylabel, 0, 0); g.restore();
  return { px: (v) => x + ((v - xmin) / (xmax - xmin)) * w, py: (v) => y + h - (Math.min(v, ymax) / ymax) * h };
}

// Thesis fig. 4.7 for one reference point and f_N: f_T against ||u^p_100|| (short plateau, top)
// and against ||Δu^p_plateau|| = ||u^p_long|| - ||u^p_short|| (bottom); one colour per direction.
// `cycles`: [{dir, ft, plateau, up}], `plateaus`: [short, long] (s).
export function drawFig47(canvas, cycles, plateaus, title) {
  const g = canvas.getContext('2d'), W = canvas.width, H = canvas.height;
  g.clearRect(0, 0, W, H);
  const short = new Map(), long = new Map();  // key dir|ft -> up
  for (const c of cycles) {
    const k = c.dir + '|' + c.ft.toFixed(4);
    (Math.abs(c.plateau - plateaus[0]) < 1e-9 ? short : long).set(k, c);
  }
  const growth = [];
  for (const [k, s] of short) if (long.has(k)) growth.push({ dir: s.dir, ft: s.ft, v: Math.max(0, long.get(k).up - s.up) });
  const fts = cycles.map((c) => c.ft), xmax = Math.max(0.1, ...fts) * 1.05;
  const xmin = fts.length ? Math.min(...fts) * 0.9 : 0;
  const top = [...short.values()].map((c) => ({ dir: c.dir, ft: c.ft, v: c.up }));
  const panel = (pts, box, ylabel) => {
    const a = axes(g, box, xmin, xmax, niceMax(Math.max(0.05, ...pts.map((p) => p.v))), 'f_T (N)', ylabel);
    const byDir = new Map();
    for (const p of pts) { if (!byDir.has(p.dir)) byDir.set(p.dir, []); byDir.get(p.dir).push(p); }
    for (const [d, list] of byDir) {
      list.sort((p, q) => p.ft - q.ft);
      g.strokeStyle = g.fillStyle = dirColors[d % dirColors.length];
      g.beginPath(); list.forEach((p, i) => (i ? g.lineTo : g.moveTo).call(g, a.px(p.ft), a.py(p.v))); g.stroke();
      for (const p of list) g.fillRect(a.px(p.ft) - 2, a.py(p.v) - 2, 4, 4);
    }
  };
  g.fillStyle = '#222'; g.font = '11px sans-serif'; g.textAlign = 'left'; g.fillText(title, 34, 10);
  const bh = (H - 58) / 2;
  panel(top, { x: 34, y: 16, w: W - 44, h: bh }, '‖u^p_100‖ mm');
  panel(growth, { x: 34, y: 16 + bh + 26, w: W - 44, h: bh }, '‖Δu^p‖ mm');
}

// Thesis fig. 4.8 in the tangent plane: the elastic limit f_T per direction as one closed polygon
// per f_N level (darker = larger f_N). `limits[level][dir].f` (N), `angles` (rad).
export function drawFig48(canvas, levels, angles, limits, title) {
  const g = canvas.getContext('2d'), W = canvas.width, H = canvas.height;
  g.clearRect(0, 0, W, H);
  const cx = W / 2, cy = H / 2 + 6, R = Math.min(W, H) / 2 - 22;
  const fmax = niceMax(Math.max(0.1, ...limits.flat().map((l) => l.f || 0)));
  g.strokeStyle = '#ccc'; g.lineWidth = 1;
  for (const r of [0.5, 1]) { g.beginPath(); g.arc(cx, cy, r * R, 0, 2 * Math.PI); g.stroke(); }
  g.beginPath(); g.moveTo(cx - R, cy); g.lineTo(cx + R, cy); g.moveTo(cx, cy - R); g.lineTo(cx, cy + R); g.stroke();
  g.fillStyle = '#444'; g.font = '10px sans-serif'; g.textAlign = 'left';
  g.fillText(`${fmax.toPrecision(2)} N`, cx + R * 0.72, cy - R * 0.72);
  g.fillText(title, 4, 11);
  levels.forEach((fn, j) => {
    const shade = Math.round(200 - (160 * (j + 1)) / levels.length);
    g.strokeStyle = `rgb(${shade},${shade},255)`; g.lineWidth = 2;
    g.beginPath();
    angles.forEach((a, k) => {
      const r = ((limits[j][k].f || 0) / fmax) * R, x = cx + r * Math.cos(a), y = cy - r * Math.sin(a);
      k ? g.lineTo(x, y) : g.moveTo(x, y);
    });
    g.closePath(); g.stroke();
    angles.forEach((a, k) => {
      const l = limits[j][k], r = ((l.f || 0) / fmax) * R;
      g.fillStyle = l.e ? '#f90' : dirColors[k % dirColors.length];
      g.fillRect(cx + r * Math.cos(a) - 2, cy - r * Math.sin(a) - 2, 4, 4);
    });
    g.fillStyle = '#444'; g.fillText(`f_N ${fn} N`, 4, H - 6 - 12 * (levels.length - 1 - j));
  });
}

// A scrolling line plot of (t, v) with a fixed time window (the explore view's |f|).
export function drawLine(canvas, ts, vs, windowS, ylabel, color) {
  const g = canvas.getContext('2d'), W = canvas.width, H = canvas.height;
  g.clearRect(0, 0, W, H);
  if (!ts.length) return;
  const t1 = ts[ts.length - 1], t0 = t1 - windowS;
  let vmax = 0.5;
  for (let i = 0; i < vs.length; ++i) if (ts[i] >= t0 && vs[i] > vmax) vmax = vs[i];
  vmax = niceMax(vmax);
  const x0 = 34, y0 = 6, w = W - 40, h = H - 24;
  g.strokeStyle = '#888'; g.lineWidth = 1; g.fillStyle = '#444'; g.font = '10px sans-serif';
  g.beginPath(); g.moveTo(x0, y0); g.lineTo(x0, y0 + h); g.lineTo(x0 + w, y0 + h); g.stroke();
  g.textAlign = 'right'; g.fillText(vmax.toPrecision(2), x0 - 2, y0 + 8); g.fillText('0', x0 - 2, y0 + h);
  g.textAlign = 'center'; g.fillText(`last ${windowS} s`, x0 + w / 2, y0 + h + 12);
  g.save(); g.translate(10, y0 + h / 2); g.rotate(-Math.PI / 2); g.fillText(ylabel, 0, 0); g.restore();
  g.strokeStyle = color; g.lineWidth = 1.5; g.beginPath();
  let first = true;
  for (let i = 0; i < ts.length; ++i) {
    if (ts[i] < t0) continue;
    const x = x0 + ((ts[i] - t0) / windowS) * w, y = y0 + h - (vs[i] / vmax) * h;
    first ? g.moveTo(x, y) : g.lineTo(x, y); first = false;
  }
  g.stroke();
}
