// Text on a plane in the 3D scene (a canvas texture), redrawn only when its text changes: the
// task's clock and hints, the targets' model names, the model menu.

import * as THREE from 'three';

export class Label {
  /** `width` x `height` metres, drawn at `px` pixels per metre. */
  constructor(
    width,
    height,
    { px = 256, background = 'rgba(20, 28, 24, 0.78)', color = '#f4f7f2', font = 'sans-serif' } = {},
  ) {
    this.canvas = document.createElement('canvas');
    this.canvas.width = Math.max(8, Math.round(width * px));
    this.canvas.height = Math.max(8, Math.round(height * px));
    this.ctx = this.canvas.getContext('2d');
    this.texture = new THREE.CanvasTexture(this.canvas);
    this.texture.colorSpace = THREE.SRGBColorSpace;
    this.style = { background, color, font };
    this.mesh = new THREE.Mesh(
      new THREE.PlaneGeometry(width, height),
      new THREE.MeshBasicMaterial({ map: this.texture, transparent: true, depthTest: true }),
    );
    this.mesh.renderOrder = 10;
    this.text = null;
  }

  /** Draws `lines` (strings; a line starting with '!' is drawn highlighted) if they changed. */
  set(lines) {
    const text = lines.join('\n');
    if (text === this.text) return;
    this.text = text;
    const { ctx, canvas } = this;
    ctx.clearRect(0, 0, canvas.width, canvas.height);
    ctx.fillStyle = this.style.background;
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    const h = canvas.height / Math.max(lines.length, 1);
    ctx.font = `${Math.round(h * 0.62)}px ${this.style.font}`;
    ctx.textBaseline = 'middle';
    lines.forEach((line, i) => {
      const hi = line.startsWith('!');
      if (hi) {
        ctx.fillStyle = 'rgba(255, 255, 255, 0.9)';
        ctx.fillRect(0, i * h, canvas.width, h);
      }
      ctx.fillStyle = hi ? '#10301a' : this.style.color;
      // A line longer than the label is narrowed to fit rather than cut off.
      ctx.fillText(hi ? line.slice(1) : line, h * 0.3, (i + 0.5) * h, canvas.width - h * 0.6);
    });
    this.texture.needsUpdate = true;
  }
}
