// The topology as a tree: from the slave cabled to the master's port 0,
// through ports in the ESC's processing order (0, 3, 1, 2), each cable with
// its link state and a button that cuts or restores it (fault link_cut).
import { el, stateBadge, portBadge } from './dom.js';

const PORT_ORDER = [0, 3, 1, 2];

function cutFault(faults, slave, port, peer) {
  return faults.find((f) => f.kind === 'link_cut' &&
    ((f.slave === slave && f.port === port) || (peer && f.slave === peer.slave && f.port === peer.port)));
}

function cableButton(faults, slave, port, peer, actions) {
  const f = cutFault(faults, slave, port, peer);
  if (f) {
    return el('button', { class: 'restore', 'data-slave': slave, 'data-port': port,
                          onclick: () => actions.clear(f.fault) }, 'Restore cable');
  }
  return el('button', { class: 'cut danger', 'data-slave': slave, 'data-port': port,
                        onclick: () => actions.engage('link_cut', slave, port, {}) }, 'Cut cable');
}

export function slaveLabel(s) {
  return [el('strong', {}, `#${s.position} ${s.name}`), ' ', stateBadge(s),
          s.al_status_code ? el('span', { class: 'code bad' }, ` ${s.al_status_code_text}`) : null];
}

// Returns {tree: <li> elements, ring: text}. A line reads as a list, not a
// staircase: the cable a slave passes frames on last (in processing order)
// continues at the same level; the branches before it (a junction's port 3,
// ...) are indented under the slave.
export function buildTopology(net, faults, actions) {
  const slaves = net.slaves;
  const visited = new Set();
  let ring = 'line: no cable back to the master (no ring)';
  // The slave and what follows it at its level: a list of <li>.
  const node = (i, inPort) => {
    visited.add(i);
    const s = slaves[i];
    const ports = s.ports.filter((p) => p.present);
    const li = el('li', { 'data-slave': i }, slaveLabel(s), el('div', { class: 'ports' }, ports.map(portBadge)));
    const onward = PORT_ORDER.filter((port) => port !== inPort && s.ports[port].peer &&
                                     s.ports[port].peer.slave !== undefined);
    const flatPort = onward.length ? onward[onward.length - 1] : -1;
    const kids = [];
    let continuation = [];
    for (const port of PORT_ORDER) {
      const p = s.ports[port];
      if (port === inPort || !p.peer) continue;
      if (p.peer.master !== undefined) {
        ring = p.link ? `ring: closed through #${i} port ${port} to master port ${p.peer.master}`
                      : `ring: cut at #${i} port ${port} (to master port ${p.peer.master})`;
        kids.push(el('li', {}, el('span', { class: 'via' }, `port ${port} \u2192 master port ${p.peer.master} `),
                     p.link ? null : el('span', { class: 'cut' }, '\u2702 cut ')));
        continue;
      }
      const via = el('span', { class: 'via' }, `port ${port} \u2192 #${p.peer.slave} port ${p.peer.port} `);
      const state = p.link ? null : el('span', { class: 'cut', 'data-cut': `${i}:${port}` }, '\u2702 cut ');
      const button = cableButton(faults, i, port, p.peer, actions);
      if (visited.has(p.peer.slave)) {
        kids.push(el('li', {}, via, state, button, el('span', { class: 'via' }, ' (closes a loop)')));
        continue;
      }
      const chain = node(p.peer.slave, p.peer.port);
      chain[0].prepend(el('div', {}, via, state, button));
      if (port === flatPort) continuation = chain;
      else kids.push(...chain);
    }
    if (kids.length) li.append(el('ul', {}, kids));
    return [li, ...continuation];
  };
  const first = slaves.findIndex((s) => s.ports.some((p) => p.peer && p.peer.master === 0));
  const tree = [];
  if (first >= 0) {
    const chain = node(first, slaves[first].ports.findIndex((p) => p.peer && p.peer.master === 0));
    chain[0].prepend(el('div', { class: 'via' }, 'master port 0 \u2192'));
    tree.push(...chain);
  }
  slaves.forEach((s, i) => { if (!visited.has(i)) tree.push(...node(i, -1)); });
  return { tree, ring };
}
