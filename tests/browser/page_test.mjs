// The operator's page in a real browser (Debian's chromium, headless), driven as an operator
// would: run by tests/system/browser_test.cc against a daemon driving the simulated rig.
//
//   node page_test.mjs SCENARIO --url URL --token TOKEN --stations DIR --artifacts DIR
//
// Scenarios:
//   survey   token, station S1, start, wait for the result, check the terrain correction
//            shown against terrain_correction.json, the verdict against the station's own;
//            sunlight contrast, touch targets, keyboard; the retake a verdict names, run from
//            its button;
//            the next station offered (S2, the fields kept), surveyed; both compared (DoD and
//            subsidence table against change.json); the zip and the campaign table fetched.
//   start    token, station R1, start, return once two poses of the ring are done.
//   resume   after the daemon restarted, in a new browser: the token, R1 offered for resume,
//            resumed, its result checked.
// Every request the page makes must succeed (no failed request, no 4xx/5xx, no page error);
// screenshots go to the artifacts directory. Exit 0 when every check held; else the failures.
import fs from 'node:fs';
import path from 'node:path';
import puppeteer from 'puppeteer-core';

const args = {scenario: process.argv[2]};
for (let i = 3; i < process.argv.length; i += 2) args[process.argv[i].slice(2)] = process.argv[i + 1];
const failures = [];
const check = (ok, what) => { if (!ok) failures.push(what); };
const readJson = (file) => JSON.parse(fs.readFileSync(file, 'utf8'));
const RESULT_TIMEOUT = 240000;

const browser = await puppeteer.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  headless: true,
  // --no-sandbox: CI runs as root, where chromium's sandbox cannot start.
  args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage', '--window-size=1280,1600'],
});
const page = await browser.newPage();
await page.setViewport({width: 1280, height: 1600});
const bad = [];
page.on('requestfailed', (r) => {
  // The event stream is cut when the page goes away, and images replaced mid-load are
  // aborted by the browser itself: neither is a request the daemon failed.
  const reason = r.failure() ? r.failure().errorText : '';
  if (reason !== 'net::ERR_ABORTED') bad.push(r.method() + ' ' + r.url() + ': ' + reason);
});
page.on('response', (r) => { if (r.status() >= 400) bad.push(r.status() + ' ' + r.url()); });
page.on('pageerror', (e) => bad.push('page error: ' + e.message));
page.on('console', (m) => { if (m.type() === 'error') bad.push('console: ' + m.text()); });

// This run's screenshots only: those of an earlier run of the scenario go.
fs.mkdirSync(args.artifacts, {recursive: true});
for (const f of fs.readdirSync(args.artifacts))
  if (f.startsWith(`${args.scenario}-`)) fs.rmSync(path.join(args.artifacts, f));
let shot = 0;
async function screenshot(name) {
  await page.screenshot({path: path.join(args.artifacts,
    `${args.scenario}-${String(++shot).padStart(2, '0')}-${name}.png`), fullPage: true});
}

async function enterToken() {
  await page.goto(args.url, {waitUntil: 'load'});
  await page.waitForSelector('#token-section:not([hidden])');
  check(await page.$eval('#start', (b) => b.disabled), 'start is enabled before the token');
  await page.type('#token', args.token);
  await page.keyboard.press('Enter');  // the form works from the keyboard
  await page.waitForSelector('#token-section[hidden]');
  await page.waitForFunction(() => document.querySelectorAll('#chips .chip.present').length >= 3,
    {timeout: 30000});
}

async function fillStation(id) {
  await page.$eval('#station', (e, v) => { e.value = v; }, id);
  await page.$eval('#height', (e) => { e.value = ''; });
  await page.type('#height', '1.52');
  await page.$eval('#line', (e) => { e.value = ''; });
  await page.type('#line', 'L7');
  await page.$eval('#operator', (e) => { e.value = ''; });
  await page.type('#operator', 'browser test');
}

