// The page's side of a protocol's steps (flow/protocol.mjs, study.mjs): the panel's frame
// (placed once in front of the head, the button under the ray highlighted, a trigger press
// returned), and the small form on the page for the answers typed once the headset is off.

/**
 * One frame of the panel: `state` { placed, down } carries over between frames. `head`
 * ({ position, rotation }, the simulation's frame), `ray` ([origin, dir]) or null, `down`
 * (the trigger now). Returns the button pressed in this frame, or null.
 */
export function panelFrame(panel, state, { head, ray, down, boxes, practice }) {
  if (!state.placed) {
    // The practice's panel small, low and to the left, leaving the scene in view.
    panel.place(head, practice ? { distance: 1.2, drop: 0.35, side: -0.35, scale: 0.55 } : {});
    state.placed = true;
  }
  panel.show(boxes);
  const hover = ray ? panel.hit(ray[0], ray[1]) : null;
  panel.setHover(hover);
  panel.pointer(practice ? null : ray?.[0] ?? null, ray?.[1]);
  const pressed = down && !state.down && hover ? hover : null;
  state.down = down;
  return pressed;
}

/**
 * Fills `container` with a form of a textarea per typed item (form.mjs's rows) and a Send
 * button; `send(texts)` is called with the texts by item and its error is shown under the form.
 */
export function typedForm(container, rows, send, say) {
  const form = document.createElement('form');
  form.id = 'typed';
  for (const row of rows) {
    const label = document.createElement('label');
    label.textContent = row.text + (row.required ? '' : ' (optional: leave it empty to skip it)');
    const t = document.createElement('textarea');
    t.name = row.id;
    t.rows = 4;
    if (row.maxChars) t.maxLength = row.maxChars;
    t.style.width = '100%';
    label.append(document.createElement('br'), t);
    form.append(label);
  }
  const button = document.createElement('button');
  button.id = 'typed-send';
  button.textContent = 'Send';
  form.append(button);
  form.addEventListener('submit', async (e) => {
    e.preventDefault();
    const texts = Object.fromEntries([...form.querySelectorAll('textarea')].map((t) => [t.name, t.value]));
    try {
      await send(texts);
    } catch (err) {
      say(err.message);
    }
  });
  container.replaceChildren(form);
}

/** A button `id` labelled `label` calling `click` (errors to `fail`). */
export function button(id, label, click, fail) {
  const b = document.createElement('button');
  b.id = id;
  b.textContent = label;
  b.addEventListener('click', () => Promise.resolve().then(click).catch(fail));
  return b;
}

/** Puts the participant's id in the page's URL, so that a reload comes back to them. */
export function rememberParticipant(id) {
  const u = new URL(location.href);
  u.searchParams.set('participant', id);
  history.replaceState(null, '', u);
}

/** An image of the server's (an instruction block's), with the page's token; `loaded` once it is. */
export function loadImage(src, loaded) {
  const token = new URL(location.href).searchParams.get('token');
  const image = new Image();
  image.onload = loaded;
  image.src = src + (token ? `?token=${encodeURIComponent(token)}` : '');
  return image;
}
