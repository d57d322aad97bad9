// The plots of the page: one entry per plot in PLOTS (adding a plot = one entry). Each entry
// belongs to a view: 'plan' entries build a Chart.js configuration from the context {plan,
// request, series, base, format, spatial?} (spatial: the planar simulations {plan, base} of a
// motion along an arc or a path), 'min-time' entries from {minTime} (the POST v1/min-time
// response); an entry with `when` is drawn only when when(context) holds.

const COLORS = { plan: '#0b63c5', base: '#8c959f', linear: '#d4731c', baseLinear: '#e3b58a', jerk: '#7a3db8' };

// Shaded x ranges, vertical and horizontal marker lines: options.plugins.markers =
// {shade: [{from, to, color, label}], vlines: [{x, label, color}], hlines: [{y, label, color,
// axis}]} (hlines on the y axis unless axis names another, e.g. 'y2').
export const markersPlugin = {
  id: 'markers',
  beforeDatasetsDraw(chart, _args, opts) {
    const { ctx, chartArea: area, scales: { x } } = chart;
    if (!opts || !area) return;
    ctx.save();
    for (const s of opts.shade || []) {
      const x0 = Math.max(area.left, x.getPixelForValue(s.from));
      const x1 = Math.min(area.right, x.getPixelForValue(s.to));
      ctx.fillStyle = s.color || 'rgba(11, 99, 197, 0.08)';
      ctx.fillRect(x0, area.top, Math.max(0, x1 - x0), area.bottom - area.top);
      if (s.label) { ctx.fillStyle = '#5b6570'; ctx.fillText(s.label, x0 + 4, area.top + 12); }
    }
    ctx.setLineDash([5, 4]);
    for (const v of opts.vlines || []) {
      const px = x.getPixelForValue(v.x);
      if (px < area.left || px > area.right) continue;
      ctx.strokeStyle = v.color || '#444';
      ctx.beginPath(); ctx.moveTo(px, area.top); ctx.lineTo(px, area.bottom); ctx.stroke();
      ctx.fillStyle = v.color || '#444'; ctx.fillText(v.label || '', px + 3, area.top + 24);
    }
    for (const h of opts.hlines || []) {
      const py = chart.scales[h.axis || 'y'].getPixelForValue(h.y);
      if (py < area.top || py > area.bottom) continue;
      ctx.strokeStyle = h.color || '#b3261e';
      ctx.beginPath(); ctx.moveTo(area.left, py); ctx.lineTo(area.right, py); ctx.stroke();
      ctx.fillStyle = h.color || '#b3261e'; ctx.fillText(h.label || '', area.left + 4, py - 4);
    }
    ctx.restore();
  },
};

function points(xs, ys, scale = 1) {
  const out = new Array(xs.length);
  for (let i = 0; i < xs.length; i++) out[i] = { x: xs[i], y: ys[i] * scale };
  return out;
}

// Jerk of the sampled acceleration (central differences; for display only: the law's jerk is
// piecewise constant and the API reports its peak exactly).
function jerk(t, a) {
  const out = new Array(t.length);
  for (let i = 0; i < t.length; i++) {
    const i0 = Math.max(0, i - 1), i1 = Math.min(t.length - 1, i + 1);
    out[i] = { x: t[i], y: (a[i1] - a[i0]) / (t[i1] - t[i0]) };
  }
  return out;
}

function line(label, data, color, extra = {}) {
  return { label, data, borderColor: color, backgroundColor: color, borderWidth: 1.5, pointRadius: 0, ...extra };
}

// One quantity of the series (`key`: 'a', 'v') of the plan and of the uniform law, as two lines.
function planAndUniform(series, base, key, unit) {
  return [
    line(`${key} plan [${unit}]`, points(series.t_s, series[key]), COLORS.plan),
    line(`${key} uniform [${unit}]`, points(base.t_s, base[key]), COLORS.base),
  ];
}

function timeChart(datasets, yTitle, markers, y2Title) {
  const scales = {
    x: { type: 'linear', title: { display: true, text: 't [s]' } },
    y: { title: { display: true, text: yTitle } },
  };
  if (y2Title) scales.y2 = { position: 'right', grid: { drawOnChartArea: false }, title: { display: true, text: y2Title } };
  return {
    type: 'line',
    data: { datasets },
    options: {
      animation: false, parsing: false, normalized: true, responsive: true, maintainAspectRatio: false,
      interaction: { mode: 'nearest', intersect: false },
      scales, plugins: { markers: markers || {}, legend: { labels: { boxWidth: 12 } } },
    },
  };
}

