// The URL as the shareable state of the page: the form's inputs under short, stable parameter
// names (a shared link must keep working when an input's id or request path changes), plus
// compare=1, mintime=1 or key=<recipe key> for the view.

import { $ } from './dom.js';
import { showCustomFluid } from './form.js';

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
};

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
    const v = $(id).value.trim();
    if (v !== '') q.set(key, v);
  }
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
    $(id).value = wanted;
    if ($(id).value !== wanted) refused.push(`${key}=${wanted.slice(0, 40)}`);
    any = true;
  }
  showCustomFluid();
  if (refused.length) {
    $('form-error').textContent = `The link holds values this form cannot take: ${refused.join(', ')}. Check the form and plan again.`;
    return { any: false, compare: false, minTime: false, key: q.get('key') };
  }
  return { any, compare: q.get('compare') === '1', minTime: q.get('mintime') === '1', key: q.get('key') };
}
