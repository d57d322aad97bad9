// The downloads of the selected plan: its JSON, and its cam table at the period typed (fetched
// before it is saved, so that a refused period is shown, never saved as the file).

import { ApiError, send } from './api.js';
import { $ } from './dom.js';
import { state } from './state.js';

// The plan JSON of `plan` (the selected one) and its cam table link, shown.
export function showDownloads(plan) {
  $('download-json').href = URL.createObjectURL(new Blob([JSON.stringify(plan, null, 2)], { type: 'application/json' }));
  $('download-json').download = `plan-${plan.key}.json`;
  updateCamLink();
  $('downloads').hidden = false;
}

// The cam table of a cached plan: optimal and acceptable plans directly, an infeasible one only as
// its best reachable law (said so); time-limited and failed plans are not cached (no link).
// A plan of the min-time view is not kept either (the service keeps the min-time answer only).
function updateCamLink() {
  const plan = state.plans[state.selected];
  if (!plan) return;
  const period = $('cam-period').value || '1';
  const link = $('download-cam');
  const fromMinTime = state.minTime !== null;
  const cached = !fromMinTime && ['optimal', 'acceptable', 'infeasible'].includes(plan.status);
  link.hidden = !cached;
  $('cam-period').disabled = !cached;
  if (fromMinTime) {
    $('cam-note').textContent = `No cam table: a plan of the min-time search is not kept by the service; plan ${plan.strategy} at T = ${plan.format.motion_time_s.toFixed(3)} s (Plan) for its cam table.`;
    return;
  }
  if (!cached) {
    $('cam-note').textContent = `No cam table: a ${plan.status} plan is not kept by the service; plan it with a larger time budget or use slosh export.`;
    return;
  }
  const force = plan.status === 'infeasible' ? '&allow_infeasible=true' : '';
  link.href = `v1/plans/${plan.key}/cam.csv?period_ms=${encodeURIComponent(period)}${force}`;
  link.download = `cam-${plan.key}-${period}ms.csv`;
  link.textContent = force ? 'Cam table CSV (infeasible plan: its best reachable law)' : 'Cam table CSV';
  $('cam-note').textContent = '';
}

// The period input as it is before a new period is read: unmarked, with no error under it.
function resetPeriodError() {
  $('cam-period').removeAttribute('aria-invalid');
  $('cam-period-error').textContent = '';
}

// A typed period the number input cannot read ("1e400", "--1", "5e"): the input then reports an
// empty value, which must not turn into the default period of 1 ms. Marks the input and says so;
// true when the period is unreadable.
function refuseUnreadablePeriod() {
  const period = $('cam-period');
  if (!period.validity.badInput) return false;
  period.setAttribute('aria-invalid', 'true');
  $('cam-period-error').textContent =
    'the period is not a number: type a decimal number of milliseconds, such as 1 or 0.5';
  $('cam-note').textContent = '';
  return true;
}

// The cam table through fetch, not a plain link: a refused period (the API's 422) is shown at the
// period input instead of being saved as the CSV file.
export async function downloadCam(event) {
  event.preventDefault();
  const { href, download: name } = $('download-cam');  // the plan and period of this click
  const period = $('cam-period');
  resetPeriodError();
  if (refuseUnreadablePeriod()) return;  // nothing is fetched or saved
  $('cam-note').textContent = 'Preparing the cam table…';
  try {
    const res = await send(href);
    const save = document.createElement('a');
    save.href = URL.createObjectURL(await res.blob());
    save.download = name;
    document.body.appendChild(save);
    save.click();
    save.remove();
    setTimeout(() => URL.revokeObjectURL(save.href), 60000);
    $('cam-note').textContent = `Saved ${name}`;
  } catch (e) {
    if (e instanceof ApiError) {
      period.setAttribute('aria-invalid', 'true');
      $('cam-period-error').textContent = e.message;
      $('cam-note').textContent = '';
    } else {
      $('cam-note').textContent = `The cam table could not be downloaded: ${e.message}`;
    }
  }
}

// A new period typed: the link takes it, or the input says it cannot be read.
export function periodTyped() {
  resetPeriodError();
  updateCamLink();
  refuseUnreadablePeriod();
}
