// The web review in a real browser: Debian's chromium, headless, driven by puppeteer-core (no
// browser download). Run by WebCli.ACuratorAndATechnicianInHeadlessChromium
// (tests/cli/web_cli_test.cpp), which sets up the lab server and the web server and passes:
//   node web-review.mjs '{"base": "http://127.0.0.1:PORT", "curator": {"login", "password"},
//     "technician": {"login", "password", "station"}, "leaf": ID, "plant": ID, "screenshots": DIR}'
// Each check that fails is printed and the exit code is 1; the screenshots are written for a
// person to look at (and for the README: scripts/update-screenshots.sh copies them).
import http from 'node:http';
import puppeteer from 'puppeteer-core';

const config = JSON.parse(process.argv[2]);
const failures = [];
function check(condition, what) {
  if (!condition) failures.push(what);
  console.log(`${condition ? 'ok  ' : 'FAIL'} ${what}`);
}

// How much of the 3-D view's canvas is drawn: the share of its pixels that are not the
// background (the canvas keeps its drawing buffer, so it can be read back).
async function drawnShare(page) {
  await page.waitForSelector('#viewer[data-drawn=true], #viewer-note', { timeout: kWaitMs });
  await page.waitForFunction(() => document.querySelector('#viewer[data-drawn=true]') ||
    !document.querySelector('#viewer-note').textContent.startsWith('Loading'), { timeout: kWaitMs });
  return page.evaluate(() => {
    const canvas = document.querySelector('#viewer canvas');
    if (!canvas) return { share: 0, note: document.querySelector('#viewer-note').textContent };
    const copy = document.createElement('canvas');
    copy.width = canvas.width;
    copy.height = canvas.height;
    const g = copy.getContext('2d');
    g.drawImage(canvas, 0, 0);
    const px = g.getImageData(0, 0, copy.width, copy.height).data;
    let drawn = 0;
    for (let i = 0; i < px.length; i += 4) {
      if (Math.abs(px[i] - 0xf4) + Math.abs(px[i + 1] - 0xf7) + Math.abs(px[i + 2] - 0xf1) > 24) drawn += 1;
    }
    return { share: drawn / (px.length / 4), note: document.querySelector('#viewer-note').textContent };
  });
}

// Generous waits: the suite runs this beside other tests on two cores, and under ASan the web
// server's exports take seconds; the checks are about what is drawn and said, never how fast.
const kWaitMs = 180000;

async function logIn(page, who) {
  await page.goto(`${config.base}/`, { waitUntil: 'networkidle0' });
  await page.waitForSelector('#login-form');
  await page.type('input[name=login]', who.login);
  await page.type('input[name=password]', who.password);
  await Promise.all([page.waitForSelector('#sessions, main .error'), page.click('#login-form button[type=submit]')]);
}

