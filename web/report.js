// Glue of the inhap demo report: reads the figures' data (JSON written by `inhap demo`) and
// hands it to plotly.js (2-D charts) and three.js (rotatable 3-D meshes). No drawing of our own.
// When done it checks that every figure drew something (a plotly figure: at least one trace or
// table rendered into its svg; a three.js figure: mesh vertices and non-background pixels in its
// canvas) and writes "REPORT_OK n_figures=K" or "REPORT_FAIL ..." into document.title and
// #report-status (read back by tests/report).
import * as THREE from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";

const report = JSON.parse(document.getElementById("inhap-data").textContent);

function el(tag, attrs = {}, text = "") {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (text) e.textContent = text;
  return e;
}

function summaryTable() {
  const t = el("table");
  const head = el("tr");
  for (const h of ["step", "thesis sec.", "quantity", "measured", "thesis"]) head.appendChild(el("th", {}, h));
  t.appendChild(head);
  for (const s of report.steps) {
    for (const r of s.rows) {
      const tr = el("tr");
      tr.appendChild(el("td", {}, s.name));
      tr.appendChild(el("td", {}, s.chapter));
      tr.appendChild(el("td", {}, r.quantity));
      tr.appendChild(el("td", r.measured.startsWith("skipped") ? { class: "na" } : {}, r.measured));
      tr.appendChild(el("td", {}, r.thesis));
      t.appendChild(tr);
    }
  }
  return t;
}

async function plotly(div, spec) {
  const layout = Object.assign({ margin: { l: 60, r: 20, t: 20, b: 50 }, legend: { orientation: "h", y: -0.2 },
                                 height: 380, paper_bgcolor: "#fff" }, spec.layout || {});
  await Plotly.newPlot(div, spec.data, layout, { displaylogo: false, responsive: true });
  // Something drawn: a trace path with a real outline (line, marker, box) or a table cell's text.
  const marks = [...div.querySelectorAll("g.trace path, .cell-text")]
    .filter(e => e.tagName.toLowerCase() !== "path" || /[LACHV].*\d/.test(e.getAttribute("d") || "")).length;
  div.dataset.marks = marks;
  return marks > 0 ? null : "plotly figure without traces";
}

function three(div, spec) {
  const width = div.clientWidth || 600, height = div.clientHeight || 420;
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setSize(width, height);
  div.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xffffff);
  const group = new THREE.Group();
  for (const m of spec.meshes || []) {
    const g = new THREE.BufferGeometry();
    g.setAttribute("position", new THREE.Float32BufferAttribute(m.positions, 3));
    g.setAttribute("color", new THREE.Float32BufferAttribute(m.colors, 3));
    g.setIndex(m.indices);
    g.computeVertexNormals();
    group.add(new THREE.Mesh(g, new THREE.MeshLambertMaterial({ vertexColors: true, side: THREE.DoubleSide })));
  }
  for (const l of spec.lines || []) {
    const pts = [];
    for (let i = 0; i + 2 < l.points.length; i += 3) pts.push(new THREE.Vector3(l.points[i], l.points[i + 1], l.points[i + 2]));
    if (pts.length < 2) continue;
    const tube = new THREE.TubeGeometry(new THREE.CatmullRomCurve3(pts), Math.min(600, 4 * pts.length), spec.line_radius || 0.5, 6, false);
    group.add(new THREE.Mesh(tube, new THREE.MeshLambertMaterial({ color: l.color })));
  }
  scene.add(group);
  scene.add(new THREE.AmbientLight(0xffffff, 1.2));
  const sun = new THREE.DirectionalLight(0xffffff, 1.8);
  sun.position.set(1, -1, 2);
  scene.add(sun);
  // z is up in inhap data.
  const box = new THREE.Box3().setFromObject(group);
  const centre = box.getCenter(new THREE.Vector3()), size = box.getSize(new THREE.Vector3()).length();
  const camera = new THREE.PerspectiveCamera(40, width / height, size / 100, size * 10);
  camera.up.set(0, 0, 1);
  const [cx, cy, cz] = spec.camera || [0.2, -0.9, 0.7];  // view direction, in scene sizes
  camera.position.copy(centre).add(new THREE.Vector3(cx * size, cy * size, cz * size));
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.target.copy(centre);
  controls.update();
  const draw = () => renderer.render(scene, camera);
  controls.addEventListener("change", draw);
  draw();
  // Something drawn: vertices in the scene and pixels that are not the white background.
  let vertices = 0;
  group.traverse(o => { if (o.geometry) vertices += o.geometry.getAttribute("position").count; });
  const gl = renderer.getContext(), w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
  const px = new Uint8Array(w * h * 4);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
  let coloured = 0;
  for (let i = 0; i < px.length; i += 4) if (px[i] < 245 || px[i + 1] < 245 || px[i + 2] < 245) ++coloured;
  div.dataset.marks = coloured;
  if (!vertices) return "three.js figure without vertices";
  return coloured > 0.005 * w * h ? null : `three.js figure drew ${coloured} of ${w * h} pixels`;
}

function figureCard(f) {
  const card = el("div", { class: "card" });
  card.appendChild(el("h3", {}, f.title));
  card.appendChild(el("p", { class: "caption" }, f.caption));
  const div = el("div", { class: "figure" + (f.kind === "three" ? " three" : ""), id: "fig-" + f.id, "data-kind": f.kind });
  card.appendChild(div);
  return [card, div];
}

async function main() {
  document.getElementById("subtitle").textContent =
    `${report.quick ? "quick run" : "full run"}, seed ${report.seed}, lab physics ${report.physics || "builtin"}, ${report.total_s} s wall, ${report.cpu_s} s CPU. ` +
    "Units: mm, N, s, N/mm. Each figure's data is also in figures.json and the CSV files beside this report.";
  document.getElementById("summary").appendChild(summaryTable());
  const jobs = [], drawn = [], problems = [];
  const check = (div, problem) => { drawn.push(div); if (problem) problems.push(`${div.id}: ${problem}`); };
  for (const s of report.steps) {
    const sec = el("section", { id: "step-" + s.name });
    sec.appendChild(el("h2", {}, `${s.title} (thesis ${s.chapter})`));
    const meta = [s.available ? `${s.seconds} s (${s.cpu_seconds} s CPU)` : "", s.note, s.files.length ? "data: " + s.files.join(", ") : ""].filter(Boolean);
    sec.appendChild(el("p", { class: "note" }, meta.join(" | ")));
    const grid = el("div", { class: "grid" });
    sec.appendChild(grid);
    document.getElementById("steps").appendChild(sec);
    for (const f of s.figures) {
      const [card, div] = figureCard(f);
      grid.appendChild(card);
      if (f.kind === "plotly") jobs.push(plotly(div, f.spec).then(p => check(div, p)));
      else if (f.kind === "three") check(div, three(div, f.spec));
      else problems.push(`${div.id}: unknown figure kind ${f.kind}`);
    }
  }
  await Promise.all(jobs);
  const empty = drawn.filter(d => !d.querySelector("svg, canvas")).map(d => d.id);
  problems.push(...empty.map(id => "figure drew nothing: " + id), ...window.INHAP_ERRORS);
  const status = problems.length ? "REPORT_FAIL " + problems.join("; ") : `REPORT_OK n_figures=${drawn.length}`;
  document.title = status;
  document.getElementById("report-status").textContent = status;
}

main().catch(e => {
  console.error(e);
  document.title = "REPORT_FAIL " + (e && e.message || e);
  document.getElementById("report-status").textContent = document.title + " " + window.INHAP_ERRORS.join("; ");
});
