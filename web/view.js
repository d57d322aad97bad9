// The plan view: the table of plans and the plots of the selected one. Every function here draws
// what it is given; the requests are app.js's.

import { $, fillSelectableRows } from './dom.js';
import { PLOTS } from './plots.js';
import { state } from './state.js';

export function fmt(v, digits = 2) {
  return typeof v === 'number' && isFinite(v) ? v.toFixed(digits) : '—';
}

function cellsOf(plan) {
  const p = plan.prediction, r = plan.reduction_pct, k = plan.kinematics;
  return [
    plan.strategy, plan.status, plan.law.type,
    fmt(p.nonlinear.eta_motion_mm), fmt(p.nonlinear.eta_rest_mm),
    fmt(p.linear.eta_motion_mm), fmt(p.linear.eta_rest_mm),
    // On the linear model when the two laws' nonlinear figures are of different models.
    ...[r.motion, r.rest].map((v) => fmt(v, 1) + (r.model === 'linear' ? ' (lin)' : '')),
    fmt(k.a_max, 3), fmt(k.a_min, 3), fmt(k.j_peak, 1),
    (plan.warnings || []).join('; '),
  ];
}

// One row per plan, the chosen strategy's in bold; selecting a row calls onSelect(strategy).
export function renderTable(plans, chosenStrategy, onSelect) {
  const rows = plans.map((plan) => ({
    strategy: plan.strategy, cells: cellsOf(plan),
    className: plan.strategy === chosenStrategy ? 'chosen' : undefined,
  }));
  fillSelectableRows($('candidates').querySelector('tbody'), rows, onSelect);
  $('candidates').hidden = false;
}

export function clearPlots() {
  for (const chart of state.charts) chart.destroy();
  state.charts = [];
  $('plots').replaceChildren();
}

// The box of one plot in `holder`: its title with a PNG link, and the canvas to draw on.
function plotBox(plot, holder) {
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
  return { png, wrap, canvas };
}

// The plots of one view ('plan' or 'min-time') into its holder; returns the charts.
export function renderPlots(context, view = 'plan', holder = $('plots')) {
  if (view === 'plan') clearPlots();
  const charts = [];
  for (const plot of PLOTS.filter((p) => p.view === view && (!p.when || p.when(context)))) {
    const { png, wrap, canvas } = plotBox(plot, holder);
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
