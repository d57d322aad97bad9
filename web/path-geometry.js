// The plane geometry of a motion of format.motion (SPEC §14) for drawing it: where the container
// is after moving s mm along the path and which way the path and the container point there. The
// conventions are the service's: x, y horizontal (top view, y to the left of +x), headings from +x
// counter-clockwise, an arc's angle signed (left positive), the path tangent continuous at every
// joint. The service computes the motion itself; this is for the top view only.

const RAD = Math.PI / 180;

// The pieces of a motion: [{kind: 'line', length}, {kind: 'arc', radius, angle (rad, signed)}],
// its start heading [rad] and whether the container turns with the path tangent; null for a
// motion the page does not draw (a trajectory) or one with a missing or unusable number.
function piecesOf(motion) {
  if (!motion) return null;
  const finite = (...v) => v.every((x) => typeof x === 'number' && Number.isFinite(x));
  let pieces;
  let heading = 0;
  let turns = false;
  if (motion.type === 'line') {
    pieces = [{ kind: 'line', length: motion.length_mm }];
    heading = motion.direction_deg ?? 0;
  } else if (motion.type === 'arc') {
    pieces = [{ kind: 'arc', radius: motion.radius_mm, angle: motion.angle_deg * RAD }];
    heading = motion.start_heading_deg ?? 0;
    turns = motion.container_turns ?? true;
  } else if (motion.type === 'path' && Array.isArray(motion.segments)) {
    pieces = motion.segments.map((s) => (s.arc
      ? { kind: 'arc', radius: s.arc.radius_mm, angle: s.arc.angle_deg * RAD }
      : { kind: 'line', length: s.line_mm }));
    heading = motion.start_heading_deg ?? 0;
    turns = motion.container_turns ?? false;
  } else {
    return null;
  }
  // Sizes the service takes at most (an arc of ±3600°, lines and radii of kilometres); beyond
  // them there is nothing to draw (the service refuses the motion), and the polyline of an arc of
  // 1e300° would never end.
  const MAX_MM = 1e7;
  const usable = pieces.length > 0 && pieces.length <= 1000 && pieces.every((p) => (p.kind === 'line'
    ? finite(p.length) && p.length > 0 && p.length <= MAX_MM
    : finite(p.radius, p.angle) && p.radius > 0 && p.radius <= MAX_MM && p.angle !== 0 && Math.abs(p.angle) <= 3600 * RAD));
  if (!usable || !finite(heading)) return null;
  for (const p of pieces) if (p.kind === 'arc') p.length = p.radius * Math.abs(p.angle);
  return { pieces, heading: heading * RAD, turns };
}

// The pose at u along one piece that starts at (x, y) with heading h.
function poseOnPiece(piece, x, y, h, u) {
  if (piece.kind === 'line') return { x: x + u * Math.cos(h), y: y + u * Math.sin(h), heading: h };
  // The centre lies to the left of the tangent for a left turn, to the right for a right turn.
  const sigma = Math.sign(piece.angle);
  const cx = x - sigma * piece.radius * Math.sin(h);
  const cy = y + sigma * piece.radius * Math.cos(h);
  const hu = h + sigma * u / piece.radius;
  return { x: cx + sigma * piece.radius * Math.sin(hu), y: cy - sigma * piece.radius * Math.cos(hu), heading: hu };
}

// The drawable path of `motion`, or null: {length [mm], turns, at(s) -> {x, y, heading,
// container}} with container the container's own heading [rad] (the path tangent's change added
// when it turns with the path, else its start heading kept), and points(n) for a polyline.
export function pathOf(motion) {
  const parsed = piecesOf(motion);
  if (!parsed) return null;
  const starts = [];
  let x = 0, y = 0, h = parsed.heading, s = 0;
  for (const p of parsed.pieces) {
    starts.push({ s, x, y, h });
    ({ x, y, heading: h } = poseOnPiece(p, x, y, h, p.length));
    s += p.length;
  }
  const length = s;
  const at = (where) => {
    const u = Math.min(Math.max(where, 0), length);
    let i = starts.length - 1;
    while (i > 0 && starts[i].s > u) i--;
    const st = starts[i];
    const pose = poseOnPiece(parsed.pieces[i], st.x, st.y, st.h, Math.min(u - st.s, parsed.pieces[i].length));
    pose.container = parsed.turns ? pose.heading : parsed.heading;
    return pose;
  };
  // Every line piece's ends and arcs every 2° at least, so a polyline of them is smooth.
  const points = () => {
    const out = [];
    parsed.pieces.forEach((p, i) => {
      const n = p.kind === 'line' ? 1 : Math.max(2, Math.ceil(Math.abs(p.angle) / (2 * RAD)));
      for (let k = i === 0 ? 0 : 1; k <= n; k++) out.push(at(starts[i].s + (p.length * k) / n));
    });
    return out;
  };
  return { length, turns: parsed.turns, startHeading: parsed.heading, at, points };
}

// s(t) of a sampled series ({t_s, s} with s in m) at time t, in mm (linear between samples).
export function sAt(series, t) {
  const ts = series.t_s;
  if (t <= ts[0]) return series.s[0] * 1e3;
  let lo = 0, hi = ts.length - 1;
  if (t >= ts[hi]) return series.s[hi] * 1e3;
  while (hi - lo > 1) {
    const mid = (lo + hi) >> 1;
    if (ts[mid] <= t) lo = mid; else hi = mid;
  }
  const f = (t - ts[lo]) / (ts[hi] - ts[lo]);
  return (series.s[lo] + f * (series.s[hi] - series.s[lo])) * 1e3;
}
