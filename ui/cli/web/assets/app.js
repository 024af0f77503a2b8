// The web review's pages (docs/web.md). Every text from the server goes into the page as
// text (textContent), never as markup; every change is a JSON POST carrying the session's
// CSRF token. No inline script, nothing from another origin (the server's CSP says so too).

let me = null;

function el(tag, attrs = {}, ...children) {
  const node = document.createElement(tag);
  for (const [key, value] of Object.entries(attrs)) {
    if (key === 'text') node.textContent = value;
    else if (key === 'class') node.className = value;
    else if (key.startsWith('on')) node.addEventListener(key.slice(2), value);
    else node.setAttribute(key, value);
  }
  for (const child of children) if (child !== null && child !== undefined) node.append(child);
  return node;
}

class ApiError extends Error {
  constructor(status, body) {
    super(body && body.error ? body.error : `the server answered ${status}`);
    this.status = status;
    this.whatToDo = body && body.what_to_do ? body.what_to_do : '';
  }
}

async function api(method, path, body) {
  const headers = { Accept: 'application/json' };
  if (method !== 'GET') {
    headers['Content-Type'] = 'application/json';
    if (me) headers['X-CSRF-Token'] = me.csrf;
  }
  const response = await fetch(path, {
    method, headers, credentials: 'same-origin',
    body: body === undefined ? undefined : JSON.stringify(body),
  });
  const data = await response.json().catch(() => null);
  if (!response.ok) throw new ApiError(response.status, data);
  return data;
}

function show(...nodes) {
  const main = document.getElementById('main');
  main.replaceChildren(...nodes);
}

function problem(error) {
  return el('p', { class: 'error', role: 'alert', text: error.whatToDo ? `${error.message} — ${error.whatToDo}` : error.message });
}

function number(value, digits = 1) {
  return typeof value === 'number' ? value.toFixed(digits) : String(value);
}

function cellText(value) {
  if (value === null || value === undefined) return '';
  if (Array.isArray(value)) return value.every((v) => typeof v === 'number') ? `(${value.map((v) => number(v)).join(', ')})` : `${value.length} items`;
  if (typeof value === 'object') return '…';
  if (typeof value === 'number') return Number.isInteger(value) ? String(value) : number(value, 2);
  return String(value);
}

// A table of objects: a column per key whose values are plain (numbers, text, a point). With
// `pick`, a click on a row hands that row's object to it (a curator picking an item to correct).
function table(rows, columns, pick) {
  if (!rows || rows.length === 0) return el('p', { class: 'quiet', text: 'none' });
  const keys = columns || [...new Set(rows.flatMap((r) => Object.keys(r)))].filter(
    (k) => rows.some((r) => r[k] !== null && (typeof r[k] !== 'object' || Array.isArray(r[k]))));
  return el('table', {},
    el('thead', {}, el('tr', {}, ...keys.map((k) => el('th', { text: k.replaceAll('_', ' ') })))),
    el('tbody', {}, ...rows.map((r) => {
      const tr = el('tr', pick ? { class: 'link', title: 'Correct this item' } : {}, ...keys.map((k) => el('td', { text: cellText(r[k]) })));
      if (pick) tr.addEventListener('click', () => pick(r));
      return tr;
    })));
}

function statusBadge(status) {
  return el('span', { class: `status ${status}`, text: status });
}

function decisionText(d) {
  return d ? `${d.action} by ${d.who} at ${d.utc}${d.why ? `: ${d.why}` : ''}` : '';
}

