// What the page says: the controls of the device in use (with Bumper's alternative on a
// controller without a squeeze), the task panel's lines, the next target.

import { LONG_PRESS_MS } from './input.mjs';

/** What a task done in `mode` ('ray-casting' or 'manual', run.mjs's modeOfTask) asks, in a few words for its participant. */
export function taskText(mode) {
  return mode === 'manual'
    ? 'Open the menu and choose the model each orange ring asks for; it appears in front of you. Drag it with the trigger onto its ring: the ball under it turns white when letting go will snap it to the ground.'
    : 'Open the menu and choose the model each orange ring asks for, then point at the ring and press the trigger to plant it there.';
}

/** Rows [control, what it does] for a mode ('ray-casting' or 'manual'). */
export function controlsFor(mode, noSqueeze, mouse) {
  if (mouse) {
    return [
      ['Left button', mode === 'manual' ? 'grab and drag a tree or a handle' : 'plant on the ground, select a tree; choose in the menu'],
      ['Right button', 'remove the tree under the ray'],
      ['M or middle button', 'open the model menu'],
      ['Wheel, Q / E', 'move the selected tree along the ray, turn it'],
    ];
  }
  const rows = [['Trigger', mode === 'manual' ? 'grab and drag a tree or a handle; choose in the menu' : 'plant on the ground, select a tree; choose in the menu']];
  if (noSqueeze) {
    rows.push(['Touchpad click', 'remove the tree under the ray (this controller has no squeeze button: a click is Bumper)']);
    rows.push([`Touchpad held ${LONG_PRESS_MS / 1000} s`, 'open the model menu']);
    rows.push(['Touchpad (touch)', 'move the selected tree along the ray and turn it']);
  } else {
    rows.push(['Squeeze (grip)', 'remove the tree under the ray (Bumper)']);
    rows.push(['A / B (X / Y)', 'open the model menu']);
    rows.push(['Thumbstick', 'move the selected tree along the ray and turn it; press: Touchpad']);
  }
  return rows;
}

/** The first target not yet satisfied, if any. */
export function nextTarget(snap) {
  return snap.task?.targets.find((t) => !t.satisfied) ?? null;
}

/** The lines of the task panel that follows the controller. */
export function hudLines(snap, { noSqueeze, connection, pending, state, verification }) {
  const t = snap.task;
  const lines = [];
  if (t) {
    lines.push(`${t.id}: ${t.satisfied}/${t.targets.length} · ${t.clock_s.toFixed(1)} s`);
    const next = nextTarget(snap);
    if (state === 'done') lines.push(`!Done: ${verification?.status ?? 'saving…'}`);
    else lines.push(next ? `!Next: ${next.model}${next.moved_to ? ' (moved to the floor)' : ''}` : '!All targets planted');
  } else {
    lines.push('free session');
    lines.push('');
  }
  lines.push(noSqueeze ? `remove: touchpad click · menu: hold touchpad` : 'remove: squeeze · menu: A/B');
  lines.push(`server: ${connection}${pending > 0 ? ` (${pending} waiting)` : ''}`);
  return lines;
}
