// inhap studio: the live probe markers over the WebGL view. The HIP (red), IHIP (green), CIHIP
// (blue) and the force arrow (orange) move with every state; the 3-D scene (the meshes, the
// samples) re-renders only when it changes. Without a GPU (software compositing) every WebGL
// frame is read back to the CPU, and that read-back held the page's main thread until SwiftShader
// had drawn the frame (docs/studio.md, "Measured"); moving four dots does not need it. Each
// marker is a small element of its own moved by a CSS transform, so a move repaints nothing and
// the compositor redraws only the few pixels around it. The markers are drawn on top of the
// surface, so a HIP pressed into it stays visible. Units: mm (the scene), CSS pixels (the page).
import * as THREE from 'three';

const c = new THREE.Vector3(), e = new THREE.Vector3(), right = new THREE.Vector3();
const BASE = 20;  // px: a dot's size before its scale (radius BASE / 2)

function element(parent, css) {
  const d = document.createElement('div');
  Object.assign(d.style, { position: 'absolute', left: '0', top: '0', willChange: 'transform, opacity', opacity: '0' }, css);
  parent.appendChild(d);
  return d;
}

export class Markers {
  constructor(host) {
    this.layer = element(host, { right: '0', bottom: '0', pointerEvents: 'none', overflow: 'hidden', opacity: '1', willChange: 'auto' });
    const dot = (color) => element(this.layer, {
      width: BASE + 'px', height: BASE + 'px', borderRadius: '50%', background: color,
      boxSizing: 'border-box', border: '1px solid rgba(0,0,0,0.55)', transformOrigin: '50% 50%' });
    this.hip = dot('#d02020'); this.ihip = dot('#20a020'); this.cihip = dot('#2040d0');
    this.shaft = element(this.layer, { width: '100px', height: '3px', background: '#ff8800', transformOrigin: '0 50%' });
    this.head = element(this.layer, { width: '12px', height: '10px', background: '#ff8800', transformOrigin: '0 50%',
      clipPath: 'polygon(0 0, 100% 50%, 0 100%)' });
    this.W = 1; this.H = 1;
  }

  resize(w, h) { this.W = w; this.H = h; }

  // Screen position (px) of a scene point and the screen radius of r mm there; null behind the camera.
  project(camera, p, r) {
    c.set(p[0], p[1], p[2]);
    right.setFromMatrixColumn(camera.matrixWorld, 0);
    e.copy(c).addScaledVector(right, r).project(camera);
    c.project(camera);
    if (c.z > 1 || c.z < -1) return null;
    const x = ((c.x + 1) / 2) * this.W, y = ((1 - c.y) / 2) * this.H;
    return { x, y, r: Math.max(2, Math.hypot(((e.x + 1) / 2) * this.W - x, ((1 - e.y) / 2) * this.H - y)) };
  }

  show(el, on) { const o = on ? '1' : '0'; if (el.style.opacity !== o) el.style.opacity = o; }

  dot(el, camera, p, r) {
    const s = p && this.project(camera, p, r);
    this.show(el, !!s);
    if (s) el.style.transform = `translate(${s.x - BASE / 2}px, ${s.y - BASE / 2}px) scale(${(2 * s.r) / BASE})`;
  }

  // The force arrow: from the IHIP along f, 4 |f| + 2 mm long (as the 3-D arrow it replaced).
  arrow(camera, from, f) {
    const fl = f ? Math.hypot(f[0], f[1], f[2]) : 0;
    let a = null, b = null;
    if (fl > 0.01) {
      const len = 4 * fl + 2;
      a = this.project(camera, from, 0);
      b = this.project(camera, [0, 1, 2].map((i) => from[i] + (f[i] / fl) * len), 0);
    }
    this.show(this.shaft, !!(a && b)); this.show(this.head, !!(a && b));
    if (!a || !b) return;
    const ang = Math.atan2(b.y - a.y, b.x - a.x), d = Math.hypot(b.x - a.x, b.y - a.y);
    this.shaft.style.transform = `translate(${a.x}px, ${a.y - 1.5}px) rotate(${ang}rad) scaleX(${Math.max(0, d - 10) / 100})`;
    this.head.style.transform = `translate(${b.x}px, ${b.y - 5}px) rotate(${ang}rad) translate(-12px, 0)`;
  }

  // `state`: the server's state message (hip, ihip, cihip, f); `explore`: the proxies and the
  // arrow too (the other 3-D views show the probe only, as a red ring: in the palpation view the
  // probe rests on the yellow point it presses, which a filled dot would hide).
  draw(camera, state, explore) {
    if (this.ring !== !explore) {  // outside explore the HIP is a ring: the points under it stay visible
      this.ring = !explore;
      Object.assign(this.hip.style, this.ring
        ? { background: 'transparent', border: '3px solid #d02020' }
        : { background: '#d02020', border: '1px solid rgba(0,0,0,0.55)' });
    }
    this.dot(this.hip, camera, state && state.hip, 2.4);
    this.dot(this.ihip, camera, explore && state && state.ihip, 1.9);
    this.dot(this.cihip, camera, explore && state && state.cihip, 1.5);
    this.arrow(camera, state && state.ihip, explore && state && state.f);
  }
}
