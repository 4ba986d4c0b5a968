// What the page says: the task's instructions, the task panel's lines, the next target. The
// controls of each device are its input source's words (input/xr.mjs, input/mouse.mjs).


/** What a task done in `mode` ('ray-casting' or 'manual', run.mjs's modeOfTask) asks, in a few words for its participant. */
export function taskText(mode) {
  return mode === 'manual'
    ? 'Open the menu and choose the model each orange ring asks for; it appears in front of you. Drag it with the trigger onto its ring: the ball under it turns white when letting go will snap it to the ground.'
    : 'Open the menu and choose the model each orange ring asks for, then point at the ring and press the trigger to plant it there.';
}

/** The first target not yet satisfied, if any. */
export function nextTarget(snap) {
  return snap.task?.targets.find((t) => !t.satisfied) ?? null;
}

/** The task panel's reminder of Bumper and Menu, by the device's mapping (input/*.mjs's `device()`). */
const REMINDERS = {
  controller: 'remove: squeeze · menu: A/B',
  'controller-no-squeeze': 'remove: touchpad click · menu: hold touchpad',
  hands: 'remove: pinch other hand · menu: hold that pinch',
  'transient-pointer': 'remove: pinch left hand · menu: hold that pinch',
  screen: 'remove, menu: the buttons below',
};

/** The lines of the task panel that follows the controller. */
export function hudLines(snap, { noSqueeze, mapping, connection, pending, state, verification }) {
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
  lines.push(REMINDERS[mapping] ?? REMINDERS[noSqueeze ? 'controller-no-squeeze' : 'controller']);
  lines.push(`server: ${connection}${pending > 0 ? ` (${pending} waiting)` : ''}`);
  return lines;
}