function loginPage(message) {
  const login = el('input', { name: 'login', autocomplete: 'username', required: '' });
  const password = el('input', { name: 'password', type: 'password', autocomplete: 'current-password', required: '' });
  const answer = el('div');
  const form = el('form', { class: 'login', id: 'login-form' },
    el('h1', { text: 'Log in' }),
    el('label', { text: 'Login (your lab server login)' }), login,
    el('label', { text: 'Password' }), password,
    el('button', { type: 'submit', text: 'Log in' }), answer);
  if (message) answer.append(el('p', { class: 'quiet', text: message }));
  form.addEventListener('submit', async (event) => {
    event.preventDefault();
    answer.replaceChildren(el('p', { class: 'quiet', text: 'Checking…' }));
    try {
      me = await api('POST', '/api/login', { login: login.value, password: password.value });
      if (location.pathname === '/login') history.replaceState(null, '', '/');
      start();
    } catch (error) {
      answer.replaceChildren(problem(error));
    }
  });
  show(form);
  login.focus();
}

async function listPage() {
  const choices = await api('GET', '/api/choices');
  const params = new URLSearchParams(location.search);
  const select = (name, words) => el('select', { name },
    el('option', { value: '', text: 'any' }),
    ...words.map((w) => { const o = el('option', { value: w, text: w }); if (params.get(name) === w) o.selected = true; return o; }));
  const filters = el('form', { class: 'filters', method: 'get', action: '/' },
    el('label', { text: 'status' }, select('status', choices.statuses)),
    el('label', { text: 'kind' }, select('kind', choices.kinds)),
    el('label', { text: 'plant' }, el('input', { name: 'plant', value: params.get('plant') || '' })),
    el('label', { text: 'station' }, el('input', { name: 'station', value: params.get('station') || '' })),
    el('label', { text: 'since (UTC day)' }, el('input', { name: 'since', placeholder: '2026-11-01', value: params.get('since') || '' })),
    el('button', { type: 'submit', text: 'Show' }));
  const query = new URLSearchParams();
  for (const key of ['status', 'kind', 'plant', 'station', 'since']) if (params.get(key)) query.set(key, params.get(key));
  const sessions = await api('GET', `/api/sessions?${query}`);
  const rows = sessions.map((s) => {
    const row = el('tr', { class: 'link', 'data-session': String(s.id) },
      el('td', {}, el('a', { href: `/sessions/${s.id}`, text: String(s.id) })),
      el('td', { text: `${s.station}:${s.station_session_id}` }),
      el('td', {}, statusBadge(s.status)),
      el('td', { text: s.kind === 'plant' ? `${s.project}/${s.plant} (plant)` : `${s.project}/${s.plant}/leaf ${s.leaf_position}` }),
      el('td', { text: s.operator }),
      el('td', { text: s.created_utc }),
      el('td', { text: decisionText(s.decision) }));
    row.addEventListener('click', (event) => { if (event.target.tagName !== 'A') location.assign(`/sessions/${s.id}`); });
    return row;
  });
  show(el('h1', { text: 'Sessions' }), filters,
    sessions.length === 0 ? el('p', { class: 'quiet', text: 'No sessions that match.' }) :
      el('table', { id: 'sessions' },
        el('thead', {}, el('tr', {}, ...['id', 'station:id', 'status', 'what', 'operator', 'created (UTC)', 'decision'].map((t) => el('th', { text: t })))),
        el('tbody', {}, ...rows)));
}

function historyTable(history) {
  if (!history || history.length === 0) return el('p', { class: 'quiet', id: 'history', text: 'No decision or correction yet.' });
  return el('table', { id: 'history' },
    el('thead', {}, el('tr', {}, ...['event', 'what', 'change', 'who', 'when (UTC)', 'why'].map((t) => el('th', { text: t })))),
    el('tbody', {}, ...history.map((h) => {
      let change = '';
      if (h.action === 'corrected') {
        const where = [h.what, h.row ? `row ${h.row}` : '', h.col ? `col ${h.col}` : ''].filter(Boolean).join(' ');
        const from = h.from || {};
        const to = h.to || {};
        if (from.position_mm && to.position_mm) change = `${where}: ${cellText(from.position_mm)} → ${cellText(to.position_mm)} mm, moved ${number(h.moved_mm)} mm`;
        else if (from.value_mm !== undefined && to.value_mm !== undefined) change = `${where}: ${number(from.value_mm, 3)} → ${number(to.value_mm, 3)} mm`;
        else change = where;
      } else if (h.action === 'reopened') {
        change = `was ${h.reopens}`;
      }
      return el('tr', {}, el('td', { text: String(h.seq) }), el('td', { text: h.action }), el('td', { text: change }),
        el('td', { text: h.who }), el('td', { text: h.utc }), el('td', { text: h.why || '' }));
    })));
}