const browser = await puppeteer.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--use-gl=swiftshader', '--enable-unsafe-swiftshader'],
});
// The page a failed wait leaves behind is described (its text, the browser's console errors) and
// photographed, so that a failure says what the page showed instead of only "timeout".
let current = null;
const consoleErrors = [];
try {
  // ---- a curator ------------------------------------------------------------------------
  const curator = await browser.createBrowserContext();
  const page = await curator.newPage();
  current = page;
  page.setDefaultTimeout(kWaitMs);
  page.setDefaultNavigationTimeout(kWaitMs);
  await page.setViewport({ width: 1280, height: 860 });
  page.on('console', (m) => { if (m.type() === 'error') consoleErrors.push(m.text()); });
  page.on('pageerror', (e) => consoleErrors.push(String(e)));

  await page.goto(`${config.base}/`, { waitUntil: 'networkidle0' });
  check(await page.$('#login-form') !== null, 'a browser without a session is shown the login form');
  await page.screenshot({ path: `${config.screenshots}/web-login.png` });
  // A wrong password is said on the page, and the form stays.
  await page.type('input[name=login]', config.curator.login);
  await page.type('input[name=password]', 'not-the-password');
  await page.click('#login-form button[type=submit]');
  await page.waitForSelector('#login-form .error');
  check((await page.$eval('#login-form .error', (e) => e.textContent)).includes('not right'), 'a wrong password is said on the page');

  await logIn(page, config.curator);
  await page.waitForSelector('#sessions');
  const rows = await page.$$eval('#sessions tbody tr', (trs) => trs.map((tr) => tr.dataset.session));
  check(rows.includes(String(config.leaf)) && rows.includes(String(config.plant)), 'the curator lists the leaf and the plant');
  check((await page.$eval('#who', (e) => e.textContent)).includes('curator'), 'the header names the login and its role');
  await page.screenshot({ path: `${config.screenshots}/web-sessions.png` });

  // The leaf: approve with a reason, and see the history say so.
  await page.goto(`${config.base}/sessions/${config.leaf}`, { waitUntil: 'networkidle0' });
  await page.waitForSelector('#decide-approve');
  const leafView = await drawnShare(page);
  check(leafView.share > 0.01, `the leaf's 3-D view draws (${(100 * leafView.share).toFixed(1)} % of its pixels; ${leafView.note})`);
  await page.waitForSelector('#metrics, #numbers .quiet:not(:first-child), #numbers .error', { timeout: kWaitMs });
  const metrics = await page.$eval('#numbers', (e) => e.textContent);
  check(metrics.includes('blade area') && metrics.includes('95 % interval'), `the leaf's metrics show the area and its interval (${metrics.slice(0, 120)})`);
  check(await page.$$eval('#thickness-chart polyline', (p) => p.length) >= 2, 'the thickness chart draws a line per kind of reading');
  check((await page.$eval('main h1', (e) => e.textContent)).startsWith(`Session ${config.leaf}`), 'the leaf page names its session');
  // A correction picked from the markers table: previewed (the move and the area's change),
  // then written against what was previewed; the history says it.
  await page.click('#items + table tbody tr:nth-child(10)');
  await page.waitForSelector('#correct');
  const x = await page.$eval('#correct-x', (i) => Number(i.value));
  await page.$eval('#correct-x', (i, v) => { i.value = String(v); }, x + 60);
  await page.type('#correct-why', 'the stylus slipped');
  await page.click('#correct-preview');
  await page.waitForSelector('#correct-effect li, #correct-effect .error');
  const effect = await page.$eval('#correct-effect', (e) => e.textContent);
  check(/moves 60\.0 mm/.test(effect) && effect.includes('area'), `a correction's preview says the move and the area's change (${effect})`);
  check(!(await page.$eval('#correct-confirm', (c) => c.parentElement.hidden)), 'a 60 mm move asks to be checked before it is written');
  await page.click('#correct-write');
  await page.waitForFunction(() => !document.querySelector('#correct-effect').textContent.startsWith('Writing'));
  check((await page.$eval('#correct-effect', (e) => e.textContent)).includes('"confirm": true'), 'unchecked, the 60 mm move is refused in words');
  await page.$eval('#correct-x', (i, v) => { i.value = String(v); }, x + 4);
  await page.click('#correct-preview');
  await page.waitForFunction(() => /moves 4\.0 mm/.test(document.querySelector('#correct-effect').textContent));
  await page.click('#correct-write');
  await page.waitForFunction(() => [...document.querySelectorAll('#history tbody tr')].some((tr) => tr.cells[1].textContent === 'corrected'));
  const corrected = await page.$$eval('#history tbody tr', (trs) => trs.map((tr) => [...tr.cells].map((c) => c.textContent)).find((r) => r[1] === 'corrected'));
  check(corrected[2].includes('moved 4.0 mm') && corrected[3] === config.curator.login && corrected[5] === 'the stylus slipped',
    `the history shows the correction: item, old → new, who, why (${corrected.join(' | ')})`);
  // The page drawn again after the correction, as the curator looks at it before deciding (and
  // the server's answers for the redrawn page are in before the decision queues behind them).
  const redrawn = await drawnShare(page);
  check(redrawn.share > 0.01, `the corrected leaf draws again (${(100 * redrawn.share).toFixed(1)} % of its pixels; ${redrawn.note})`);
  await page.waitForSelector('#metrics, #numbers .quiet:not(:first-child), #numbers .error', { timeout: kWaitMs });
  await page.waitForSelector('#decide-approve');
  await page.type('#why', 'checked against the photos <b>not bold</b>');
  await page.click('#decide-approve');
  await page.waitForFunction(() => [...document.querySelectorAll('#history tbody tr')].some((tr) => tr.cells[1].textContent === 'approved'));
  const history = await page.$$eval('#history tbody tr', (trs) => trs.map((tr) => [...tr.cells].map((c) => c.textContent)));
  const last = history[history.length - 1];
  check(last[1] === 'approved' && last[3] === config.curator.login, 'the history names the approval and the curator');
  check(last[5] === 'checked against the photos <b>not bold</b>', 'the reason is shown as text, not markup');
  check(await page.$('#history b') === null, 'no markup from the reason reached the page');
  check(await page.$('#decide-reopen') !== null && await page.$('#decide-approve') === null, 'an approved session offers only reopen');
  await drawnShare(page);
  await page.evaluate(() => window.scrollTo(0, 0));
  await page.screenshot({ path: `${config.screenshots}/web-leaf.png` });

  // The plant: its nodes.
  await page.goto(`${config.base}/sessions/${config.plant}`, { waitUntil: 'networkidle0' });
  await page.waitForSelector('main h1');
  check((await page.$eval('main h1', (e) => e.textContent)).includes('Plant'), 'the plant page names a plant');
  const plantView = await drawnShare(page);
  check(plantView.share > 0.01, `the plant's 3-D view draws (${(100 * plantView.share).toFixed(1)} % of its pixels; ${plantView.note})`);
  // Its files download from the page's links.
  const mtg = await page.evaluate(async (id) => {
    const r = await fetch(`/api/sessions/${id}/export?format=mtg`);
    return { status: r.status, disposition: r.headers.get('Content-Disposition'), text: await r.text() };
  }, config.plant);
  check(mtg.status === 200 && mtg.disposition.includes('attachment') && mtg.text.includes('MTG'), `the plant's MTG downloads (${mtg.status})`);
  // Helios XML and VegeSTAR, the light models' formats, from the page's own links.
  const links = await page.$$eval('.downloads a', (as) => as.map((a) => a.getAttribute('href')));
  const simulators = await page.evaluate(async (hrefs) => Promise.all(hrefs.filter((h) => /format=(xml|vgx)$/.test(h)).map(async (h) => {
    const r = await fetch(h);
    return { href: h, status: r.status, type: r.headers.get('Content-Type'), text: await r.text() };
  })), links);
  const helios = simulators.find((d) => d.href.endsWith('format=xml'));
  const vgx = simulators.find((d) => d.href.endsWith('format=vgx'));
  check(helios && helios.status === 200 && helios.type.startsWith('application/xml') && helios.text.includes('<helios>') && helios.text.includes('<triangle>'),
    `the plant's Helios XML downloads from its link (${helios ? helios.status : 'no link'})`);
  check(vgx && vgx.status === 200 && /^Obj\s+EchX/m.test(vgx.text), `the plant's VegeSTAR file downloads from its link (${vgx ? vgx.status : 'no link'})`);
  const headings = await page.$$eval('main h2', (hs) => hs.map((h) => h.textContent));
  const tree = await page.$$eval('#plant-tree li', (lis) => lis.length);
  check(tree >= 6, `the plant page draws the plant as a tree of its nodes and leaves (${tree} entries)`);
  await page.waitForSelector('#surveys table', { timeout: kWaitMs });
  const surveys = await page.$eval('#surveys', (e) => e.textContent);
  check(surveys.includes('(this one)') && surveys.includes('2026-06-12'), `the plant page lists the plant's surveys (${surveys.slice(0, 100)})`);
  check(headings.includes('Nodes') && headings.includes('Leaves as surveyed (plant frame)'), 'the plant page shows its nodes and leaves');
  await page.evaluate(() => window.scrollTo(0, 0));
  await page.screenshot({ path: `${config.screenshots}/web-plant.png` });

  // From the page's own origin, a change without the CSRF token is refused.
  const noToken = await page.evaluate(async (id) => {
    const r = await fetch(`/api/sessions/${id}/reject`, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: '{"why":"x"}' });
    return r.status;
  }, config.plant);
  check(noToken === 403, `a change without the CSRF token is refused (${noToken})`);
  // The refusals above (401, 403, the unchecked move's 409) are the browser's "failed to load"
  // lines; anything else is a fault.
  const faults = consoleErrors.filter((e) => !/status of 40[139] /.test(e));
  check(faults.length === 0, `no script errors and no missing resource (${faults.join(' | ')})`);

  // ---- another site's page, in the curator's browser ------------------------------------------
  // A form on another origin posts to the review: the cookie is SameSite=Strict and the body is
  // not JSON, so nothing changes.
  const evil = http.createServer((req, res) => {
    res.writeHead(200, { 'Content-Type': 'text/html' });
    res.end(`<form id="f" method="post" enctype="text/plain" action="${config.base}/api/sessions/${config.plant}/approve">` +
      '<input name=\'{"why":"x","pad":"\' value=\'"}\'></form><script>document.getElementById("f").submit()</script>');
  });
  await new Promise((resolve) => evil.listen(0, '127.0.0.1', resolve));
  const evilPage = await curator.newPage();
  current = evilPage;
  evilPage.setDefaultTimeout(kWaitMs);
  evilPage.setDefaultNavigationTimeout(kWaitMs);
  const answer = evilPage.waitForResponse((r) => r.url().includes('/approve'));
  await evilPage.goto(`http://localhost:${evil.address().port}/`);
  const posted = await answer;
  check(posted.status() === 401 || posted.status() === 403 || posted.status() === 415, `a cross-site form post is refused (${posted.status()})`);
  evil.close();
  const plantAfter = await page.evaluate(async (id) => (await (await fetch(`/api/sessions/${id}`)).json()).status, config.plant);
  check(plantAfter === 'complete', `the plant is still complete after the cross-site post (${plantAfter})`);

  // ---- a technician ------------------------------------------------------------------------------
  const techContext = await browser.createBrowserContext();
  const tech = await techContext.newPage();
  current = tech;
  tech.setDefaultTimeout(kWaitMs);
  tech.setDefaultNavigationTimeout(kWaitMs);
  await tech.setViewport({ width: 1280, height: 860 });
  await logIn(tech, config.technician);
  await tech.waitForSelector('#sessions');
  const stations = await tech.$$eval('#sessions tbody tr td:nth-child(2)', (tds) => tds.map((td) => td.textContent.split(':')[0]));
  check(stations.length > 0 && stations.every((s) => s === config.technician.station), `the technician lists its own station only (${stations.join(', ')})`);
  await tech.screenshot({ path: `${config.screenshots}/web-technician.png` });
  // One of its own sessions that takes a decision (complete): the server, not the session's
  // state, must be what refuses the technician.
  const ownId = await tech.$$eval('#sessions tbody tr', (trs) => trs.find((tr) => tr.querySelector('.status.complete')).dataset.session);
  await tech.goto(`${config.base}/sessions/${ownId}`, { waitUntil: 'networkidle0' });
  await tech.waitForSelector('main h1');
  check(await tech.$('[id^=decide-]') === null, 'the technician is offered no decision');
  const refused = await tech.evaluate(async (id) => {
    const me = await (await fetch('/api/me')).json();
    const r = await fetch(`/api/sessions/${id}/approve`, {
      method: 'POST', headers: { 'Content-Type': 'application/json', 'X-CSRF-Token': me.csrf }, body: '{"why":"mine"}',
    });
    return r.status;
  }, ownId);
  check(refused === 403, `the API refuses the technician's decision (${refused})`);
} catch (error) {
  if (current) {
    const shown = await current.evaluate(() => document.querySelector('main')?.innerText ?? '').catch(() => '');
    console.log(`the page showed:\n${shown.slice(0, 4000)}`);
    console.log(`the browser's console errors: ${consoleErrors.length ? consoleErrors.join('\n') : 'none'}`);
    await current.screenshot({ path: `${config.screenshots}/web-failure.png` }).catch(() => {});
  }
  throw error;
} finally {
  await browser.close();
}
console.log(failures.length === 0 ? 'web review: every check passed' : `web review: ${failures.length} check(s) failed`);
process.exit(failures.length === 0 ? 0 : 1);
