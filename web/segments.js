// The segments of a path motion (format.motion.segments): one row of inputs per segment, a line
// (its length) or an arc (its radius and signed angle). A row's inputs carry their request path
// in data-field like every other input of the form (form.js), numbered by the row's place, so an
// error the API names at "format.motion.segments[2].arc.radius_mm" lands at that row's radius.
// Adding or removing a row renumbers the rows after it.

import { $ } from './dom.js';

// The path a new page starts with: a line, a left quarter turn, a line (a curve of a track).
export const DEFAULT_SEGMENTS = [{ line_mm: 200 }, { arc: { radius_mm: 150, angle_deg: 90 } }, { line_mm: 200 }];

// A segment added by "Add line" or "Add arc".
const NEW = { line: { line_mm: 100 }, arc: { arc: { radius_mm: 100, angle_deg: 90 } } };

// The inputs of a row of kind `kind`: [id suffix, label, request path below the segment].
const INPUTS = {
  line: [['line', 'Length [mm]', 'line_mm']],
  arc: [['radius', 'Radius [mm]', 'arc.radius_mm'], ['angle', 'Angle [°] (left positive)', 'arc.angle_deg']],
};

let onChange = () => {};

function labelled(id, text, input) {
  const label = document.createElement('label');
  label.htmlFor = id;
  label.textContent = text;
  const error = document.createElement('p');
  error.className = 'field-error';
  error.id = `${id}-error`;
  error.setAttribute('role', 'alert');
  return [label, input, error];
}

function numberInput(id, path, value) {
  const input = document.createElement('input');
  input.id = id;
  input.type = 'number';
  input.step = 'any';
  input.dataset.field = path;
  if (value !== undefined && value !== null) input.value = String(value);
  input.addEventListener('input', () => onChange());
  return input;
}

// One row for segment `segment` ({line_mm} or {arc: {radius_mm, angle_deg}}) at place i.
function segmentRow(segment, i) {
  const row = document.createElement('div');
  row.className = 'segment';
  const id = `seg${i}`;
  const kind = document.createElement('select');
  kind.id = `${id}_kind`;
  kind.add(new Option('line', 'line'));
  kind.add(new Option('arc', 'arc'));
  kind.value = segment.arc ? 'arc' : 'line';
  kind.addEventListener('change', () => {
    for (const group of row.querySelectorAll('[data-when]')) group.hidden = group.dataset.when !== `${kind.id}=${kind.value}`;
    onChange();
  });
  const remove = document.createElement('button');
  remove.type = 'button';
  remove.className = 'remove-segment';
  remove.textContent = 'Remove';
  remove.setAttribute('aria-label', `Remove segment ${i + 1}`);
  remove.addEventListener('click', () => {
    const segments = readSegments();
    segments.splice(i, 1);
    setSegments(segments);
    onChange();
  });
  const head = document.createElement('div');
  head.className = 'segment-head';
  const kindLabel = document.createElement('label');
  kindLabel.htmlFor = kind.id;
  kindLabel.textContent = `Segment ${i + 1}`;
  head.append(kindLabel, kind, remove);
  row.appendChild(head);
  // The inputs of the other kind start with the values of a new segment of that kind, so a row
  // switched from line to arc (or back) holds a whole segment.
  const values = segment.arc
    ? { line: NEW.line.line_mm, radius: segment.arc.radius_mm, angle: segment.arc.angle_deg }
    : { line: segment.line_mm, radius: NEW.arc.arc.radius_mm, angle: NEW.arc.arc.angle_deg };
  for (const [which, inputs] of Object.entries(INPUTS)) {
    const group = document.createElement('div');
    group.dataset.when = `${kind.id}=${which}`;
    group.hidden = kind.value !== which;
    for (const [suffix, text, member] of inputs) {
      const inputId = `${id}_${suffix}`;
      group.append(...labelled(inputId, text, numberInput(inputId, `format.motion.segments[${i}].${member}`, values[suffix])));
    }
    row.appendChild(group);
  }
  return row;
}

// The segments the rows now hold, as the request members (text as typed; numbers where given).
export function readSegments() {
  return [...$('segments').querySelectorAll('.segment')].map((row, i) => {
    const value = (suffix) => {
      const text = $(`seg${i}_${suffix}`).value.trim();
      return text === '' ? undefined : Number(text);
    };
    return $(`seg${i}_kind`).value === 'arc'
      ? { arc: { radius_mm: value('radius'), angle_deg: value('angle') } }
      : { line_mm: value('line') };
  });
}

// The rows of `segments`, replacing the rows there were.
export function setSegments(segments) {
  $('segments').replaceChildren(...segments.map(segmentRow));
}

// The rows of the default path, the add buttons, and `changed` called on every edit of a row.
export function initSegments(changed) {
  onChange = changed;
  setSegments(DEFAULT_SEGMENTS);
  const add = (segment) => () => {
    setSegments([...readSegments(), segment]);
    onChange();
  };
  $('add-line').addEventListener('click', add(NEW.line));
  $('add-arc').addEventListener('click', add(NEW.arc));
}
