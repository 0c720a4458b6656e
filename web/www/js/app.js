// ecat-slave --http's page (docs/webview.md): one snapshot of the network
// 5 times a second and the control interface's events, both from GET
// /events; every action is one request of docs/control.md to POST /api.
import { el, hex, replace, portBadge } from './dom.js';
import { request, stream } from './api.js';
import { buildTopology, slaveLabel } from './topology.js';
import { renderDetail } from './slave_detail.js';
import { buildFaultForm, renderEngaged } from './faults.js';

const HISTORY = 150;  // samples per drive: 30 s at 5 Hz
const KEEP = 50;      // events in the log, emergencies and SDO writes per slave

const view = { snapshot: null, selected: 0, history: new Map(), emergencies: new Map(), sdoWrites: new Map(),
               events: [], topologyKey: '', formBuilt: false, lastFrames: null,
               pdo: { slave: -1, entries: [], asking: false } };
const $ = (id) => document.getElementById(id);

function report(text, bad = false) {
  const p = $('fault-result');
  p.textContent = text;
  p.className = bad ? 'code bad' : 'muted';
}

async function act(what, cmd, fields) {
  try {
    const r = await request(cmd, fields);
    report(`${what}: done`);
    return r;
  } catch (e) {
    report(`${what}: ${e.message}`, true);
    return null;
  }
}

const actions = {
  engage: (kind, slave, port, params) => act(`engage ${kind}`, 'fault_engage', { kind, slave, port, params }),
  clear: (fault) => act(`clear fault ${fault}`, 'fault_clear', { fault }),
  clearAll: () => act('clear all faults', 'fault_clear', { all: true }),
  setPdo: (slave, name, text) => {
    let value = text;
    try { value = JSON.parse(text); } catch { /* a string as typed */ }
    return act(`set ${name}`, 'pdo', { slave, name, value });
  },
};

// The plots' history is kept per axis of each drive ("slave/axis").
function axisKey(d) { return `${d.slave}/${d.axis}`; }

function push(map, key, item, limit = KEEP) {
  if (!map.has(key)) map.set(key, []);
  const list = map.get(key);
  list.push(item);
  if (list.length > limit) list.shift();
}

function describeEvent(e) {
  const who = e.slave !== undefined ? `#${e.slave} ` : '';
  switch (e.type) {
    case 'al_state': return `${who}AL ${e.from} \u2192 ${e.to}${e.error ? ` ERR ${hex(e.al_status_code)} ${e.al_status_code_text}` : ''}`;
    case 'al_control': return `${who}AL control requests ${e.requested}${e.error_ack ? ' (error ack)' : ''}`;
    case 'link': return `${who}port ${e.port} link ${e.up ? 'up' : 'down'}`;
    case 'sdo_write': return `${who}SDO write ${hex(e.index)}:${e.subindex} = ${JSON.stringify(e.value)}`;
    case 'emergency': return `${who}EMCY ${hex(e.error_code)} register ${hex(e.error_register, 2)}`;
    case 'fault_engaged': case 'fault_cleared':
      return `${e.type.replace('_', ' ')} ${e.kind} ${who}${e.port !== undefined ? `port ${e.port}` : ''}`;
    default: return `${e.type} ${JSON.stringify(e)}`;
  }
}

function onEvent(e) {
  if (e.type === 'emergency') push(view.emergencies, e.slave, e);
  if (e.type === 'sdo_write') push(view.sdoWrites, e.slave, e);
  view.events.push(e);
  if (view.events.length > KEEP) view.events.shift();
  const seconds = (e.time_ns / 1e9).toFixed(3);
  $('events').prepend(el('li', { 'data-type': e.type }, `${seconds} ${describeEvent(e)}`));
  while ($('events').children.length > KEEP) $('events').lastChild.remove();
}

function renderFrames(f, time) {
  const rate = view.lastFrames && time > view.lastFrames.time
    ? Math.round((f.received - view.lastFrames.received) / ((time - view.lastFrames.time) / 1e9)) : '-';
  view.lastFrames = { received: f.received, time };
  const rows = [['Frames received', f.received], ['Frames / s', rate], ['Returned', f.returned], ['Lost', f.lost],
                ['Malformed', f.malformed], ['Stale (too old)', f.stale], ['Datagrams', f.datagrams],
                ['Sum of WKCs', f.wkc_total]];
  replace($('frames'), rows.map(([k, v]) => el('tr', {}, el('td', {}, k), el('td', { class: 'num', 'data-frames': k }, v))));
  renderLateness(f);
}

// The master's cycle as the slaves see it (slave::CycleTiming): the period is
// the median interval between cycle starts, each interval sorted by how late
// it came against it. Bars with their counts as text, not length alone.
const LATENESS = [['early', 'early (< -10 %)'], ['on_time', 'on time (\u00b110 %)'],
                  ['late_10_25', 'late 10-25 %'], ['late_25_50', 'late 25-50 %'],
                  ['missed_1', '~1 cycle missed'],
                  ['missed_2_or_more', '2+ cycles missed']];