// One colour per strategy in the min-time view.
const STRATEGY_COLORS = {
  baseline: '#8c959f', notch: '#d4731c', multi_notch: '#0b63c5', min_jerk_band: '#1a7f37',
  time_domain: '#b3261e', fir_chain: '#7a3db8', shaper: '#bf8700', iir: '#1b7c83',
};

// η of a min-time curve point on the model the limits apply to ('both' = the larger of the two).
function etaOnLimitModel(curve, quantity, i, model) {
  const nl = curve.nonlinear[quantity][i], lin = curve.linear[quantity][i];
  if (model === 'linear') return lin;
  return model === 'both' ? Math.max(nl, lin) : nl;
}

// Labels of a logarithmic axis at 1, 2 and 5 times a power of ten, in as few digits as they need.
function logTick(value) {
  const mantissa = value / 10 ** Math.floor(Math.log10(value) + 1e-9);
  return [1, 2, 5].some((k) => Math.abs(mantissa - k) < 1e-6) ? String(Number(value.toPrecision(3))) : '';
}

// η_motion or η_rest over T: one dataset per strategy with one point per planned T (infeasible T
// drawn as crosses, T_min as a large diamond), the limit as a horizontal line and the winner's
// T_min as a vertical one. The y axis is logarithmic: η spans decades over T.
function etaOverT(minTime, quantity, limit, what) {
  const model = minTime.limits.model;
  const datasets = minTime.strategies.map((s) => {
    const c = s.curve;
    const color = STRATEGY_COLORS[s.strategy] || '#444';
    const atMin = (i) => s.t_min_s !== null && c.t_s[i] === s.t_min_s;
    const data = c.t_s.map((t, i) => ({ x: t, y: Math.max(1e-3, etaOnLimitModel(c, quantity, i, model)) }));
    const tMin = s.t_min_s === null ? 'none' : `${s.t_min_s.toFixed(3)} s`;
    return line(`${s.strategy} (T_min ${tMin})`, data, color, {
      strategy: s.strategy, borderWidth: 1,
      pointStyle: c.t_s.map((_, i) => (atMin(i) ? 'rectRot' : c.feasible[i] ? 'circle' : 'crossRot')),
      pointRadius: c.t_s.map((_, i) => (atMin(i) ? 6 : c.feasible[i] ? 2.5 : 4)),
      pointBorderWidth: 1.5,
    });
  });
  const markers = { hlines: [{ y: limit, label: `${what} limit ${limit.toFixed(1)} mm (${model})` }], vlines: [] };
  const h = minTime.headline;
  if (h.winner) markers.vlines.push({ x: h.t_min_s, label: `T_min ${h.winner} ${h.t_min_s.toFixed(3)} s`, color: '#1b1f24' });
  const config = timeChart(datasets, `${what} [mm] (${model} model)`, markers);
  config.options.scales.x.title.text = 'motion time T [s]';
  config.options.scales.y.type = 'logarithmic';
  // The axis starts just below the lowest point or limit (not at the power of ten below it).
  const lowest = Math.min(limit, ...datasets.flatMap((d) => d.data.map((p) => p.y)));
  config.options.scales.y.min = 0.8 * lowest;
  config.options.scales.y.ticks = { callback: logTick };
  config.options.interaction = { mode: 'nearest', intersect: true };
  config.options.plugins.legend.labels.usePointStyle = false;
  return config;
}

