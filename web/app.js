// The page of `slosh serve`: a format form, one plan or every candidate of `auto`, the plots of the
// selected plan against the uniform law and its robustness over the frequency error, the minimum
// motion time of the strategies ("How fast can it go?", POST v1/min-time) with η over T,
// downloads, a measured η(t) overlaid on the predicted one, and the URL as the shareable state. Every URL is relative, so the page also works
// behind a reverse proxy at a sub-path.

import { PLOTS, markersPlugin } from './plots.js';

Chart.register(markersPlugin);

const $ = (id) => document.getElementById(id);

// Form inputs and their URL parameter names.
const PARAMS = {
  radius: 'r', height: 'h', fill: 'fill', fluid: 'fluid', density: 'rho', viscosity: 'mu',
  stroke: 'stroke', time: 'T', strategy: 'strategy', a_max: 'a_max', v_max: 'v_max',
  j_max: 'j_max', eta_rest_max: 'eta_rest', rest_time: 'rest', p_notch: 'p_notch', band: 'band',
  tol_rel: 'tol_rel', min_ramp: 'min_ramp', shaper: 'shaper', base: 'base', time_limit: 'budget',
  n_band: 'n_band', objective: 'objective', eta_motion_max: 'eta_motion', residual: 'residual',
  iir_order: 'iir_order', iir_tau: 'iir_tau', iir_period: 'iir_period', solver: 'solver',
  t_max: 't_max', margin: 'margin', limit_model: 'limit_model', omega_error: 'omega_err',
  fill_min: 'fill_lo', fill_max: 'fill_hi', visc_min: 'mu_lo', visc_max: 'mu_hi',
};
// Parameters that only mean something for a custom fluid.
const CUSTOM_FLUID_PARAMS = new Set(['density', 'viscosity']);
// Options: input id -> [path inside options, is a number].
const OPTIONS = {
  a_max: ['limits.a_max', true], v_max: ['limits.v_max', true], j_max: ['limits.j_max', true],
  eta_rest_max: ['eta_rest_max_mm', true], rest_time: ['rest_time_s', true], p_notch: ['p_notch', true],
  band: ['band', true], tol_rel: ['tol_rel', true], min_ramp: ['min_ramp_s', true],
  shaper: ['shaper', false], base: ['base', false], time_limit: ['time_limit_s', true],
  n_band: ['n_band', true], objective: ['objective', false], eta_motion_max: ['eta_motion_max_mm', true],
  residual: ['residual', true], iir_order: ['iir_order', true], iir_tau: ['iir_tau', true],
  iir_period: ['iir_sample_period_s', true], solver: ['solver', false],
  omega_error: ['uncertainty.omega_error_pct', true],
};
// Ranges [min, max] of options, each from two inputs: given when either is (an empty end goes as
// null, and the API names that end).
const RANGES = {
  'uncertainty.fill_height_mm': ['fill_min', 'fill_max'],
  'uncertainty.viscosity_pa_s': ['visc_min', 'visc_max'],
};

// A min-time request takes the η limits at its top level, not in its options: the fields of its
// errors -> the data-field of the input that holds them.
const MIN_TIME_FIELDS = {
  eta_motion_max_mm: 'options.eta_motion_max_mm', eta_rest_max_mm: 'options.eta_rest_max_mm',
  strategies: 'strategy',
};

const state = {
  request: null, plans: {}, selected: null, charts: [],
  minTimeRequest: null, minTime: null, minTimeCharts: [],
  measured: null, plotContext: null, fluids: [],
  // The fetches of the latest request of each kind ('view': plan, compare, min-time; 'plots': the
  // series of the selected plan): a newer request aborts them, and an answer that arrives all the
  // same is dropped because its signal is aborted.
  aborts: {},
};
window.sloshPage = state;  // for the browser test and the curious

function number(id) {
  const text = $(id).value.trim();
  return text === '' ? undefined : Number(text);
}

// options at a dotted path ("limits.a_max", "uncertainty.omega_error_pct").
function setOption(options, path, value) {
  const keys = path.split('.');
  let at = options;
  for (const k of keys.slice(0, -1)) at = at[k] = at[k] || {};
  at[keys[keys.length - 1]] = value;
}

