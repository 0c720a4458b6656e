// CiA 402 (IEC 61800-7-201): the state from the statusword, the mode's name,
// and the plots of demand and actual values.
import { el } from './dom.js';
import { drawPlot } from './plot.js';

// Statusword bits 0-3, 5, 6 (mask, value, state).
const STATES = [
  [0x4f, 0x00, 'Not ready to switch on'], [0x4f, 0x40, 'Switch on disabled'],
  [0x6f, 0x21, 'Ready to switch on'], [0x6f, 0x23, 'Switched on'], [0x6f, 0x27, 'Operation enabled'],
  [0x6f, 0x07, 'Quick stop active'], [0x4f, 0x0f, 'Fault reaction active'], [0x4f, 0x08, 'Fault'],
];
const MODES = { 1: 'Profile position', 3: 'Profile velocity', 4: 'Profile torque', 6: 'Homing',
                7: 'Interpolated position', 8: 'Cyclic sync position', 9: 'Cyclic sync velocity', 10: 'Cyclic sync torque' };

export function cia402State(sw) {
  if (typeof sw !== 'number') return 'unknown';
  const s = STATES.find(([mask, value]) => (sw & mask) === value);
  return s ? s[2] : 'unknown';
}
export function modeName(m) { return typeof m === 'number' ? `${MODES[m] || 'mode'} (${m})` : 'unknown'; }

const PLOTS = [['Position', 'position_demand', 'position_actual'], ['Velocity', 'velocity_demand', 'velocity_actual'],
               ['Torque', 'torque_demand', 'torque_actual']];

// One section per axis; `numbered` titles it with the axis when the drive has several.
export function driveSection(drive, history, numbered) {
  const state = cia402State(drive.statusword);
  const canvases = PLOTS.map(([title, d, a]) => {
    const c = el('canvas', { 'aria-label': `${title}: demand and actual over the last seconds` });
    return { c, title, d, a };
  });
  const box = el('div', { 'data-axis': String(drive.axis) },
    el('h3', {}, numbered ? `Axis ${drive.axis} (CiA 402)` : 'Drive (CiA 402)'),
    el('table', { class: 'kv' },
      el('tr', {}, el('td', {}, 'State'), el('td', { 'data-cia402': state, class: state === 'Fault' ? 'code bad' : '' }, state)),
      el('tr', {}, el('td', {}, 'Mode'), el('td', {}, modeName(drive.mode))),
      el('tr', {}, el('td', {}, 'Statusword'), el('td', {}, typeof drive.statusword === 'number' ? '0x' + drive.statusword.toString(16).padStart(4, '0') : '-'))),
    el('p', { class: 'legend' }, el('span', { class: 'demand' }, '\u2014 demand'), ' ', el('span', { class: 'actual' }, '\u2014 actual'),
       ` (last ${Math.round(history.length / 5)} s)`),
    el('div', { class: 'plots' }, canvases.map(({ c, title }) => el('div', {}, el('div', {}, title), c))));
  requestAnimationFrame(() => canvases.forEach(({ c, d, a }) => drawPlot(c, history, d, a)));
  return box;
}