// η_rest (left axis) and η_motion (right axis) of the plan's law with every mode frequency scaled
// by (1 + δ), against δ in %: nonlinear solid, linear dashed; the limits as horizontal lines, the
// nonlinear model's holding interval shaded. A point where a model diverged is a gap (null).
function robustnessChart(plan) {
  const r = plan.robustness;
  const s = r.sweep;
  const curve = (model, quantity) => r.points.map((p) => ({ x: p.delta_pct, y: p[model] ? p[model][quantity] : null }));
  const dashed = { borderDash: [6, 4] };
  const datasets = [
    line('η rest nonlinear [mm]', curve('nonlinear', 'eta_rest_mm'), COLORS.plan, { pointRadius: 2 }),
    line('η rest linear [mm]', curve('linear', 'eta_rest_mm'), COLORS.linear, { pointRadius: 2, ...dashed }),
    line('η motion nonlinear [mm]', curve('nonlinear', 'eta_motion_mm'), COLORS.jerk, { yAxisID: 'y2', pointRadius: 2 }),
    line('η motion linear [mm]', curve('linear', 'eta_motion_mm'), COLORS.baseLinear, { yAxisID: 'y2', pointRadius: 2, ...dashed }),
  ];
  const markers = {
    hlines: [{ y: s.eta_rest_max_mm, label: `η rest limit ${s.eta_rest_max_mm} mm` }],
    vlines: [{ x: 0, label: 'model f1', color: '#444' }],
    shade: [],
  };
  if (s.eta_motion_max_mm !== null) {
    markers.hlines.push({ y: s.eta_motion_max_mm, label: `η motion limit ${s.eta_motion_max_mm} mm`, axis: 'y2', color: '#7a3db8' });
  }
  const holds = r.holds.nonlinear;
  if (holds) {
    const open = (end) => (end ? ' (sweep end)' : '');
    markers.shade.push({
      from: holds.from_pct, to: holds.to_pct, color: 'rgba(26, 127, 55, 0.14)',
      label: `limits hold (nonlinear): ${holds.from_pct.toFixed(2)}${open(holds.from_is_sweep_end)} to ` +
        `${holds.to_pct.toFixed(2)}${open(holds.to_is_sweep_end)} %`,
    });
  }
  const config = timeChart(datasets, 'η rest [mm]', markers, 'η motion [mm]');
  config.options.scales.x.title.text = 'frequency error δ [%] (every mode frequency × (1 + δ))';
  config.options.scales.x.min = s.delta_pct[0];
  config.options.scales.x.max = s.delta_pct[1];
  config.options.scales.y.suggestedMin = 0;
  config.options.scales.y.suggestedMax = 1.2 * s.eta_rest_max_mm;
  config.options.scales.y2.suggestedMin = 0;
  return config;
}

// η over the wall of a planar motion: max over the wall angle φ of η(φ, t), per model, for the
// plan's law and the uniform law. The series when the service gives them (series.eta_*_mm of the
// planar answer), else its peaks (during the motion and in the rest window, at their times) as
// points; the rest window shaded and the free board marked as for the straight line.
function wallChart({ plan, format, spatial }) {
  const T = format.motion_time_s;
  const markers = { shade: [{ from: T, to: T + plan.rest_time_s, label: 'rest window' }], hlines: [] };
  const height = format.container && format.container.height_mm;
  const board = height ? height - format.fill_height_mm : null;
  if (board !== null) markers.hlines.push({ y: board, label: `free board ${board.toFixed(1)} mm` });
  const of = (answer, model, label, color, extra = {}) => {
    const s = answer.series;
    const key = `eta_${model}_mm`;
    if (s && s[key]) return line(label, points(s.t_s, s[key]), color, extra);
    const p = answer.prediction[model];
    const data = [{ x: p.t_motion_s, y: p.eta_motion_mm }, { x: p.t_rest_s, y: p.eta_rest_mm }];
    return line(`${label} (peaks)`, data, color, { showLine: false, pointRadius: 5, ...extra });
  };
  const config = timeChart([
    of(spatial.plan, 'nonlinear', 'η nonlinear plan', COLORS.plan),
    of(spatial.plan, 'linear', 'η linear plan', COLORS.linear, { pointStyle: 'rect' }),
    of(spatial.base, 'nonlinear', 'η nonlinear uniform', COLORS.base),
    of(spatial.base, 'linear', 'η linear uniform', COLORS.baseLinear, { pointStyle: 'rect' }),
  ], 'max over the wall of η [mm]', markers);
  config.options.scales.x.min = 0;
  config.options.scales.x.max = T + plan.rest_time_s;
  config.options.scales.y.suggestedMin = 0;
  if (board !== null) config.options.scales.y.suggestedMax = 1.05 * board;
  return config;
}