function buildRequest(strategy) {
  const container = { radius_mm: number('radius') };
  if (number('height') !== undefined) container.height_mm = number('height');
  const fluid = $('fluid').value === 'custom'
    ? { density_kg_m3: number('density'), viscosity_pa_s: number('viscosity') }
    : $('fluid').value;
  const options = {};
  for (const [id, [path, numeric]] of Object.entries(OPTIONS)) {
    const raw = $(id).value.trim();
    if (raw !== '') setOption(options, path, numeric ? Number(raw) : raw);
  }
  for (const [path, [lo, hi]] of Object.entries(RANGES)) {
    if (number(lo) === undefined && number(hi) === undefined) continue;
    setOption(options, path, [number(lo) ?? null, number(hi) ?? null]);
  }
  return {
    format: {
      container, fill_height_mm: number('fill'), fluid,
      stroke_mm: number('stroke'), motion_time_s: number('time'),
    },
    strategy,
    options,
  };
}

// The min-time request of the form: its format without the motion time, the η limits and the
// search's own inputs at the top level, the other options as for a plan, and the strategy chosen
// (none for auto: the service then searches every strategy but iir).
function buildMinTimeRequest() {
  const plan = buildRequest($('strategy').value);
  const { motion_time_s: _, ...format } = plan.format;
  const { eta_motion_max_mm: etaMotion, eta_rest_max_mm: etaRest, ...options } = plan.options;
  const request = { format };
  if (number('t_max') !== undefined) request.motion_time_max_s = number('t_max');
  if (etaMotion !== undefined) request.eta_motion_max_mm = etaMotion;
  if (number('margin') !== undefined) request.free_board_margin_mm = number('margin');
  if (etaRest !== undefined) request.eta_rest_max_mm = etaRest;
  if ($('limit_model').value) request.limit_model = $('limit_model').value;
  if (plan.strategy !== 'auto') request.strategies = [plan.strategy];
  request.options = options;
  return request;
}

function clearErrors() {
  for (const el of document.querySelectorAll('.field-error, .form-error')) el.textContent = '';
  for (const el of document.querySelectorAll('[aria-invalid]')) el.removeAttribute('aria-invalid');
}

// The API's error at the field its error.field names (the longest matching path), else at the form.
// aliases maps the fields of a request that differ from the inputs' data-field (min-time).
function showError(error, aliases = {}) {
  let field = error.field || '';
  for (const [from, to] of Object.entries(aliases)) {
    if (field === from || field.startsWith(from + '.') || field.startsWith(from + '[')) {
      field = to + field.slice(from.length);
    }
  }
  let best = null;
  for (const el of document.querySelectorAll('[data-field]')) {
    const f = el.dataset.field;
    if ((field === f || field.startsWith(f + '.') || field.startsWith(f + '[')) &&
        (!best || f.length > best.dataset.field.length)) best = el;
  }
  if (best) {
    best.setAttribute('aria-invalid', 'true');
    $(best.id + '-error').textContent = error.message;
    if (best.closest('details')) best.closest('details').open = true;
    if (best.closest('#custom-fluid')) $('custom-fluid').hidden = false;
    best.focus();
  } else {
    $('form-error').textContent = error.message;
  }
  $('status-line').textContent = `The service refused the request (${error.code}).`;
}

// Aborts the fetches of the latest request of `kind`; its answers, should they arrive all the same,
// are dropped by the code that awaits them (it checks its signal).
function cancel(kind) {
  if (state.aborts[kind]) state.aborts[kind].abort();
}

// A new request of `kind`: the previous one is cancelled; returns the new one's signal.
function freshSignal(kind) {
  cancel(kind);
  state.aborts[kind] = new AbortController();
  return state.aborts[kind].signal;
}

async function postJson(path, body, signal) {
  const res = await fetch(path, {
    method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body), signal,
  });
  const json = await res.json();
  if (!res.ok) throw Object.assign(new Error(json.error.message), { api: json.error });
  return json;
}

async function getJson(path, signal) {
  const res = await fetch(path, { signal });
  const json = await res.json();
  if (!res.ok) throw Object.assign(new Error(json.error.message), { api: json.error });
  return json;
}

function fmt(v, digits = 2) {
  return typeof v === 'number' && isFinite(v) ? v.toFixed(digits) : '—';
}

