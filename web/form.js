// The form and the requests it makes. Each input names, in its data-field attribute, its path in
// the request it goes into ("format.container.radius_mm", "options.uncertainty.fill_height_mm[1]"):
// the request body is built from these paths, and an error of the API, which names a path, is
// shown at the input of that path: an input goes into the requests by its element in index.html
// alone (url.js gives it its name in a shared link).
// data-request="plan" or "min-time" (on the input or on its fieldset) keeps an input to that one
// request; data-min-time-field is an input's path in the min-time request where it differs.
// data-when="id=value" on a group shows it only while the select `id` has that value (the custom
// fluid's properties, the arc's or path's inputs, a rectangular container's sides): the inputs of
// a hidden group put nothing into a request.

import { $ } from './dom.js';
import { setSegments } from './segments.js';

export const PLAN = 'plan';  // POST v1/plans
export const MIN_TIME = 'min-time';  // POST v1/min-time

// The choice of a select that is an object given by the inputs of its group (a custom fluid).
const CUSTOM = 'custom';

// The path of input `el` in a request of `kind`; undefined when it does not go into that request.
function pathIn(el, kind) {
  const only = el.closest('[data-request]');
  if (only && only.dataset.request !== kind) return undefined;
  return (kind === MIN_TIME && el.dataset.minTimeField) || el.dataset.field;
}

// [input, path] of every input that goes into a request of `kind`, in the order of the form.
export function fieldsOf(kind) {
  return [...document.querySelectorAll('[data-field]')]
    .map((el) => [el, pathIn(el, kind)])
    .filter(([, path]) => path !== undefined);
}