export const PLOTS = [
  {
    id: 'min-time-motion',
    view: 'min-time',
    title: 'η motion over the motion time T (crosses: infeasible T, diamond: T_min)',
    build: ({ minTime }) => etaOverT(minTime, 'eta_motion_mm', minTime.limits.eta_motion_max_mm, 'η motion'),
  },
  {
    id: 'min-time-rest',
    view: 'min-time',
    title: 'η rest over the motion time T (crosses: infeasible T, diamond: T_min)',
    build: ({ minTime }) => etaOverT(minTime, 'eta_rest_mm', minTime.limits.eta_rest_max_mm, 'η rest'),
  },
  {
    id: 'acceleration',
    view: 'plan',
    title: 'Acceleration and jerk',
    build: ({ series, base }) => timeChart([
      ...planAndUniform(series, base, 'a', 'm/s²'),
      line('jerk plan [m/s³]', jerk(series.t_s, series.a), COLORS.jerk, { yAxisID: 'y2', borderWidth: 1 }),
    ], 'a [m/s²]', {}, 'j [m/s³]'),
  },
  {
    id: 'velocity',
    view: 'plan',
    title: 'Velocity and position',
    build: ({ series, base }) => timeChart([
      ...planAndUniform(series, base, 'v', 'm/s'),
      line('s plan [mm]', points(series.t_s, series.s, 1e3), COLORS.linear, { yAxisID: 'y2' }),
    ], 'v [m/s]', {}, 's [mm]'),
  },
  {
    id: 'eta',
    view: 'plan',
    title: 'Wave height η(t) at the wall',
    when: ({ spatial }) => !spatial,
    build: ({ plan, series, base, format, measured }) => {
      const T = format.motion_time_s;
      const markers = { shade: [{ from: T, to: T + plan.rest_time_s, label: 'rest window' }], hlines: [] };
      const height = format.container && format.container.height_mm;
      const board = height ? height - format.fill_height_mm : null;  // the free board
      if (board !== null) {
        markers.hlines.push({ y: board, label: `free board ${board.toFixed(1)} mm` });
        markers.hlines.push({ y: -board, label: '' });
      }
      const config = timeChart([
        line('η nonlinear plan', points(series.t_s, series.eta_nonlinear_mm), COLORS.plan),
        line('η linear plan', points(series.t_s, series.eta_linear_mm), COLORS.linear),
        line('η nonlinear uniform', points(base.t_s, base.eta_nonlinear_mm), COLORS.base),
        line('η linear uniform', points(base.t_s, base.eta_linear_mm), COLORS.baseLinear),
        // A measured series uploaded on the page: samples, drawn as points, not a line.
        ...(measured ? [line('η measured', points(measured.t_s, measured.eta_mm), '#111',
          { showLine: false, pointRadius: 1.5 })] : []),
      ], 'η [mm]', markers);
      if (board !== null) {  // the free board stays in view
        config.options.scales.y.suggestedMax = 1.05 * board;
        config.options.scales.y.suggestedMin = -1.05 * board;
      }
      return config;
    },
  },
  {
    id: 'eta-wall',
    view: 'plan',
    title: 'Wave height at the wall, the maximum over the wall angle (arc or path)',
    when: ({ spatial }) => Boolean(spatial),
    build: (context) => wallChart(context),
  },
  {
    id: 'spectrum',
    view: 'plan',
    title: 'Acceleration spectrum |X(f)|',
    build: ({ plan }) => {
      const s = plan.spectrum;
      const m = s.markers;
      const markers = {
        shade: [{ from: m.band_hz[0], to: m.band_hz[1], label: 'band' }],
        vlines: m.f_modes_hz.map((f, i) => ({ x: f, label: `f${i + 1}`, color: i === 0 ? '#b3261e' : '#444' })),
      };
      for (const f of m.notch_hz || []) {  // every frequency the law notches
        if (f !== m.f1_hz) markers.vlines.push({ x: f, label: 'notch', color: '#7a3db8' });
      }
      const config = timeChart([
        line('|X| plan', points(s.f_hz, s.amplitude), COLORS.plan),
        line('|X| uniform', points(s.f_hz, s.baseline_amplitude), COLORS.base),
      ], '|X_a| [m/s]', markers);
      config.options.scales.x.title.text = 'f [Hz]';
      return config;
    },
  },
  {
    id: 'robustness',
    view: 'plan',
    title: 'Robustness: η when the tank\'s frequencies are off by δ (solid nonlinear, dashed linear; shaded: the limits hold)',
    when: ({ plan }) => Boolean(plan.robustness),  // absent with options.robustness false
    build: ({ plan }) => robustnessChart(plan),
  },
];
