// A phone's screen in AR (a `screen` input source: Android Chrome) as grove's input source. An XR
// input source of this mode exists while a finger touches the screen; its target ray leaves the
// camera through the finger. A tap is the Trigger, at the ray where the finger came down (it
// plants, selects, chooses in the menu). A finger whose point on the floor moves more than 3 cm
// drags. A tree it grabbed follows that point: the ray of the touch's start is moved so that the
// tree's base goes where the finger points on the floor, found by the browser's hit test for
// transient input (`generic-touchscreen`), else by the ray's crossing of the floor (y = 0 of the
// simulation's frame); a tree taken from the menu in manual mode comes down onto the floor there
// and snaps on release. Anything else it grabbed (a handle of the box) follows the finger's own
// ray. Between touches the ray stays where the last one left it, so that Remove acts on the tree
// last tapped.
//
// Remove, Menu and the Move pad are the DOM overlay's (input/touchbar.mjs); a touch that the bar
// claims is not the scene's. A new touch waits one frame before it counts, so that the bar's
// own events (which may arrive after the XR frame that first shows the touch) can claim it.
//
// One object serves every screen source of the session (`static shared`) and stays the pointer
// between touches (`persistent`).

import { deviceOf } from './device.mjs';
import { forward, shifted, simPose } from './pose.mjs';

/** How far the finger's floor point must move before a touch is a drag, metres. */
export const DRAG_M = 0.03;

/** The point where a ray (a pose) meets the floor y = 0, [x, y, z], or null. */
export function floorPoint(pose) {
  const d = forward(pose.rotation);
  const o = pose.position;
  if (d[1] >= -1e-6) return null;
  const t = -o[1] / d[1];
  return [o[0] + d[0] * t, 0, o[2] + d[2] * t];
}

const sub = (a, b) => a.map((v, i) => v - b[i]);

export class ScreenTouch {
  static accepts(source) {
    return source.targetRayMode === 'screen';
  }

  static shared = true;

  /**
   * `ctx`: { space, offset(), now(), session, bar (input/touchbar.mjs's TouchBar, or null),
   * snapshot() (the run's last snapshot, or null) }.
   */
  constructor(ctx) {
    this.ctx = ctx;
    this.noSqueeze = false;
    this.persistent = true;
    this.handedness = 'none';
    this.bar = ctx.bar ?? null;
    this.bar?.show(true);
    this.touches = new Map(); // XRInputSource -> { state: 'new' | 'scene' | 'bar', … }
    this.pose = null;
    this.last = null;
    this.hits = null;
    ctx.session
      ?.requestHitTestSourceForTransientInput?.({ profile: 'generic-touchscreen' })
      .then((s) => (this.hits = s))
      .catch(() => {});
  }

  attach(source) {
    this.touches.set(source, { state: this.bar?.claims() ? 'bar' : 'new' });
    this.last = source;
  }

  detach(source) {
    this.touches.delete(source);
  }

  /** The finger's point on the floor for a touch, [x, y, z] in the simulation's frame, or null. */
  #anchor(frame, source, ray) {
    const results = this.hits ? (frame.getHitTestResultsForTransientInput?.(this.hits) ?? []) : [];
    const mine = results.find((r) => r.inputSource === source)?.results?.[0];
    const at = mine ? simPose(mine.getPose(this.ctx.space)?.transform, this.ctx.offset()) : null;
    return at ? at.position : floorPoint(ray);
  }

  /**
   * The base of the tree the touch grabbed (a drag that begins now follows the finger with it), or
   * null. A press on a tree selects and grabs it, and the ray then passes through the tree it
   * drags: the grabbed tree is the selected one, unless the ray is on one of its handles.
   */
  #grabbed() {
    const snap = this.ctx.snapshot?.();
    const box = snap?.bounding_box;
    if (!box || snap.controller?.hit?.kind === 'handle') return null;
    return snap.trees.find((x) => x.id === box.tree)?.position ?? null;
  }

  poll(frame) {
    for (const t of this.touches.values()) {
      if (t.state === 'new' && t.seen) t.state = this.bar?.claims() ? 'bar' : 'scene';
      t.seen = true;
    }
    const entry = [...this.touches].find(([, t]) => t.state === 'scene');
    if (entry) {
      const [source, t] = entry;
      const ray = simPose(frame.getPose(source.targetRaySpace, this.ctx.space)?.transform, this.ctx.offset());
      if (ray) {
        const anchor = this.#anchor(frame, source, ray);
        if (!t.ray0) Object.assign(t, { ray0: ray, anchor0: anchor });
        else if (!t.drag && anchor && t.anchor0 && Math.hypot(...sub(anchor, t.anchor0)) > DRAG_M)
          t.drag = { base: this.#grabbed() };
        if (!t.drag) this.pose = t.ray0;
        else if (t.drag.base && anchor) this.pose = shifted(t.ray0, sub(anchor, t.drag.base));
        else this.pose = ray;
      }
    }
    const bar = this.bar?.read() ?? { bumper: false, menu: false, axes: [0, 0], scale: 0 };
    return {
      pose: this.pose,
      buttons: { trigger: Boolean(entry?.[1].ray0), bumper: bar.bumper, touchpad: false, menu: bar.menu },
      axes: bar.axes,
      scale: bar.scale,
    };
  }

  controls(mode) {
    return [
      [
        'Tap',
        mode === 'manual'
          ? 'select a tree; choose in the menu'
          : 'plant on the floor, select a tree; choose in the menu',
      ],
      ['Drag a tree', 'its base follows your finger over the floor; let go to snap it (manual)'],
      ['Remove', 'remove the tree last tapped (Bumper)'],
      ['Menu', 'open the model menu'],
      ['Move pad', 'drag up or down: move the selected tree along the ray; left or right: turn it'],
      ['Scale pad', 'drag up: grow the selected tree; down: shrink it'],
    ];
  }

  device() {
    return deviceOf(this.last ?? { targetRayMode: 'screen' }, 'screen');
  }

  refuses() {
    return null;
  }
}