function rowOf(plan, chosen) {
  const p = plan.prediction, r = plan.reduction_pct, k = plan.kinematics;
  return [
    plan.strategy, plan.status, plan.law.type,
    fmt(p.nonlinear.eta_motion_mm), fmt(p.nonlinear.eta_rest_mm),
    fmt(p.linear.eta_motion_mm), fmt(p.linear.eta_rest_mm),
    fmt(r.motion, 1), fmt(r.rest, 1), fmt(k.a_max, 3), fmt(k.a_min, 3), fmt(k.j_peak, 1),
    (plan.warnings || []).join('; '),
  ].map((text, i) => ({ text, chosen: chosen && i === 0 }));
}

function renderTable(plans, chosenStrategy) {
  const body = $('candidates').querySelector('tbody');
  body.replaceChildren();
  for (const plan of plans) {
    const tr = document.createElement('tr');
    tr.dataset.strategy = plan.strategy;
    tr.tabIndex = 0;
    if (plan.strategy === chosenStrategy) tr.classList.add('chosen');
    for (const cell of rowOf(plan)) {
      const td = document.createElement('td');
      td.textContent = cell.text;
      tr.appendChild(td);
    }
    const select = () => selectPlan(plan.strategy);
    tr.addEventListener('click', select);
    tr.addEventListener('keydown', (e) => { if (e.key === 'Enter' || e.key === ' ') { e.preventDefault(); select(); } });
    body.appendChild(tr);
  }
  $('candidates').hidden = false;
}

// The series of a law on the plan's format and model (POST v1/simulate); a calibrated model
// (options.model) keeps its frequency scale and height gain.
function simulateRequest(plan, law) {
  const m = plan.model;
  const T = plan.format.motion_time_s;
  const options = { damping: m.damping === 'explicit' ? m.zeta : m.damping, alpha: m.alpha, modes: m.f_hz.length, min_ramp_s: 0.001 };
  if (m.calibration) options.model = m.calibration;
  return {
    format: plan.format,
    law,
    rest_time_s: plan.rest_time_s,
    options,
    sample_period_s: (T + plan.rest_time_s) / 2000,
  };
}

// What a measured series may hold: a wave height is millimetres to metres, a test run seconds to
// minutes; beyond these a value is a unit or export error, and Chart.js cannot scale an axis to
// ±1e308 (it throws or allocates without bound).
const MEASURED = { maxBytes: 8 << 20, maxSamples: 100000, etaMaxMm: 10000, tMaxS: 3600 };

// A decimal number as a measurement file writes it ("-0.5", "1e-3", ".5"); never hex, "Infinity"
// or an empty cell, which Number() would all accept.
const DECIMAL = /^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$/;

// The cells of one line: ';' separates them when the line holds one (and a decimal comma is then
// a decimal point, as spreadsheets of comma-decimal locales write it), else a tab, else ','.
// Splitting on any of them would read "0,5;10,0" as four values and keep two wrong ones.
function measuredCells(line) {
  if (line.includes(';')) return line.split(';').map((c) => c.trim().replace(',', '.'));
  return line.split(line.includes('\t') ? '\t' : ',').map((c) => c.trim());
}

function plural(n, word) {
  return `${n} ${word}${n === 1 ? '' : 's'}`;
}

// A measured wave height as CSV: one "t_s,eta_mm" pair a line (separated as measuredCells says),
// times increasing, |t_s| and |eta_mm| within MEASURED, at most MEASURED.maxSamples samples; the
// first non-blank line is a header when none of its cells starts like a number. Throws an Error naming the
// line, the value and the allowed range.
function parseMeasuredCsv(text) {
  const out = { t_s: [], eta_mm: [] };
  const lines = text.split(/\r?\n/);
  let first = true;
  lines.forEach((raw, i) => {
    const line = raw.trim();
    if (line === '') return;
    const cells = measuredCells(line);
    // A header names its columns: none of its cells starts like a number ("0x10" does).
    const header = first && !cells.some((c) => /^[+-]?\.?\d/.test(c));
    first = false;
    if (header) return;
    if (cells.length !== 2) {
      throw new Error(`line ${i + 1}: ${plural(cells.length, 'value')}, expected 2: t_s, eta_mm`);
    }
    ['t_s', 'eta_mm'].forEach((name, k) => {
      if (!DECIMAL.test(cells[k])) {
        throw new Error(`line ${i + 1}: ${name} = "${cells[k].slice(0, 40)}" is not a decimal number`);
      }
    });
    const t = Number(cells[0]), eta = Number(cells[1]);
    if (!Number.isFinite(t) || Math.abs(t) > MEASURED.tMaxS) {
      throw new Error(`line ${i + 1}: t_s = ${t} is outside [-${MEASURED.tMaxS}, ${MEASURED.tMaxS}] s`);
    }
    if (!Number.isFinite(eta) || Math.abs(eta) > MEASURED.etaMaxMm) {
      throw new Error(`line ${i + 1}: eta_mm = ${eta} is outside [-${MEASURED.etaMaxMm}, ${MEASURED.etaMaxMm}] mm`);
    }
    const n = out.t_s.length;
    if (n >= MEASURED.maxSamples) {
      throw new Error(`line ${i + 1}: more than ${MEASURED.maxSamples} samples`);
    }
    if (n > 0 && !(t > out.t_s[n - 1])) {
      throw new Error(`line ${i + 1}: t_s = ${t} is not after ${out.t_s[n - 1]}: times must increase`);
    }
    out.t_s.push(t);
    out.eta_mm.push(eta);
  });
  if (out.t_s.length < 2) throw new Error(`${plural(out.t_s.length, 'sample')}: at least 2 are needed`);
  return out;
}

