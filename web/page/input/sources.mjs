// The input of an immersive session: one grove input source per XR input source the session has,
// made by the first kind in SOURCES that accepts it (by its `targetRayMode`, its gamepad, its
// profiles), the participant's pointer among them (the right hand's, else the first), and the
// head from the viewer's pose, all in the simulation's frame.
//
// A new kind of device is one module beside input/xr.mjs with the same shape (`accepts`,
// `poll(frame)`, `controls(mode)`, `noSqueeze`) and one entry in SOURCES: hands (pinch),
// `transient-pointer` (gaze and pinch) and `screen` (a phone's taps) go there. An XR input
// source no kind accepts is not grove's (today: hands and everything but a controller).

import { simPose } from './pose.mjs';
import { XrController } from './xr.mjs';

/** The kinds of input source, in order: the first that accepts an XR input source makes it. */
export const SOURCES = [XrController];

/** grove's source for an XR input source (`ctx` as the kinds take it), or null when no kind takes it. */
export function sourceFor(xrSource, ctx, kinds = SOURCES) {
  const Kind = kinds.find((K) => K.accepts(xrSource));
  return Kind ? new Kind(xrSource, ctx) : null;
}

/** The participant's pointer among sources: the right hand's, else the first. */
export function primaryOf(sources) {
  return sources.find((s) => s.handedness === 'right') ?? sources[0] ?? null;
}

/** No source: no pose, the buttons as they were (none named), the touchpad at rest. */
const NONE = Object.freeze({ pose: null, buttons: Object.freeze({}), axes: [0, 0] });

export class XrInput {
  /**
   * `ctx`: { space (the session's reference space), offset() (the simulation's frame in it, or
   * null), now() (ms, for held buttons) }; `onSource(source)` is told when the pointer changes.
   */
  constructor(ctx, { onSource = () => {} } = {}) {
    this.ctx = ctx;
    this.onSource = onSource;
    this.made = new Map(); // XRInputSource -> grove's source, or null when no kind takes it
    this.pointer = null;
  }

  /** This frame's { head, pose, buttons, axes } (the pointer's), or null outside an XR frame. */
  poll(frame) {
    if (!frame) return null;
    const now = [...frame.session.inputSources];
    for (const s of now) if (!this.made.has(s)) this.made.set(s, sourceFor(s, this.ctx));
    for (const s of this.made.keys()) if (!now.includes(s)) this.made.delete(s);
    const pointer = primaryOf(now.map((s) => this.made.get(s)).filter(Boolean));
    if (pointer && pointer !== this.pointer) this.onSource(pointer);
    this.pointer = pointer;
    const viewer = frame.getViewerPose(this.ctx.space);
    return { head: simPose(viewer?.transform, this.ctx.offset()), ...(pointer?.poll(frame) ?? NONE) };
  }
}
