// The fault catalogue (docs/faults.md) from "fault_kinds": any kind engaged
// with its slave, port and parameters; the engaged ones listed with Clear.
import { el, replace } from './dom.js';

export function buildFaultForm(form, kinds, slaveCount, actions) {
  const kindSelect = el('select', { id: 'fault-kind', name: 'kind' },
    kinds.map((k) => el('option', { value: k.name }, k.name)));
  const fields = el('div');
  const describe = el('p', { class: 'muted' });
  const redraw = () => {
    const k = kinds.find((x) => x.name === kindSelect.value);
    describe.textContent = k.description;
    const parts = [];
    if (k.takes_slave || k.needs_slave) {
      parts.push(el('label', {}, `Slave${k.needs_slave ? '' : ' (optional)'} `,
        el('select', { name: 'slave' }, k.needs_slave ? null : el('option', { value: '' }, 'none'),
           Array.from({ length: slaveCount }, (_, i) => el('option', { value: i }, `#${i}`)))));
    }
    if (k.needs_port) {
      parts.push(el('label', {}, 'Port ', el('select', { name: 'port' }, [0, 1, 2, 3].map((p) => el('option', { value: p }, p)))));
    }
    for (const p of k.params) {
      parts.push(el('label', {}, `${p.name}${p.required ? ' (required)' : ''} `,
        el('input', { type: 'text', name: `param-${p.name}`, required: p.required }),
        el('span', { class: 'hint' }, p.meaning)));
    }
    replace(fields, parts);
  };
  kindSelect.addEventListener('change', redraw);
  replace(form, el('label', {}, 'Kind ', kindSelect), describe, fields,
          el('button', { type: 'submit', id: 'fault-engage', class: 'danger' }, 'Engage'));
  form.onsubmit = (ev) => {
    ev.preventDefault();
    const data = new FormData(form);
    const params = {};
    for (const [key, value] of data.entries()) {
      if (key.startsWith('param-') && value !== '') params[key.slice(6)] = Number.isNaN(Number(value)) ? value : Number(value);
    }
    const slave = data.get('slave');
    const port = data.get('port');
    actions.engage(data.get('kind'), slave === null || slave === '' ? undefined : Number(slave),
                   port === null ? undefined : Number(port), params);
  };
  redraw();
}

export function renderEngaged(list, faults, actions) {
  const items = faults.map((f) => el('li', { 'data-fault': f.fault },
    `${f.kind}`, f.slave !== undefined ? ` slave #${f.slave}` : '', f.port !== undefined ? ` port ${f.port}` : '',
    Object.keys(f.params).length ? ` ${JSON.stringify(f.params)}` : '', ' ',
    el('button', { onclick: () => actions.clear(f.fault) }, 'Clear')));
  if (faults.length > 1) items.push(el('li', {}, el('button', { onclick: () => actions.clearAll() }, 'Clear all')));
  replace(list, items.length ? items : [el('li', { class: 'muted' }, 'no fault engaged')]);
}
