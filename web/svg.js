// Drawing in SVG for the top views: elements, arrows and a container's outline seen from above.
// Coordinates are the world's in mm (x right, y up, angles counter-clockwise from +x); the
// drawings flip y themselves (screen y = -y), so a left turn is drawn to the left.

const NS = 'http://www.w3.org/2000/svg';
const RAD = Math.PI / 180;

// An SVG element with attributes (and text content under the key 'text').
export function el(tag, attrs = {}) {
  const node = document.createElementNS(NS, tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === 'text') node.textContent = v;
    else node.setAttribute(k, String(v));
  }
  return node;
}

// An arrow from world (x, y) of `length` mm in direction `angle` [rad], its head `head` mm long.
export function arrow(x, y, angle, length, head, attrs = {}) {
  const x1 = x + length * Math.cos(angle), y1 = y + length * Math.sin(angle);
  const wing = (side) => {
    const a = angle + Math.PI - side * 25 * RAD;
    return `${x1 + head * Math.cos(a)},${-(y1 + head * Math.sin(a))}`;
  };
  const g = el('g', attrs);
  g.append(
    el('line', { x1: x, y1: -y, x2: x1, y2: -y1 }),
    el('polyline', { points: `${wing(1)} ${x1},${-y1} ${wing(-1)}`, fill: 'none' }),
  );
  return g;
}

// The outline of `container` (the format's: {radius_mm} or {shape: 'rectangular', length_mm,
// width_mm, orientation_deg}) centred at world (x, y), its own heading `heading` [rad] (the
// direction its length L points to is heading + orientation), with a mark of its heading: a
// radius for a round container (which looks the same however it turns), the L side for a tank.
export function containerOutline(container, x, y, heading, attrs = {}) {
  const g = el('g', attrs);
  if (container.shape === 'rectangular') {
    const a = heading + (container.orientation_deg ?? 0) * RAD;
    const hl = container.length_mm / 2, hw = container.width_mm / 2;
    const corner = (u, v) => `${x + u * Math.cos(a) - v * Math.sin(a)},${-(y + u * Math.sin(a) + v * Math.cos(a))}`;
    g.append(el('polygon', { points: [corner(hl, hw), corner(-hl, hw), corner(-hl, -hw), corner(hl, -hw)].join(' ') }));
    g.append(el('line', { x1: x, y1: -y, x2: x + hl * Math.cos(a), y2: -(y + hl * Math.sin(a)), class: 'heading-mark' }));
  } else {
    const r = container.radius_mm;
    g.append(el('circle', { cx: x, cy: -y, r }));
    g.append(el('line', { x1: x, y1: -y, x2: x + r * Math.cos(heading), y2: -(y + r * Math.sin(heading)), class: 'heading-mark' }));
  }
  return g;
}

// The half extent of a container's outline [mm] (to size a drawing around it).
export function containerReach(container) {
  if (container.shape === 'rectangular') return Math.hypot(container.length_mm, container.width_mm) / 2;
  return container.radius_mm;
}

// An <svg> whose viewBox holds the world box [x0, x1] x [y0, y1] with a margin, drawn in about
// `width` x `height` pixels, and its mm per pixel (for text and arrow sizes; strokes do not
// scale, style.css).
export function svgFor(box, width, height, label) {
  const w = Math.max(box.x1 - box.x0, 1e-6), h = Math.max(box.y1 - box.y0, 1e-6);
  const margin = 0.08 * Math.max(w, h);
  const svg = el('svg', {
    viewBox: `${box.x0 - margin} ${-box.y1 - margin} ${w + 2 * margin} ${h + 2 * margin}`,
    role: 'img', 'aria-label': label, preserveAspectRatio: 'xMidYMid meet',
  });
  svg.setAttribute('width', String(width));
  svg.setAttribute('height', String(height));
  return { svg, unit: Math.max((w + 2 * margin) / width, (h + 2 * margin) / height) };
}
