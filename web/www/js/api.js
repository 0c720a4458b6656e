// The control interface over HTTP: POST /api (one request of docs/control.md,
// the RequestHandler's reply) and GET /events (server-sent events).
export class ControlError extends Error {
  constructor(code, message) { super(`${code}: ${message}`); this.code = code; }
}

export async function request(cmd, fields = {}) {
  const r = await fetch('api', { method: 'POST', headers: { 'Content-Type': 'application/json' },
                                 body: JSON.stringify({ cmd, ...fields }) });
  const reply = await r.json();
  if (reply.error) throw new ControlError(reply.error.code, reply.error.message);
  return reply.result;
}

// Calls onSnapshot(snapshot) and onEvent(event); onState(true/false) as the stream opens and drops
// (EventSource reconnects by itself).
export function stream({ onSnapshot, onEvent, onState }) {
  const source = new EventSource('events');
  source.addEventListener('open', () => onState(true));
  source.addEventListener('error', () => onState(false));
  source.addEventListener('snapshot', (m) => onSnapshot(JSON.parse(m.data)));
  source.addEventListener('event', (m) => onEvent(JSON.parse(m.data)));
  return source;
}