// "a.b[1]" -> ['a', 'b', 1]
function keysOf(path) {
  return path.split(/\.|(?=\[)/).map((k) => (k.startsWith('[') ? Number(k.slice(1, -1)) : k));
}

function valueAt(object, path) {
  let at = object;
  for (const k of keysOf(path)) {
    if (at === null || typeof at !== 'object') return undefined;
    at = at[k];
  }
  return at;
}

function setAt(object, path, value) {
  const keys = keysOf(path);
  let at = object;
  keys.slice(0, -1).forEach((k, i) => {
    if (at[k] === undefined) at[k] = typeof keys[i + 1] === 'number' ? [] : {};
    at = at[k];
  });
  at[keys[keys.length - 1]] = value;
}

// What input `el` puts into the request: a number from a number input (or a select marked
// data-number), else its text, and for the custom choice an object its group's inputs fill;
// undefined when it puts nothing: left empty (the API's default applies) or inside a hidden group
// (the custom fluid's properties while a catalogue fluid is chosen).
function valueOf(el) {
  if (el.closest('[hidden]')) return undefined;
  const text = el.value.trim();
  if (text === '' && el.type !== 'checkbox') return undefined;
  if (el.tagName === 'SELECT' && text === CUSTOM) return {};
  if (el.type === 'checkbox') return el.checked;
  return el.type === 'number' || 'number' in el.dataset ? Number(text) : text;
}

// The request of `kind` the form holds, built on `skeleton` (the members it always has).
function requestOf(kind, skeleton) {
  const request = skeleton;
  const emptyEnds = [];
  for (const [el, path] of fieldsOf(kind)) {
    const value = valueOf(el);
    if (value !== undefined) setAt(request, path, value);
    else if (path.endsWith(']')) emptyEnds.push(path);
  }
  // A range is given when either end is: an empty end goes as null, and the API names that end.
  for (const path of emptyEnds) {
    if (valueAt(request, path.replace(/\[\d+\]$/, '')) !== undefined) setAt(request, path, null);
  }
  return request;
}

// The plan request of the form, for `strategy` (the form's, or auto for a comparison).
export function planRequest(strategy) {
  const request = requestOf(PLAN, { format: { container: {} }, strategy, options: {} });
  request.strategy = strategy;
  return request;
}

// The min-time request of the form: its format without the motion time, the η limits and the
// search's own inputs at the top level, the other options as for a plan, and the strategy chosen.
export function minTimeRequest() {
  const request = requestOf(MIN_TIME, { format: { container: {} }, options: {} });
  // auto is the service's default: every strategy but iir.
  if (request.strategies && request.strategies[0] === 'auto') delete request.strategies;
  return request;
}

// Shows each data-when group while its select holds the value it names, and only then.
export function showGroups() {
  for (const group of document.querySelectorAll('[data-when]')) {
    const [id, value] = group.dataset.when.split('=');
    group.hidden = $(id).value !== value;
  }
}

// The custom fluid's inputs shown when the custom fluid is chosen (one of the groups).
export const showCustomFluid = showGroups;

export function clearErrors() {
  for (const el of document.querySelectorAll('.field-error, .form-error')) el.textContent = '';
  for (const el of document.querySelectorAll('[aria-invalid]')) el.removeAttribute('aria-invalid');
}

// The input an error of a `kind` request names: the input of the error's field or of the longest
// path that holds it (a member of a custom fluid is its own input's); an error about a whole range
// is its first end's; an error about an object no input holds (the whole motion, one segment of
// a path) is its first shown input's.
function inputOf(field, kind) {
  let best = null;
  let bestLength = -1;
  let firstInside = null;
  for (const [el, path] of fieldsOf(kind)) {
    if (path.endsWith('[0]') && field === path.slice(0, -3)) return el;
    const holds = field === path || field.startsWith(`${path}.`) || field.startsWith(`${path}[`);
    if (holds && path.length > bestLength) [best, bestLength] = [el, path.length];
    // Not a whole top-level member ("format"): that is the form's.
    const nested = /[.[]/.test(field);
    const inside = nested && (path.startsWith(`${field}.`) || path.startsWith(`${field}[`));
    if (inside && !firstInside && !el.closest('[hidden]')) firstInside = el;
  }
  return best || firstInside;
}

// The API's refusal of a `kind` request at the input its error.field names, else at the form.
export function showError(error, kind) {
  const el = inputOf(error.field || '', kind);
  if (el) {
    el.setAttribute('aria-invalid', 'true');
    $(`${el.id}-error`).textContent = error.message;
    const details = el.closest('details');
    if (details) details.open = true;
    const hidden = el.closest('[hidden]');
    if (hidden) hidden.hidden = false;
    el.focus();
  } else {
    $('form-error').textContent = error.message;
  }
  $('status-line').textContent = `The service refused the request (${error.code}).`;
}

// The parts of a plan request a plan echoes: its other options are not part of a plan.
const ECHOED = ['format', 'strategy', 'options.uncertainty'];

// Sets input `el` to `value` (empty for none); a select keeps its choice when it has no option
// of that value.
function setInput(el, value) {
  if (el.type === 'checkbox') {  // absent: the input's own default
    el.checked = value === undefined || value === null ? el.defaultChecked : Boolean(value);
    return;
  }
  const text = value === undefined || value === null ? '' : String(value);
  if (el.tagName === 'SELECT' && ![...el.options].some((o) => o.value === text)) return;
  el.value = text;
}

// The form from a plan opened by its key: the format, strategy and uncertainty it echoes.
// `fluids` is the catalogue (every entry is an option of the fluid select).
export function fillFormFromPlan(plan, fluids) {
  const u = plan.uncertainty || {};
  // The echo says "no frequency error" as 0, the form with an empty input.
  const echo = {
    format: plan.format, strategy: plan.strategy,
    options: { uncertainty: { ...u, omega_error_pct: u.omega_error_pct || undefined } },
  };
  // A path's segments get their rows before the rows' inputs are filled.
  const motion = plan.format.motion;
  if (motion && motion.type === 'path') setSegments(motion.segments);
  for (const [el, path] of fieldsOf(PLAN)) {
    if (!ECHOED.some((p) => path === p || path.startsWith(`${p}.`))) continue;
    const value = valueAt(echo, path);
    if (value === null || typeof value !== 'object') setInput(el, value);
  }
  // A catalogue fluid only when its properties are the catalogue entry's: a custom fluid may carry
  // a catalogue name ({"name": "water", "density_kg_m3": 1260, ...}), and refilled as catalogue
  // water it would be replanned with water's density.
  const f = plan.format.fluid;
  const entry = fluids.find((c) => c.name === f.name);
  const known = entry !== undefined && entry.density_kg_m3 === f.density_kg_m3 &&
    entry.viscosity_pa_s === f.viscosity_pa_s;
  $('fluid').value = known ? f.name : CUSTOM;
  // A straight line is the form's stroke (its short form), which sends no motion.
  if (motion && motion.type === 'line') {
    $('motion_type').value = '';
    $('stroke').value = String(motion.length_mm);
  }
  // A cylinder is the form's default shape, which sends no shape.
  if (plan.format.container.shape === 'cylinder') $('shape').value = '';
  showGroups();
}
