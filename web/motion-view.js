// The motion seen from above: a preview in the form as the motion and the container are typed,
// and the top view of the selected plan with the peaks of the wave (top-view.js draws both).

import { $ } from './dom.js';
import { planRequest } from './form.js';
import { pathOf, sAt } from './path-geometry.js';
import { formContainer } from './tank-view.js';
import { topView } from './top-view.js';

// Whether a format moves along an arc or a path (a planar simulation), not a straight line.
export function isSpatial(format) {
  return Boolean(format.motion) && format.motion.type !== 'line';
}

// The format moved along a straight line of `length_mm` instead of its motion.
export function lineFormat(format, length_mm) {
  const { motion, ...rest } = format;
  return { ...rest, stroke_mm: length_mm };
}

// The motion of a format: its format.motion, or the straight line of its stroke.
function motionOf(format) {
  return format.motion || { type: 'line', length_mm: format.stroke_mm };
}

// The preview of the form's motion and container; nothing while a number is missing.
export function drawPreview() {
  const holder = $('motion-preview');
  const format = planRequest('').format;
  const path = pathOf(motionOf(format));
  const container = formContainer();
  if (!path || !container) {
    holder.replaceChildren();
    return;
  }
  holder.replaceChildren(topView(path, container, [], { width: 280, height: 170 }));
}

export function clearTopView() {
  $('top-view').replaceChildren();
  $('top-note').textContent = '';
  $('top').hidden = true;
}

// The wall-direction peaks of a planar simulation's answer, where the container is at each.
function peaksOf(answer, series, length) {
  const out = [];
  for (const model of ['nonlinear', 'linear']) {
    const p = answer.prediction[model];
    out.push({
      id: `peak-motion-${model}`, model, when: 'motion', t_s: p.t_motion_s, s_mm: sAt(series, p.t_motion_s),
      direction_deg: p.direction_motion_deg, eta_mm: p.eta_motion_mm,
    });
    out.push({
      id: `peak-rest-${model}`, model, when: 'rest', t_s: p.t_rest_s, s_mm: length,
      direction_deg: p.direction_rest_deg, eta_mm: p.eta_rest_mm,
    });
  }
  return out;
}

// The top view of a plot context (app.js): the plan's path and container, and for a planar
// simulation the peaks of the plan's law.
export function renderTopView(context) {
  const path = pathOf(motionOf(context.format));
  if (!path) {
    clearTopView();
    return;
  }
  const answer = context.spatial && context.spatial.plan;
  const peaks = answer ? peaksOf(answer, context.series, path.length) : [];
  $('top-view').replaceChildren(topView(path, context.format.container, peaks));
  if (answer) {
    const nl = answer.prediction.nonlinear;
    $('top-note').textContent = `Arrows: the wall direction of the highest wave (solid: nonlinear model, dashed: linear) ` +
      `during the motion (η ${nl.eta_motion_mm.toFixed(2)} mm at t = ${nl.t_motion_s.toFixed(3)} s, toward ` +
      `${nl.direction_motion_deg.toFixed(1)}°) and in the rest window (η ${nl.eta_rest_mm.toFixed(2)} mm toward ` +
      `${nl.direction_rest_deg.toFixed(1)}°), where the container is then. Angles from +x, counter-clockwise.`;
  } else if (context.format.container.shape === 'rectangular') {
    $('top-note').textContent = 'On a straight line the height reported is the highest over the tank\'s walls and corners.';
  } else {
    $('top-note').textContent = 'On a straight line the wave peaks at the front or back wall along the line.';
  }
  $('top').hidden = false;
}