function decidePanel(session, redraw) {
  if (!me || me.role !== 'curator') return null;
  const decisions = session.status === 'complete' ? ['approve', 'reject'] :
    session.status === 'approved' || session.status === 'rejected' ? ['reopen'] : [];
  if (decisions.length === 0) return el('p', { class: 'quiet', text: `A ${session.status} session takes no decision.` });
  const why = el('textarea', { id: 'why', placeholder: 'Why (every decision says why; it is kept in the history)' });
  const answer = el('div');
  const buttons = decisions.map((d) => el('button', {
    type: 'button', id: `decide-${d}`, text: d[0].toUpperCase() + d.slice(1),
    onclick: async () => {
      if (!why.value.trim()) { answer.replaceChildren(el('p', { class: 'error', text: 'Say why first.' })); return; }
      try {
        const updated = await api('POST', `/api/sessions/${session.id}/${d}`, { why: why.value });
        redraw(updated, `${{ approve: 'Approved', reject: 'Rejected', reopen: 'Reopened' }[d]}: recorded in the history below.`);
      } catch (error) {
        answer.replaceChildren(problem(error));
      }
    },
  }));
  return el('section', { class: 'decide' }, el('h2', { text: 'Decide' }), why, el('div', { class: 'buttons' }, ...buttons), answer);
}

