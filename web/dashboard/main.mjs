// The researcher's live page of a protocol run by `grove serve --protocol` (`/dashboard`,
// docs/protocol.md): every participant's step, every session with its live view (the server's
// replay of its lines as they came: figures, model, the verification so far) and its verification
// once ended, and the open sessions' task areas from above, from
// `/api/dashboard` every second. Bundled into web/dist/dashboard.js by web/page/build.mjs; the
// page's markup is web/dashboard/index.html.

const $ = (s) => document.querySelector(s);
const NS = 'http://www.w3.org/2000/svg';

function td(text, cls) {
  const c = document.createElement('td');
  c.textContent = text ?? '';
  if (cls) c.className = cls;
  return c;
}

function row(attrs, cells) {
  const r = document.createElement('tr');
  for (const [k, v] of Object.entries(attrs)) r.dataset[k] = v;
  r.append(...cells);
  return r;
}

function svg(tag, a) {
  const e = document.createElementNS(NS, tag);
  for (const [k, v] of Object.entries(a)) e.setAttribute(k, v);
  return e;
}

/** The live verification of a session's lines so far: where it has verified to, or what it found wrong. */
function checked(v) {
  if (!v) return '';
  if (v.status === 'diverged') return `diverged at tick ${v.first_divergence.tick}`;
  if (v.status === 'invalid') return `invalid: ${v.error}`;
  return `${v.status} to tick ${v.verified_to_tick ?? 0}`;
}

/** An open session's task area from above, north up: heat of where the ray hit, targets, trees. */
function map(s) {
  const l = s.live;
  const pts = [...l.targets, ...l.trees, ...l.hits.map(([x, z]) => [(x + 0.5) * l.cell_m, (z + 0.5) * l.cell_m])];
  if (!pts.length) return null;
  let [x0, z0, x1, z1] = [Infinity, Infinity, -Infinity, -Infinity];
  for (const [x, z] of pts) {
    x0 = Math.min(x0, x);
    x1 = Math.max(x1, x);
    z0 = Math.min(z0, z);
    z1 = Math.max(z1, z);
  }
  const pad = 2;
  x0 -= pad;
  z0 -= pad;
  x1 += pad;
  z1 += pad;
  const size = 260;
  const k = size / Math.max(x1 - x0, z1 - z0);
  const g = svg('svg', { class: 'map', width: size, height: size, viewBox: `0 0 ${size} ${size}`, 'data-file': s.file });
  const most = Math.max(1, ...l.hits.map((h) => h[2]));
  for (const [x, z, n] of l.hits) {
    g.append(svg('rect', { x: (x * l.cell_m - x0) * k, y: (z * l.cell_m - z0) * k, width: l.cell_m * k, height: l.cell_m * k, fill: '#e07020', 'fill-opacity': 0.15 + (0.85 * n) / most }));
  }
  for (const [x, z] of l.targets) g.append(svg('circle', { cx: (x - x0) * k, cy: (z - z0) * k, r: 6, fill: 'none', stroke: '#2050c0', 'stroke-width': 2 }));
  for (const [x, z] of l.trees) g.append(svg('circle', { class: 'tree', cx: (x - x0) * k, cy: (z - z0) * k, r: 3.5, fill: '#1a7a35' }));
  const f = document.createElement('figure');
  const c = document.createElement('figcaption');
  c.textContent = `${s.participant} · ${s.task ?? 'free'} · ${l.trees.length} trees · north up`;
  f.append(g, c);
  return f;
}

async function refresh() {
  let d;
  try {
    d = await (await fetch('/api/dashboard')).json();
  } catch {
    return;
  }
  $('#protocol').textContent = d.protocol;
  $('#participants tbody').replaceChildren(
    ...d.participants.map((p) => {
      const st = p.done ? null : p.steps[p.step - 1];
      return row({ participant: p.participant }, [
        td(p.participant),
        td(p.order.join(' → ')),
        td(p.done ? 'done' : `${p.step} of ${p.steps.length}`, 'step'),
        td(p.done ? 'done' : st.block, 'block'),
        td(p.done ? '' : st.kind + (st.condition ? ` (${st.condition})` : ''), 'kind'),
      ]);
    }),
  );
  $('#sessions tbody').replaceChildren(
    ...d.sessions.map((s) => {
      const l = s.live || {};
      const v = s.verification ? s.verification.status : '';
      return row({ file: s.file }, [
        td(s.file),
        td(s.participant),
        td(s.task),
        td(s.state, 'state'),
        td(l.task_clock_s != null ? `${l.task_clock_s.toFixed(1)} s` : '', 'clock'),
        td(l.trees_planted ?? '', 'planted'),
        td(l.targets_satisfied ?? '', 'targets'),
        td(l.errors ?? '', 'errors'),
        td(l.model ?? '', 'model'),
        td(checked(l.verification), `live ${l.verification ? l.verification.status : ''}`),
        td(v, `verification ${v}`),
        td(s.not_this_steps ? `not this step's: ${s.not_this_steps}` : '', 'step'),
      ]);
    }),
  );
  $('#maps').replaceChildren(...d.sessions.filter((s) => s.state === 'open' && s.live && s.live.trees).map(map).filter(Boolean));
  $('#updated').textContent = `updated ${new Date().toLocaleTimeString()}`;
}

refresh();
setInterval(refresh, 1000);
