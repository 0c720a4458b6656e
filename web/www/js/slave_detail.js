// One slave in full: identity, registers and error counters, process data
// (inputs editable, outputs read-only), emergencies and SDO writes, and the
// drive's state and plots.
import { el, hex, portBadge, replace } from './dom.js';
import { slaveLabel } from './topology.js';
import { driveSection } from './drive.js';

function identity(s) {
  const id = s.identity;
  return el('table', { class: 'kv' },
    [['Device', s.device], ['Vendor ID', hex(id.vendor_id, 8)], ['Product code', hex(id.product_code, 8)],
     ['Revision', hex(id.revision, 8)], ['Serial', id.serial], ['Station address', hex(s.station_address)],
     ['AL status code', `${hex(s.al_status_code)} ${s.al_status_code_text}`], ['AL control', hex(s.al_control)],
     ['DL status', hex(s.dl_status)], ['PU / PDI errors', `${s.processing_unit_errors} / ${s.pdi_errors}`],
     ['Sync errors', s.sync_errors],
     ['Watchdog', `${s.watchdog.process_data_ok ? 'ok' : 'EXPIRED'}, expiries ${s.watchdog.process_data_expiries}`],
     ['Application cycles', s.application_cycles]]
      .map(([k, v]) => el('tr', {}, el('td', {}, k), el('td', {}, v))));
}

function counters(s) {
  const head = el('tr', {}, ['Port', 'Link', 'Loop', 'Invalid', 'RX err', 'Fwd err', 'Lost links'].map((h) => el('th', {}, h)));
  const rows = s.ports.filter((p) => p.present).map((p) => el('tr', {},
    el('td', {}, p.port), el('td', {}, portBadge(p)), el('td', {}, p.loop_closed ? 'closed' : 'open'),
    [p.invalid_frames, p.rx_errors, p.forwarded_rx_errors, p.lost_links].map((v) => el('td', { class: 'num' }, v))));
  return el('div', { class: 'scroll' }, el('table', {}, head, rows));
}

function pdoTable(slave, entries, actions) {
  const head = el('tr', {}, ['Entry', 'Dir', 'Object', 'Bits', 'Value', 'Set'].map((h) => el('th', {}, h)));
  const rows = entries.map((e) => {
    const input = e.direction === 'tx' ? el('input', { type: 'text', 'aria-label': `new value of ${e.name}` }) : null;
    const set = input ? el('button', { onclick: () => actions.setPdo(slave, `${e.pdo_name}/${e.name}`, input.value) }, 'Set') : null;
    return el('tr', {},
      el('td', {}, e.name), el('td', {}, e.direction === 'tx' ? 'input' : 'output'),
      el('td', {}, `${hex(e.index)}:${e.subindex}`), el('td', { class: 'num' }, e.bit_length),
      el('td', { class: 'num', 'data-entry': e.name }, JSON.stringify(e.value)),
      el('td', {}, input ? [input, ' ', set] : el('span', { class: 'muted' }, 'read-only')));
  });
  return el('div', { class: 'scroll' }, el('table', {}, head, rows));
}

function recent(title, items, format) {
  return [el('h3', {}, title),
          items.length ? el('ul', { class: 'list log' }, items.slice(-8).reverse().map((e) => el('li', {}, format(e))))
                       : el('p', { class: 'muted' }, 'none yet')];
}

// Rebuilt at each snapshot, except the input fields the user is typing in.
export function renderDetail(box, ctx) {
  const { slave: s, pdo, drives, emergencies, sdoWrites, actions } = ctx;
  const typing = box.querySelector('input:focus');
  if (typing) {  // update the values only
    for (const e of pdo) {
      const cell = box.querySelector(`[data-entry="${CSS.escape(e.name)}"]`);
      if (cell) cell.textContent = JSON.stringify(e.value);
    }
    return;
  }
  replace(box,
    el('div', {}, slaveLabel(s)),
    el('div', { class: 'plots' }, el('div', {}, el('h3', {}, 'Identity and registers'), identity(s)),
       el('div', {}, el('h3', {}, 'Ports and error counters'), counters(s))),
    drives.map(({ drive, history }) => driveSection(drive, history, drives.length > 1)),
    el('h3', {}, 'Process data'), pdo.length ? pdoTable(s.position, pdo, actions) : el('p', { class: 'muted' }, 'no process data'),
    el('div', { class: 'plots' },
       el('div', {}, recent('Emergencies', emergencies, (e) => `${hex(e.error_code)} register ${hex(e.error_register, 2)}`)),
       el('div', {}, recent('SDO writes by the master', sdoWrites, (e) => `${hex(e.index)}:${e.subindex} = ${JSON.stringify(e.value)}`))));
}
