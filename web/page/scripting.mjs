// The page's scripting interface, `window.grove` (docs/headset.md, "The page's scripting
// interface"): the page's state for the people running a session (in the browser's console) and
// for the tests and the benchmark, which drive the page through it. Points are in the
// simulation's frame ([x, y, z] metres, +Y up) unless a member says otherwise. It reads the page;
// it changes nothing.

import { toSession } from './room.mjs';

/**
 * Makes `app.page` (the page's record: mode, participant, task, seed, file, verification,
 * noSqueeze, device, floorOutline, offset, floor, frameMs, perf, frames, resumed) the page's
 * scripting interface, with
 * the members read from the rest of the page; returns it.
 */
export function install(app) {
  const features = () => app.view?.features ?? null;
  const panel = () => features()?.panel ?? null;
  const members = {
    /** The page's state (flow/flow.mjs's State). */
    state: { get: () => app.flow.state, enumerable: true },
    /** Why the page failed (the error state's message), or null. */
    error: { get: () => app.flow.error, enumerable: true },
    /** The run's last snapshot (a task's or the practice's), or null. */
    snapshot: { get: () => app.run?.snapshot ?? null, enumerable: true },
    /** The connection to the server: connecting, online, offline, refused or ended. */
    connection: { get: () => app.recorder.state, enumerable: true },
    /** Lines handed to the client library and not yet on the server's disk. */
    pending: { get: () => app.recorder.pending, enumerable: true },
    /** The anchor ball as drawn: 'hidden', 'white' or 'green'. */
    overlayBall: { value: () => features()?.overlay.ballState() ?? 'hidden' },
    /** The middle of the menu's item for `model` ('finish': Finish task), or null when the menu is closed. */
    menuItemPoint: {
      value: (model) => {
        const menu = features()?.menu;
        if (!menu?.isOpen) return null;
        const i = model === 'finish' ? menu.models.length - 1 : menu.models.indexOf(model);
        return i < 0 ? null : menu.itemPoint(i);
      },
    },
    /** A point of the simulation's frame in the XR session's local-floor space, {x, y, z}. */
    toSession: {
      value: (p) => {
        const o = app.page.offset;
        return o ? toSession(o, { x: p[0], y: p[1], z: p[2] }) : { x: p[0], y: p[1], z: p[2] };
      },
    },
    /** Where a point of the simulation's frame is on the inline preview's canvas, {x, y} CSS pixels. */
    screenPoint: { value: (p) => app.view.screenPoint(p) },
    /** The WebXR input profile each drawn controller uses ('' while it loads, 'none' without one). */
    profiles: { value: () => features()?.controllers.profiles() ?? [] },
    /** Where a protocol's participant is: { participant, step, steps, kind, block, item, typing, message }, or null. */
    study: { get: () => app.study?.summary() ?? null, enumerable: true },
    /** The protocol's panel while it shows: { buttons: [{ id, label, on }], texts, hover }, or null. */
    panel: { get: () => (panel()?.isOpen ? { buttons: panel().buttons(), texts: panel().texts(), hover: panel().hover } : null), enumerable: true },
    /** What hides the trees in AR: the session's depth sensing ({ usage, format }) while it is used, else null. */
    occlusion: { get: () => features()?.occlusion.active ?? null, enumerable: true },
    /** AR's light: { source: 'estimate' (the browser's light estimation) or 'neutral', main: the estimate's main light }, or null outside AR. */
    lighting: { get: () => features()?.xrlight.state() ?? null, enumerable: true },
    /** The middle of the panel's button `id`, or null. */
    panelPoint: { value: (id) => panel()?.buttonPoint(id) ?? null },
  };
  window.grove = Object.defineProperties(app.page, members);
  return window.grove;
}