async function loadMeasured() {
  const file = $('measured-csv').files[0];
  if (!file) return;
  try {
    if (file.size > MEASURED.maxBytes) {
      throw new Error(`${file.size} bytes: at most ${MEASURED.maxBytes} (${MEASURED.maxSamples} samples)`);
    }
    state.measured = parseMeasuredCsv(await file.text());
    $('measured-note').textContent = `${file.name}: ${state.measured.t_s.length} samples overlaid on η(t)`;
  } catch (e) {
    state.measured = null;
    $('measured-note').textContent = `${file.name} is not a series: ${e.message}`;
  }
  if (state.plotContext) renderPlots({ ...state.plotContext, measured: state.measured });
  document.body.dataset.measured = state.measured ? String(state.measured.t_s.length) : 'invalid';
}

async function selectPlan(strategy) {
  const plan = state.plans[strategy];
  if (!plan) return;  // a row of a view that has been replaced
  // The plots of this selection only: an earlier selection's series that answer later (the same
  // strategy of an earlier request, say) are aborted or dropped.
  const signal = freshSignal('plots');
  state.selected = strategy;
  for (const tr of $('candidates').querySelectorAll('tbody tr')) {
    tr.classList.toggle('selected', tr.dataset.strategy === strategy);
  }
  $('status-line').textContent = `${plan.strategy}: ${plan.status}. ${plan.message}`;
  $('download-json').href = URL.createObjectURL(new Blob([JSON.stringify(plan, null, 2)], { type: 'application/json' }));
  $('download-json').download = `plan-${plan.key}.json`;
  updateCamLink();
  $('downloads').hidden = false;
  let series, base;
  try {
    [series, base] = await Promise.all([
      postJson('v1/simulate', simulateRequest(plan, plan.law), signal),
      postJson('v1/simulate', simulateRequest(plan, { type: 'seven_segment_uniform' }), signal),
    ]);
  } catch (e) {
    if (signal.aborted) return;
    clearPlots();
    $('form-error').textContent = `The plots could not be computed: ${e.api ? e.api.message : e.message}`;
    return;
  }
  if (signal.aborted) return;  // a newer selection or request replaced this one
  state.plotContext = { plan, request: state.request, series: series.series, base: base.series, format: plan.format };
  renderPlots({ ...state.plotContext, measured: state.measured });
  document.body.dataset.ready = strategy;  // the browser test waits for this
}

// The cam table of a cached plan: optimal and acceptable plans directly, an infeasible one only as
// its best reachable law (said so); time-limited and failed plans are not cached (no link).
// A plan of the min-time view is not kept either (the service keeps the min-time answer only).
function updateCamLink() {
  const plan = state.plans[state.selected];
  if (!plan) return;
  const period = $('cam-period').value || '1';
  const link = $('download-cam');
  const fromMinTime = state.minTime !== null;
  const cached = !fromMinTime && ['optimal', 'acceptable', 'infeasible'].includes(plan.status);
  link.hidden = !cached;
  $('cam-period').disabled = !cached;
  if (fromMinTime) {
    $('cam-note').textContent = `No cam table: a plan of the min-time search is not kept by the service; plan ${plan.strategy} at T = ${plan.format.motion_time_s.toFixed(3)} s (Plan) for its cam table.`;
    return;
  }
  if (!cached) {
    $('cam-note').textContent = `No cam table: a ${plan.status} plan is not kept by the service; plan it with a larger time budget or use slosh export.`;
    return;
  }
  const force = plan.status === 'infeasible' ? '&allow_infeasible=true' : '';
  link.href = `v1/plans/${plan.key}/cam.csv?period_ms=${encodeURIComponent(period)}${force}`;
  link.download = `cam-${plan.key}-${period}ms.csv`;
  link.textContent = force ? 'Cam table CSV (infeasible plan: its best reachable law)' : 'Cam table CSV';
  $('cam-note').textContent = '';
}