// The session's model in 3-D (three.js, served by leafdig from npm's package): the GLB that
// `sessions export --format glb --resolution preview` writes, parsed by three's own glTF loader,
// with the captured points on it. A leaf is drawn in the digitizer's frame (its markers'), a
// plant in its own (its points' position_plant_mm).
function viewer(session) {
  const box = el('div', { class: 'viewer', id: 'viewer' });
  const note = el('p', { class: 'quiet', id: 'viewer-note', text: 'Loading the 3-D model…' });
  (async () => {
    let THREE;
    let GLTFLoader;
    let OrbitControls;
    try {
      THREE = await import('/static/vendor/three.module.min.js');
      ({ GLTFLoader } = await import('/static/vendor/GLTFLoader.js'));
      ({ OrbitControls } = await import('/static/vendor/OrbitControls.js'));
    } catch (error) {
      note.textContent = 'The 3-D view is not built into this leafdig: three.js was not installed when it was built (scripts/setup.sh ci or release installs it).';
      return;
    }
    const url = `/api/sessions/${session.id}/export?format=glb&resolution=preview${session.kind === 'plant' ? '' : '&frame=digitizer'}`;
    let gltf;
    try {
      const response = await fetch(url, { credentials: 'same-origin' });
      if (!response.ok) {
        const body = await response.json().catch(() => ({}));
        note.textContent = `No 3-D model: ${body.error || `the server answered ${response.status}`}`;
        return;
      }
      gltf = await new GLTFLoader().parseAsync(await response.arrayBuffer(), '');
    } catch (error) {
      note.textContent = `No 3-D model: ${error}`;
      return;
    }
    const scene = new THREE.Scene();
    scene.background = new THREE.Color(0xf4f7f1);
    scene.add(new THREE.HemisphereLight(0xffffff, 0x667755, 2.2));
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(1, 2, 1);
    scene.add(sun);
    scene.add(gltf.scene);
    let triangles = 0;
    gltf.scene.traverse((o) => {
      if (!o.isMesh) return;
      o.material.side = THREE.DoubleSide;
      triangles += (o.geometry.index ? o.geometry.index.count : o.geometry.attributes.position.count) / 3;
    });
    const bounds = new THREE.Box3().setFromObject(gltf.scene);
    const size = bounds.getSize(new THREE.Vector3()).length() || 0.1;
    const center = bounds.getCenter(new THREE.Vector3());
    const points = session.kind === 'plant'
      ? (session.points || []).map((p) => p.position_plant_mm).filter(Boolean)
      : (session.markers || []).map((m) => m.position_mm).concat(session.tip ? [session.tip] : []);
    if (points.length > 0) {
      const dots = new THREE.InstancedMesh(new THREE.SphereGeometry(size * 0.006, 10, 8),
        new THREE.MeshBasicMaterial({ color: 0xc0392b }), points.length);
      const m = new THREE.Matrix4();
      // glTF's +Y is the frame's +Z (the GLB's asset says so): a frame point (x, y, z) in mm is (x, z, -y) in metres.
      points.forEach((p, i) => dots.setMatrixAt(i, m.makeTranslation(p[0] / 1000, p[2] / 1000, -p[1] / 1000)));
      scene.add(dots);
    }
    const width = Math.min(box.clientWidth || 900, 1100);
    const height = Math.round(width * 0.45);
    const camera = new THREE.PerspectiveCamera(35, width / height, size / 1000, size * 20);
    camera.position.copy(center).add(new THREE.Vector3(size * 0.45, size * 0.35, size * 0.6));
    const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.setSize(width, height);
    box.append(renderer.domElement);
    const controls = new OrbitControls(camera, renderer.domElement);
    controls.target.copy(center);
    const draw = () => renderer.render(scene, camera);
    controls.addEventListener('change', draw);
    controls.update();
    draw();
    note.textContent = `${Math.round(triangles).toLocaleString('en')} triangles (preview resolution), ${points.length} captured points in red. Drag to turn, scroll to zoom.`;
    box.dataset.drawn = 'true';
  })();
  return [box, note];
}

function downloads(session) {
  const formats = session.kind === 'plant' ? ['mtg', 'csv', 'json', 'glb', 'can', 'xml', 'vgx'] : ['glb', 'csv', 'model', 'markers'];
  return el('p', { class: 'downloads' }, el('span', { class: 'quiet', text: 'Download: ' }),
    ...formats.map((f) => el('a', { href: `/api/sessions/${session.id}/export?format=${f}`, download: '', text: f })));
}

// A leaf's numbers (GET /api/sessions/ID/review): its areas with the 95 % interval, the area
// constraint, the warnings and the flags, filled in when they arrive.
function leafNumbers(session) {
  const box = el('section', { id: 'numbers' }, el('p', { class: 'quiet', text: 'Working out the metrics…' }));
  (async () => {
    try {
      const review = await api('GET', `/api/sessions/${session.id}/review`);
      const parts = [];
      const m = review.metrics;
      if (m) {
        const area = (v) => `${Math.round(v).toLocaleString('en')} mm²`;
        const rows = [['blade area', area(m.blade_area_mm2)]];
        if (m.area_interval) rows.push(['95 % interval', `${area(m.area_interval.low_mm2)} – ${area(m.area_interval.high_mm2)}`]);
        rows.push(['projected area', area(m.projected_area_mm2)]);
        if (m.area_constraint) rows.push(['measured area', `${area(m.area_constraint.measured_mm2)} (${number(m.area_constraint.difference_percent)} % from the model${m.area_constraint.exceeded ? ', over its threshold' : ''})`]);
        parts.push(el('dl', { class: 'facts', id: 'metrics' }, ...rows.flatMap(([k, v]) => [el('dt', { text: k }), el('dd', { text: v })])));
        for (const w of m.warnings) parts.push(el('p', { class: 'error', text: `${w.name}: ${w.message}` }));
      } else {
        parts.push(el('p', { class: 'quiet', text: `No metrics: ${review.metrics_problem}` }));
      }
      parts.push(el('h2', { text: 'Flags' }), review.flags.length ? table(review.flags, ['what', 'row', 'col', 'text']) : el('p', { class: 'quiet', text: 'none' }));
      box.replaceChildren(...parts);
    } catch (error) {
      box.replaceChildren(problem(error));
    }
  })();
  return box;
}

