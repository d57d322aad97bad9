// The URL as the shareable state of the page: the form's inputs under short, stable parameter
// names (a shared link must keep working when an input's id or request path changes), plus
// compare=1, mintime=1 or key=<recipe key> for the view. A checkbox is 1 or 0; the segments of a
// path are one parameter, seg=l200,a150:90,l200 (a line of 200 mm, an arc of radius 150 mm
// turning 90°, ...).

import { $ } from './dom.js';
import { showGroups } from './form.js';
import { readSegments, setSegments } from './segments.js';

// Form inputs and their URL parameter names, in the order a written URL lists them.
const PARAMS = {
  radius: 'r', height: 'h', fill: 'fill', fluid: 'fluid', density: 'rho', viscosity: 'mu',
  stroke: 'stroke', time: 'T', strategy: 'strategy', a_max: 'a_max', v_max: 'v_max',
  j_max: 'j_max', eta_rest_max: 'eta_rest', rest_time: 'rest', p_notch: 'p_notch', band: 'band',
  tol_rel: 'tol_rel', min_ramp: 'min_ramp', shaper: 'shaper', base: 'base', time_limit: 'budget',
  n_band: 'n_band', objective: 'objective', eta_motion_max: 'eta_motion', residual: 'residual',
  iir_order: 'iir_order', iir_tau: 'iir_tau', iir_period: 'iir_period', solver: 'solver',
  t_max: 't_max', margin: 'margin', limit_model: 'limit_model', omega_error: 'omega_err',
  fill_min: 'fill_lo', fill_max: 'fill_hi', visc_min: 'mu_lo', visc_max: 'mu_hi',
  shape: 'shape', length: 'L', width: 'W', orientation: 'orient', motion_type: 'motion',
  arc_radius: 'arc_r', arc_angle: 'arc_deg', arc_turns: 'arc_turns', path_heading: 'heading',
  path_turns: 'path_turns',
};

// The segments' text of a link ("l200,a150:90"), and back (null when it is not one).
function segmentsText(segments) {
  const n = (v) => (v === undefined ? '' : String(v));
  return segments.map((s) => (s.arc ? `a${n(s.arc.radius_mm)}:${n(s.arc.angle_deg)}` : `l${n(s.line_mm)}`)).join(',');
}

function segmentsOf(text) {
  const number = (t) => (t === '' ? undefined : Number(t));
  const out = [];
  for (const part of text.split(',')) {
    const line = /^l(-?[0-9.e+-]*)$/i.exec(part);
    const arc = /^a(-?[0-9.e+-]*):(-?[0-9.e+-]*)$/i.exec(part);
    if (line) out.push({ line_mm: number(line[1]) });
    else if (arc) out.push({ arc: { radius_mm: number(arc[1]), angle_deg: number(arc[2]) } });
    else return null;
    const values = line ? [out.at(-1).line_mm] : [out.at(-1).arc.radius_mm, out.at(-1).arc.angle_deg];
    if (values.some((v) => v !== undefined && !Number.isFinite(v))) return null;
  }
  return out;
}

// The text of an input in a link, and whether the input took a text of a link.
function inputText(el) {
  return el.type === 'checkbox' ? (el.checked ? '1' : '0') : el.value.trim();
}

function setFromLink(el, text) {
  if (el.type === 'checkbox') {
    el.checked = text === '1';
    return text === '1' || text === '0';
  }
  el.value = text;
  return el.value === text;
}

// The share link is the URL as it now is.
function updateShareLink() {
  $('share-link').href = location.href;
}

// The URL of the form's view; `extra` adds the view's own parameters ({compare: '1'}). An input
// of a hidden group (the custom fluid's, for a catalogue fluid) is not part of the view.
export function writeUrl(extra) {
  const q = new URLSearchParams();
  for (const [id, key] of Object.entries(PARAMS)) {
    if ($(id).closest('[hidden]')) continue;
    const v = inputText($(id));
    if (v !== '') q.set(key, v);
  }
  if (!$('segments').closest('[hidden]')) q.set('seg', segmentsText(readSegments()));
  for (const [k, v] of Object.entries(extra || {})) q.set(k, v);
  history.replaceState(null, '', `?${q.toString()}`);
  updateShareLink();
}

// The URL of a plan opened by its key.
export function writeKeyUrl(key) {
  history.replaceState(null, '', `?key=${encodeURIComponent(key)}`);
  updateShareLink();
}

// The form from the URL; a value the form cannot hold (an unknown fluid or strategy, text in a
// number field) is named in the form error instead of being dropped.
export function readUrl() {
  const q = new URLSearchParams(location.search);
  let any = false;
  const refused = [];
  for (const [id, key] of Object.entries(PARAMS)) {
    if (!q.has(key)) continue;
    const wanted = q.get(key);
    if (!setFromLink($(id), wanted)) refused.push(`${key}=${wanted.slice(0, 40)}`);
    any = true;
  }
  if (q.has('seg')) {
    const segments = segmentsOf(q.get('seg'));
    if (segments) setSegments(segments); else refused.push(`seg=${q.get('seg').slice(0, 40)}`);
  }
  showGroups();
  if (refused.length) {
    $('form-error').textContent = `The link holds values this form cannot take: ${refused.join(', ')}. Check the form and plan again.`;
    return { any: false, compare: false, minTime: false, key: q.get('key') };
  }
  return { any, compare: q.get('compare') === '1', minTime: q.get('mintime') === '1', key: q.get('key') };
}
