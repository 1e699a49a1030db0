// The operator's page: devices, the station form, the capture going round, the result with
// its verdict, the history and the comparison of two epochs. Plain DOM, no framework and
// nothing fetched from elsewhere: the page works offline on the tripod's network.
'use strict';

const API = '/api/v1';
const TOKEN_KEY = 'topostation.token';
const LAST_KEY = 'topostation.last-station';
const $ = (id) => document.getElementById(id);

let current = null;      // the rig job shown live: {id, station, kind}
let shownStation = null; // the station whose result is shown
let plan = [];           // its capture plan [{pan_deg, tilt_deg}]
let captured = new Set();  // plan indices with a pair on disk
let lastPairsDone = -1;
const ended = new Set();  // jobs whose end was seen: a late progress event must not revive them
const FINAL = ['done', 'failed', 'cancelled', 'interrupted'];

// ---- talking to the daemon -------------------------------------------------------------

function token() { return localStorage.getItem(TOKEN_KEY) || ''; }

function say(text) { $('message').textContent = text || ''; }

async function api(method, path, body) {
  const headers = {};
  if (method !== 'GET') {
    headers['Authorization'] = 'Bearer ' + token();
    headers['Content-Type'] = 'application/json';
    headers['Idempotency-Key'] = crypto.getRandomValues(new Uint32Array(4)).join('-');
  }
  const res = await fetch(API + path, {method, headers,
    body: body === undefined ? undefined : JSON.stringify(body)});
  const data = res.headers.get('Content-Type') === 'application/json' ? await res.json() : null;
  if (res.status === 401) {
    localStorage.removeItem(TOKEN_KEY);
    $('token-section').hidden = false;
    $('token').focus();
  }
  if (!res.ok) throw new Error((data && data.error) || (method + ' ' + path + ': ' + res.status));
  return data;
}

function fixed(v, digits) {
  return typeof v === 'number' && isFinite(v) ? v.toFixed(digits) : '–';
}

function el(tag, attrs, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) {
    if (k === 'class') e.className = v; else if (k in e) e[k] = v; else e.setAttribute(k, v);
  }
  for (const c of children) e.append(c instanceof Node ? c : String(c));
  return e;
}

// ---- devices ---------------------------------------------------------------------------

const DEVICE_NAMES = {left_camera: 'left camera', right_camera: 'right camera', stage: 'stage',
  gnss: 'GNSS'};

function renderChips(status) {
  const chips = $('chips');
  chips.replaceChildren();
  for (const [key, d] of Object.entries(status.devices || {})) {
    const state = d.state.replace('_', ' ');
    const chip = el('li', {class: 'chip ' + d.state, id: 'chip-' + key,
      title: d.device || ''}, (DEVICE_NAMES[key] || key) + ': ' + state);
    if (d.reason) chip.append(el('span', {class: 'reason'}, ' – ' + d.reason));
    chips.append(chip);
  }
  const gib = (status.disk_free_bytes || 0) / 2 ** 30;
  chips.append(el('li', {class: 'chip ' + (gib < 1 ? 'bad' : gib < 5 ? 'warn' : 'ok'),
    id: 'chip-disk'}, 'disk: ' + gib.toFixed(1) + ' GiB free'));
}

function applyStatus(status) {
  renderChips(status);
  const job = status.current_job && !FINAL.includes(status.current_job.state) ?
    status.current_job : null;
  let why = status.ready ? '' : status.not_ready_because;
  if (job && job.id) why = 'job ' + job.id + ' (' + job.kind + ' of ' + job.station + ') is ' +
    job.state;
  if (!token()) why = why || 'enter the token first';
  $('start').disabled = Boolean(why);
  $('why-not').textContent = why;
  if (job && job.id && ['survey', 'capture', 'retake'].includes(job.kind)) showLive(job);
}

async function refreshStatus() {
  try { applyStatus(await api('GET', '/status')); } catch (e) { say(e.message); }
}

// ---- the station form ------------------------------------------------------------------

// G-0412 -> G-0413, keeping the zero padding; a name without a number is kept.
function nextStationId(id) {
  const m = /^(.*?)(\d+)$/.exec(id || '');
  if (!m) return id || '';
  const n = String(Number(m[2]) + 1).padStart(m[2].length, '0');
  return m[1] + n;
}

function offerPreviousStation() {
  const last = JSON.parse(localStorage.getItem(LAST_KEY) || 'null');
  if (!last) return;
  $('station').value = nextStationId(last.station);
  for (const [id, key] of [['line', 'line'], ['height', 'instrument_height_m'],
    ['operator', 'operator'], ['required-sigma', 'required_sigma_mgal']])
    if (last[key] !== undefined) $(id).value = last[key];
}