// The thickness readings along the leaf: each kind a line over the rows (an SVG drawn here; the
// margin thickness d a dashed level).
function thicknessChart(readings) {
  const ns = 'http://www.w3.org/2000/svg';
  const svg = (tag, attrs) => {
    const node = document.createElementNS(ns, tag);
    for (const [k, v] of Object.entries(attrs)) node.setAttribute(k, String(v));
    return node;
  };
  const rowed = (readings || []).filter((r) => r.row);
  if (rowed.length === 0) return el('p', { class: 'quiet', text: 'No thickness readings by row.' });
  const W = 640; const H = 220; const L = 48; const B = 30; const T = 12; const R = 150;
  const rows = Math.max(...rowed.map((r) => r.row));
  const all = (readings || []).map((r) => r.value_mm);
  const top = Math.max(...all) * 1.1 || 1;
  const x = (row) => L + (rows === 1 ? 0 : ((row - 1) / (rows - 1)) * (W - L - R));
  const y = (v) => H - B - (v / top) * (H - B - T);
  const chart = svg('svg', { viewBox: `0 0 ${W} ${H}`, width: W, height: H, id: 'thickness-chart', role: 'img' });
  chart.append(svg('line', { x1: L, y1: H - B, x2: W - R, y2: H - B, stroke: '#889' }), svg('line', { x1: L, y1: T, x2: L, y2: H - B, stroke: '#889' }));
  for (const v of [0, top / 2, top]) {
    const t = svg('text', { x: L - 6, y: y(v) + 4, 'text-anchor': 'end', 'font-size': 11, fill: '#5b6b5d' });
    t.textContent = v.toFixed(2);
    chart.append(t);
  }
  const label = svg('text', { x: (L + W - R) / 2, y: H - 6, 'text-anchor': 'middle', 'font-size': 11, fill: '#5b6b5d' });
  label.textContent = 'row (base → tip), thickness in mm';
  chart.append(label);
  const colours = ['#2f7d32', '#1f5fa3', '#a35f1f', '#7d2f6b'];
  const kinds = [...new Set(rowed.map((r) => r.what))];
  kinds.forEach((kind, k) => {
    const pts = rowed.filter((r) => r.what === kind).sort((a, b) => a.row - b.row);
    chart.append(svg('polyline', { points: pts.map((p) => `${x(p.row)},${y(p.value_mm)}`).join(' '), fill: 'none', stroke: colours[k % 4], 'stroke-width': 2 }));
    for (const p of pts) chart.append(svg('circle', { cx: x(p.row), cy: y(p.value_mm), r: 3, fill: colours[k % 4] }));
    const key = svg('text', { x: W - R + 10, y: T + 14 + 16 * k, 'font-size': 11, fill: colours[k % 4] });
    key.textContent = kind.replaceAll('_', ' ');
    chart.append(key);
  });
  const edge = (readings || []).find((r) => !r.row && r.what.startsWith('edge'));
  if (edge) {
    chart.append(svg('line', { x1: L, y1: y(edge.value_mm), x2: W - R, y2: y(edge.value_mm), stroke: '#999', 'stroke-dasharray': '4 3' }));
    const key = svg('text', { x: W - R + 10, y: T + 14 + 16 * kinds.length, 'font-size': 11, fill: '#777' });
    key.textContent = `margin d ${edge.value_mm.toFixed(2)}`;
    chart.append(key);
  }
  return chart;
}

