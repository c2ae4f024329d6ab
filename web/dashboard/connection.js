// The WebSocket /ws to the emulator (messages documented in docs/dashboard.md):
// connects, reconnects with back-off (the emulator may be restarted behind the
// same address), times and dispatches each message to the handler main.js
// registered for its type.
import { $ } from './dom.js';
import { showMessage } from './messages.js';
import { state } from './state.js';

const pill = $('#conn-state');
let ws = null;
let retryMs = 500;
let handlers = new Map();  // message type -> (message, its JSON text) => void

/** The control token of the page's URL (?token=..., printed by the emulator when
 *  the dashboard is reachable beyond loopback), or null. It goes with the
 *  WebSocket upgrade: without it this viewer may watch but not move nodes. */
export const controlToken = new URLSearchParams(location.search).get('token');

function setConn(s, detail = '') {
  state.conn = s;
  pill.dataset.state = s;
  pill.textContent = s === 'open' ? 'live' : s === 'connecting' ? 'connecting…'
    : `disconnected${detail}`;
}

/** Sends `msg` as JSON; false when not connected (the caller says so if it matters). */
export function send(msg) {
  if (ws && ws.readyState === WebSocket.OPEN) {
    ws.send(JSON.stringify(msg));
    return true;
  }
  return false;
}

/** Connects, and keeps reconnecting; `onType` maps message types to their handlers. */
export function connect(onType) {
  handlers = new Map(Object.entries(onType));
  open();
}

function open() {
  setConn('connecting');
  const proto = location.protocol === 'https:' ? 'wss:' : 'ws:';
  const query = controlToken ? `?token=${encodeURIComponent(controlToken)}` : '';
  const socket = new WebSocket(`${proto}//${location.host}/ws${query}`);
  ws = socket;
  socket.onopen = () => {
    setConn('open');
    retryMs = 500;
    // The server forgets what a viewer watched when the connection drops.
    if (state.selected != null) send({ type: 'watch', node: state.selected });
  };
  socket.onmessage = (ev) => {
    const t0 = performance.now();
    let m;
    try {
      m = JSON.parse(ev.data);
    } catch {
      showMessage('the server sent a message that is not JSON');
      return;
    }
    const t1 = performance.now();
    state.timings.add('parse', t1 - t0);
    dispatch(m, ev.data);
    state.timings.add(`handle_${m.type}`, performance.now() - t1);
  };
  socket.onclose = () => {
    if (ws !== socket) return;
    const wait = retryMs;
    retryMs = Math.min(5000, retryMs * 2);
    setConn('closed', ` – retrying in ${(wait / 1000).toFixed(1)} s`);
    setTimeout(open, wait);
  };
}

function dispatch(m, text) {
  if (m.type === 'error') {
    showMessage(`server: ${m.message}`);
    return;
  }
  const handler = handlers.get(m.type);  // unknown types: a newer server, ignored
  if (handler) handler(m, text);
}