function stationRequest() {
  const r = {kind: 'survey', station: $('station').value.trim(),
    instrument_height_m: Number($('height').value),
    required_sigma_mgal: Number($('required-sigma').value)};
  for (const [id, key] of [['line', 'line'], ['operator', 'operator'], ['notes', 'notes']])
    if ($(id).value.trim()) r[key] = $(id).value.trim();
  if ($('lat').value !== '' && $('lon').value !== '') {
    r.gnss = {lat_deg: Number($('lat').value), lon_deg: Number($('lon').value)};
    if ($('gnss-height').value !== '') r.gnss.height_m = Number($('gnss-height').value);
  }
  return r;
}

async function startSurvey(event) {
  event.preventDefault();
  say('');
  const request = stationRequest();
  try {
    const job = await api('POST', '/jobs', request);
    localStorage.setItem(LAST_KEY, JSON.stringify(request));
    showLive(job);
  } catch (e) { say('Cannot start: ' + e.message); }
}

// ---- live capture ----------------------------------------------------------------------

function showLive(job) {
  if (!current || current.id !== job.id) {
    current = {id: job.id, station: job.station, kind: job.kind};
    plan = []; captured = new Set(); lastPairsDone = -1;
    $('thumbs').replaceChildren();
    $('live-station').textContent = job.station;
    drawRing(-1);  // the plan comes with the first progress: the manifest exists by then
  }
  $('live-section').hidden = false;
  $('phase').textContent = job.state + (job.step ? ': ' + job.step : '');
}

async function loadPlan(station) {
  try {
    const s = await api('GET', '/stations/' + encodeURIComponent(station));
    const m = s.manifest || {};
    plan = m.capture_plan || [];
    for (const p of m.pairs || []) {
      if (!captured.has(p.index)) addThumb(station, p.index);
      captured.add(p.index);
    }
    drawRing(-1);
  } catch (e) { /* the station directory is created with the first pair */ }
}

function drawRing(currentPair) {
  const ring = $('ring');
  ring.replaceChildren();
  const lowest = Math.min(...plan.map((p) => p.tilt_deg));
  plan.forEach((p, i) => {
    const r = p.tilt_deg > lowest + 0.5 ? 50 : 88;  // upper poses inside the row
    const a = p.pan_deg * Math.PI / 180;            // clockwise from north, as the stage pans
    const x = r * Math.sin(a), y = -r * Math.cos(a);
    const state = captured.has(i) ? ' done' : i === currentPair ? ' current' : '';
    const c = document.createElementNS('http://www.w3.org/2000/svg', 'circle');
    c.setAttribute('cx', x); c.setAttribute('cy', y); c.setAttribute('r', 13);
    c.setAttribute('class', 'pose' + state);
    c.setAttribute('data-pair', i);
    const t = document.createElementNS('http://www.w3.org/2000/svg', 'title');
    t.textContent = 'pair ' + i + ': pan ' + p.pan_deg.toFixed(0) + '°, tilt ' +
      p.tilt_deg.toFixed(1) + '°' + (state ? ' (' + state.trim() + ')' : '');
    c.append(t);
    ring.append(c);
  });
  const label = document.createElementNS('http://www.w3.org/2000/svg', 'text');
  label.textContent = captured.size + '/' + plan.length;
  ring.append(label);
}

function addThumb(station, index) {
  const src = API + '/stations/' + encodeURIComponent(station) + '/pairs/' + index;
  $('thumbs').append(el('figure', {},
    el('img', {src: src + '/left.jpg', alt: 'pair ' + index + ' left', loading: 'lazy'}),
    el('img', {src: src + '/right.jpg', alt: 'pair ' + index + ' right', loading: 'lazy'}),
    el('figcaption', {}, 'pair ' + index)));
}

function onProgress(p) {
  if (ended.has(p.id)) return;
  if (!current || p.id !== current.id) showLive(p);
  $('pairs').textContent = (p.pairs_done ?? 0) + ' of ' + (p.pairs_total ?? '–');
  $('angles').textContent = 'pan ' + fixed(p.pan_deg, 1) + '°, tilt ' + fixed(p.tilt_deg, 1) + '°';
  $('exposure').textContent = fixed(p.exposure_us / 1000, 2) + ' ms';
  $('time-left').textContent = typeof p.time_left_s === 'number' ?
    Math.ceil(p.time_left_s) + ' s' : '–';
  $('phase').textContent = p.state + (p.step ? ': ' + p.step : '');
  if ((p.pairs_done ?? 0) !== lastPairsDone || (p.pairs_total ?? 0) !== plan.length) {
    lastPairsDone = p.pairs_done ?? 0;
    loadPlan(p.station);
  } else {
    drawRing(p.pair ?? -1);
  }
}