// The period input as it is before a new period is read: unmarked, with no error under it.
function resetPeriodError() {
  $('cam-period').removeAttribute('aria-invalid');
  $('cam-period-error').textContent = '';
}

// A typed period the number input cannot read ("1e400", "--1", "5e"): the input then reports an
// empty value, which must not turn into the default period of 1 ms. Marks the input and says so;
// true when the period is unreadable.
function refuseUnreadablePeriod() {
  const period = $('cam-period');
  if (!period.validity.badInput) return false;
  period.setAttribute('aria-invalid', 'true');
  $('cam-period-error').textContent =
    'the period is not a number: type a decimal number of milliseconds, such as 1 or 0.5';
  $('cam-note').textContent = '';
  return true;
}

// The cam table through fetch, not a plain link: a refused period (the API's 422) is shown at the
// period input instead of being saved as the CSV file.
async function downloadCam(event) {
  event.preventDefault();
  const { href, download: name } = $('download-cam');  // the plan and period of this click
  const period = $('cam-period');
  resetPeriodError();
  if (refuseUnreadablePeriod()) return;  // nothing is fetched or saved
  $('cam-note').textContent = 'Preparing the cam table…';
  try {
    const res = await fetch(href);
    if (!res.ok) {
      const json = await res.json();
      period.setAttribute('aria-invalid', 'true');
      $('cam-period-error').textContent = json.error.message;
      $('cam-note').textContent = '';
      return;
    }
    const save = document.createElement('a');
    save.href = URL.createObjectURL(await res.blob());
    save.download = name;
    document.body.appendChild(save);
    save.click();
    save.remove();
    setTimeout(() => URL.revokeObjectURL(save.href), 60000);
    $('cam-note').textContent = `Saved ${name}`;
  } catch (e) {
    $('cam-note').textContent = `The cam table could not be downloaded: ${e.message}`;
  }
}

function clearPlots() {
  for (const chart of state.charts) chart.destroy();
  state.charts = [];
  $('plots').replaceChildren();
}

function clearMinTime() {
  for (const chart of state.minTimeCharts) chart.destroy();
  state.minTimeCharts = [];
  $('min-time-plots').replaceChildren();
  $('min-time-table').querySelector('tbody').replaceChildren();
  $('min-time-headline').textContent = '';
  $('min-time').hidden = true;
  state.minTime = null;
  state.minTimeRequest = null;
}

// Nothing of a previous view stays on screen once a new request starts.
function clearResults() {
  cancel('plots');  // the series still on their way are for a view that is gone
  state.plotContext = null;  // a measured series uploaded now has no plan to overlay
  clearPlots();
  clearMinTime();
  state.plans = {};
  state.selected = null;
  $('candidates').querySelector('tbody').replaceChildren();
  $('candidates').hidden = true;
  $('downloads').hidden = true;
}

// The plots of one view ('plan' or 'min-time') into its holder; returns the charts.
function renderPlots(context, view = 'plan', holder = $('plots')) {
  if (view === 'plan') clearPlots();
  const charts = [];
  for (const plot of PLOTS.filter((p) => p.view === view && (!p.when || p.when(context)))) {
    const box = document.createElement('div');
    box.className = 'plot';
    const title = document.createElement('h2');
    title.textContent = plot.title;
    const png = document.createElement('a');
    png.textContent = 'PNG';
    png.href = '#';
    png.download = `${plot.id}.png`;
    title.appendChild(png);
    const wrap = document.createElement('div');
    wrap.style.height = '260px';
    const canvas = document.createElement('canvas');
    canvas.id = `plot-${plot.id}`;
    canvas.setAttribute('role', 'img');
    canvas.setAttribute('aria-label', plot.title);
    wrap.appendChild(canvas);
    box.append(title, wrap);
    holder.appendChild(box);
    // One plot that cannot be drawn (Chart.js throws on an axis it cannot scale, say) costs that
    // plot only: its chart is destroyed (Chart.js registers it before drawing) and the box says why.
    try {
      const chart = new Chart(canvas, plot.build(context));
      charts.push(chart);
      png.addEventListener('click', () => { png.href = chart.toBase64Image('image/png', 1); });
    } catch (e) {
      const broken = Chart.getChart(canvas);
      if (broken) broken.destroy();
      wrap.replaceChildren();
      const note = document.createElement('p');
      note.className = 'plot-error';
      note.setAttribute('role', 'alert');
      note.textContent = `This plot could not be drawn: ${e.message}`;
      wrap.appendChild(note);
      png.remove();
    }
  }
  if (view === 'plan') state.charts = charts;
  return charts;
}

