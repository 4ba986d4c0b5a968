// A panel in the 3D scene for the protocol's steps (docs/protocol.md, "In the headset"): text,
// an image and buttons drawn on a canvas texture, placed in front of the head, level and facing
// it. The controller's ray (or the mouse's, in the inline preview) picks a button and the
// trigger presses it, as in the model menu (draw/menu.mjs). What it shows is the protocol's
// (flow/protocol.mjs, steps.mjs's panelFrame); as a feature of the view (view/features.mjs) it
// hides when the page leaves a step.
//
// A layout is a list of boxes in the canvas's pixels: `{ type: 'text', text, x, y, w, size,
// bold, color, align }` (wrapped to `w`), `{ type: 'button', id, label, x, y, w, h, on }`,
// `{ type: 'image', image, x, y, w, h }`.

import * as THREE from 'three';

const PX = 800; // canvas pixels per metre

/** Splits `text` into lines no wider than `w` pixels in the context's font. */
export function wrap(ctx, text, w) {
  const lines = [];
  for (const para of String(text).split('\n')) {
    let line = '';
    for (const word of para.split(/\s+/).filter(Boolean)) {
      const next = line ? `${line} ${word}` : word;
      if (line && ctx.measureText(next).width > w) {
        lines.push(line);
        line = word;
      } else line = next;
    }
    lines.push(line);
  }
  return lines;
}

/** The horizontal unit direction a head with `rotation` ([x, y, z, w]) looks along (-Z when it
 * looks straight up or down): where a panel opens in front of it. */
export function horizontalForward(rotation) {
  const f = new THREE.Vector3(0, 0, -1).applyQuaternion(new THREE.Quaternion(...rotation));
  f.y = 0;
  if (f.lengthSq() < 1e-6) f.set(0, 0, -1);
  return f.normalize();
}

