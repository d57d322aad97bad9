// The min-time view ("How fast can it go?", the answer of POST v1/min-time): the headline, one
// row per strategy searched and the η-over-T plots.

import { $, fillSelectableRows } from './dom.js';
import { state } from './state.js';
import { fmt, renderPlots } from './view.js';

// The η of a min-time curve point at the strategy's T_min, on the model the limits apply to.
function etaAtTMin(s, quantity, model) {
  const i = s.t_min_s === null ? -1 : s.curve.t_s.indexOf(s.t_min_s);
  if (i < 0) return undefined;
  const nl = s.curve.nonlinear[quantity][i], lin = s.curve.linear[quantity][i];
  return model === 'linear' ? lin : model === 'both' ? Math.max(nl, lin) : nl;
}

function cellsOf(s, model) {
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
function headline(m) {
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

// The view of answer m; selecting a row calls onSelect(strategy).
export function renderMinTime(m, onSelect) {
  const model = m.limits.model;
  const rows = m.strategies.map((s) => ({
    strategy: s.strategy, cells: cellsOf(s, model), title: s.message,
    className: s.strategy === m.headline.winner ? 'winner' : undefined,
  }));
  fillSelectableRows($('min-time-table').querySelector('tbody'), rows, onSelect);
  $('min-time-headline').textContent = headline(m);
  const l = m.limits;
  const scanStart = Math.min(...m.strategies.map((s) => s.scan_start_s));
  $('status-line').textContent = `Limits: η motion ≤ ${l.eta_motion_max_mm.toFixed(1)} mm, η rest ≤ ` +
    `${l.eta_rest_max_mm.toFixed(1)} mm over ${l.rest_time_s} s (${model} model); T searched from ` +
    `${scanStart.toFixed(3)} s (kinematic bound ${m.kinematic_lower_bound_s.toFixed(3)} s) up to ` +
    `${m.motion_time_max_s} s on a 1 ms grid.`;
  $('min-time').hidden = false;
  state.minTimeCharts = renderPlots({ minTime: m }, 'min-time', $('min-time-plots'));
}

export function clearMinTime() {
  for (const chart of state.minTimeCharts) chart.destroy();
  state.minTimeCharts = [];
  $('min-time-plots').replaceChildren();
  $('min-time-table').querySelector('tbody').replaceChildren();
  $('min-time-headline').textContent = '';
  $('min-time').hidden = true;
  state.minTime = null;
  state.minTimeRequest = null;
}
