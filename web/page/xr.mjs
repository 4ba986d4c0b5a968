// The immersive session: AR where the browser offers it, else VR; the reference spaces (the
// session's `local-floor` and the simulation's frame offset from it, room.mjs); the floor an AR
// session finds, from plane detection, else a hit test straight down, else `local-floor` itself.
// AR asks for depth sensing and light estimation too, both optional (draw/occlusion.mjs,
// draw/xrlight.mjs).

import { floorOf, horizontalPlanes, simOffset, yawOf } from './room.mjs';

/** Which immersive modes this browser offers: { ar, vr }. */
export async function offeredModes() {
  const xr = navigator.xr;
  if (!xr) return { ar: false, vr: false };
  const ask = (m) => xr.isSessionSupported(m).catch(() => false);
  const [ar, vr] = await Promise.all([ask('immersive-ar'), ask('immersive-vr')]);
  return { ar, vr };
}

/** The depth the page asks an AR session for (WebXR Depth Sensing): a GPU texture of floats. */
export const DEPTH_SENSING = { usagePreference: ['gpu-optimized'], dataFormatPreference: ['float32'] };

/** Requests an immersive session (`ar` or `vr`); `overlay` is the DOM overlay's root (AR on phones). */
export async function requestSession(mode, overlay) {
  if (mode === 'ar') {
    // A phone's screen taps need no feature; hands need `hand-tracking` (input/hands.mjs).
    return navigator.xr.requestSession('immersive-ar', {
      requiredFeatures: ['local-floor'],
      optionalFeatures: ['hit-test', 'plane-detection', 'dom-overlay', 'hand-tracking', 'depth-sensing', 'light-estimation'],
      domOverlay: overlay ? { root: overlay } : undefined,
      // Real things hide the trees (draw/occlusion.mjs): the depth as a texture, as Quest 3 offers it.
      depthSensing: DEPTH_SENSING,
    });
  }
  return navigator.xr.requestSession('immersive-vr', { requiredFeatures: ['local-floor'], optionalFeatures: ['hand-tracking'] });
}

/**
 * What an AR session knows of the room so far: the floor's height in `local-floor` and how it
 * was found, refined frame by frame until the task starts.
 */
export class FloorFinder {
  constructor(session, base) {
    this.session = session;
    this.base = base;
    this.floor = null; // { y, source }
    this.hitSource = null;
    if (session.requestHitTestSource) {
      session
        .requestReferenceSpace('viewer')
        .then((viewer) => session.requestHitTestSource({ space: viewer, offsetRay: new XRRay({ x: 0, y: 0, z: 0, w: 1 }, { x: 0, y: -1, z: 0, w: 0 }) }))
        .then((s) => (this.hitSource = s))
        .catch(() => {});
    }
  }

  /** Looks at one frame: a floor plane wins over a hit test, which wins over local-floor. */
  frame(frame) {
    const planes = horizontalPlanes(frame, this.base);
    const floor = floorOf(planes);
    if (floor) {
      this.floor = { y: floor.y, source: `plane detection (${floor.label}, ${floor.area.toFixed(1)} m²)` };
      return;
    }
    if (this.hitSource && this.floor?.source?.startsWith('plane') !== true) {
      const hits = frame.getHitTestResults(this.hitSource);
      const pose = hits[0]?.getPose(this.base);
      if (pose) {
        this.floor = { y: pose.transform.position.y, source: 'a hit test straight down' };
        return;
      }
    }
    if (!this.floor) this.floor = { y: 0, source: "the session's local-floor" };
  }

  get found() {
    return this.floor ?? { y: 0, source: "the session's local-floor" };
  }

  dispose() {
    this.hitSource?.cancel?.();
  }
}

/** The simulation's frame for a head pose (an XRViewerPose's transform) and a floor height. */
export function offsetFor(transform, floorY) {
  return simOffset(transform.position, yawOf(transform.orientation), floorY);
}
