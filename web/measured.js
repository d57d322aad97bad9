// A measured wave height η(t) overlaid on the predicted one: the CSV file is read and checked here,
// and the plots of the selected plan are drawn again with it.

import { $ } from './dom.js';
import { state } from './state.js';
import { renderPlots } from './view.js';

// What a measured series may hold: a wave height is millimetres to metres, a test run seconds to
// minutes; beyond these a value is a unit or export error, and Chart.js cannot scale an axis to
// ±1e308 (it throws or allocates without bound).
const MEASURED = { maxBytes: 8 << 20, maxSamples: 100000, etaMaxMm: 10000, tMaxS: 3600 };

// A decimal number as a measurement file writes it ("-0.5", "1e-3", ".5"); never hex, "Infinity"
// or an empty cell, which Number() would all accept.
const DECIMAL = /^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$/;

// The cells of one line: ';' separates them when the line holds one (and a decimal comma is then
// a decimal point, as spreadsheets of comma-decimal locales write it), else a tab, else ','.
// Splitting on any of them would read "0,5;10,0" as four values and keep two wrong ones.
function measuredCells(line) {
  if (line.includes(';')) return line.split(';').map((c) => c.trim().replace(',', '.'));
  return line.split(line.includes('\t') ? '\t' : ',').map((c) => c.trim());
}

function plural(n, word) {
  return `${n} ${word}${n === 1 ? '' : 's'}`;
}

// A measured wave height as CSV: one "t_s,eta_mm" pair a line (separated as measuredCells says),
// times increasing, |t_s| and |eta_mm| within MEASURED, at most MEASURED.maxSamples samples; the
// first non-blank line is a header when none of its cells starts like a number. Throws an Error naming the
// line, the value and the allowed range.
function parseMeasuredCsv(text) {
  const out = { t_s: [], eta_mm: [] };
  const lines = text.split(/\r?\n/);
  let first = true;
  lines.forEach((raw, i) => {
    const line = raw.trim();
    if (line === '') return;
    const cells = measuredCells(line);
    // A header names its columns: none of its cells starts like a number ("0x10" does).
    const header = first && !cells.some((c) => /^[+-]?\.?\d/.test(c));
    first = false;
    if (header) return;
    if (cells.length !== 2) {
      throw new Error(`line ${i + 1}: ${plural(cells.length, 'value')}, expected 2: t_s, eta_mm`);
    }
    ['t_s', 'eta_mm'].forEach((name, k) => {
      if (!DECIMAL.test(cells[k])) {
        throw new Error(`line ${i + 1}: ${name} = "${cells[k].slice(0, 40)}" is not a decimal number`);
      }
    });
    const t = Number(cells[0]), eta = Number(cells[1]);
    if (!Number.isFinite(t) || Math.abs(t) > MEASURED.tMaxS) {
      throw new Error(`line ${i + 1}: t_s = ${t} is outside [-${MEASURED.tMaxS}, ${MEASURED.tMaxS}] s`);
    }
    if (!Number.isFinite(eta) || Math.abs(eta) > MEASURED.etaMaxMm) {
      throw new Error(`line ${i + 1}: eta_mm = ${eta} is outside [-${MEASURED.etaMaxMm}, ${MEASURED.etaMaxMm}] mm`);
    }
    const n = out.t_s.length;
    if (n >= MEASURED.maxSamples) {
      throw new Error(`line ${i + 1}: more than ${MEASURED.maxSamples} samples`);
    }
    if (n > 0 && !(t > out.t_s[n - 1])) {
      throw new Error(`line ${i + 1}: t_s = ${t} is not after ${out.t_s[n - 1]}: times must increase`);
    }
    out.t_s.push(t);
    out.eta_mm.push(eta);
  });
  if (out.t_s.length < 2) throw new Error(`${plural(out.t_s.length, 'sample')}: at least 2 are needed`);
  return out;
}

export async function loadMeasured() {
  const file = $('measured-csv').files[0];
  if (!file) return;
  try {
    if (file.size > MEASURED.maxBytes) {
      throw new Error(`${file.size} bytes: at most ${MEASURED.maxBytes} (${MEASURED.maxSamples} samples)`);
    }
    state.measured = parseMeasuredCsv(await file.text());
    $('measured-note').textContent = `${file.name}: ${state.measured.t_s.length} samples overlaid on η(t)`;
  } catch (e) {
    state.measured = null;
    $('measured-note').textContent = `${file.name} is not a series: ${e.message}`;
  }
  if (state.plotContext) renderPlots({ ...state.plotContext, measured: state.measured });
  document.body.dataset.measured = state.measured ? String(state.measured.t_s.length) : 'invalid';
}