// A curator's correction of one item (a row picked in a table): the new position or value and a
// reason; Preview asks the server what it would change (the move, the areas, a plant's heights
// and lengths) and only then may it be written, against the very state previewed (seen_head);
// a move beyond the server's limit needs a tick that the curator checked it.
function correctionPanel(session, item, redraw) {
  const isPoint = Array.isArray(item.position_plant_mm) || Array.isArray(item.position_mm);
  const start = isPoint ? (session.kind === 'plant' && item.position_plant_mm ? item.position_plant_mm : item.position_mm) : null;
  const frame = session.kind === 'plant' && isPoint ? 'plant' : 'digitizer';
  const inputs = isPoint ? start.map((v, i) => el('input', { type: 'number', step: '0.1', value: v.toFixed(2), id: `correct-${'xyz'[i]}`, 'aria-label': 'xyz'[i] }))
    : [el('input', { type: 'number', step: '0.01', value: String(item.value_mm), id: 'correct-value', 'aria-label': 'value in mm' })];
  const why = el('textarea', { id: 'correct-why', placeholder: 'Why (kept in the history)' });
  const effect = el('div', { id: 'correct-effect' });
  const confirm = el('input', { type: 'checkbox', id: 'correct-confirm' });
  const confirmLine = el('label', { hidden: '' }, confirm, ' I checked the position: write this move');
  const write = el('button', { type: 'button', id: 'correct-write', text: 'Write correction', disabled: '' });
  let head = null;
  const body = (dryRun) => {
    const b = { what: item.what, why: why.value, dry_run: dryRun };
    if (item.row !== null && item.row !== undefined) b.row = item.row;
    if (item.col !== null && item.col !== undefined) b.col = item.col;
    if (isPoint) { b.position_mm = inputs.map((i) => Number(i.value)); b.frame = frame; } else b.value_mm = Number(inputs[0].value);
    if (!dryRun) { b.seen_head = head; b.confirm = confirm.checked; }
    return b;
  };
  const preview = el('button', {
    type: 'button', id: 'correct-preview', text: 'Preview',
    onclick: async () => {
      write.disabled = true;
      if (!why.value.trim()) { effect.replaceChildren(el('p', { class: 'error', text: 'Say why first.' })); return; }
      try {
        const e = await api('POST', `/api/sessions/${session.id}/correct`, body(true));
        head = e.head;
        const lines = [];
        if (e.moved_mm !== null) lines.push(`the point moves ${number(e.moved_mm)} mm (${e.frame} frame)`);
        for (const c of e.changes) lines.push(`${c.what}: ${number(c.before)} → ${number(c.after)}${c.before ? ` (${c.after >= c.before ? '+' : ''}${number(100 * (c.after - c.before) / c.before)} %)` : ''}`);
        if (lines.length === 0) lines.push('nothing measured changes');
        effect.replaceChildren(el('ul', {}, ...lines.map((t) => el('li', { text: t }))));
        confirmLine.hidden = !e.needs_confirm;
        if (e.needs_confirm) effect.append(el('p', { class: 'error', text: `That is more than the ${number(e.confirm_above_mm)} mm a correction moves unchecked.` }));
        write.disabled = false;
      } catch (error) {
        effect.replaceChildren(problem(error));
      }
    },
  });
  write.addEventListener('click', async () => {
    effect.replaceChildren(el('p', { class: 'quiet', text: 'Writing…' }));
    try {
      const updated = await api('POST', `/api/sessions/${session.id}/correct`, body(false));
      redraw(updated, `Corrected ${item.what}${item.row ? ` row ${item.row}` : ''}${item.col ? ` col ${item.col}` : ''}: recorded in the history below.`);
    } catch (error) {
      effect.replaceChildren(problem(error));
    }
  });
  const where = [item.what, item.row ? `row ${item.row}` : '', item.col ? `col ${item.col}` : ''].filter(Boolean).join(' ');
  return el('section', { class: 'decide', id: 'correct' },
    el('h2', { text: `Correct ${where}` }),
    el('p', { class: 'quiet', text: isPoint ? `New position in mm (${frame} frame), now ${cellText(start)}` : `New value in mm, now ${number(item.value_mm, 3)}` }),
    el('div', { class: 'buttons' }, ...inputs), why, el('div', { class: 'buttons' }, preview, write), confirmLine, effect);
}

