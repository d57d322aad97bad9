// The page of `slosh serve`: a format form, one plan or every candidate of `auto`, the plots of the
// selected plan against the uniform law and its robustness over the frequency error, the minimum
// motion time of the strategies ("How fast can it go?", POST v1/min-time) with η over T,
// downloads, a measured η(t) overlaid on the predicted one, and the URL as the shareable state.
// A motion along an arc or a path (format.motion, SPEC §14) and a rectangular container (SPEC
// §15) are drawn from above (motion-view.js): the path, the container's heading and the wall
// direction of the peak wave, from the plan's planar peaks (or a planar simulation of its law).
// This module runs the requests of the views; form.js builds them from the form, url.js keeps
// the URL, api.js sends them, view.js, min-time.js, downloads.js, measured.js and motion-view.js
// draw the answers.

import { Latest, requestJson } from './api.js';
import { $, markSelectedRow } from './dom.js';
import { downloadCam, periodTyped, showDownloads } from './downloads.js';
import {
  MIN_TIME, PLAN, clearErrors, fillFormFromPlan, minTimeRequest, planRequest, showError, showGroups,
} from './form.js';
import { clearTopView, drawPreview, isSpatial, lineFormat, renderTopView } from './motion-view.js';
import { initSegments } from './segments.js';
import { drawTank } from './tank-view.js';
import { loadMeasured } from './measured.js';
import { clearMinTime, renderMinTime } from './min-time.js';
import { markersPlugin } from './plots.js';
import { state } from './state.js';
import { readUrl, writeKeyUrl, writeUrl } from './url.js';
import { clearPlots, renderPlots, renderTable } from './view.js';

Chart.register(markersPlugin);

// Only the latest request of each kind is shown: a plan, comparison, search or opened key
// replaces the view, a selected row the plots.
const views = new Latest();
const plots = new Latest();

// The error of a request of `kind` that failed: the API's at the field it names, anything else
// (the service unreachable, say) at the form.
function failed(kind) {
  return (e) => {
    if (e.api) showError(e.api, kind); else $('form-error').textContent = String(e);
  };
}

// Nothing of a previous view stays on screen once a new request starts.
function clearResults() {
  plots.cancel();  // the series still on their way are for a view that is gone
  state.plotContext = null;  // a measured series uploaded now has no plan to overlay
  clearPlots();
  clearTopView();
  clearMinTime();
  state.plans = {};
  state.selected = null;
  $('candidates').querySelector('tbody').replaceChildren();
  $('candidates').hidden = true;
  $('downloads').hidden = true;
}

// The series of a law on the plan's format and model (POST v1/simulate); a calibrated model
// (options.model) keeps its frequency scale and height gain.
function simulateRequest(plan, law) {
  const m = plan.model;
  const T = plan.format.motion_time_s;
  const options = { damping: m.damping === 'explicit' ? { zeta: m.zeta } : m.damping, alpha: m.alpha, modes: m.f_hz.length, min_ramp_s: 0.001 };
  // A rectangular tank's model reports its own damping ("rectangular"), which simulate applies
  // when none is given, and its own nonlinear model (the cylinder's alpha is not part of it).
  if (m.rectangular) {
    if (m.damping === 'rectangular') delete options.damping;
    delete options.alpha;
  }
  if (m.calibration) options.model = m.calibration;
  return {
    format: plan.format,
    law,
    rest_time_s: plan.rest_time_s,
    options,
    sample_period_s: (T + plan.rest_time_s) / 2000,
  };
}

// The series of the plan's law and of the uniform law for the plots; for a motion along an arc or
// a path also both laws' planar simulations on it, sampled: the η(t) series as the maximum over
// the wall, the peaks and their directions. The acceleration and velocity plots then come from
// the same law along a straight line of the path's length, which is the law's s(t) along the path
// (its tangential a and v).
async function plotContext(plan, signal) {
  const simulate = (body) => requestJson('v1/simulate', { body, signal });
  const uniform = { type: 'seven_segment_uniform' };
  if (!isSpatial(plan.format)) {
    const [series, base] = await Promise.all([simulate(simulateRequest(plan, plan.law)), simulate(simulateRequest(plan, uniform))]);
    return { plan, request: state.request, series: series.series, base: base.series, format: plan.format };
  }
  const planar = (law) => {
    const { stroke_mm, ...format } = plan.format;  // the motion gives the move
    return simulate({ ...simulateRequest(plan, law), format });
  };
  const [onPath, baseOnPath] = await Promise.all([planar(plan.law), planar(uniform)]);
  const line = (law) => ({ ...simulateRequest(plan, law), format: lineFormat(plan.format, onPath.motion.length_mm) });
  const [series, base] = await Promise.all([simulate(line(plan.law)), simulate(line(uniform))]);
  return {
    plan, request: state.request, series: series.series, base: base.series, format: plan.format,
    spatial: { plan: onPath, base: baseOnPath },
  };
}