function renderLateness(f) {
  const period = f.cycle_period_ns > 0 ? `${(f.cycle_period_ns / 1e3).toFixed(1)} \u00b5s` : '-';
  const total = Math.max(1, LATENESS.reduce((n, [key]) => n + f.lateness[key], 0));
  const rows = [el('tr', {}, el('td', {}, 'Cycles'), el('td', { class: 'num', 'data-frames': 'cycles' }, f.cycles)),
                el('tr', {}, el('td', {}, 'Cycle period'), el('td', { class: 'num', 'data-frames': 'period' }, period))];
  for (const [key, label] of LATENESS) {
    const n = f.lateness[key];
    const bar = el('span', { class: `bar${key === 'on_time' ? '' : ' late'}` });
    bar.style.width = `${Math.round((100 * n) / total)}%`;
    rows.push(el('tr', { 'data-lateness': key }, el('td', {}, label),
                 el('td', { class: 'num' }, el('span', { class: 'barbox' }, bar), ` ${n}`)));
  }
  replace($('lateness'), rows);
}

function slaveCard(s) {
  const errors = s.ports.reduce((n, p) => n + p.rx_errors + p.invalid_frames + p.lost_links, 0);
  return el('div', { class: `card${s.position === view.selected ? ' selected' : ''}`, 'data-slave': s.position,
                     'data-state': s.al_state, role: 'button', tabindex: 0,
                     onclick: () => { view.selected = s.position; render(); } },
    slaveLabel(s), el('div', { class: 'muted' }, s.device),
    el('div', { class: `code${s.al_status_code ? ' bad' : ''}` }, `${hex(s.al_status_code)} ${s.al_status_code_text}`),
    el('div', { class: 'ports' }, s.ports.filter((p) => p.present).map(portBadge)),
    el('div', { class: 'muted' }, `port errors ${errors}, sync errors ${s.sync_errors}`));
}

// A card is replaced only when what it shows changed (so a click lands on it).
function renderSlaves(net) {
  const box = $('slaves');
  net.slaves.forEach((s, i) => {
    const shown = box.children[i];
    // application_cycles changes every cycle and is not on the card.
    const key = JSON.stringify([{ ...s, application_cycles: 0 }, s.position === view.selected]);
    if (shown && shown.dataset.key === key) return;
    const card = slaveCard(s);
    card.dataset.key = key;
    if (shown) shown.replaceWith(card); else box.append(card);
  });
  while (box.children.length > net.slaves.length) box.lastChild.remove();
}

function render() {
  const snap = view.snapshot;
  if (!snap) return;
  const net = snap.network;
  $('clock').textContent = `t = ${(snap.time_ns / 1e9).toFixed(1)} s, ${net.slaves.length} slaves`;
  const key = JSON.stringify([net.slaves.map((s) => [s.al_state, s.al_error, s.al_status_code, s.ports.map((p) => [p.link, p.peer])]),
                              snap.faults.map((f) => f.fault)]);
  if (key !== view.topologyKey) {
    view.topologyKey = key;
    const { tree, ring } = buildTopology(net, snap.faults, actions);
    replace($('topology'), tree);
    $('ring').textContent = ring;
    renderEngaged($('faults-engaged'), snap.faults, actions);
  }
  renderFrames(net.frames, snap.time_ns);
  renderSlaves(net);
  const s = net.slaves[view.selected];
  if (!s) return;
  $('detail-title').textContent = `Slave #${s.position} ${s.name}`;
  const drives = snap.drives.filter((d) => d.slave === s.position)
                            .map((d) => ({ drive: d, history: view.history.get(axisKey(d)) || [] }));
  renderDetail($('detail'), { slave: s, pdo: view.pdo.slave === s.position ? view.pdo.entries : [], drives,
                              emergencies: view.emergencies.get(s.position) || [],
                              sdoWrites: view.sdoWrites.get(s.position) || [], actions });
}

async function onSnapshot(snap) {
  view.snapshot = snap;
  for (const d of snap.drives) push(view.history, axisKey(d), d, HISTORY);
  if (!view.formBuilt) {
    view.formBuilt = true;
    const kinds = await request('fault_kinds').catch(() => null);
    if (kinds) buildFaultForm($('fault-form'), kinds.kinds, snap.network.slaves.length, actions);
  }
  render();
  // The process data of the slave shown: one "pdo" request, not part of the snapshot.
  if (!view.pdo.asking) {
    view.pdo.asking = true;
    const slave = view.selected;
    request('pdo', { slave }).then((r) => { view.pdo = { slave, entries: r.entries, asking: false }; },
                                   () => { view.pdo.asking = false; });
  }
}

function onState(up) {
  const c = $('connection');
  c.textContent = up ? 'live' : 'disconnected';
  c.className = `badge ${up ? 'on' : 'off'}`;
}

stream({ onSnapshot, onEvent, onState });
