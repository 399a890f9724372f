// Pieces of the page both viewers use (one run, runs side by side): a
// labelled select, the run's events and their marks under the time slider.
import { eventColours } from './plots.js';

// A labelled select in the header's controls; `onChange(value)`.
export function addSelect(container, labelText, options, value, onChange, id) {
  const label = document.createElement('label');
  label.textContent = `${labelText} `;
  const select = document.createElement('select');
  if (id) select.id = id;
  for (const [key, text] of options) {
    const option = document.createElement('option');
    option.value = key;
    option.textContent = text;
    select.append(option);
  }
  select.value = value;
  select.addEventListener('change', () => onChange(select.value));
  label.append(select);
  container.append(label);
  return select;
}

// The run's events (its summary.json), as {t, kind, detail}.
export function runEvents(manifest) {
  if (typeof manifest.summary !== 'string') return [];
  let summary;
  try {
    summary = JSON.parse(manifest.summary);
  } catch (error) {
    console.error(`the run's summary.json is not JSON (${error.message}): no events shown`);
    return [];
  }
  const events = Array.isArray(summary.events) ? summary.events : [];
  return events.filter((e) => e && Number.isFinite(e.t) && typeof e.kind === 'string')
    .map((e) => ({ t: e.t, kind: e.kind, detail: typeof e.detail === 'string' ? e.detail : '' }));
}

// Marks under the time slider, one per event: a click goes to its time.
export function addEventMarks(events, end, seek) {
  const marks = document.getElementById('marks');
  const colours = eventColours(events);
  for (const e of events) {
    const mark = document.createElement('button');
    mark.className = 'mark';
    mark.style.left = `${(100 * e.t) / Math.max(end, 1e-9)}%`;
    mark.style.background = colours[e.kind];
    mark.title = `${e.t.toFixed(3)} s: ${e.kind.replace(/_/g, ' ')}${e.detail ? ' (' + e.detail + ')' : ''}`;
    mark.dataset.t = String(e.t);
    mark.dataset.kind = e.kind;
    mark.addEventListener('click', () => seek(e.t));
    marks.append(mark);
  }
}

// The t= parameter (s), 0 when absent or not a number (said through `warn`).
export function startTimeOf(parameters, warn) {
  const t = Number(parameters.get('t') || 0);
  if (Number.isFinite(t)) return t;
  warn(`t=${parameters.get('t')}: not a number of seconds; opening at 0 s`);
  return 0;
}

// The speed= parameter (times real time), 1 when absent or not positive.
export function speedOf(parameters, warn) {
  const speed = Number(parameters.get('speed') || 1);
  if (speed > 0 && Number.isFinite(speed)) return speed;
  warn(`speed=${parameters.get('speed')}: not a positive number (times real time); playing at 1`);
  return 1;
}
