// inhap studio: the live probe markers on a 2-D canvas over the WebGL view. The HIP (red), IHIP
// (green), CIHIP (blue) and the force arrow (orange) move with every state; the 3-D scene (the
// meshes, the samples) re-renders only when it changes. Without a GPU (software compositing)
// every WebGL frame is read back to the CPU, and that read-back holds the page's main thread
// until SwiftShader has drawn the frame (see docs/studio.md, "Measured"); moving four dots does
// not need it. The markers are drawn on top of the surface, so a HIP pressed into it stays
// visible. Units: mm (the scene), CSS pixels (the canvas).
import * as THREE from 'three';

const c = new THREE.Vector3(), e = new THREE.Vector3(), right = new THREE.Vector3();

export class Markers {
  constructor(host) {
    this.canvas = document.createElement('canvas');
    Object.assign(this.canvas.style, { position: 'absolute', left: '0', top: '0', pointerEvents: 'none' });
    host.appendChild(this.canvas);
    this.g = this.canvas.getContext('2d');
  }

  resize(w, h) {
    this.canvas.width = w; this.canvas.height = h;
    this.canvas.style.width = w + 'px'; this.canvas.style.height = h + 'px';
  }

  // Screen position (px) of a scene point and the screen radius of r mm there; null behind the camera.
  project(camera, p, r) {
    c.set(p[0], p[1], p[2]);
    right.setFromMatrixColumn(camera.matrixWorld, 0);
    e.copy(c).addScaledVector(right, r).project(camera);
    c.project(camera);
    if (c.z > 1 || c.z < -1) return null;
    const W = this.canvas.width, H = this.canvas.height;
    const x = ((c.x + 1) / 2) * W, y = ((1 - c.y) / 2) * H;
    return { x, y, r: Math.max(2, Math.hypot(((e.x + 1) / 2) * W - x, ((1 - e.y) / 2) * H - y)) };
  }

  dot(camera, p, r, color) {
    const s = this.project(camera, p, r);
    if (!s) return;
    const g = this.g;
    g.beginPath(); g.arc(s.x, s.y, s.r, 0, 2 * Math.PI);
    g.fillStyle = color; g.fill();
    g.lineWidth = 1; g.strokeStyle = 'rgba(0,0,0,0.55)'; g.stroke();
  }

  // The force arrow: from the IHIP along f, 4 |f| + 2 mm long (as the 3-D arrow it replaces).
  arrow(camera, from, f) {
    const fl = Math.hypot(f[0], f[1], f[2]);
    if (!(fl > 0.01)) return;
    const len = 4 * fl + 2, to = [0, 1, 2].map((i) => from[i] + (f[i] / fl) * len);
    const a = this.project(camera, from, 0), b = this.project(camera, to, 0);
    if (!a || !b) return;
    const g = this.g, dx = b.x - a.x, dy = b.y - a.y, d = Math.hypot(dx, dy) || 1, ux = dx / d, uy = dy / d;
    g.strokeStyle = '#ff8800'; g.fillStyle = '#ff8800'; g.lineWidth = 3;
    g.beginPath(); g.moveTo(a.x, a.y); g.lineTo(b.x - 8 * ux, b.y - 8 * uy); g.stroke();
    g.beginPath(); g.moveTo(b.x, b.y); g.lineTo(b.x - 10 * ux - 5 * uy, b.y - 10 * uy + 5 * ux);
    g.lineTo(b.x - 10 * ux + 5 * uy, b.y - 10 * uy - 5 * ux); g.closePath(); g.fill();
  }

  // `state`: the server's state message (hip, ihip, cihip, f); `explore`: draw the proxies and
  // the arrow too (the other 3-D views show the probe only).
  draw(camera, state, explore) {
    this.g.clearRect(0, 0, this.canvas.width, this.canvas.height);
    if (!state) return;
    this.dot(camera, state.hip, 2.4, '#d02020');
    if (!explore) return;
    this.dot(camera, state.ihip, 1.9, '#20a020');
    this.dot(camera, state.cihip, 1.5, '#2040d0');
    this.arrow(camera, state.ihip, state.f);
  }
}