async function startAndWaitForResult(id) {
  await page.waitForFunction(() => !document.querySelector('#start').disabled, {timeout: 30000});
  await page.click('#start');
  await page.waitForSelector('#live-section:not([hidden])', {timeout: 30000});
  await page.waitForFunction(() => document.querySelectorAll('#ring .pose.done').length >= 2,
    {timeout: 60000});
  await screenshot(`${id}-capture`);
  check(await page.$$eval('#thumbs img', (i) => i.length) >= 4, `${id}: no pair thumbnails`);
  await page.waitForFunction((s) => document.querySelector('#result-station').textContent === s &&
    !document.querySelector('#result-section').hidden, {timeout: RESULT_TIMEOUT}, id);
  await page.waitForFunction(() => document.querySelector('#dem-img').complete &&
    document.querySelector('#dem-img').naturalWidth > 0, {timeout: 30000});
}

// The terrain correction and verdict shown against the station's own files; the rig shown
// free again once the job gave it back.
async function checkResult(id) {
  await page.waitForFunction(() => document.querySelectorAll('#chips .chip.present').length >= 3,
    {timeout: 10000}).catch(() => failures.push(`${id}: the devices still shown in use`));
  const tc = readJson(path.join(args.stations, id, 'products/terrain_correction.json'));
  const shown = await page.$eval('#tc-value', (e) => ({text: e.textContent, value: e.dataset.value}));
  check(Number(shown.value) === tc.terrain_correction_mgal,
    `${id}: TC shown ${shown.value}, terrain_correction.json ${tc.terrain_correction_mgal}`);
  check(shown.text === tc.terrain_correction_mgal.toFixed(4), `${id}: TC text ${shown.text}`);
  const sigma = await page.$eval('#tc-sigma', (e) => Number(e.dataset.value));
  check(sigma === tc.sigma_mgal, `${id}: sigma shown ${sigma}, file ${tc.sigma_mgal}`);
  check(await page.$$eval('#rings tbody tr', (r) => r.length) === tc.rings.length,
    `${id}: ring table rows`);
  const station = await (await fetch(`${args.url}api/v1/stations/${id}`)).json();
  const verdict = await page.$eval('#verdict', (e) => e.textContent);
  check(verdict.length > 0 && verdict === station.assessment.text,
    `${id}: verdict shown '${verdict}', the station's '${station.assessment.text}'`);
  await screenshot(`${id}-result`);
}

