// The layouts of the protocol's panel (draw/panel.mjs): a questionnaire one item at a time (the
// instrument's title, the question, its answers as rows of buttons with the anchors at the
// ends, Back / Next, Send on the last; a message line for what stops the sending), and the
// other steps as text with their buttons. The logic of the items is form.mjs's, which hands
// these layouts their lines of buttons.

const M = 36; // margin, px
const GAP = 10;

/** Button ids of an item's options: `opt:K` for its K-th option. */
export const optionId = (k) => `opt:${k}`;

function footer(w, h, buttons) {
  const bw = 200;
  const bh = 64;
  const right = buttons.filter((b) => !b.left);
  return buttons.map((b) => {
    const k = right.indexOf(b);
    const x = b.left ? M : w - M - (right.length - k) * bw - (right.length - 1 - k) * GAP;
    return { type: 'button', id: b.id, label: b.label, x, y: h - M - bh, w: bw, h: bh, on: b.on };
  });
}

/**
 * One item of a questionnaire: `{ title, index, count, row, lines, message }` (row: form.mjs's
 * rowOf; lines: its optionLines, the buttons with the participant's choices). Size `{ w, h }`
 * in pixels.
 */
export function itemLayout({ w, h }, { title, index, count, row, lines, message }) {
  const boxes = [
    { type: 'text', text: title, x: M, y: M, w: w - 2 * M - 180, size: 32, bold: true },
    {
      type: 'text',
      text: `${index + 1} / ${count}`,
      x: w - M - 180,
      y: M,
      w: 180,
      size: 28,
      align: 'right',
      color: '#b9c8bc',
    },
    {
      type: 'text',
      text: row.text + (row.multi ? ' (choose any, or none)' : '') + (row.required ? '' : ' (optional)'),
      x: M,
      y: M + 64,
      w: w - 2 * M,
      size: 34,
    },
  ];
  let y = M + 200;
  if (row.typed) {
    boxes.push({
      type: 'text',
      text: 'You will type this answer on the page after you take the headset off.',
      x: M,
      y,
      w: w - 2 * M,
      size: 28,
      color: '#f5d58a',
    });
    y += 90;
  }
  // The buttons' height: what is left above the anchors, the message and the footer, at most 60 px.
  const room = h - M - 64 - y - (row.anchors ? 44 : 0) - (message ? 56 : 12);
  const bh = Math.max(30, Math.min(60, Math.floor(room / Math.max(1, lines.length)) - GAP));
  for (const line of lines) {
    const bw = (w - 2 * M - GAP * (line.length - 1)) / line.length;
    line.forEach((o, i) =>
      boxes.push({
        type: 'button',
        id: optionId(o.k),
        label: o.label,
        x: M + i * (bw + GAP),
        y,
        w: bw,
        h: bh,
        on: o.on,
      }),
    );
    y += bh + GAP;
  }
  if (row.anchors) {
    boxes.push({ type: 'text', text: row.anchors[0], x: M, y: y + 4, w: (w - 2 * M) / 2, size: 26, color: '#b9c8bc' });
    boxes.push({
      type: 'text',
      text: row.anchors[1],
      x: w / 2,
      y: y + 4,
      w: (w - 2 * M) / 2,
      size: 26,
      color: '#b9c8bc',
      align: 'right',
    });
  }
  if (message)
    boxes.push({ type: 'text', text: message, x: M, y: h - M - 64 - 48, w: w - 2 * M, size: 28, color: '#ff9d85' });
  const foot = [];
  if (index > 0) foot.push({ id: 'back', label: 'Back', left: true });
  foot.push(index < count - 1 ? { id: 'next', label: 'Next' } : { id: 'send', label: 'Send', on: true });
  return boxes.concat(footer(w, h, foot));
}

/**
 * A step shown as text: `{ title, text, image, note, message, buttons: [{ id, label }] }`.
 * `image` (an HTMLImageElement) takes the space between the text and the buttons.
 */
export function textLayout({ w, h }, { title, text, image, note, message, buttons = [] }) {
  const boxes = [{ type: 'text', text: title, x: M, y: M, w: w - 2 * M, size: 34, bold: true }];
  if (text) boxes.push({ type: 'text', text, x: M, y: M + 60, w: w - 2 * M, size: image ? 24 : 28 });
  if (image) boxes.push({ type: 'image', image, x: M, y: h * 0.45, w: w - 2 * M, h: h * 0.55 - M - 64 - GAP * 2 });
  if (note)
    boxes.push({ type: 'text', text: note, x: M, y: h - M - 64 - 120, w: w - 2 * M, size: 28, color: '#f5d58a' });
  if (message)
    boxes.push({ type: 'text', text: message, x: M, y: h - M - 64 - 60, w: w - 2 * M, size: 28, color: '#ff9d85' });
  return boxes.concat(
    footer(
      w,
      h,
      buttons.map((b) => ({ ...b, on: true })),
    ),
  );
}
