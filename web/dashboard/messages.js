// Messages above the panels (errors from the server, refused moves). A repeat
// of the newest message bumps its counter instead of stacking another box, so
// a server refusing every move of a drag shows one line, not dozens.
import { $, el } from './dom.js';
import { state } from './state.js';

const list = $('#messages');

export function showMessage(text, kind = 'error', ttlMs = 10000) {
  state.messages.push({ text, kind, at: Date.now() });
  if (state.messages.length > 50) state.messages.shift();
  const last = list.lastElementChild;
  if (last && last.dataset.text === text) {
    const count = $('.count', last);
    const n = Number(last.dataset.count) + 1;
    last.dataset.count = n;
    count.textContent = `×${n}`;
    clearTimeout(last._timer);
    last._timer = setTimeout(() => last.remove(), ttlMs);
    return;
  }
  const close = el('button', { type: 'button', title: 'dismiss' }, '×');
  const box = el('div', { class: `msg ${kind}`, role: kind === 'error' ? 'alert' : 'status',
    dataset: { text, count: 1 } },
  el('span', { class: 'text' }, text), el('span', { class: 'count' }), close);
  close.addEventListener('click', () => box.remove());
  box._timer = setTimeout(() => box.remove(), ttlMs);
  list.append(box);
  while (list.children.length > 5) list.firstElementChild.remove();
}