// Sunlight: every visible text at least 7:1 against its background (WCAG AAA). Touch: every
// control at least 44 x 44 px (WCAG 2.5.5). Keyboard: Tab alone reaches the form, the start
// button and the history, each with a focus ring at least 3 px wide.
async function checkSunlightTouchKeyboard() {
  failures.push(...await page.evaluate(() => {
    const rgb = (c) => {
      const v = (c.match(/rgba?\(([^)]+)\)/) || [, '0,0,0,0'])[1].split(',').map(Number);
      return {r: v[0], g: v[1], b: v[2], a: v.length > 3 ? v[3] : 1};
    };
    const luminance = ({r, g, b}) => {
      const f = (x) => (x /= 255) <= 0.03928 ? x / 12.92 : ((x + 0.055) / 1.055) ** 2.4;
      return 0.2126 * f(r) + 0.7152 * f(g) + 0.0722 * f(b);
    };
    const background = (e) => {
      for (; e; e = e.parentElement) {
        const c = rgb(getComputedStyle(e).backgroundColor);
        if (c.a > 0) return c;
      }
      return {r: 255, g: 255, b: 255, a: 1};
    };
    const visible = (e) => e.getClientRects().length > 0;
    const found = [];
    for (const e of document.querySelectorAll('body *')) {
      const text = [...e.childNodes].some((n) => n.nodeType === 3 && n.textContent.trim());
      if (!text || !visible(e)) continue;
      const [hi, lo] = [luminance(rgb(getComputedStyle(e).color)), luminance(background(e))]
        .sort((x, y) => y - x);
      const ratio = (hi + 0.05) / (lo + 0.05);
      if (ratio < 7) found.push(`contrast ${ratio.toFixed(1)}:1: '${e.textContent.trim().slice(0, 40)}'`);
    }
    for (const e of document.querySelectorAll('button, input, textarea, a')) {
      const r = e.getBoundingClientRect();
      if (visible(e) && (r.width < 44 || r.height < 44))
        found.push(`${e.tagName} ${e.id || e.textContent.trim().slice(0, 20)}: ` +
          `${r.width.toFixed(0)} x ${r.height.toFixed(0)} px, under 44 px`);
    }
    return found;
  }));
  await page.evaluate(() => { document.activeElement.blur(); window.scrollTo(0, 0); });
  const reached = new Set();
  for (let i = 0; i < 60; ++i) {
    await page.keyboard.press('Tab');
    const focus = await page.evaluate(() => {
      const e = document.activeElement;
      if (e === document.body) return null;  // past the last control: the browser's own
      return {id: e.id || e.textContent.trim(), ring: parseFloat(getComputedStyle(e).outlineWidth)};
    });
    if (!focus) continue;
    reached.add(focus.id);
    check(focus.ring >= 3, `focus ring of '${focus.id}' is ${focus.ring} px`);
  }
  for (const id of ['station', 'height', 'start', 'S1', 'campaign-link'])
    check(reached.has(id), `Tab never reaches ${id} (reached: ${[...reached].join(', ')})`);
}

// The retake button runs exactly the retake its verdict names. S1's correction is edited as
// if the ground 20-30 m out toward 90° had gone unseen (a vehicle parked there): the verdict
// names the poses at pan 90°, the button takes them again, the station is processed anew.
async function retakeFromTheVerdict() {
  const file = path.join(args.stations, 'S1/products/terrain_correction.json');
  const tc = readJson(file);
  const sector = tc.rings.find((r) => r.inner_m === 20).sectors[3];
  Object.assign(sector, {coverage: 0.2, seen: 0.0, sigma_mgal: 2 * tc.sigma_mgal});
  tc.sigma_mgal = Math.hypot(tc.sigma_mgal, sector.sigma_mgal);
  fs.writeFileSync(file, JSON.stringify(tc));
  await page.click('#history tr[data-station="S1"] button');
  await page.waitForSelector('#retake:not([hidden])', {timeout: 30000});
  const named = (await (await fetch(`${args.url}api/v1/stations/S1`)).json()).assessment;
  check(named.verdict === 'retake' && named.retake.length > 0 &&
    named.retake.every((p) => Math.round(p.pan_deg) === 90), `verdict ${JSON.stringify(named)}`);
  check((await page.$eval('#verdict', (e) => e.textContent)) === named.text, 'verdict shown');
  await screenshot('S1-retake-offered');
  await page.click('#retake');
  await page.waitForSelector('#live-section:not([hidden])', {timeout: 30000});
  await page.waitForFunction((before) => !document.querySelector('#result-section').hidden &&
    document.querySelector('#verdict').textContent !== before, {timeout: RESULT_TIMEOUT},
    named.text);
  const jobs = await (await fetch(`${args.url}api/v1/jobs`)).json();
  const retake = jobs.find((j) => j.kind === 'retake');
  check(retake && retake.state === 'done' &&
    JSON.stringify(retake.parameters.poses) === JSON.stringify(named.retake),
    `retake job ${JSON.stringify(retake)} for ${JSON.stringify(named.retake)}`);
  await checkResult('S1');
}