// A plan of the view (a row of its table) as the selected one: its status, downloads and plots.
function selectPlan(strategy) {
  const plan = state.plans[strategy];
  if (!plan) return undefined;  // a row of a view that has been replaced
  state.selected = strategy;
  markSelectedRow($('candidates').querySelector('tbody'), strategy);
  $('status-line').textContent = `${plan.strategy}: ${plan.status}. ${plan.message}`;
  showDownloads(plan);
  return plots.run(async (signal) => {
    state.plotContext = await plotContext(plan, signal);
    renderTopView(state.plotContext);
    renderPlots({ ...state.plotContext, measured: state.measured });
    document.body.dataset.ready = strategy;  // the browser test waits for this
  }, (e) => {
    clearPlots();
    clearTopView();
    $('form-error').textContent = `The plots could not be computed: ${e.api ? e.api.message : e.message}`;
  });
}

// A new view: what the previous one showed goes, the URL becomes this view's.
function startView(extraUrl) {
  clearErrors();
  clearResults();
  delete document.body.dataset.ready;
  writeUrl(extraUrl);
}

// Plan the form's strategy, or (compare) auto and then every candidate of it as a plan of its
// own (its kinematics, warnings and law in full).
function run(compare) {
  const strategy = compare ? 'auto' : $('strategy').value;
  return views.run(async (signal) => {
    state.request = planRequest(strategy);
    startView(compare ? { compare: '1' } : {});
    $('status-line').textContent = compare ? 'Planning every strategy…' : `Planning ${strategy}…`;
    const first = await requestJson('v1/plans', { body: state.request, signal });
    if (!compare) {
      state.plans[first.strategy] = first;
      renderTable([first], first.strategy, selectPlan);
      return selectPlan(first.strategy);
    }
    const names = first.candidates.map((c) => c.strategy);
    const chosen = (first.candidates.find((c) => c.chosen) || {}).strategy;
    const plans = await Promise.all(
      names.map((s) => requestJson('v1/plans', { body: { ...state.request, strategy: s }, signal })));
    for (const p of plans) state.plans[p.strategy] = p;
    renderTable(plans, chosen, selectPlan);
    // Why auto did not return a row: its reason with the deciding figures, on hover.
    for (const c of first.candidates) {
      const tr = $('candidates').querySelector(`tbody tr[data-strategy="${c.strategy}"]`);
      if (tr && c.reason_detail) tr.title = `auto did not choose it: ${c.reason_detail}`;
    }
    return selectPlan(chosen || names[0]);
  }, failed(PLAN));
}

// A row of the min-time table: its plan at T_min (the response holds it whole) in the plan view.
function selectMinTimePlan(strategy) {
  const s = state.minTime && state.minTime.strategies.find((x) => x.strategy === strategy);
  if (!s || !s.plan) return undefined;
  markSelectedRow($('min-time-table').querySelector('tbody'), strategy);
  state.plans = { [strategy]: s.plan };
  state.request = null;
  renderTable([s.plan], strategy, selectPlan);
  return selectPlan(strategy);
}

function runMinTime() {
  return views.run(async (signal) => {
    const request = minTimeRequest();
    state.request = null;
    startView({ mintime: '1' });
    delete document.body.dataset.minTime;
    const which = request.strategies ? request.strategies[0] : 'every strategy but iir';
    $('status-line').textContent = `Searching the shortest motion time of ${which}…`;
    const response = await requestJson('v1/min-time', { body: request, signal });
    state.minTimeRequest = request;
    state.minTime = response;
    renderMinTime(response, selectMinTimePlan);
    document.body.dataset.minTime = 'ready';  // the browser test waits for this
  }, failed(MIN_TIME));
}

// A plan opened by its key (?key=): the form from its format, the plan in the view. A late answer
// must not refill the form and the results over a newer plan: it is a view like the others.
function openKey(key) {
  return views.run(async (signal) => {
    const plan = await requestJson(`v1/plans/${encodeURIComponent(key)}`, { signal });
    fillFormFromPlan(plan, state.fluids);
    drawTank();
    drawPreview();
    state.request = { format: plan.format, strategy: plan.strategy, options: {} };
    state.plans = { [plan.strategy]: plan };
    writeKeyUrl(plan.key);
    renderTable([plan], plan.strategy, selectPlan);
    await selectPlan(plan.strategy);
  }, (e) => { $('form-error').textContent = e.api ? e.api.message : String(e); });
}

async function loadFluids() {
  try {
    const { fluids } = await requestJson('v1/fluids');
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
  initSegments(drawPreview);
  for (const id of ['fluid', 'shape', 'motion_type']) $(id).addEventListener('change', showGroups);
  $('format-form').addEventListener('input', () => { drawTank(); drawPreview(); });
  $('format-form').addEventListener('change', () => { drawTank(); drawPreview(); });
  $('format-form').addEventListener('submit', (e) => { e.preventDefault(); run(false); });
  $('compare-button').addEventListener('click', () => run(true));
  $('min-time-button').addEventListener('click', runMinTime);
  $('cam-period').addEventListener('input', periodTyped);
  $('download-cam').addEventListener('click', downloadCam);
  $('measured-csv').addEventListener('change', loadMeasured);
  const url = readUrl();
  drawTank();
  drawPreview();
  document.body.dataset.loaded = '1';
  if (url.key) return openKey(url.key);
  if (url.any) return url.minTime ? runMinTime() : run(url.compare);
  return undefined;
}

main();