// A plant as a tree: its stem, node by node from the base, each node's leaf under it (the
// survey's numbers; a leaf's kind and state when it has none).
function plantTree(survey) {
  const mm = (v) => (typeof v === 'number' ? `${number(v)} mm` : '—');
  const leafText = (l) => {
    const parts = [`${l.kind} leaf`, l.state];
    if (typeof l.midrib_length_mm === 'number') parts.push(`length ${mm(l.midrib_length_mm)}`);
    if (typeof l.area_mm2 === 'number') parts.push(`area ${Math.round(l.area_mm2).toLocaleString('en')} mm²`);
    if (typeof l.inclination_deg === 'number') parts.push(`inclination ${number(l.inclination_deg)}°`);
    return parts.join(', ');
  };
  const nodes = (survey.nodes || []).map((n) => {
    const leaves = (survey.leaves || []).filter((l) => l.node === n.node);
    return el('li', { text: `Node ${n.node}: height ${mm(n.height_mm)}, internode ${mm(n.internode_mm)}, stem Ø ${mm(n.diameter_mm)}` },
      leaves.length ? el('ul', {}, ...leaves.map((l) => el('li', { text: leafText(l) }))) : null);
  });
  return el('ul', { class: 'tree', id: 'plant-tree' },
    el('li', { text: `${survey.plant || 'plant'}: collar Ø ${mm(survey.collar_diameter_mm)}` }, el('ul', {}, ...nodes)));
}

// The plant's other surveys (the same plant on other dates), each a link to its page.
function plantSurveys(session) {
  const box = el('section', { id: 'surveys' }, el('p', { class: 'quiet', text: 'Looking for this plant\'s other surveys…' }));
  (async () => {
    try {
      const answer = await api('GET', `/api/sessions/${session.id}/surveys`);
      box.replaceChildren(el('table', {},
        el('thead', {}, el('tr', {}, ...['session', 'date', 'status', 'station', 'nodes', 'leaves (full/quick/none)', 'verified'].map((t) => el('th', { text: t })))),
        el('tbody', {}, ...answer.surveys.map((v) => el('tr', {},
          el('td', {}, v.session === session.id ? el('strong', { text: `${v.session} (this one)` }) : el('a', { href: `/sessions/${v.session}`, text: String(v.session) })),
          el('td', { text: v.date }), el('td', {}, statusBadge(v.status)), el('td', { text: v.station }),
          el('td', { text: String(v.nodes) }), el('td', { text: `${v.leaves.full}/${v.leaves.quick}/${v.leaves.none}` }),
          el('td', { text: v.verified ? 'yes' : `no: ${v.problem || ''}` }))))));
    } catch (error) {
      box.replaceChildren(problem(error));
    }
  })();
  return box;
}

