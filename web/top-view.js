// The top view of a motion (SPEC §14): the path, the container at its start, along the way and at
// its end with its heading (turning with the path or keeping its orientation), and, for a
// simulated law, where the container is when the wave peaks and the wall direction of that peak
// (an arrow from the container's centre; solid for the nonlinear model, dashed for the linear).
// Each peak arrow carries its figures in data- attributes (the browser test reads them).

import { arrow, containerOutline, containerReach, el, svgFor } from './svg.js';

const RAD = Math.PI / 180;

// The world box of the path's points and the container around them.
function boxOf(points, reach) {
  const xs = points.map((p) => p.x), ys = points.map((p) => p.y);
  return {
    x0: Math.min(...xs) - reach, x1: Math.max(...xs) + reach,
    y0: Math.min(...ys) - reach, y1: Math.max(...ys) + reach,
  };
}

// The drawing of `path` (path-geometry.js) with the format's `container`; `peaks` are
// [{id, model, when ('motion'|'rest'), s_mm, direction_deg, eta_mm, t_s}] to mark. Returns the
// <svg>.
export function topView(path, container, peaks = [], { width = 560, height = 320 } = {}) {
  const points = path.points();
  const reach = containerReach(container);
  // As tall as the motion needs (a straight line is a strip), up to `height`.
  const box = boxOf(points, reach * 2.2);
  const tall = Math.min(height, Math.max(110, (width * (box.y1 - box.y0)) / Math.max(box.x1 - box.x0, 1e-9)));
  const { svg, unit } = svgFor(box, width, tall, 'Top view of the motion');
  svg.classList.add('top-view');
  const end = points[points.length - 1];
  svg.appendChild(el('polyline', {
    id: 'path-line', class: 'path', fill: 'none',
    points: points.map((p) => `${p.x},${-p.y}`).join(' '),
    'data-end-x': end.x, 'data-end-y': end.y, 'data-length-mm': path.length,
  }));
  // The container at five places along the path, the first and last labelled.
  for (let k = 0; k <= 4; k++) {
    const pose = path.at((path.length * k) / 4);
    svg.appendChild(containerOutline(container, pose.x, pose.y, pose.container, {
      class: 'ghost', 'data-heading-deg': pose.container / RAD,
    }));
  }
  const start = path.at(0);
  svg.appendChild(arrow(start.x, start.y, start.heading, Math.max(reach * 2, 40 * unit), 8 * unit, { class: 'start-arrow' }));
  const text = (x, y, content, cls) => el('text', { x, y: -y, class: cls, 'font-size': 12 * unit, text: content });
  svg.appendChild(text(start.x + 4 * unit, start.y - reach - 14 * unit, 'start', 'label'));
  svg.appendChild(text(end.x + 4 * unit, end.y - reach - 14 * unit, 'end', 'label'));
  const length = Math.max(reach * 2.2, 60 * unit);
  peaks.forEach((p, i) => {
    const pose = path.at(p.s_mm);
    const attrs = {
      id: p.id, class: `peak peak-${p.model} peak-${p.when}`,
      'data-x': pose.x, 'data-y': pose.y, 'data-direction-deg': p.direction_deg, 'data-eta-mm': p.eta_mm, 'data-t-s': p.t_s,
    };
    svg.appendChild(containerOutline(container, pose.x, pose.y, pose.container, { class: `peak-container peak-${p.when}` }));
    const g = arrow(pose.x, pose.y, p.direction_deg * RAD, length, 10 * unit, attrs);
    const title = el('title', { text: `${p.when} peak, ${p.model} model: η ${p.eta_mm.toFixed(2)} mm at t = ${p.t_s.toFixed(3)} s toward ${p.direction_deg.toFixed(1)}°` });
    g.appendChild(title);
    svg.appendChild(g);
    if (p.model === 'nonlinear') {
      const tip = pose.x + length * Math.cos(p.direction_deg * RAD), tipY = pose.y + length * Math.sin(p.direction_deg * RAD);
      svg.appendChild(text(tip + 4 * unit, tipY + (i % 2 ? -14 : 4) * unit, `${p.when} peak ${p.eta_mm.toFixed(1)} mm`, 'label peak-label'));
    }
  });
  return svg;
}
