// Small DOM helpers: elements built with textContent only (names come from
// device files: never parsed as HTML).
export function el(tag, attrs = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (v === undefined || v === null || v === false) continue;
    if (k.startsWith('on')) e.addEventListener(k.slice(2), v);
    else if (k === 'class') e.className = v;
    else e.setAttribute(k, v === true ? '' : String(v));
  }
  for (const c of children.flat()) {
    if (c === null || c === undefined || c === false) continue;
    e.append(c instanceof Node ? c : document.createTextNode(String(c)));
  }
  return e;
}

export function hex(n, digits = 4) {
  return typeof n === 'number' ? '0x' + n.toString(16).toUpperCase().padStart(digits, '0') : String(n);
}

export function replace(parent, ...children) {
  parent.replaceChildren(...children.flat().filter((c) => c));
}

// An AL state badge: colour and the state's name, "+ERR" with the error flag.
export function stateBadge(slave) {
  const text = slave.al_state + (slave.al_error ? ' +ERR' : '');
  return el('span', { class: `badge state-${slave.al_state}${slave.al_error ? ' error' : ''}`, 'data-state': slave.al_state }, text);
}

// A port's link: a filled or open dot AND the word.
export function portBadge(p) {
  const up = p.link;
  return el('span', { class: `port ${up ? 'up' : 'down'}`, 'data-port': p.port, 'data-link': up ? 'up' : 'down',
                      title: `DL status port ${p.port}: link ${up ? 'up' : 'down'}, loop ${p.loop_closed ? 'closed' : 'open'}` },
            `P${p.port} ${up ? 'up' : 'down'}`);
}