function sessionPage(session, notice) {
  const title = session.kind === 'plant' ? `Plant ${session.project}/${session.plant}` :
    `Leaf ${session.project}/${session.plant}/${session.leaf_position}`;
  const facts = [
    ['status', statusBadge(session.status)],
    ['station', `${session.station}:${session.station_session_id}`],
    ['operator', session.operator],
    ['events', `${session.events}, chain ${session.chain_ok ? 'OK' : `BROKEN: ${session.problem}`}`],
    ['step', session.step ? session.step.prompt : ''],
  ];
  if (session.date) facts.push(['date', session.date]);
  const sections = [
    el('h1', { text: `Session ${session.id} · ${title}` }),
    notice ? el('p', { class: 'ok', role: 'status', text: notice }) : null,
    el('dl', { class: 'facts' }, ...facts.flatMap(([k, v]) => [el('dt', { text: k }), el('dd', {}, v)])),
    ...viewer(session), downloads(session),
    session.kind === 'plant' ? null : leafNumbers(session),
    decidePanel(session, (updated, message) => sessionPage(updated, message)),
    el('h2', { text: 'History' }), historyTable(session.history),
  ];
  if (session.kind === 'plant') {
    if (session.survey && Array.isArray(session.survey.nodes)) {
      sections.push(el('h2', { text: 'The plant' }), plantTree(session.survey));
      sections.push(el('h2', { text: 'Nodes' }), table(session.survey.nodes, ['node', 'height_mm', 'internode_mm', 'diameter_mm', 'point_mm']));
      if (Array.isArray(session.survey.leaves)) sections.push(el('h2', { text: 'Leaves as surveyed (plant frame)' }), table(session.survey.leaves));
    } else {
      sections.push(el('p', { class: 'quiet', text: `No survey yet: ${session.survey_problem || ''}` }));
    }
    sections.push(el('h2', { text: 'Surveys of this plant' }), plantSurveys(session));
    sections.push(el('h2', { text: 'Leaves as captured' }), table(session.leaves, ['node', 'kind', 'state', 'complete', 'type']));
    sections.push(el('h2', { text: 'Points', id: 'items' }), table(session.points, ['what', 'row', 'col', 'position_plant_mm', 'position_mm', 'transmitter_position'], picker(session)));
    sections.push(el('h2', { text: 'Readings' }), table(session.readings, ['what', 'row', 'col', 'value_mm'], picker(session)));
  } else {
    const markers = (session.markers || []).map((m) => ({ what: 'marker', ...m }));
    sections.push(el('h2', { text: 'Markers', id: 'items' }), table(markers, ['row', 'col', 'position_mm'], picker(session)));
    sections.push(el('h2', { text: 'Thickness' }), thicknessChart(session.thickness), table(session.thickness, ['what', 'row', 'col', 'value_mm'], picker(session)));
  }
  if (picker(session)) sections.splice(sections.findIndex((n) => n && n.id === 'items'), 0, el('p', { class: 'quiet', text: 'Click an item below to correct it.' }));
  show(...sections.filter(Boolean));
}

// The item a curator picked, in a correction panel at the head of the tables (none for a
// session that takes no correction, or a login that may not make one).
function picker(session) {
  if (!me || me.role !== 'curator' || session.status !== 'complete') return undefined;
  return (item) => {
    const old = document.getElementById('correct');
    const panel = correctionPanel(session, item, (updated, message) => sessionPage(updated, message));
    if (old) old.replaceWith(panel); else document.getElementById('items').before(panel);
    panel.scrollIntoView();
  };
}

async function start() {
  const who = document.getElementById('who');
  const logout = document.getElementById('logout');
  try {
    me = await api('GET', '/api/me');
  } catch (error) {
    me = null;
    who.textContent = '';
    logout.hidden = true;
    if (error.status === 401) { loginPage(); return; }
    show(problem(error));
    return;
  }
  who.textContent = `${me.login} (${me.role})`;
  logout.hidden = false;
  const match = location.pathname.match(/^\/sessions\/(\d+)$/);
  try {
    if (match) sessionPage(await api('GET', `/api/sessions/${match[1]}`));
    else await listPage();
  } catch (error) {
    if (error.status === 401) loginPage('Your session ended: log in again.');
    else show(problem(error), el('p', {}, el('a', { href: '/', text: 'All sessions' })));
  }
}

document.getElementById('logout').addEventListener('click', async () => {
  try { await api('POST', '/api/logout', {}); } catch (error) { /* ended already */ }
  me = null;
  location.assign('/');
});

start();