function writeUrl(extra) {
  const q = new URLSearchParams();
  for (const [id, key] of Object.entries(PARAMS)) {
    if (CUSTOM_FLUID_PARAMS.has(id) && $('fluid').value !== 'custom') continue;
    const v = $(id).value.trim();
    if (v !== '') q.set(key, v);
  }
  for (const [k, v] of Object.entries(extra || {})) q.set(k, v);
  history.replaceState(null, '', `?${q.toString()}`);
  $('share-link').href = location.href;
}

// The form from the URL; a value the form cannot hold (an unknown fluid or strategy, text in a
// number field) is named in the form error instead of being dropped.
function readUrl() {
  const q = new URLSearchParams(location.search);
  let any = false;
  const refused = [];
  for (const [id, key] of Object.entries(PARAMS)) {
    if (!q.has(key)) continue;
    const wanted = q.get(key);
    $(id).value = wanted;
    if ($(id).value !== wanted) refused.push(`${key}=${wanted.slice(0, 40)}`);
    any = true;
  }
  $('custom-fluid').hidden = $('fluid').value !== 'custom';
  if (refused.length) {
    $('form-error').textContent = `The link holds values this form cannot take: ${refused.join(', ')}. Check the form and plan again.`;
    return { any: false, compare: false, minTime: false, key: q.get('key') };
  }
  return { any, compare: q.get('compare') === '1', minTime: q.get('mintime') === '1', key: q.get('key') };
}

// The form from a plan opened by its key (its format and uncertainty; the other options are not
// part of a plan).
function fillFormFromPlan(plan) {
  const f = plan.format;
  $('radius').value = f.container.radius_mm;
  $('height').value = f.container.height_mm ?? '';
  $('fill').value = f.fill_height_mm;
  $('stroke').value = f.stroke_mm;
  $('time').value = f.motion_time_s;
  // A catalogue fluid only when its properties are the catalogue entry's: a custom fluid may carry
  // a catalogue name ({"name": "water", "density_kg_m3": 1260, ...}), and refilled as catalogue
  // water it would be replanned with water's density.
  const entry = state.fluids.find((c) => c.name === f.fluid.name);
  // (Every catalogue entry is an option of the fluid select: loadFluids adds them all.)
  const known = entry !== undefined && entry.density_kg_m3 === f.fluid.density_kg_m3 &&
    entry.viscosity_pa_s === f.fluid.viscosity_pa_s;
  $('fluid').value = known ? f.fluid.name : 'custom';
  $('density').value = f.fluid.density_kg_m3;
  $('viscosity').value = f.fluid.viscosity_pa_s;
  $('custom-fluid').hidden = $('fluid').value !== 'custom';
  if ([...$('strategy').options].some((o) => o.value === plan.strategy)) $('strategy').value = plan.strategy;
  // The uncertainty the plan was made for (the plan echoes it).
  const u = plan.uncertainty || {};
  $('omega_error').value = u.omega_error_pct ? u.omega_error_pct : '';
  [$('fill_min').value, $('fill_max').value] = u.fill_height_mm || ['', ''];
  [$('visc_min').value, $('visc_max').value] = u.viscosity_pa_s || ['', ''];
}

