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

// A table of objects: a column per key whose values are plain (numbers, text, a point).
function table(rows, columns) {
  if (!rows || rows.length === 0) return el('p', { class: 'quiet', text: 'none' });
  const keys = columns || [...new Set(rows.flatMap((r) => Object.keys(r)))].filter(
    (k) => rows.some((r) => r[k] !== null && (typeof r[k] !== 'object' || Array.isArray(r[k]))));
  return el('table', {},
    el('thead', {}, el('tr', {}, ...keys.map((k) => el('th', { text: k.replaceAll('_', ' ') })))),
    el('tbody', {}, ...rows.map((r) => el('tr', {}, ...keys.map((k) => el('td', { text: cellText(r[k]) }))))));
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
    decidePanel(session, (updated, message) => sessionPage(updated, message)),
    el('h2', { text: 'History' }), historyTable(session.history),
  ];
  if (session.kind === 'plant') {
    if (session.survey && Array.isArray(session.survey.nodes)) {
      sections.push(el('h2', { text: 'Nodes' }), table(session.survey.nodes, ['node', 'height_mm', 'internode_mm', 'diameter_mm', 'point_mm']));
      if (Array.isArray(session.survey.leaves)) sections.push(el('h2', { text: 'Leaves as surveyed (plant frame)' }), table(session.survey.leaves));
    } else {
      sections.push(el('p', { class: 'quiet', text: `No survey yet: ${session.survey_problem || ''}` }));
    }
    sections.push(el('h2', { text: 'Leaves as captured' }), table(session.leaves, ['node', 'kind', 'state', 'complete', 'type']));
    sections.push(el('h2', { text: 'Points' }), table(session.points, ['what', 'row', 'col', 'position_plant_mm', 'position_mm', 'transmitter_position']));
    sections.push(el('h2', { text: 'Readings' }), table(session.readings, ['what', 'row', 'col', 'value_mm']));
  } else {
    sections.push(el('h2', { text: 'Markers' }), table(session.markers, ['row', 'col', 'position_mm']));
    sections.push(el('h2', { text: 'Thickness' }), table(session.thickness, ['what', 'row', 'col', 'value_mm']));
  }
  show(...sections.filter(Boolean));
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