export class Panel {
  /** A panel `width` x `height` metres in `parent` (the simulation's frame). */
  constructor(parent, { width = 1.1, height = 0.8, name = 'panel' } = {}) {
    this.width = width;
    this.height = height;
    this.canvas = document.createElement('canvas');
    this.canvas.width = Math.round(width * PX);
    this.canvas.height = Math.round(height * PX);
    this.ctx = this.canvas.getContext('2d');
    this.texture = new THREE.CanvasTexture(this.canvas);
    this.texture.colorSpace = THREE.SRGBColorSpace;
    this.group = new THREE.Group();
    this.group.name = name;
    this.group.visible = false;
    const mesh = new THREE.Mesh(new THREE.PlaneGeometry(width, height), new THREE.MeshBasicMaterial({ map: this.texture, transparent: true }));
    mesh.renderOrder = 20;
    this.group.add(mesh);
    parent.add(this.group);
    // The ray from the controller while the panel is open, up to the panel (or 3 m).
    this.ray = new THREE.Line(new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3(0, 0, -1)]), new THREE.LineBasicMaterial({ color: 0xf5d58a }));
    this.ray.frustumCulled = false;
    this.ray.visible = false;
    parent.add(this.ray);
    this.boxes = [];
    this.hover = null;
    this.key = null;
  }

  /** The canvas's size in pixels, for layouts. */
  get size() {
    return { w: this.canvas.width, h: this.canvas.height };
  }

  get isOpen() {
    return this.group.visible;
  }

  /**
   * Places the panel `distance` metres in front of `head` ({ position: [x, y, z], rotation:
   * [x, y, z, w] }, the simulation's frame), `drop` below the eyes and `side` to the right,
   * facing it, drawn at `scale`.
   */
  place(head, { distance = 1.1, drop = 0.1, side = 0, scale = 1 } = {}) {
    const [x, y, z] = head.position;
    const f = horizontalForward(head.rotation);
    const r = new THREE.Vector3(-f.z, 0, f.x);
    this.group.position.set(x + f.x * distance + r.x * side, y - drop, z + f.z * distance + r.z * side);
    const eye = new THREE.Vector3(x + r.x * side, y - drop, z + r.z * side);
    this.group.lookAt(this.group.parent.localToWorld(eye));
    this.group.scale.setScalar(scale);
    this.group.visible = true;
    this.group.updateMatrixWorld(true);
  }

  /** Hidden unless the page shows a step (`s.panel`). */
  update(s) {
    if (!s.panel && (this.group.visible || this.ray.visible)) this.hide();
  }

  hide() {
    this.group.visible = false;
    this.ray.visible = false;
    this.hover = null;
  }

  /** Draws the ray from `origin` along `dir` (or none, when `origin` is null). */
  pointer(origin, dir) {
    this.ray.visible = Boolean(origin) && this.group.visible;
    if (!this.ray.visible) return;
    const t = this.#distance(origin, dir) ?? 3;
    const pos = this.ray.geometry.attributes.position;
    pos.setXYZ(0, ...origin);
    pos.setXYZ(1, origin[0] + dir[0] * t, origin[1] + dir[1] * t, origin[2] + dir[2] * t);
    pos.needsUpdate = true;
  }

  /** Draws `boxes` (redrawn only when they or the hovered button changed). */
  show(boxes) {
    this.boxes = boxes;
    this.#draw();
  }

  /** Highlights the button `id` (or none). */
  setHover(id) {
    if (id === this.hover) return;
    this.hover = id;
    this.#draw();
  }

  /** The buttons drawn now: [{ id, label, on }]. */
  buttons() {
    return this.boxes.filter((b) => b.type === 'button').map(({ id, label, on }) => ({ id, label, on: Boolean(on) }));
  }

  /** The text drawn now, one string per text box. */
  texts() {
    return this.boxes.filter((b) => b.type === 'text').map((b) => b.text);
  }

  #draw() {
    const key = JSON.stringify([this.boxes.map((b) => ({ ...b, image: b.image ? b.image.src ?? 'img' : undefined })), this.hover]);
    if (key === this.key) return;
    this.key = key;
    const { ctx, canvas } = this;
    ctx.clearRect(0, 0, canvas.width, canvas.height);
    ctx.fillStyle = 'rgba(20, 28, 24, 0.92)';
    ctx.beginPath();
    ctx.roundRect(0, 0, canvas.width, canvas.height, 24);
    ctx.fill();
    ctx.textBaseline = 'top';
    for (const b of this.boxes) {
      if (b.type === 'text') {
        ctx.font = `${b.bold ? '600 ' : ''}${b.size ?? 30}px sans-serif`;
        ctx.fillStyle = b.color ?? '#f4f7f2';
        ctx.textAlign = b.align ?? 'left';
        const lh = (b.size ?? 30) * 1.25;
        const x = b.align === 'right' ? b.x + b.w : b.align === 'center' ? b.x + b.w / 2 : b.x;
        wrap(ctx, b.text, b.w).forEach((line, i) => ctx.fillText(line, x, b.y + i * lh, b.w));
      } else if (b.type === 'image' && b.image?.complete && b.image.naturalWidth > 0) {
        const s = Math.min(b.w / b.image.naturalWidth, b.h / b.image.naturalHeight);
        const w = b.image.naturalWidth * s;
        const h = b.image.naturalHeight * s;
        ctx.drawImage(b.image, b.x + (b.w - w) / 2, b.y + (b.h - h) / 2, w, h);
      } else if (b.type === 'button') {
        const hover = b.id === this.hover;
        ctx.fillStyle = b.on ? '#3d8a55' : hover ? '#f4f7f2' : '#34453a';
        ctx.beginPath();
        ctx.roundRect(b.x, b.y, b.w, b.h, 10);
        ctx.fill();
        if (hover) {
          ctx.lineWidth = 5;
          ctx.strokeStyle = '#f5d58a';
          ctx.stroke();
        }
        ctx.fillStyle = hover && !b.on ? '#10301a' : '#f4f7f2';
        ctx.textAlign = 'center';
        ctx.textBaseline = 'middle';
        ctx.font = `${b.size ?? Math.min(30, Math.round(b.h * 0.45))}px sans-serif`;
        ctx.fillText(b.label, b.x + b.w / 2, b.y + b.h / 2, b.w - 8);
        ctx.textBaseline = 'top';
      }
    }
    this.texture.needsUpdate = true;
  }

  /** The button the ray from `origin` along `dir` ([x, y, z], the parent's frame) points at, or null. */
  hit(origin, dir) {
    const p = this.#onPlane(origin, dir);
    if (!p) return null;
    const u = (p.x / this.width + 0.5) * this.canvas.width;
    const v = (0.5 - p.y / this.height) * this.canvas.height;
    const b = this.boxes.find((b) => b.type === 'button' && u >= b.x && u <= b.x + b.w && v >= b.y && v <= b.y + b.h);
    return b ? b.id : null;
  }

  /** Whether the ray meets the panel at all. */
  meets(origin, dir) {
    return this.#distance(origin, dir) !== null;
  }

  /** How far along the ray (a unit `dir`) it meets the panel, or null. */
  #distance(origin, dir) {
    const p = this.#onPlane(origin, dir);
    // In the panel's units; the parent's are `scale` times larger.
    return p && Math.abs(p.x) <= this.width / 2 && Math.abs(p.y) <= this.height / 2 ? p.t * this.group.scale.x : null;
  }

  /** Where the ray meets the visible panel's plane, in its own units ({ x, y } from its centre,
   * `t` along the ray), or null when it is hidden or the ray points away from it. */
  #onPlane(origin, dir) {
    if (!this.group.visible) return null;
    this.group.updateMatrix();
    const inv = this.group.matrix.clone().invert();
    const o = new THREE.Vector3(...origin).applyMatrix4(inv);
    const d = new THREE.Vector3(...dir).transformDirection(inv);
    if (Math.abs(d.z) < 1e-6) return null;
    const t = -o.z / d.z;
    return t >= 0 ? { x: o.x + d.x * t, y: o.y + d.y * t, t } : null;
  }

  /** The middle of button `id` in the parent's frame, [x, y, z] (for tests aiming at it), or null. */
  buttonPoint(id) {
    const b = this.boxes.find((b) => b.type === 'button' && b.id === id);
    if (!b || !this.group.visible) return null;
    this.group.updateMatrix();
    const x = ((b.x + b.w / 2) / this.canvas.width - 0.5) * this.width;
    const y = (0.5 - (b.y + b.h / 2) / this.canvas.height) * this.height;
    const p = new THREE.Vector3(x, y, 0).applyMatrix4(this.group.matrix);
    return [p.x, p.y, p.z];
  }
}