async function run(compare) {
  clearErrors();
  const strategy = compare ? 'auto' : $('strategy').value;
  const signal = freshSignal('view');
  state.request = buildRequest(strategy);
  clearResults();
  delete document.body.dataset.ready;
  writeUrl(compare ? { compare: '1' } : {});
  $('status-line').textContent = compare ? 'Planning every strategy…' : `Planning ${strategy}…`;
  try {
    const first = await postJson('v1/plans', state.request, signal);
    if (signal.aborted) return;  // a newer request replaced this view
    if (!compare) {
      state.plans[first.strategy] = first;
      renderTable([first], first.strategy);
      return selectPlan(first.strategy);
    }
    // Every candidate of auto as a plan of its own (its kinematics, warnings and law in full).
    const names = first.candidates.map((c) => c.strategy);
    const chosen = (first.candidates.find((c) => c.chosen) || {}).strategy;
    const plans = await Promise.all(names.map((s) => postJson('v1/plans', { ...state.request, strategy: s }, signal)));
    if (signal.aborted) return;
    for (const p of plans) state.plans[p.strategy] = p;
    renderTable(plans, chosen);
    // Why auto did not return a row: its reason with the deciding figures, on hover.
    for (const c of first.candidates) {
      const tr = $('candidates').querySelector(`tbody tr[data-strategy="${c.strategy}"]`);
      if (tr && c.reason_detail) tr.title = `auto did not choose it: ${c.reason_detail}`;
    }
    return selectPlan(chosen || names[0]);
  } catch (e) {
    if (signal.aborted) return;
    if (e.api) showError(e.api); else $('form-error').textContent = String(e);
  }
}

// The η of a min-time curve point at the strategy's T_min, on the model the limits apply to.
function etaAtTMin(s, quantity, model) {
  const i = s.t_min_s === null ? -1 : s.curve.t_s.indexOf(s.t_min_s);
  if (i < 0) return undefined;
  const nl = s.curve.nonlinear[quantity][i], lin = s.curve.linear[quantity][i];
  return model === 'linear' ? lin : model === 'both' ? Math.max(nl, lin) : nl;
}

function minTimeRow(s, model) {
  const feasibleAbove = s.feasible_above === null ? '—' : s.feasible_above ? 'yes' : 'no';
  return [
    s.strategy, s.status, fmt(s.t_min_s, 3), fmt(s.t_min_s === null ? null : 60 / s.t_min_s, 1),
    feasibleAbove, fmt(etaAtTMin(s, 'eta_motion_mm', model)), fmt(etaAtTMin(s, 'eta_rest_mm', model)),
    String(s.plans),
  ];
}

function signed(v, digits) {
  return (v >= 0 ? '+' : '') + v.toFixed(digits);
}

// The answer in one sentence: the winner, its T_min and its gain over the uniform law.
function minTimeHeadline(m) {
  const h = m.headline;
  if (!h.winner) return `No strategy meets the limits with a motion time up to ${m.motion_time_max_s} s.`;
  let text = `Fastest: ${h.winner}, T_min ${h.t_min_s.toFixed(3)} s (${h.cycles_per_min.toFixed(1)} cycles/min)`;
  if (h.gain_pct !== null) {
    text += `: ${signed(h.gain_pct, 1)} % (${signed(h.gain_cycles_per_min, 1)} cycles/min) vs the uniform law` +
      ` (baseline, T_min ${h.baseline_t_min_s.toFixed(3)} s, ${h.baseline_cycles_per_min.toFixed(1)} cycles/min).`;
  } else if (m.strategies.some((s) => s.strategy === 'baseline')) {
    text += '; the uniform law (baseline) meets the limits nowhere in the search: no gain to give.';
  } else {
    text += '; the uniform law (baseline) was not searched: no gain to give.';
  }
  return text;
}

function renderMinTime(m) {
  const model = m.limits.model;
  const body = $('min-time-table').querySelector('tbody');
  body.replaceChildren();
  for (const s of m.strategies) {
    const tr = document.createElement('tr');
    tr.dataset.strategy = s.strategy;
    tr.tabIndex = 0;
    tr.title = s.message;
    if (s.strategy === m.headline.winner) tr.classList.add('winner');
    for (const text of minTimeRow(s, model)) {
      const td = document.createElement('td');
      td.textContent = text;
      tr.appendChild(td);
    }
    const select = () => selectMinTimePlan(s.strategy);
    tr.addEventListener('click', select);
    tr.addEventListener('keydown', (e) => { if (e.key === 'Enter' || e.key === ' ') { e.preventDefault(); select(); } });
    body.appendChild(tr);
  }
  $('min-time-headline').textContent = minTimeHeadline(m);
  const l = m.limits;
  const scanStart = Math.min(...m.strategies.map((s) => s.scan_start_s));
  $('status-line').textContent = `Limits: η motion ≤ ${l.eta_motion_max_mm.toFixed(1)} mm, η rest ≤ ` +
    `${l.eta_rest_max_mm.toFixed(1)} mm over ${l.rest_time_s} s (${model} model); T searched from ` +
    `${scanStart.toFixed(3)} s (kinematic bound ${m.kinematic_lower_bound_s.toFixed(3)} s) up to ` +
    `${m.motion_time_max_s} s on a 1 ms grid.`;
  $('min-time').hidden = false;
  state.minTimeCharts = renderPlots({ minTime: m }, 'min-time', $('min-time-plots'));
}