async function survey() {
  await enterToken();
  await fillStation('S1');
  await screenshot('form');
  await startAndWaitForResult('S1');
  await checkResult('S1');
  await checkSunlightTouchKeyboard();
  await retakeFromTheVerdict();
  // The next station: its id counted on, the crew's fields kept.
  await page.reload({waitUntil: 'load'});
  const offered = await page.$eval('#station', (e) => e.value);
  check(offered === 'S2', `next station offered '${offered}', not S2`);
  check(await page.$eval('#line', (e) => e.value) === 'L7', 'line not kept for the next station');
  check(await page.$eval('#height', (e) => e.value) === '1.52', 'height not kept');
  await startAndWaitForResult('S2');
  await checkResult('S2');
  // Two epochs of the site compared from the history.
  await page.waitForFunction(() => document.querySelectorAll('#history tbody tr').length >= 2);
  for (const id of ['S1', 'S2']) await page.click(`#history tr[data-station="${id}"] input`);
  await page.click('#compare');
  await page.waitForFunction(() => document.querySelector('#dod-img').complete &&
    document.querySelector('#dod-img').naturalWidth > 0, {timeout: 60000});
  const change = readJson(path.join(args.diffs, 'S1--S2/change.json'));
  const summary = await page.$eval('#diff-summary', (e) => e.textContent);
  check(summary.includes(change.lowering.volume_m3.toFixed(2)),
    `diff summary '${summary}' lacks change.json's ${change.lowering.volume_m3}`);
  check(await page.$$eval('#subsidence tbody tr', (r) => r.length) ===
    change.subsidence_regions.length, 'subsidence table rows differ from change.json');
  await screenshot('compare');
  // Downloads: a zip per station, the campaign table.
  const zip = await page.evaluate(async () => {
    const a = document.querySelector('#history tr[data-station="S1"] a');
    const bytes = new Uint8Array(await (await fetch(a.href)).arrayBuffer());
    return [bytes.length, bytes[0], bytes[1]];
  });
  check(zip[0] > 1000 && zip[1] === 0x50 && zip[2] === 0x4b, `S1 zip: ${zip}`);
  const csv = await page.evaluate(async () =>
    (await fetch(document.querySelector('#campaign-link').href)).text());
  check(/\nS[12],L7,/.test(csv) && csv.trim().split('\n').length === 3, `campaign csv: ${csv}`);
  const gpkg = await page.evaluate(async () => {
    const href = document.querySelector('#campaign-gpkg-link').href;
    const bytes = new Uint8Array(await (await fetch(href)).arrayBuffer());
    return String.fromCharCode(...bytes.slice(0, 15));
  });
  check(gpkg === 'SQLite format 3', `campaign GeoPackage starts with '${gpkg}'`);
}

async function start() {
  await enterToken();
  await fillStation('R1');
  await page.click('#start');
  await page.waitForFunction(() => document.querySelectorAll('#ring .pose.done').length >= 2,
    {timeout: 60000});
  await screenshot('capturing');
}

async function resume() {
  await enterToken();  // a browser of its own: it asks for the token again
  await page.waitForSelector('#interrupted-section:not([hidden])', {timeout: 30000});
  await screenshot('interrupted');
  const button = await page.waitForSelector('#interrupted button');
  check((await button.evaluate((b) => b.textContent)).includes('R1'), 'resume button not for R1');
  await page.waitForFunction(() => !document.querySelector('#interrupted button').disabled &&
    document.querySelectorAll('#chips .chip.present').length >= 3, {timeout: 30000});
  await button.click();
  await page.waitForFunction(() => document.querySelector('#result-station').textContent === 'R1' &&
    !document.querySelector('#result-section').hidden, {timeout: RESULT_TIMEOUT});
  await checkResult('R1');
  check(await page.$eval('#interrupted-section', (e) => e.hidden), 'R1 still offered for resume');
}

try {
  await {survey, start, resume}[args.scenario]();
} catch (e) {
  failures.push(String(e.stack || e));
  await screenshot('failure').catch(() => {});
}
// The page's requests, every one of them answered.
failures.push(...bad);
await browser.close();
if (failures.length) {
  console.error(failures.join('\n'));
  process.exit(1);
}
console.log(`${args.scenario}: every check held`);
