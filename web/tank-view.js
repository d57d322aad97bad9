// The drawing of the container in the form: its outline from above, turned by its orientation
// relative to the motion (the arrow: the direction of the path at the start), redrawn as the
// inputs change. A rectangular tank's L side is marked; a side not given yet draws nothing.

import { $ } from './dom.js';
import { arrow, containerOutline, containerReach, el, svgFor } from './svg.js';

// The container the inputs describe (as the request gives it), or null when a size is missing.
export function formContainer() {
  const number = (id) => {
    const text = $(id).value.trim();
    const v = Number(text);
    return text !== '' && Number.isFinite(v) && v > 0 ? v : null;
  };
  if ($('shape').value === 'rectangular') {
    const length = number('length'), width = number('width');
    const orientation = Number($('orientation').value.trim() || 0);
    if (length === null || width === null || !Number.isFinite(orientation)) return null;
    return { shape: 'rectangular', length_mm: length, width_mm: width, orientation_deg: orientation };
  }
  const radius = number('radius');
  return radius === null ? null : { radius_mm: radius };
}

export function drawTank() {
  const holder = $('tank-view');
  const container = formContainer();
  if (!container) {
    holder.replaceChildren();
    return;
  }
  const reach = containerReach(container);
  const box = { x0: -reach, x1: reach * 2.2, y0: -reach, y1: reach };
  const { svg, unit } = svgFor(box, 240, 120, 'Top view of the container and the motion direction');
  svg.classList.add('tank-view');
  svg.appendChild(containerOutline(container, 0, 0, 0, { class: 'tank' }));
  svg.appendChild(arrow(reach * 1.15, 0, 0, reach, 8 * unit, { class: 'start-arrow' }));
  svg.appendChild(el('text', { x: reach * 1.15, y: -12 * unit, 'font-size': 11 * unit, class: 'label', text: 'motion' }));
  if (container.shape === 'rectangular') {
    const a = container.orientation_deg * Math.PI / 180;
    const lx = (container.length_mm / 2 + 12 * unit) * Math.cos(a), ly = (container.length_mm / 2 + 12 * unit) * Math.sin(a);
    svg.appendChild(el('text', { x: lx, y: -ly, 'font-size': 11 * unit, class: 'label', text: 'L' }));
  }
  holder.replaceChildren(svg);
}