async function cancelJob() {
  if (!current) return;
  try { await api('POST', '/jobs/' + current.id + '/cancel'); } catch (e) { say(e.message); }
}

// ---- jobs ending, interrupted jobs -----------------------------------------------------

function onJob(job) {
  if (!FINAL.includes(job.state)) ended.delete(job.id);  // resumed: the same job again
  const rigKind = ['survey', 'capture', 'retake'].includes(job.kind);
  if (rigKind && ['queued', 'capturing', 'processing'].includes(job.state)) showLive(job);
  if (FINAL.includes(job.state)) {
    ended.add(job.id);
    if (current && current.id === job.id) {
      $('live-section').hidden = true;
      current = null;
    }
    if (job.state === 'failed') say('Job ' + job.id + ' (' + job.station + ') failed: ' + job.error);
    if (job.state === 'done' && ['survey', 'process', 'retake'].includes(job.kind))
      showResult(job.station);
    refreshHistory();
    refreshInterrupted();
  }
  refreshStatus();
}

async function refreshInterrupted() {
  try {
    const jobs = (await api('GET', '/jobs')).filter((j) => j.state === 'interrupted');
    const list = $('interrupted');
    list.replaceChildren();
    for (const j of jobs) {
      const button = el('button', {type: 'button', class: 'primary', id: 'resume-' + j.id},
        'Resume ' + j.station);
      button.addEventListener('click', async () => {
        try {
          ended.delete(j.id);
          showLive(await api('POST', '/jobs/' + j.id + '/resume'));
          refreshInterrupted();
        }
        catch (e) { say('Cannot resume: ' + e.message); }
      });
      list.append(el('li', {}, j.kind + ' of ' + j.station + ' (job ' + j.id + '): ' +
        (j.error || 'interrupted') + ' ', button));
    }
    $('interrupted-section').hidden = jobs.length === 0;
  } catch (e) { say(e.message); }
}

// ---- the result ------------------------------------------------------------------------

async function showResult(station) {
  let s;
  try { s = await api('GET', '/stations/' + encodeURIComponent(station)); }
  catch (e) { say(e.message); return; }
  shownStation = station;
  const tc = s.terrain_correction || {};
  const assessment = s.assessment || {};
  $('result-section').hidden = false;
  $('result-station').textContent = station;
  const value = $('tc-value');
  value.textContent = fixed(tc.terrain_correction_mgal, 4);
  value.dataset.value = tc.terrain_correction_mgal ?? '';
  $('tc-sigma').textContent = fixed(tc.sigma_mgal, 4);
  $('tc-sigma').dataset.value = tc.sigma_mgal ?? '';
  $('tc-density').textContent = tc.density_g_cm3 ? '(density ' + tc.density_g_cm3 + ' g/cm³)' : '';
  const verdict = $('verdict');
  verdict.textContent = assessment.text || '';
  verdict.className = 'verdict ' + (assessment.verdict || '').replace(/ /g, '-');
  const retake = $('retake');
  retake.hidden = !(assessment.retake && assessment.retake.length);
  retake.textContent = 'Retake ' + (assessment.retake || []).map((p) =>
    'pan ' + p.pan_deg.toFixed(0) + '° tilt ' + p.tilt_deg.toFixed(1) + '°').join(', ');
  const body = $('rings').tBodies[0];
  body.replaceChildren();
  for (const r of tc.rings || [])
    body.append(el('tr', {}, el('td', {}, r.inner_m + '–' + (typeof r.outer_m === 'number' ?
      r.outer_m : 'end')), el('td', {}, fixed(r.mgal, 4)), el('td', {}, fixed(r.sigma_mgal, 4)),
      el('td', {}, fixed(r.sigma_unseen_mgal, 4)), el('td', {}, fixed(100 * r.coverage, 0) + ' %')));
  const warnings = $('warnings');
  warnings.replaceChildren();
  for (const w of (s.report && s.report.warnings) || []) warnings.append(el('li', {}, w));
  const products = API + '/stations/' + encodeURIComponent(station) + '/products/';
  const stamp = '?t=' + Date.now();
  const has = (name) => (s.products || []).includes(name);
  $('dem-img').src = has('dem.png') ? products + 'dem.png' + stamp : '';
  $('panorama-img').src = has('panorama.png') ? products + 'panorama.png' + stamp : '';
}