// A row of the min-time table: its plan at T_min (the response holds it whole) in the plan view.
function selectMinTimePlan(strategy) {
  const s = state.minTime && state.minTime.strategies.find((x) => x.strategy === strategy);
  if (!s || !s.plan) return;
  for (const tr of $('min-time-table').querySelectorAll('tbody tr')) {
    tr.classList.toggle('selected', tr.dataset.strategy === strategy);
  }
  state.plans = { [strategy]: s.plan };
  state.request = null;
  renderTable([s.plan], strategy);
  return selectPlan(strategy);
}

async function runMinTime() {
  clearErrors();
  const signal = freshSignal('view');
  const request = buildMinTimeRequest();
  state.request = null;
  clearResults();
  delete document.body.dataset.ready;
  delete document.body.dataset.minTime;
  writeUrl({ mintime: '1' });
  const which = request.strategies ? request.strategies[0] : 'every strategy but iir';
  $('status-line').textContent = `Searching the shortest motion time of ${which}…`;
  try {
    const response = await postJson('v1/min-time', request, signal);
    if (signal.aborted) return;  // a newer request replaced this view
    state.minTimeRequest = request;
    state.minTime = response;
    renderMinTime(response);
    document.body.dataset.minTime = 'ready';  // the browser test waits for this
  } catch (e) {
    if (signal.aborted) return;
    if (e.api) showError(e.api, MIN_TIME_FIELDS); else $('form-error').textContent = String(e);
  }
}

async function openKey(key) {
  // A view request like run and runMinTime: a newer one aborts it, and a late answer is dropped
  // (it would refill the form and the results over the newer plan).
  const signal = freshSignal('view');
  try {
    const plan = await getJson(`v1/plans/${encodeURIComponent(key)}`, signal);
    if (signal.aborted) return;  // a newer request replaced this view
    fillFormFromPlan(plan);
    state.request = { format: plan.format, strategy: plan.strategy, options: {} };
    state.plans = { [plan.strategy]: plan };
    history.replaceState(null, '', `?key=${encodeURIComponent(plan.key)}`);
    $('share-link').href = location.href;
    renderTable([plan], plan.strategy);
    await selectPlan(plan.strategy);
  } catch (e) {
    if (signal.aborted) return;
    $('form-error').textContent = e.api ? e.api.message : String(e);
  }
}

async function loadFluids() {
  try {
    const { fluids } = await getJson('v1/fluids');
    state.fluids = fluids;
    const select = $('fluid');
    const current = select.value;
    select.replaceChildren();
    for (const f of fluids) select.add(new Option(`${f.name} (${f.density_kg_m3} kg/m³)`, f.name));
    select.add(new Option('custom…', 'custom'));
    select.value = current;
  } catch (e) {
    $('form-error').textContent = `The fluid catalogue could not be loaded: ${e.message}`;
  }
}

async function main() {
  await loadFluids();
  $('fluid').addEventListener('change', () => { $('custom-fluid').hidden = $('fluid').value !== 'custom'; });
  $('format-form').addEventListener('submit', (e) => { e.preventDefault(); run(false); });
  $('compare-button').addEventListener('click', () => run(true));
  $('min-time-button').addEventListener('click', runMinTime);
  $('cam-period').addEventListener('input', () => {
    resetPeriodError();
    updateCamLink();
    refuseUnreadablePeriod();
  });
  $('download-cam').addEventListener('click', downloadCam);
  $('measured-csv').addEventListener('change', loadMeasured);
  const url = readUrl();
  document.body.dataset.loaded = '1';
  if (url.key) return openKey(url.key);
  if (url.any) return url.minTime ? runMinTime() : run(url.compare);
}

main();
