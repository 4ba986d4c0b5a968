// The input of an immersive session: one grove input source per XR input source the session has,
// made by the first kind in SOURCES that accepts it (by its `targetRayMode`, its hand, its
// gamepad, its profiles), the participant's pointer among them, and the head from the viewer's
// pose, all in the simulation's frame (docs/headset.md, "Devices and their mappings").
//
// A kind of device is one module beside input/xr.mjs with the same shape (`accepts`,
// `poll(frame)`, `controls(mode)`, `device()`, `refuses(mode)`, `noSqueeze`) and one entry in
// SOURCES. A kind whose XR input sources come and go with each touch or pinch (`transient-pointer`,
// `screen`) is `static shared`: one object for the session, made with `ctx` alone, to which each
// such XR source is attached while it exists; it is `persistent`, the pointer between touches too,
// so that a touch's end is seen. An XR input source no kind accepts (a `gaze` source) is not
// grove's.

import { Hands } from './hands.mjs';
import { simPose } from './pose.mjs';
import { ScreenTouch } from './screen.mjs';
import { TransientPointer } from './transient.mjs';
import { XrController } from './xr.mjs';

/** The kinds of input source, in order: the first that accepts an XR input source makes it. */
export const SOURCES = [Hands, TransientPointer, ScreenTouch, XrController];

/**
 * grove's source for an XR input source (`ctx` as the kinds take it; `shared` the session's
 * objects of shared kinds, by kind), or null when no kind takes it.
 */
export function sourceFor(xrSource, ctx, kinds = SOURCES, shared = new Map()) {
  const Kind = kinds.find((K) => K.accepts(xrSource));
  if (!Kind) return null;
  if (!Kind.shared) return new Kind(xrSource, ctx);
  if (!shared.has(Kind)) shared.set(Kind, new Kind(ctx));
  const s = shared.get(Kind);
  s.attach(xrSource);
  return s;
}

/**
 * The participant's pointer among sources: a persistent one (gaze and pinch, a phone's screen:
 * such a device has nothing else), else the right hand's, else the first.
 */
export function primaryOf(sources) {
  return sources.find((s) => s.persistent) ?? sources.find((s) => s.handedness === 'right') ?? sources[0] ?? null;
}

/** No source: no pose, the buttons as they were (none named), the touchpad at rest. */
const NONE = Object.freeze({ pose: null, buttons: Object.freeze({}), axes: [0, 0] });

export class XrInput {
  /**
   * `ctx`: { space (the session's reference space), offset() (the simulation's frame in it, or
   * null), now() (ms, for held buttons), session, bar (a phone's TouchBar, input/touchbar.mjs),
   * snapshot() (the run's last snapshot, or null) }; `onSource(source)` is told when the pointer
   * changes.
   */
  constructor(ctx, { onSource = () => {} } = {}) {
    this.ctx = ctx;
    this.onSource = onSource;
    this.made = new Map(); // XRInputSource -> grove's source, or null when no kind takes it
    this.shared = new Map(); // a shared kind -> its one object for the session
    this.pointer = null;
    this.seen = []; // the XR input sources of the last frame, for a page that finds none of them grove's
  }

  /** This frame's { head, pose, buttons, axes } (the pointer's), or null outside an XR frame. */
  poll(frame) {
    if (!frame) return null;
    const now = [...frame.session.inputSources];
    this.seen = now;
    for (const s of now) if (!this.made.has(s)) this.made.set(s, sourceFor(s, this.ctx, SOURCES, this.shared));
    for (const [s, made] of this.made) {
      if (now.includes(s)) continue;
      made?.detach?.(s);
      this.made.delete(s);
    }
    const live = now.map((s) => this.made.get(s)).filter(Boolean);
    // A persistent pointer stays the pointer while none of its sources is there (between touches).
    const pointer = primaryOf(this.pointer?.persistent ? [this.pointer, ...live] : live);
    if (pointer && pointer !== this.pointer) this.onSource(pointer);
    this.pointer = pointer;
    const viewer = frame.getViewerPose(this.ctx.space);
    return { head: simPose(viewer?.transform, this.ctx.offset()), ...(pointer?.poll(frame) ?? NONE) };
  }

  /** What the recording's header says of the pointer's device, or null before there is one. */
  device() {
    return this.pointer?.device() ?? null;
  }

  /** Why the pointer's device cannot do a task's mode, or null. */
  refuses(mode) {
    return this.pointer?.refuses(mode) ?? null;
  }

  /** The target-ray modes of the session's input sources when none is grove's (for the page to say), else null. */
  unusable() {
    return this.pointer || this.seen.length === 0 ? null : [...new Set(this.seen.map((s) => s.targetRayMode))];
  }
}