async function retake() {
  if (!shownStation) return;
  const s = await api('GET', '/stations/' + encodeURIComponent(shownStation));
  const poses = (s.assessment && s.assessment.retake) || [];
  try {
    showLive(await api('POST', '/jobs', {kind: 'retake', station: shownStation, poses}));
  } catch (e) { say('Cannot retake: ' + e.message); }
}

// ---- history and the comparison of two epochs -------------------------------------------

async function refreshHistory() {
  let stations;
  try { stations = await api('GET', '/stations'); } catch (e) { say(e.message); return; }
  const body = $('history').tBodies[0];
  body.replaceChildren();
  for (const s of stations) {
    const tick = el('input', {type: 'checkbox', value: s.id, 'aria-label': 'compare ' + s.id,
      'data-created': s.created_utc || ''});
    tick.addEventListener('change', updateCompare);
    const open = el('button', {type: 'button'}, s.id);
    open.addEventListener('click', () => showResult(s.id));
    const verdict = (s.assessment && s.assessment.verdict) || (s.processed ? '' : 'not processed');
    body.append(el('tr', {'data-station': s.id}, el('td', {}, tick), el('td', {}, open),
      el('td', {}, (s.created_utc || '').replace('T', ' ').replace(/\.\d+Z$/, 'Z')),
      el('td', {}, fixed(s.terrain_correction_mgal, 4) + ' ± ' +
        fixed(s.terrain_correction_sigma_mgal, 4)),
      el('td', {}, verdict),
      el('td', {}, el('a', {href: API + '/stations/' + encodeURIComponent(s.id) +
        '/station.zip', download: s.id + '.zip'}, 'zip'))));
  }
  updateCompare();
}

function ticked() {
  return [...document.querySelectorAll('#history tbody input:checked')];
}

function updateCompare() { $('compare').disabled = ticked().length !== 2; }

async function compare() {
  const [a, b] = ticked().sort((x, y) => x.dataset.created.localeCompare(y.dataset.created));
  say('');
  let d;
  try { d = await api('POST', '/diffs', {before: a.value, after: b.value}); }
  catch (e) { say('Cannot compare: ' + e.message); return; }
  const c = d.change;
  $('diff').hidden = false;
  $('diff-title').textContent = a.value + ' → ' + b.value;
  const max = c.max_subsidence;
  $('diff-summary').textContent = 'Lowering ' + fixed(c.lowering.volume_m3, 2) + ' ± ' +
    fixed(c.lowering.sigma_m3, 2) + ' m³ over ' + fixed(c.lowering.area_m2, 0) + ' m²; ' +
    (max ? 'deepest ' + fixed(max.depth_m, 3) + ' ± ' + fixed(max.sigma_m, 3) + ' m' :
      'no significant subsidence');
  const body = $('subsidence').tBodies[0];
  body.replaceChildren();
  for (const r of c.subsidence_regions || [])
    body.append(el('tr', {}, el('td', {}, r.id), el('td', {}, fixed(r.area_m2, 0)),
      el('td', {}, fixed(r.volume_m3, 2) + ' ± ' + fixed(r.sigma_m3, 2)),
      el('td', {}, fixed(r.max_depth_m, 3) + ' ± ' + fixed(r.max_depth_sigma_m, 3))));
  $('dod-img').src = API + '/diffs/' + encodeURIComponent(d.id) + '/dod.png?t=' + Date.now();
}

// ---- events ----------------------------------------------------------------------------

function listen() {
  const events = new EventSource(API + '/events');
  events.addEventListener('open', () => {
    $('connection').textContent = 'connected';
    $('connection').className = 'chip ok';
  });
  events.addEventListener('error', () => {
    $('connection').textContent = 'reconnecting…';
    $('connection').className = 'chip bad';
  });
  events.addEventListener('snapshot', (e) => applyStatus(JSON.parse(e.data).status));
  events.addEventListener('devices', () => refreshStatus());
  events.addEventListener('job', (e) => onJob(JSON.parse(e.data)));
  events.addEventListener('progress', (e) => onProgress(JSON.parse(e.data)));
}

function init() {
  $('token-section').hidden = Boolean(token());
  $('token-form').addEventListener('submit', (e) => {
    e.preventDefault();
    localStorage.setItem(TOKEN_KEY, $('token').value.trim());
    $('token-section').hidden = true;
    refreshStatus();
  });
  $('station-form').addEventListener('submit', startSurvey);
  $('cancel').addEventListener('click', cancelJob);
  $('retake').addEventListener('click', retake);
  $('compare').addEventListener('click', compare);
  offerPreviousStation();
  listen();
  refreshStatus();
  refreshHistory();
  refreshInterrupted();
}

init();
