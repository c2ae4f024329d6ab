// rfsitl live dashboard. Plain browser JavaScript, no dependencies: it talks to
// the emulator's WebSocket /ws (messages documented in docs/dashboard.md) and
// draws the map, link matrix, spectrum, waterfall and constellation on canvases.
//
// Performance rules (64 nodes = 4032 directed links at 4 snapshots/s):
//   * the DOM is built once per node set; snapshots only change text nodes;
//   * drawing happens in one requestAnimationFrame per burst of messages;
//   * map links are batched by style so a frame strokes a few dozen paths;
//   * the matrix is one N x N ImageData scaled up by drawImage.
'use strict';

(() => {
  // ---- constants ----------------------------------------------------------------
  const ACTIVE_MS = 2000;  // a link "carried frames recently" for this long
  const LOSS_REASONS = ['below_sensitivity', 'collision', 'half_duplex', 'decode_failure',
    'unknown_destination'];
  const CONTROL_OFF_TEXT = 'moving nodes is off; start with --dashboard-control';
  const MOVE_SEND_INTERVAL_MS = 100;
  const HISTORY_POINTS = 480;  // 2 minutes at 4 snapshots/s
  const WATERFALL_ROWS = 80;  // 20 s at 4 spectra/s
  const BG_RGB = [11, 15, 20];
  const PHY_COLOURS = {
    gmsk: '#4fc3f7', 'gmsk-liquid': '#7fd8a4', ofdm: '#ffb74d', dsss: '#c792ea',
    external: '#e8e8e8',
  };

  // ---- colour scale (own design: violet -> blue -> teal -> green -> gold) ------------
  const STOPS = [
    [0.00, [40, 18, 78]], [0.20, [56, 78, 186]], [0.42, [32, 152, 172]],
    [0.62, [72, 196, 112]], [0.80, [192, 222, 64]], [1.00, [255, 226, 84]],
  ];
  const LUT = [];      // 256 x [r, g, b]
  const LUT_CSS = [];  // 256 x 'rgb(...)'
  for (let i = 0; i < 256; ++i) {
    const t = i / 255;
    let s = 1;
    while (s < STOPS.length - 1 && STOPS[s][0] < t) ++s;
    const [t0, c0] = STOPS[s - 1];
    const [t1, c1] = STOPS[s];
    const f = (t - t0) / (t1 - t0);
    const rgb = c0.map((v, j) => Math.round(v + (c1[j] - v) * f));
    LUT.push(rgb);
    LUT_CSS.push(`rgb(${rgb[0]},${rgb[1]},${rgb[2]})`);
  }
  const dimRgb = (rgb) => rgb.map((v, j) => Math.round(v * 0.34 + BG_RGB[j] * 0.66));
  const cssGradient = (dim) => {
    const parts = [];
    for (let i = 0; i <= 16; ++i) {
      const rgb = LUT[Math.round(i * 255 / 16)];
      const c = dim ? dimRgb(rgb) : rgb;
      parts.push(`rgb(${c[0]},${c[1]},${c[2]}) ${(i * 100 / 16).toFixed(1)}%`);
    }
    return `linear-gradient(to right, ${parts.join(', ')})`;
  };

  // ---- helpers ----------------------------------------------------------------------
  const $ = (sel, root = document) => root.querySelector(sel);
  const clamp = (v, lo, hi) => Math.max(lo, Math.min(hi, v));
  const el = (tag, props = {}, ...children) => {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(props)) {
      if (k === 'class') e.className = v;
      else if (k === 'dataset') Object.assign(e.dataset, v);
      else if (k in e) e[k] = v;
      else e.setAttribute(k, v);
    }
    for (const c of children) e.append(c);
    return e;
  };
  const phyColour = (phy) => {
    if (PHY_COLOURS[phy]) return PHY_COLOURS[phy];
    let h = 0;
    for (const ch of String(phy)) h = (h * 31 + ch.charCodeAt(0)) % 360;
    return `hsl(${h},65%,68%)`;
  };
  const fmtClock = (s) => {
    if (s == null || !Number.isFinite(s)) return '–';
    if (s < 60) return `${s.toFixed(2)} s`;
    const h = Math.floor(s / 3600);
    const m = Math.floor((s % 3600) / 60);
    const sec = (s % 60).toFixed(1).padStart(4, '0');
    return h > 0 ? `${h}:${String(m).padStart(2, '0')}:${sec}` : `${m}:${sec}`;
  };
  const fmtSeconds = (s) => {
    if (s == null || !Number.isFinite(s)) return '–';
    const a = Math.abs(s);
    if (a < 1e-3) return `${(s * 1e6).toFixed(0)} µs`;
    if (a < 1) return `${(s * 1e3).toFixed(1)} ms`;
    return `${s.toFixed(2)} s`;
  };
  const fmtMetres = (m) => (Math.abs(m) >= 1000 ? `${(m / 1000).toPrecision(3)} km`
    : `${Number(m.toPrecision(3))} m`);
  const fmtHz = (hz) => {
    const a = Math.abs(hz);
    if (a >= 1e6) return `${Number((hz / 1e6).toPrecision(3))} MHz`;
    if (a >= 1e3) return `${Number((hz / 1e3).toPrecision(3))} kHz`;
    return `${Number(hz.toPrecision(3))} Hz`;
  };
  /// A usable position (the server sends null coordinates for non-finite ones).
  const posOk = (p) => !!p && Number.isFinite(p.x) && Number.isFinite(p.y) && Number.isFinite(p.z);
  const niceStep = (raw) => {
    const p = 10 ** Math.floor(Math.log10(raw));
    const f = raw / p;
    return (f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10) * p;
  };

  /// A canvas that follows its box's CSS size at the device pixel ratio.
  class Surface {
    constructor(box, onResize) {
      this.box = box;
      this.canvas = $('canvas', box);
      this.ctx = this.canvas.getContext('2d');
      this.w = 0;
      this.h = 0;
      this.dpr = 1;
      this.onResize = onResize;
      new ResizeObserver(() => { if (this.fit()) this.onResize(); }).observe(box);
      this.fit();
    }
    /// Matches the backing store to the CSS size; true when it changed.
    fit(cssW = this.box.clientWidth, cssH = this.box.clientHeight) {
      const dpr = window.devicePixelRatio || 1;
      if (cssW === this.w && cssH === this.h && dpr === this.dpr) return false;
      this.w = cssW;
      this.h = cssH;
      this.dpr = dpr;
      this.canvas.width = Math.max(1, Math.round(cssW * dpr));
      this.canvas.height = Math.max(1, Math.round(cssH * dpr));
      return true;
    }
    begin() {
      const { ctx } = this;
      ctx.setTransform(this.dpr, 0, 0, this.dpr, 0, 0);
      ctx.clearRect(0, 0, this.w, this.h);
      return ctx;
    }
  }

  /// Mean / p95 / max of the last few hundred samples of each timing.
  class Timings {
    constructor() { this.series = new Map(); }
    add(name, ms) {
      let s = this.series.get(name);
      if (!s) this.series.set(name, (s = []));
      s.push(ms);
      if (s.length > 400) s.shift();
    }
    summary() {
      const out = {};
      for (const [name, s] of this.series) {
        const sorted = [...s].sort((a, b) => a - b);
        const mean = s.reduce((a, b) => a + b, 0) / s.length;
        out[name] = {
          n: s.length, mean: +mean.toFixed(3),
          p95: +sorted[Math.min(sorted.length - 1, Math.floor(sorted.length * 0.95))].toFixed(3),
          max: +sorted[sorted.length - 1].toFixed(3),
        };
      }
      return out;
    }
  }

  // ---- state ---------------------------------------------------------------------------
  const state = {
    ws: null,
    conn: 'connecting',
    retryMs: 500,
    hello: null,
    helloText: null,
    snap: null,
    snapText: null,
    ids: [],            // node ids in `nodes` order
    indexOf: new Map(), // id -> index
    control: null,      // null until known
    selected: null,     // node id
    spectrum: null,
    constellation: null,
    snrLo: -10,
    snrHi: 60,
    activeRx: new Float64Array(0),    // per directed link: time of the last decoded-frame increase
    activeLost: new Float64Array(0),  // ... and of the last lost-frame increase
    history: [],        // {t, delivered, lost, received}
    linkWindow: [],     // {t, received, lost}: per-link counts over the last ACTIVE_MS
    drag: null,         // pointer gesture on the map
    overrides: new Map(),  // id -> {x, y, z, until}: where the viewer put a node
    hover: null,        // node id under the pointer (map)
    matrixHover: null,  // [tx, rx] index
    view: { cx: 0, cy: 0, scale: 10 },
    autoFit: true,
    messages: [],
    timings: new Timings(),
    specHi: 40,
  };

  // ---- DOM references -------------------------------------------------------------------
  const ui = {
    scenario: $('#scenario'), virtual: $('#virtual-time'), wall: $('#wall-time'), lag: $('#lag'),
    lateTicks: $('#late-ticks'), lateDecodes: $('#late-decodes'), conn: $('#conn-state'),
    control: $('#control-state'), messages: $('#messages'), mapHint: $('#map-hint'),
    mapTip: $('#map-tooltip'), mapInfo: $('#map-info'), linkFilter: $('#link-filter'),
    unknown: $('#unknown-nodes'), matrixTip: $('#matrix-tooltip'), tbody: $('#node-table tbody'),
    selNode: $('#selected-node'), selInfo: $('#selected-info'), unwatch: $('#unwatch'),
    specInfo: $('#spectrum-info'), constMeta: $('#constellation-meta'),
    totals: $('#traffic-totals'), mapHelp: $('#map-help'),
  };
  for (const bar of document.querySelectorAll('.snr-bar')) {
    bar.style.background = cssGradient(bar.classList.contains('dim'));
  }

  const setText = (node, text) => { if (node.textContent !== text) node.textContent = text; };

  // ---- rendering scheduler -----------------------------------------------------------------
  const dirty = new Set();
  let frameRequested = false;
  const requestDraw = (...what) => {
    for (const w of what) dirty.add(w);
    if (!frameRequested) {
      frameRequested = true;
      requestAnimationFrame(drawFrame);
    }
  };
  const drawers = {};
  function drawFrame() {
    frameRequested = false;
    const todo = [...dirty];
    dirty.clear();
    const t0 = performance.now();
    for (const what of todo) {
      const s = performance.now();
      drawers[what]();
      state.timings.add(`draw_${what}`, performance.now() - s);
    }
    state.timings.add('frame', performance.now() - t0);
  }

  // ---- messages (errors from the server, hints) ------------------------------------------------
  function showMessage(text, kind = 'error', ttlMs = 10000) {
    state.messages.push({ text, kind, at: Date.now() });
    if (state.messages.length > 50) state.messages.shift();
    const last = ui.messages.lastElementChild;
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
    ui.messages.append(box);
    while (ui.messages.children.length > 5) ui.messages.firstElementChild.remove();
  }

  let hintTimer = 0;
  function showHint(text, ms = 3500) {
    ui.mapHint.textContent = text;
    ui.mapHint.hidden = false;
    clearTimeout(hintTimer);
    hintTimer = setTimeout(() => { ui.mapHint.hidden = true; }, ms);
  }

  // ---- WebSocket ------------------------------------------------------------------------------
  function setConn(s, detail = '') {
    state.conn = s;
    ui.conn.dataset.state = s;
    ui.conn.textContent = s === 'open' ? 'live' : s === 'connecting' ? 'connecting…'
      : `disconnected${detail}`;
  }

  function send(msg) {
    if (state.ws && state.ws.readyState === WebSocket.OPEN) {
      state.ws.send(JSON.stringify(msg));
      return true;
    }
    return false;
  }

  function connect() {
    setConn('connecting');
    const proto = location.protocol === 'https:' ? 'wss:' : 'ws:';
    const ws = new WebSocket(`${proto}//${location.host}/ws`);
    state.ws = ws;
    ws.onopen = () => {
      setConn('open');
      state.retryMs = 500;
      if (state.selected != null) send({ type: 'watch', node: state.selected });
    };
    ws.onmessage = (ev) => {
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
      onMessage(m, ev.data);
      state.timings.add(`handle_${m.type}`, performance.now() - t1);
    };
    ws.onclose = () => {
      if (state.ws !== ws) return;
      const wait = state.retryMs;
      state.retryMs = Math.min(5000, state.retryMs * 2);
      setConn('closed', ` – retrying in ${(wait / 1000).toFixed(1)} s`);
      setTimeout(connect, wait);
    };
  }

  function onMessage(m, text) {
    switch (m.type) {
      case 'hello':
        state.hello = m;
        state.helloText = text;
        setText(ui.scenario, m.scenario || '–');
        document.title = `rfsitl · ${m.scenario}`;
        setControl(!!m.control);
        setNodes(m.node_ids || []);
        break;
      case 'snapshot':
        onSnapshot(m, text);
        break;
      case 'spectrum':
        if (m.node === state.selected) {
          state.spectrum = m;
          pushWaterfall(m.bins_db);
          requestDraw('spectrum', 'waterfall');
        }
        break;
      case 'constellation':
        if (m.node === state.selected) {
          state.constellation = m;
          updateConstellationMeta();
          requestDraw('constellation');
        }
        break;
      case 'error':
        showMessage(`server: ${m.message}`);
        break;
      default:
        break;
    }
  }

  function setControl(on) {
    if (state.control === on) return;
    state.control = on;
    ui.control.dataset.control = on ? 'on' : 'off';
    ui.control.textContent = on ? 'moving nodes allowed (drag a node on the map)' : CONTROL_OFF_TEXT;
    ui.mapHelp.textContent = on
      ? 'Click a node to watch it. Drag a node to move it. Wheel zooms, dragging the background pans.'
      : `Click a node to watch it. ${CONTROL_OFF_TEXT[0].toUpperCase()}${CONTROL_OFF_TEXT.slice(1)}. `
        + 'Wheel zooms, dragging the background pans.';
    mapSurface.canvas.classList.toggle('movable', on);
  }

  // ---- node set and table ---------------------------------------------------------------------
  const COLUMNS = [
    ['handed_in', (n) => n.handed_in],
    ['transmitted', (n) => n.transmitted],
    ['delivered', (n) => n.delivered],
    ['lost', (n) => LOSS_REASONS.reduce((a, r) => a + (n.lost?.[r] ?? 0), 0)],
    ...LOSS_REASONS.map((r) => [`lost-${r}`, (n) => n.lost?.[r] ?? 0]),
    ['queue_dropped', (n) => n.queue_dropped],
    ['queue_depth', (n) => n.queue_depth],
    ['received', (n) => n.received],
    ['rx_crc_failures', (n) => n.rx_crc_failures],
  ];
  const rows = new Map();  // id -> {tr, phy, phyDot, position, cells: [{td, text, value}]}

  function setNodes(ids) {
    const same = ids.length === state.ids.length && ids.every((id, i) => id === state.ids[i]);
    if (same) return;
    state.ids = ids.slice();
    state.indexOf = new Map(ids.map((id, i) => [id, i]));
    const n2 = ids.length * ids.length;
    state.activeRx = new Float64Array(n2);
    state.activeLost = new Float64Array(n2);
    state.history = [];
    state.linkWindow = [];
    rows.clear();
    const frag = document.createDocumentFragment();
    for (const id of ids) {
      const tr = el('tr', { dataset: { node: id } });
      const idTd = el('td', { class: 'id' }, String(id));
      const phyDot = el('span', { class: 'phy-dot' });
      const phyText = document.createTextNode('–');
      const phyTd = el('td', { class: 'phy' }, phyDot, phyText);
      const posText = document.createTextNode('–');
      const posTd = el('td', { class: 'position' }, posText);
      tr.append(idTd, phyTd, posTd);
      const cells = COLUMNS.map(([key]) => {
        const text = document.createTextNode('–');
        const td = el('td', { class: key.startsWith('lost-') ? `${key} lost-reason` : key }, text);
        tr.append(td);
        return { td, text, value: null };
      });
      tr.addEventListener('click', () => select(id));
      rows.set(id, { tr, phyText, phyDot, phy: null, posText, pos: '', cells });
      frag.append(tr);
    }
    ui.tbody.replaceChildren(frag);
    if (state.selected != null && !state.indexOf.has(state.selected)) select(null);
    layoutMatrix();
    requestDraw('map', 'matrix', 'traffic');
  }

  const FLASH = [{ backgroundColor: 'rgba(255, 214, 90, 0.55)' }, { backgroundColor: 'rgba(255, 214, 90, 0)' }];
  function updateTable(nodes) {
    for (const n of nodes) {
      const row = rows.get(n.id);
      if (!row) continue;
      if (row.phy !== n.phy) {
        row.phy = n.phy;
        row.phyText.data = n.phy;
        row.phyDot.style.background = phyColour(n.phy);
      }
      const p = n.position;
      const pos = posOk(p) ? `${p.x.toFixed(1)}, ${p.y.toFixed(1)}, ${p.z.toFixed(1)}`
        : p ? 'invalid' : 'unknown';
      if (pos !== row.pos) {
        row.pos = pos;
        row.posText.data = pos;
      }
      for (let c = 0; c < COLUMNS.length; ++c) {
        const v = COLUMNS[c][1](n) ?? 0;
        const cell = row.cells[c];
        if (cell.value === v) continue;
        const first = cell.value === null;
        if (first || (cell.value === 0) !== (v === 0)) {
          cell.td.classList.toggle('zero', v === 0);
          cell.td.classList.toggle('nonzero', v !== 0);
        }
        cell.value = v;
        cell.text.data = String(v);
        if (!first) cell.td.animate(FLASH, { duration: 900, easing: 'ease-out' });
      }
    }
  }

  // ---- snapshots ------------------------------------------------------------------------------------
  function onSnapshot(s, text) {
    const prev = state.snap;
    if (prev && s.wall_s < prev.wall_s) {  // a new emulator run behind the same address
      state.history = [];
      state.linkWindow = [];
      state.activeRx.fill(0);
      state.activeLost.fill(0);
    }
    setNodes(s.nodes.map((n) => n.id));
    state.snap = s;
    state.snapText = text;
    if (typeof s.control === 'boolean') setControl(s.control);
    setText(ui.scenario, s.scenario ?? '–');
    setText(ui.virtual, fmtClock(s.virtual_s));
    setText(ui.wall, fmtClock(s.wall_s));
    setText(ui.lag, `${fmtSeconds(s.lag_s)} / ${fmtSeconds(s.max_lag_s)}`);
    ui.lag.classList.toggle('warn', s.lag_s > 0.02 && s.lag_s <= 0.2);
    ui.lag.classList.toggle('bad', s.lag_s > 0.2);
    setText(ui.lateTicks, String(s.late_ticks ?? '–'));
    setText(ui.lateDecodes, String(s.late_decodes ?? '–'));

    const now = performance.now();
    const L = s.links;
    const P = prev && prev.links;
    if (L && P && P.n === L.n && prev.wall_s <= s.wall_s) {
      const rec = L.received, lost = L.lost, prec = P.received, plost = P.lost;
      for (let k = 0; k < rec.length; ++k) {
        if (rec[k] > prec[k]) state.activeRx[k] = now;
        if (lost[k] > plost[k]) state.activeLost[k] = now;
      }
    }
    updateSnrRange(s);
    updateTable(s.nodes);
    updatePhyLegend(s.nodes);
    updateBusiest(s);
    updateUnknown(s.nodes);
    settleOverrides(s);

    let delivered = 0, lost = 0, received = 0;
    for (const n of s.nodes) {
      delivered += n.delivered;
      received += n.received;
      for (const r of LOSS_REASONS) lost += n.lost?.[r] ?? 0;
    }
    state.history.push({ t: s.wall_s, delivered, lost, received });
    if (state.history.length > HISTORY_POINTS) state.history.shift();
    if (state.selected != null) updateSelectedInfo();
    // Tooltips under a still pointer follow the data.
    if (state.matrixHover && state.matrixHoverAt) {
      showMatrixTooltip(...state.matrixHover, ...state.matrixHoverAt);
    }
    if (state.hover != null && state.hoverAt && !state.drag) showMapTooltip(state.hover, state.hoverAt);
    requestDraw('map', 'matrix', 'traffic');
  }

  function updateSnrRange(s) {
    let lo = -10, hi = state.snrHi;
    for (const n of s.nodes) {
      if (n.sensitivity_db != null) lo = Math.min(lo, Math.floor((n.sensitivity_db - 15) / 10) * 10);
    }
    const snr = s.links?.snr_db || [];
    let max = -Infinity;
    for (const v of snr) if (v != null && v > max) max = v;
    if (max > hi) hi = Math.min(100, Math.ceil(max / 10) * 10);
    if (lo !== state.snrLo || hi !== state.snrHi) {
      state.snrLo = lo;
      state.snrHi = hi;
      for (const e of document.querySelectorAll('.snr-lo')) e.textContent = String(lo);
      for (const e of document.querySelectorAll('.snr-hi')) e.textContent = String(hi);
      for (const e of document.querySelectorAll('.snr-mid')) e.textContent = String((lo + hi) / 2);
    }
  }
  for (const e of document.querySelectorAll('.snr-lo')) e.textContent = String(state.snrLo);
  for (const e of document.querySelectorAll('.snr-hi')) e.textContent = String(state.snrHi);
  for (const e of document.querySelectorAll('.snr-mid')) e.textContent = String((state.snrLo + state.snrHi) / 2);

  const snrIndex = (v) => clamp(Math.round((v - state.snrLo) / (state.snrHi - state.snrLo) * 255), 0, 255);

  let unknownKey = '';
  function updateUnknown(nodes) {
    const ids = nodes.filter((n) => !posOk(n.position)).map((n) => n.id);
    const key = `${ids.join(',')}|${state.selected}`;
    if (key === unknownKey) return;
    unknownKey = key;
    if (!ids.length) {
      ui.unknown.replaceChildren(el('li', { class: 'none' }, 'none'));
      return;
    }
    ui.unknown.replaceChildren(...ids.map((id) => {
      const b = el('button', { type: 'button', title: `node ${id}: waiting for its location feed`,
        class: id === state.selected ? 'selected' : '' }, String(id));
      b.addEventListener('click', () => select(id));
      return el('li', { dataset: { node: id } }, b);
    }));
  }

  /// Does rx decode tx now? true / false / null (receiver's sensitivity unknown).
  function decodes(tx, rx) {
    const s = state.snap;
    const v = s.links.snr_db[tx * s.links.n + rx];
    if (v == null) return false;
    const sens = s.nodes[rx].sensitivity_db;
    if (sens == null) return null;
    return v >= sens;
  }

  // ---- selection ------------------------------------------------------------------------------------
  function select(id) {
    if (id === state.selected) return;
    const old = state.selected != null && rows.get(state.selected);
    if (old) old.tr.classList.remove('selected');
    state.selected = id;
    state.spectrum = null;
    state.constellation = null;
    state.specHi = 40;
    clearWaterfall();
    const row = id != null && rows.get(id);
    if (row) row.tr.classList.add('selected');
    send({ type: 'watch', node: id });
    setText(ui.selNode, id == null ? '–' : String(id));
    ui.unwatch.disabled = id == null;
    updateSelectedInfo();
    updateConstellationMeta();
    unknownKey = '';
    if (state.snap) updateUnknown(state.snap.nodes);
    requestDraw('map', 'matrix', 'spectrum', 'waterfall', 'constellation');
  }
  ui.unwatch.addEventListener('click', () => select(null));
  document.addEventListener('keydown', (e) => { if (e.key === 'Escape' && !state.drag) select(null); });

  function updateSelectedInfo() {
    const id = state.selected;
    if (id == null) {
      setText(ui.selInfo, 'click a node on the map or in the table');
      return;
    }
    const i = state.indexOf.get(id);
    const n = state.snap?.nodes[i];
    if (!n) {
      setText(ui.selInfo, 'watching');
      return;
    }
    const sens = n.sensitivity_db != null ? `needs ${n.sensitivity_db.toFixed(1)} dB SNR` : 'sensitivity unknown';
    const p = n.position;
    const where = posOk(p) ? `x ${p.x.toFixed(1)} y ${p.y.toFixed(1)} z ${p.z.toFixed(1)} m` : 'position unknown';
    setText(ui.selInfo, `${n.phy} · ${sens} · ${where} · received ${n.received}`);
  }

  // ---- map -------------------------------------------------------------------------------------------------
  const mapSurface = new Surface($('#map'), () => requestDraw('map'));
  const mapCanvas = mapSurface.canvas;

  /// Where node i is drawn: the viewer's own placement while it holds, else the snapshot's.
  function nodeWorld(i) {
    const id = state.ids[i];
    const o = state.overrides.get(id);
    if (o) return o;
    const p = state.snap?.nodes[i]?.position;
    return posOk(p) ? p : null;
  }
  const toScreenX = (x) => mapSurface.w / 2 + (x - state.view.cx) * state.view.scale;
  const toScreenY = (y) => mapSurface.h / 2 - (y - state.view.cy) * state.view.scale;
  const toWorld = (sx, sy) => ({
    x: state.view.cx + (sx - mapSurface.w / 2) / state.view.scale,
    y: state.view.cy - (sy - mapSurface.h / 2) / state.view.scale,
  });

  function fitView() {
    let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
    for (let i = 0; i < state.ids.length; ++i) {
      const p = nodeWorld(i);
      if (!p) continue;
      x0 = Math.min(x0, p.x); x1 = Math.max(x1, p.x);
      y0 = Math.min(y0, p.y); y1 = Math.max(y1, p.y);
    }
    if (x0 === Infinity) return;
    const pad = 46;
    const w = Math.max(10, x1 - x0), h = Math.max(10, y1 - y0);
    const scale = Math.min((mapSurface.w - 2 * pad) / w, (mapSurface.h - 2 * pad) / h);
    state.view = { cx: (x0 + x1) / 2, cy: (y0 + y1) / 2, scale: Math.max(scale, 1e-6) };
  }

  function nodeRadius() {
    const n = state.ids.length;
    return n <= 16 ? 9 : n <= 40 ? 7 : 5.5;
  }

  let fadeTimer = 0;
  drawers.map = function drawMap() {
    const ctx = mapSurface.begin();
    const W = mapSurface.w, H = mapSurface.h;
    const s = state.snap;
    if (!s) {
      ctx.fillStyle = '#8793a4';
      ctx.font = '13px system-ui, sans-serif';
      ctx.fillText(state.conn === 'open' ? 'waiting for the first snapshot…' : 'connecting…', 16, 24);
      return;
    }
    if (state.autoFit && !state.drag) fitView();
    const N = s.links.n;
    const sx = new Float64Array(N), sy = new Float64Array(N), known = new Uint8Array(N);
    let nKnown = 0;
    for (let i = 0; i < N; ++i) {
      const p = nodeWorld(i);
      if (!p) continue;
      sx[i] = toScreenX(p.x);
      sy[i] = toScreenY(p.y);
      known[i] = 1;
      ++nKnown;
    }

    // Grid at the scale bar's step, origin axes a little brighter.
    const step = niceStep(110 / state.view.scale);
    const wx0 = toWorld(0, H).x, wx1 = toWorld(W, 0).x, wy0 = toWorld(0, H).y, wy1 = toWorld(W, 0).y;
    if ((wx1 - wx0) / step < 80 && (wy1 - wy0) / step < 80) {
      ctx.beginPath();
      for (let x = Math.ceil(wx0 / step) * step; x <= wx1; x += step) {
        const X = Math.round(toScreenX(x)) + 0.5;
        ctx.moveTo(X, 0); ctx.lineTo(X, H);
      }
      for (let y = Math.ceil(wy0 / step) * step; y <= wy1; y += step) {
        const Y = Math.round(toScreenY(y)) + 0.5;
        ctx.moveTo(0, Y); ctx.lineTo(W, Y);
      }
      ctx.strokeStyle = '#161d26';
      ctx.lineWidth = 1;
      ctx.stroke();
    }
    ctx.beginPath();
    ctx.moveTo(toScreenX(0), 0); ctx.lineTo(toScreenX(0), H);
    ctx.moveTo(0, toScreenY(0)); ctx.lineTo(W, toScreenY(0));
    ctx.strokeStyle = '#222c39';
    ctx.stroke();

    // Links: each undirected pair once, batched by (style, colour, width).
    const filter = ui.linkFilter.value;
    const snr = s.links.snr_db;
    const dense = nKnown > 24;
    const now = performance.now();
    let decoding = 0;
    if (filter !== 'none') {
      const buckets = new Map();
      for (let i = 0; i < N; ++i) {
        if (!known[i]) continue;
        for (let j = i + 1; j < N; ++j) {
          if (!known[j]) continue;
          const a = snr[i * N + j], b = snr[j * N + i];
          if (a == null && b == null) continue;
          const v = a == null ? b : b == null ? a : Math.max(a, b);
          const dij = decodes(i, j), dji = decodes(j, i);
          const ok = (dij !== false) + (dji !== false);
          if (ok > 0) ++decoding;
          if (filter === 'decoding' && ok === 0) continue;
          if (filter === 'active') {
            const t = Math.max(state.activeRx[i * N + j], state.activeRx[j * N + i],
              state.activeLost[i * N + j], state.activeLost[j * N + i]);
            if (!(now - t < ACTIVE_MS)) continue;
          }
          let cls;
          if (ok === 2) cls = 0;
          else if (ok === 1) cls = 1;
          else {
            // Far below sensitivity: not drawn at all (keeps big swarms readable).
            const need = Math.min(s.nodes[i].sensitivity_db ?? 0, s.nodes[j].sensitivity_db ?? 0);
            if (v < need - 20) continue;
            cls = 2;
          }
          const ci = snrIndex(v) >> 3;  // 32 colour steps
          const wi = cls === 2 ? 0 : Math.min(3, Math.floor((ci / 32) * 4));
          const key = (cls * 32 + ci) * 4 + wi;
          let bucket = buckets.get(key);
          if (!bucket) buckets.set(key, (bucket = { cls, ci, wi, pts: [] }));
          bucket.pts.push(sx[i], sy[i], sx[j], sy[j]);
        }
      }
      ctx.lineCap = 'round';
      for (const bucket of buckets.values()) {
        const { cls, ci, wi, pts } = bucket;
        ctx.beginPath();
        for (let k = 0; k < pts.length; k += 4) {
          ctx.moveTo(pts[k], pts[k + 1]);
          ctx.lineTo(pts[k + 2], pts[k + 3]);
        }
        ctx.strokeStyle = LUT_CSS[ci * 8 + 4];
        const width = (0.9 + wi * 0.9) * (dense ? 0.6 : 1);
        if (cls === 0) {
          ctx.setLineDash([]);
          ctx.globalAlpha = dense ? 0.4 : 0.9;
          ctx.lineWidth = width;
        } else if (cls === 1) {
          ctx.setLineDash([7, 5]);
          ctx.globalAlpha = dense ? 0.45 : 0.85;
          ctx.lineWidth = Math.max(1, width * 0.8);
        } else {
          ctx.setLineDash([1.5, 5]);
          ctx.globalAlpha = dense ? 0.18 : 0.4;
          ctx.lineWidth = 1.2;
        }
        ctx.stroke();
      }
      ctx.setLineDash([]);
      ctx.globalAlpha = 1;
    }

    // Links that carried (or lost) frames in the last ACTIVE_MS: a glow and an
    // arrowhead toward the receiver, fading with age (4 alpha steps, batched).
    const glow = [[], [], [], [], [], [], [], []];  // [kind * 4 + level] -> tx, rx pairs
    const Nn = N * N;
    for (let k = 0; k < Nn; ++k) {
      const tr = state.activeRx[k], tl = state.activeLost[k];
      if (tr === 0 && tl === 0) continue;
      const i = (k / N) | 0, j = k - i * N;
      if (!known[i] || !known[j]) continue;
      const ageR = now - tr, ageL = now - tl;
      if (ageR < ACTIVE_MS) glow[Math.min(3, Math.floor(ageR / ACTIVE_MS * 4))].push(i, j);
      if (ageL < ACTIVE_MS) glow[4 + Math.min(3, Math.floor(ageL / ACTIVE_MS * 4))].push(i, j);
    }
    let anyGlow = false;
    const r = nodeRadius();
    for (let g = 0; g < 8; ++g) {
      const list = glow[g];
      if (!list.length) continue;
      anyGlow = true;
      const alpha = (1 - (g % 4) / 4) * 0.75;
      const colour = g < 4 ? '255,255,255' : '255,90,90';
      ctx.beginPath();
      for (let k = 0; k < list.length; k += 2) {
        ctx.moveTo(sx[list[k]], sy[list[k]]);
        ctx.lineTo(sx[list[k + 1]], sy[list[k + 1]]);
      }
      ctx.strokeStyle = `rgba(${colour},${alpha * 0.45})`;
      ctx.lineWidth = 7;
      ctx.stroke();
      ctx.beginPath();
      for (let k = 0; k < list.length; k += 2) {
        const a = list[k], b = list[k + 1];
        const dx = sx[b] - sx[a], dy = sy[b] - sy[a];
        const len = Math.hypot(dx, dy);
        if (len < 3 * r) continue;
        const ux = dx / len, uy = dy / len;
        const tipX = sx[b] - ux * (r + 4), tipY = sy[b] - uy * (r + 4);
        ctx.moveTo(tipX, tipY);
        ctx.lineTo(tipX - ux * 10 - uy * 5, tipY - uy * 10 + ux * 5);
        ctx.lineTo(tipX - ux * 10 + uy * 5, tipY - uy * 10 - ux * 5);
        ctx.closePath();
      }
      ctx.fillStyle = `rgba(${colour},${alpha + 0.2})`;
      ctx.fill();
    }
    if (anyGlow && !fadeTimer) {  // keep fading between snapshots (one timer at a time)
      fadeTimer = setTimeout(() => { fadeTimer = 0; requestDraw('map'); }, 250);
    }

    // Nodes and their ids.
    ctx.font = `600 ${N > 40 ? 10 : 11.5}px system-ui, sans-serif`;
    ctx.textBaseline = 'middle';
    for (let i = 0; i < N; ++i) {
      if (!known[i]) continue;
      const id = state.ids[i];
      const selected = id === state.selected;
      ctx.beginPath();
      ctx.arc(sx[i], sy[i], r, 0, 2 * Math.PI);
      ctx.fillStyle = phyColour(s.nodes[i].phy);
      ctx.fill();
      ctx.lineWidth = selected ? 3 : 1.5;
      ctx.strokeStyle = selected ? '#5cc8ff' : id === state.hover ? '#ffffff' : '#0b0f14';
      ctx.stroke();
      if (selected) {
        ctx.beginPath();
        ctx.arc(sx[i], sy[i], r + 5, 0, 2 * Math.PI);
        ctx.strokeStyle = 'rgba(92,200,255,.55)';
        ctx.lineWidth = 2;
        ctx.stroke();
      }
      if (state.overrides.has(id)) {
        ctx.beginPath();
        ctx.arc(sx[i], sy[i], r + 2.5, 0, 2 * Math.PI);
        ctx.setLineDash([3, 3]);
        ctx.strokeStyle = '#f0c05a';
        ctx.lineWidth = 1.5;
        ctx.stroke();
        ctx.setLineDash([]);
      }
      const label = String(id);
      const lx = sx[i] + r + 3, ly = sy[i] - r - 2;
      ctx.lineWidth = 3;
      ctx.strokeStyle = 'rgba(11,15,20,.85)';
      ctx.strokeText(label, lx, ly);
      ctx.fillStyle = selected ? '#9fe0ff' : '#e8edf4';
      ctx.fillText(label, lx, ly);
    }

    // Scale bar (bottom left).
    const barPx = step * state.view.scale;
    const bx = 14, by = H - 16;
    ctx.fillStyle = 'rgba(11,15,20,.75)';
    ctx.fillRect(bx - 6, by - 18, barPx + 12 + 60, 28);
    ctx.strokeStyle = '#d9dee7';
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.moveTo(bx, by - 5); ctx.lineTo(bx, by); ctx.lineTo(bx + barPx, by); ctx.lineTo(bx + barPx, by - 5);
    ctx.stroke();
    ctx.fillStyle = '#d9dee7';
    ctx.font = '12px system-ui, sans-serif';
    ctx.textBaseline = 'alphabetic';
    ctx.fillText(fmtMetres(step), bx + barPx + 8, by);
    if (!nKnown) {
      ctx.fillStyle = '#8793a4';
      ctx.fillText('no node has a known position yet', 16, 24);
    }
    const mode = state.autoFit ? 'auto-fit' : 'manual view (Fit resets)';
    setText(ui.mapInfo, `${N} nodes · ${decoding} of ${N * (N - 1) / 2} pairs decode · `
      + `${fmtMetres((W) / state.view.scale)} wide · ${mode}`);
  };

  function nodeAt(px, py) {
    if (!state.snap) return null;
    const r = nodeRadius() + 5;
    let best = null, bestD = r * r;
    for (let i = 0; i < state.ids.length; ++i) {
      const p = nodeWorld(i);
      if (!p) continue;
      const dx = toScreenX(p.x) - px, dy = toScreenY(p.y) - py;
      const d = dx * dx + dy * dy;
      if (d <= bestD) { bestD = d; best = state.ids[i]; }
    }
    return best;
  }

  const localPoint = (e) => {
    const rect = mapCanvas.getBoundingClientRect();
    return { x: e.clientX - rect.left, y: e.clientY - rect.top };
  };

  function sendMove(id, p, force = false) {
    const d = state.drag;
    const now = performance.now();
    if (!force && d && now - d.lastSent < MOVE_SEND_INTERVAL_MS) return;
    if (d) d.lastSent = now;
    const msg = { type: 'move', node: id, x: +p.x.toFixed(2), y: +p.y.toFixed(2), z: +p.z.toFixed(2) };
    if (!send(msg)) showMessage('not connected: the move was not sent');
  }

  mapCanvas.addEventListener('pointerdown', (e) => {
    if (e.button !== 0) return;
    const p = localPoint(e);
    const id = nodeAt(p.x, p.y);
    mapCanvas.setPointerCapture(e.pointerId);
    if (id != null) {
      const i = state.indexOf.get(id);
      const w = nodeWorld(i);
      state.drag = { kind: 'node', id, start: p, moved: false, lastSent: 0, z: w ? w.z : 0,
        offX: toScreenX(w.x) - p.x, offY: toScreenY(w.y) - p.y };
    } else {
      state.drag = { kind: 'pan', start: p, moved: false, view: { ...state.view } };
    }
  });

  mapCanvas.addEventListener('pointermove', (e) => {
    const p = localPoint(e);
    const d = state.drag;
    if (!d) {
      const id = nodeAt(p.x, p.y);
      if (id !== state.hover) {
        state.hover = id;
        mapCanvas.classList.toggle('over-node', id != null);
        requestDraw('map');
      }
      state.hoverAt = p;
      showMapTooltip(id, p);
      return;
    }
    const moved = Math.hypot(p.x - d.start.x, p.y - d.start.y) > 3;
    if (!d.moved && !moved) return;
    if (!d.moved) {
      d.moved = true;
      ui.mapTip.hidden = true;
      if (d.kind === 'node' && !state.control) {
        showHint(state.control === false ? CONTROL_OFF_TEXT : 'not connected yet');
      }
    }
    if (d.kind === 'node') {
      if (!state.control) return;  // nothing moves without control
      mapCanvas.classList.add('dragging');
      const w = toWorld(p.x + d.offX, p.y + d.offY);
      const target = { x: w.x, y: w.y, z: d.z, until: Infinity };
      state.overrides.set(d.id, target);
      sendMove(d.id, target);
      requestDraw('map');
    } else {
      mapCanvas.classList.add('panning');
      state.autoFit = false;
      state.view = { ...d.view, cx: d.view.cx - (p.x - d.start.x) / d.view.scale,
        cy: d.view.cy + (p.y - d.start.y) / d.view.scale };
      requestDraw('map');
    }
  });

  function endDrag(e, cancelled) {
    const d = state.drag;
    if (!d) return;
    state.drag = null;
    mapCanvas.classList.remove('dragging', 'panning');
    if (mapCanvas.hasPointerCapture(e.pointerId)) mapCanvas.releasePointerCapture(e.pointerId);
    if (d.kind === 'node') {
      if (!d.moved && !cancelled) {
        select(d.id);
      } else if (state.control && state.overrides.has(d.id)) {
        const o = state.overrides.get(d.id);
        sendMove(d.id, o, true);
        o.until = performance.now() + 2500;  // hold it there until the snapshot agrees
      }
    }
    requestDraw('map');
  }
  mapCanvas.addEventListener('pointerup', (e) => endDrag(e, false));
  mapCanvas.addEventListener('pointercancel', (e) => endDrag(e, true));
  mapCanvas.addEventListener('pointerleave', () => {
    if (!state.drag) {
      ui.mapTip.hidden = true;
      if (state.hover != null) { state.hover = null; requestDraw('map'); }
    }
  });
  mapCanvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    const p = localPoint(e);
    const before = toWorld(p.x, p.y);
    const f = Math.exp(-clamp(e.deltaY, -300, 300) * 0.0015);
    state.view.scale = clamp(state.view.scale * f, 1e-6, 1e4);
    const after = toWorld(p.x, p.y);
    state.view.cx += before.x - after.x;
    state.view.cy += before.y - after.y;
    state.autoFit = false;
    requestDraw('map');
  }, { passive: false });
  mapCanvas.addEventListener('dblclick', () => { state.autoFit = true; requestDraw('map'); });
  $('#map-fit').addEventListener('click', () => { state.autoFit = true; requestDraw('map'); });
  ui.linkFilter.addEventListener('change', () => requestDraw('map'));

  /// Drops the viewer's placements once the snapshot agrees (or after a while).
  function settleOverrides(s) {
    const now = performance.now();
    for (const [id, o] of state.overrides) {
      if (state.drag && state.drag.id === id) continue;
      const p = s.nodes[state.indexOf.get(id)]?.position;
      const agrees = posOk(p) && Math.abs(p.x - o.x) < 0.05 && Math.abs(p.y - o.y) < 0.05;
      if (agrees || now > o.until) state.overrides.delete(id);
    }
  }

  function showMapTooltip(id, p) {
    if (id == null || !state.snap) {
      ui.mapTip.hidden = true;
      return;
    }
    const i = state.indexOf.get(id);
    const n = state.snap.nodes[i];
    const w = nodeWorld(i);
    const N = state.snap.links.n;
    let dec = 0, total = 0;
    for (let j = 0; j < N; ++j) {
      if (j === i || state.snap.links.snr_db[j * N + i] == null) continue;
      ++total;
      if (decodes(j, i) !== false) ++dec;
    }
    const sens = n.sensitivity_db != null ? `${n.sensitivity_db.toFixed(1)} dB` : 'unknown';
    ui.mapTip.innerHTML = '';
    ui.mapTip.append(
      el('b', {}, `node ${id}`), ` · ${n.phy}`, el('br'),
      w ? `x ${w.x.toFixed(1)}  y ${w.y.toFixed(1)}  z ${w.z.toFixed(1)} m` : 'position unknown', el('br'),
      el('span', { class: 'muted' }, `sensitivity ${sens} · hears ${dec} of ${total} senders`), el('br'),
      el('span', { class: 'muted' }, state.control ? 'click: watch · drag: move' : 'click: watch'));
    ui.mapTip.hidden = false;
    const bw = mapSurface.w;
    ui.mapTip.style.left = `${Math.min(p.x + 14, bw - ui.mapTip.offsetWidth - 4)}px`;
    ui.mapTip.style.top = `${p.y + 14}px`;
  }

  // ---- link matrix ------------------------------------------------------------------------------------
  const matrixBox = $('#matrix');
  const mx = { surface: null, off: document.createElement('canvas'), img: null, cell: 8, left: 30, top: 30 };
  mx.offCtx = mx.off.getContext('2d');
  mx.surface = new Surface(matrixBox, () => {});
  new ResizeObserver(() => layoutMatrix()).observe($('#matrix-panel'));

  function layoutMatrix() {
    const N = state.ids.length;
    // As wide as the panel allows, about as tall as the map beside it.
    const avail = Math.min($('#matrix-panel').clientWidth - 24, 470);
    const label = N > 99 ? 34 : 28;
    const cell = N ? clamp(Math.floor((avail - label - 4) / N), 3, 56) : 8;
    const size = N ? label + N * cell + 2 : 60;
    mx.cell = cell;
    mx.left = label;
    mx.top = label;
    matrixBox.style.width = `${size}px`;
    matrixBox.style.height = `${size}px`;
    mx.surface.canvas.style.width = `${size}px`;
    mx.surface.canvas.style.height = `${size}px`;
    mx.surface.fit(size, size);
    if (mx.off.width !== Math.max(1, N)) {
      mx.off.width = Math.max(1, N);
      mx.off.height = Math.max(1, N);
      mx.img = mx.offCtx.createImageData(Math.max(1, N), Math.max(1, N));
    }
    requestDraw('matrix');
  }

  drawers.matrix = function drawMatrix() {
    const s = state.snap;
    const ctx = mx.surface.begin();
    const N = state.ids.length;
    if (!s || !N || s.links.n !== N || !mx.img) return;
    const { cell, left, top } = mx;
    const data = mx.img.data;
    const snr = s.links.snr_db;
    for (let tx = 0; tx < N; ++tx) {
      for (let rx = 0; rx < N; ++rx) {
        const k = tx * N + rx;
        const o = k * 4;
        const v = snr[k];
        let rgb;
        if (tx === rx) rgb = [44, 50, 60];
        else if (v == null) rgb = [22, 25, 30];
        else {
          rgb = LUT[snrIndex(v)];
          if (decodes(tx, rx) === false) rgb = dimRgb(rgb);
        }
        data[o] = rgb[0]; data[o + 1] = rgb[1]; data[o + 2] = rgb[2]; data[o + 3] = 255;
      }
    }
    mx.offCtx.putImageData(mx.img, 0, 0);
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(mx.off, left, top, N * cell, N * cell);

    if (cell >= 9) {
      ctx.beginPath();
      for (let i = 0; i <= N; ++i) {
        ctx.moveTo(left + i * cell + 0.5, top); ctx.lineTo(left + i * cell + 0.5, top + N * cell);
        ctx.moveTo(left, top + i * cell + 0.5); ctx.lineTo(left + N * cell, top + i * cell + 0.5);
      }
      ctx.strokeStyle = 'rgba(11,15,20,.55)';
      ctx.lineWidth = 1;
      ctx.stroke();
    }

    // Cells whose link decoded (white) or lost (red, inside) frames recently.
    const now = performance.now();
    const lw = cell >= 10 ? 2 : 1;
    for (const [arr, colour, inner] of [[state.activeRx, '#ffffff', 0], [state.activeLost, '#ff5a5a', 1]]) {
      const inset = (cell >= 6 ? 1 : 0) + (inner && cell >= 12 ? lw + 1 : 0);
      ctx.beginPath();
      let any = false;
      for (let k = 0; k < arr.length; ++k) {
        if (arr[k] === 0 || now - arr[k] >= ACTIVE_MS) continue;
        const tx = (k / N) | 0, rx = k - tx * N;
        ctx.rect(left + rx * cell + inset + lw / 2, top + tx * cell + inset + lw / 2,
          cell - 2 * inset - lw, cell - 2 * inset - lw);
        any = true;
      }
      if (any) {
        ctx.strokeStyle = colour;
        ctx.lineWidth = lw;
        ctx.stroke();
      }
    }

    // Selected node: its row (what it sends) and column (what it hears).
    const si = state.selected != null ? state.indexOf.get(state.selected) : undefined;
    if (si !== undefined) {
      ctx.strokeStyle = 'rgba(92,200,255,.9)';
      ctx.lineWidth = 1.5;
      ctx.strokeRect(left - 0.5, top + si * cell - 0.5, N * cell + 1, cell + 1);
      ctx.strokeRect(left + si * cell - 0.5, top - 0.5, cell + 1, N * cell + 1);
    }
    if (state.matrixHover) {
      const [tx, rx] = state.matrixHover;
      ctx.strokeStyle = '#ffffff';
      ctx.lineWidth = 1.5;
      ctx.strokeRect(left + rx * cell - 1, top + tx * cell - 1, cell + 2, cell + 2);
    }

    // Labels: tx ids down the left, rx ids across the top.
    ctx.fillStyle = '#8793a4';
    ctx.font = `${cell >= 12 ? 11 : 9.5}px system-ui, sans-serif`;
    const stepY = Math.max(1, Math.ceil(11 / cell));
    ctx.textAlign = 'right';
    ctx.textBaseline = 'middle';
    for (let i = 0; i < N; i += stepY) ctx.fillText(String(state.ids[i]), left - 4, top + (i + 0.5) * cell);
    const horizontal = cell >= 18;
    const stepX = horizontal ? 1 : Math.max(1, Math.ceil(11 / cell));
    for (let i = 0; i < N; i += stepX) {
      const x = left + (i + 0.5) * cell;
      if (horizontal) {
        ctx.textAlign = 'center';
        ctx.textBaseline = 'bottom';
        ctx.fillText(String(state.ids[i]), x, top - 3);
      } else {
        ctx.save();
        ctx.translate(x, top - 3);
        ctx.rotate(-Math.PI / 2);
        ctx.textAlign = 'left';
        ctx.textBaseline = 'middle';
        ctx.fillText(String(state.ids[i]), 0, 0);
        ctx.restore();
      }
    }
    ctx.textAlign = 'left';
    ctx.textBaseline = 'top';
    ctx.fillStyle = '#5cc8ff';
    ctx.font = '600 10px system-ui, sans-serif';
    ctx.fillText('tx↓ rx→', 1, 1);
  };

  function matrixCellAt(e) {
    const rect = mx.surface.canvas.getBoundingClientRect();
    const x = e.clientX - rect.left - mx.left, y = e.clientY - rect.top - mx.top;
    const N = state.ids.length;
    const rx = Math.floor(x / mx.cell), tx = Math.floor(y / mx.cell);
    if (x < 0 || y < 0 || rx >= N || tx >= N) return null;
    return [tx, rx, e.clientX - rect.left, e.clientY - rect.top];
  }
  mx.surface.canvas.addEventListener('pointermove', (e) => {
    const c = matrixCellAt(e);
    const key = c ? `${c[0]},${c[1]}` : '';
    const oldKey = state.matrixHover ? state.matrixHover.join(',') : '';
    state.matrixHover = c ? [c[0], c[1]] : null;
    if (key !== oldKey) requestDraw('matrix');
    state.matrixHoverAt = c ? [c[2], c[3]] : null;
    if (!c) {
      ui.matrixTip.hidden = true;
      return;
    }
    showMatrixTooltip(c[0], c[1], c[2], c[3]);
  });
  mx.surface.canvas.addEventListener('pointerleave', () => {
    state.matrixHover = null;
    ui.matrixTip.hidden = true;
    requestDraw('matrix');
  });
  mx.surface.canvas.addEventListener('click', (e) => {
    const c = matrixCellAt(e);
    if (c) select(state.ids[c[1]]);
  });

  function showMatrixTooltip(tx, rx, px, py) {
    const s = state.snap;
    if (!s) return;
    const N = s.links.n;
    const k = tx * N + rx;
    const v = s.links.snr_db[k];
    const rxNode = s.nodes[rx], txNode = s.nodes[tx];
    const tip = ui.matrixTip;
    tip.replaceChildren();
    tip.append(el('b', {}, `tx ${state.ids[tx]} → rx ${state.ids[rx]}`), el('br'));
    if (tx === rx) {
      tip.append(el('span', { class: 'muted' }, 'same node'));
    } else {
      const d = decodes(tx, rx);
      const sens = rxNode.sensitivity_db;
      tip.append(v == null ? 'SNR: no link' : `SNR ${v.toFixed(1)} dB`,
        sens != null ? el('span', { class: 'muted' }, ` (rx needs ${sens.toFixed(1)} dB)`) : '', el('br'),
        d === null ? el('span', { class: 'muted' }, 'decodes: unknown (external receiver)')
          : el('span', { class: d ? 'good' : 'bad' }, d ? 'decodes' : 'does not decode'), el('br'),
        `received ${s.links.received[k]} · lost ${s.links.lost[k]}`);
      if (txNode.phy !== rxNode.phy) {
        tip.append(el('br'), el('span', { class: 'muted' }, `${txNode.phy} → ${rxNode.phy}: different PHY types`));
      }
    }
    tip.hidden = false;
    const boxW = matrixBox.clientWidth;
    tip.style.left = `${Math.max(0, Math.min(px + 14, boxW - tip.offsetWidth - 2))}px`;
    tip.style.top = `${py + 16}px`;
  }

  // ---- traffic over time ------------------------------------------------------------------------------
  const trafficSurface = new Surface($('#traffic'), () => requestDraw('traffic'));
  drawers.traffic = function drawTraffic() {
    const ctx = trafficSurface.begin();
    const W = trafficSurface.w, H = trafficSurface.h;
    const h = state.history;
    const padL = 40, padR = 8, padT = 8, padB = 20;
    const rates = [];
    for (let k = 1; k < h.length; ++k) {
      const dt = h[k].t - h[k - 1].t;
      if (dt <= 0) continue;
      rates.push({ t: h[k].t, d: (h[k].delivered - h[k - 1].delivered) / dt,
        l: (h[k].lost - h[k - 1].lost) / dt });
    }
    const tNow = h.length ? h[h.length - 1].t : 0;
    const span = h.length ? clamp(Math.ceil((tNow - h[0].t) / 30) * 30, 30, 120) : 30;
    let ymax = 1;
    for (const r of rates) ymax = Math.max(ymax, r.d, r.l);
    const yStep = niceStep(ymax / 4);
    ymax = Math.ceil(ymax / yStep) * yStep;
    const X = (t) => padL + (W - padL - padR) * (1 - (tNow - t) / span);
    const Y = (v) => H - padB - (H - padT - padB) * (v / ymax);
    ctx.strokeStyle = '#1f2833';
    ctx.fillStyle = '#8793a4';
    ctx.font = '10.5px system-ui, sans-serif';
    ctx.lineWidth = 1;
    ctx.textAlign = 'right';
    ctx.textBaseline = 'middle';
    ctx.beginPath();
    for (let v = 0; v <= ymax + 1e-9; v += yStep) {
      const y = Math.round(Y(v)) + 0.5;
      ctx.moveTo(padL, y); ctx.lineTo(W - padR, y);
      ctx.fillText(Number(v.toPrecision(3)).toString(), padL - 4, y);
    }
    ctx.stroke();
    ctx.textAlign = 'center';
    ctx.textBaseline = 'top';
    for (let a = 0; a <= span; a += span / 4) ctx.fillText(a === 0 ? 'now' : `-${a} s`, X(tNow - a), H - padB + 4);
    for (const [key, colour] of [['d', '#5fd38d'], ['l', '#ff6b6b']]) {
      ctx.beginPath();
      let started = false;
      for (const r of rates) {
        if (tNow - r.t > span) continue;
        if (!started) { ctx.moveTo(X(r.t), Y(r[key])); started = true; } else ctx.lineTo(X(r.t), Y(r[key]));
      }
      ctx.strokeStyle = colour;
      ctx.lineWidth = 1.6;
      ctx.stroke();
    }
    if (h.length) {
      const last = h[h.length - 1];
      const r = rates.length ? rates[rates.length - 1] : { d: 0, l: 0 };
      setText(ui.totals, `total delivered ${last.delivered} · lost ${last.lost} · received ${last.received}`
        + ` · now ${r.d.toFixed(1)}/s delivered, ${r.l.toFixed(1)}/s lost`);
    }
  };

  // ---- busiest links -------------------------------------------------------------------------------
  const BUSIEST_ROWS = 8;
  const busiest = [];
  {
    const tbody = $('#busiest-links tbody');
    for (let r = 0; r < BUSIEST_ROWS; ++r) {
      const texts = ['link', 'decoded', 'lost', 'snr', 'margin'].map((cls) => {
        const t = document.createTextNode('');
        return { cls, t, td: el('td', { class: cls }, t) };
      });
      const tr = el('tr', {}, ...texts.map((x) => x.td));
      tr.hidden = true;
      const row = { tr, texts, rx: null };
      tr.addEventListener('click', () => { if (row.rx != null) select(row.rx); });
      busiest.push(row);
      tbody.append(tr);
    }
  }

  function updateBusiest(s) {
    const L = s.links;
    if (!L || !L.received) return;
    const w = state.linkWindow;
    w.push({ t: s.wall_s, received: Uint32Array.from(L.received), lost: Uint32Array.from(L.lost) });
    while (w.length > 1 && w[1].t <= s.wall_s - ACTIVE_MS / 1000) w.shift();
    const base = w[0];
    const top = [];
    if (w.length > 1) {
      const cur = w[w.length - 1];
      for (let k = 0; k < cur.received.length; ++k) {
        const d = cur.received[k] - base.received[k], l = cur.lost[k] - base.lost[k];
        if (d > 0 || l > 0) top.push([d + l, k, d, l]);
      }
      top.sort((a, b) => b[0] - a[0]);
    }
    const N = L.n;
    for (let r = 0; r < BUSIEST_ROWS; ++r) {
      const row = busiest[r];
      const item = top[r];
      row.tr.hidden = !item;
      if (!item) { row.rx = null; continue; }
      const [, k, d, l] = item;
      const tx = (k / N) | 0, rx = k - tx * N;
      const v = L.snr_db[k];
      const sens = s.nodes[rx].sensitivity_db;
      const margin = v != null && sens != null ? v - sens : null;
      row.rx = state.ids[rx];
      const vals = [`${state.ids[tx]} → ${state.ids[rx]}`, String(d), String(l),
        v == null ? '–' : v.toFixed(1), margin == null ? '–' : margin.toFixed(1)];
      row.texts.forEach((x, j) => { if (x.t.data !== vals[j]) x.t.data = vals[j]; });
      row.texts[2].td.classList.toggle('nonzero', l > 0);
      row.texts[4].td.classList.toggle('neg', margin != null && margin < 0);
    }
    $('#busiest-none').hidden = top.length > 0;
  }

  let phyKey = '';
  function updatePhyLegend(nodes) {
    const counts = new Map();
    for (const n of nodes) counts.set(n.phy, (counts.get(n.phy) || 0) + 1);
    const key = [...counts].map(([p, c]) => `${p}:${c}`).join(',');
    if (key === phyKey) return;
    phyKey = key;
    $('#phy-legend').replaceChildren(...[...counts].map(([phy, c]) => el('li', { dataset: { phy } },
      el('span', { class: 'phy-dot', style: `background:${phyColour(phy)}` }), `${phy} (${c})`)));
  }

  // ---- spectrum and waterfall ----------------------------------------------------------------------
  const specSurface = new Surface($('#spectrum'), () => requestDraw('spectrum'));
  const wfSurface = new Surface($('#waterfall'), () => requestDraw('waterfall'));
  const wf = { off: document.createElement('canvas'), rows: 0 };
  wf.off.width = 256;
  wf.off.height = WATERFALL_ROWS;
  wf.ctx = wf.off.getContext('2d');

  function specRange() {
    return { lo: -10, hi: state.specHi };
  }

  function clearWaterfall() {
    wf.ctx.fillStyle = `rgb(${BG_RGB.join(',')})`;
    wf.ctx.fillRect(0, 0, wf.off.width, wf.off.height);
    wf.rows = 0;
  }
  clearWaterfall();

  function pushWaterfall(bins) {
    if (!bins || !bins.length) return;
    let max = -Infinity;
    for (const b of bins) if (b > max) max = b;
    if (max + 5 > state.specHi) state.specHi = Math.min(150, Math.ceil((max + 5) / 10) * 10);
    if (wf.off.width !== bins.length) {
      wf.off.width = bins.length;
      clearWaterfall();
    }
    const { lo, hi } = specRange();
    wf.ctx.drawImage(wf.off, 0, 0, wf.off.width, WATERFALL_ROWS - 1, 0, 1, wf.off.width, WATERFALL_ROWS - 1);
    const row = wf.ctx.createImageData(bins.length, 1);
    for (let k = 0; k < bins.length; ++k) {
      const rgb = LUT[clamp(Math.round((bins[k] - lo) / (hi - lo) * 255), 0, 255)];
      row.data[k * 4] = rgb[0]; row.data[k * 4 + 1] = rgb[1]; row.data[k * 4 + 2] = rgb[2];
      row.data[k * 4 + 3] = 255;
    }
    wf.ctx.putImageData(row, 0, 0);
    wf.rows = Math.min(WATERFALL_ROWS, wf.rows + 1);
  }

  function freqAxis(ctx, W, H, padL, padR, padB, fs) {
    ctx.fillStyle = '#8793a4';
    ctx.font = '10.5px system-ui, sans-serif';
    ctx.textAlign = 'center';
    ctx.textBaseline = 'top';
    for (let q = -2; q <= 2; ++q) {
      const x = padL + (W - padL - padR) * (q + 2) / 4;
      ctx.textAlign = q === -2 ? 'left' : q === 2 ? 'right' : 'center';
      ctx.fillText(fmtHz(q * fs / 4), x, H - padB + 3);
    }
  }

  drawers.spectrum = function drawSpectrum() {
    const ctx = specSurface.begin();
    const W = specSurface.w, H = specSurface.h;
    const padL = 34, padR = 8, padT = 8, padB = 18;
    const m = state.spectrum;
    if (state.selected == null || !m || !m.bins_db || !m.bins_db.length) {
      ctx.fillStyle = '#8793a4';
      ctx.font = '12px system-ui, sans-serif';
      ctx.fillText(state.selected == null ? 'no node watched' : 'waiting for samples…', 12, 20);
      setText(ui.specInfo, '');
      return;
    }
    const bins = m.bins_db;
    const { lo, hi } = specRange();
    const X = (k) => padL + (W - padL - padR) * k / (bins.length - 1);
    const Y = (v) => padT + (H - padT - padB) * (1 - (clamp(v, lo, hi) - lo) / (hi - lo));
    ctx.strokeStyle = '#1f2833';
    ctx.lineWidth = 1;
    ctx.fillStyle = '#8793a4';
    ctx.font = '10.5px system-ui, sans-serif';
    ctx.textAlign = 'right';
    ctx.textBaseline = 'middle';
    const step = hi - lo > 60 ? 20 : 10;
    ctx.beginPath();
    for (let v = Math.ceil(lo / step) * step; v <= hi; v += step) {
      const y = Math.round(Y(v)) + 0.5;
      ctx.moveTo(padL, y); ctx.lineTo(W - padR, y);
      ctx.fillText(String(v), padL - 4, y);
    }
    ctx.stroke();
    freqAxis(ctx, W, H, padL, padR, padB, m.sample_rate_hz);
    ctx.beginPath();
    ctx.moveTo(X(0), Y(lo));
    for (let k = 0; k < bins.length; ++k) ctx.lineTo(X(k), Y(bins[k]));
    ctx.lineTo(X(bins.length - 1), Y(lo));
    ctx.closePath();
    ctx.fillStyle = 'rgba(92,200,255,.12)';
    ctx.fill();
    ctx.beginPath();
    for (let k = 0; k < bins.length; ++k) {
      if (k === 0) ctx.moveTo(X(k), Y(bins[k])); else ctx.lineTo(X(k), Y(bins[k]));
    }
    ctx.strokeStyle = '#5cc8ff';
    ctx.lineWidth = 1.3;
    ctx.stroke();
    let peak = -Infinity;
    for (const b of bins) peak = Math.max(peak, b);
    setText(ui.specInfo, `node ${m.node} · t ${fmtClock(m.virtual_s)} · peak ${peak.toFixed(1)} dB · `
      + `fs ${fmtHz(m.sample_rate_hz)} · dB re noise floor`);
  };

  drawers.waterfall = function drawWaterfall() {
    const ctx = wfSurface.begin();
    const W = wfSurface.w, H = wfSurface.h;
    if (state.selected == null || !wf.rows) {
      ctx.fillStyle = '#8793a4';
      ctx.font = '12px system-ui, sans-serif';
      ctx.fillText(state.selected == null ? 'no node watched' : 'waiting for samples…', 12, 20);
      return;
    }
    const padL = 34, padR = 8, padB = 18;
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(wf.off, padL, 0, W - padL - padR, H - padB);
    ctx.fillStyle = '#8793a4';
    ctx.font = '10.5px system-ui, sans-serif';
    ctx.textAlign = 'right';
    ctx.textBaseline = 'top';
    ctx.fillText('now', padL - 4, 0);
    ctx.textBaseline = 'bottom';
    ctx.fillText(`-${(WATERFALL_ROWS * 0.25).toFixed(0)} s`, padL - 4, H - padB);
    freqAxis(ctx, W, H, padL, padR, padB, state.spectrum?.sample_rate_hz ?? state.hello?.sample_rate_hz ?? 1);
  };

  // ---- constellation ------------------------------------------------------------------------------------
  const constSurface = new Surface($('#constellation'), () => requestDraw('constellation'));
  const metaCells = {};
  for (const k of ['src', 'dst', 'serial', 'valid', 'time', 'points']) metaCells[k] = $(`dd.${k}`, ui.constMeta);

  function updateConstellationMeta() {
    const c = state.constellation;
    setText(metaCells.src, c ? String(c.src) : '–');
    setText(metaCells.dst, c ? String(c.dst) : '–');
    setText(metaCells.serial, c ? String(c.serial) : '–');
    setText(metaCells.valid, c ? (c.valid ? 'yes (CRC ok)' : 'no (CRC failed)') : '–');
    metaCells.valid.classList.toggle('yes', !!c && c.valid);
    metaCells.valid.classList.toggle('no', !!c && !c.valid);
    setText(metaCells.time, c ? fmtClock(c.virtual_s) : '–');
    setText(metaCells.points, c ? String(c.points.length) : '–');
  }

  drawers.constellation = function drawConstellation() {
    const ctx = constSurface.begin();
    const W = constSurface.w, H = constSurface.h;
    const c = state.constellation;
    const cx = W / 2, cy = H / 2;
    ctx.strokeStyle = '#1f2833';
    ctx.lineWidth = 1;
    ctx.beginPath();
    ctx.moveTo(cx + 0.5, 0); ctx.lineTo(cx + 0.5, H);
    ctx.moveTo(0, cy + 0.5); ctx.lineTo(W, cy + 0.5);
    ctx.stroke();
    if (!c || !c.points.length) {
      ctx.fillStyle = '#8793a4';
      ctx.font = '12px system-ui, sans-serif';
      ctx.textAlign = 'center';
      ctx.fillText(state.selected == null ? 'no node watched' : 'no frame decoded yet', cx, cy - 12);
      return;
    }
    const mags = c.points.map(([i, q]) => Math.max(Math.abs(i), Math.abs(q))).sort((a, b) => a - b);
    const ref = mags[Math.floor(mags.length * 0.98)] || 1;
    const range = ref * 1.3;
    const scale = (Math.min(W, H) / 2 - 6) / range;
    ctx.beginPath();
    ctx.arc(cx, cy, ref * scale, 0, 2 * Math.PI);
    ctx.strokeStyle = '#26303d';
    ctx.setLineDash([3, 4]);
    ctx.stroke();
    ctx.setLineDash([]);
    ctx.fillStyle = c.valid ? 'rgba(95,211,141,.8)' : 'rgba(255,107,107,.8)';
    for (const [i, q] of c.points) ctx.fillRect(cx + i * scale - 1.2, cy - q * scale - 1.2, 2.4, 2.4);
    ctx.fillStyle = '#8793a4';
    ctx.font = '10.5px system-ui, sans-serif';
    ctx.textAlign = 'left';
    ctx.textBaseline = 'top';
    ctx.fillText(`I/Q · ±${Number(range.toPrecision(2))}`, 4, 4);
  };

  // ---- read-only test / automation hooks -------------------------------------------------------------------
  function nodeCanvasPosition(id) {
    const i = state.indexOf.get(id);
    if (i === undefined) return null;
    const p = nodeWorld(i);
    if (!p) return null;
    return { x: toScreenX(p.x), y: toScreenY(p.y) };
  }
  const api = {
    /** A copy of the last snapshot message (null before the first). */
    get snapshot() { return state.snapText ? JSON.parse(state.snapText) : null; },
    /** A copy of the hello message. */
    get hello() { return state.helloText ? JSON.parse(state.helloText) : null; },
    get connection() { return state.conn; },
    get control() { return state.control; },
    get selected() { return state.selected; },
    get nodeIds() { return state.ids.slice(); },
    get spectrum() { return state.spectrum ? JSON.parse(JSON.stringify(state.spectrum)) : null; },
    get constellation() { return state.constellation ? JSON.parse(JSON.stringify(state.constellation)) : null; },
    get messages() { return state.messages.map((m) => ({ ...m })); },
    get snrRange() { return [state.snrLo, state.snrHi]; },
    /** A node's centre in the map canvas, CSS pixels from the canvas's top left (null if unknown). */
    nodeCanvasPosition,
    /** The same in viewport (client) coordinates, as mouse events use. */
    nodeClientPosition(id) {
      const p = nodeCanvasPosition(id);
      if (!p) return null;
      const r = mapCanvas.getBoundingClientRect();
      return { x: r.left + p.x, y: r.top + p.y };
    },
    /** Local metres under a viewport point of the map. */
    worldAtClient(clientX, clientY) {
      const r = mapCanvas.getBoundingClientRect();
      return toWorld(clientX - r.left, clientY - r.top);
    },
    /** Centre of the heat-map cell tx -> rx: canvas CSS pixels and viewport coordinates. */
    matrixCell(txId, rxId) {
      const tx = state.indexOf.get(txId), rx = state.indexOf.get(rxId);
      if (tx === undefined || rx === undefined) return null;
      const x = mx.left + (rx + 0.5) * mx.cell, y = mx.top + (tx + 0.5) * mx.cell;
      const r = mx.surface.canvas.getBoundingClientRect();
      return { x, y, clientX: r.left + x, clientY: r.top + y, cell: mx.cell, dpr: mx.surface.dpr };
    },
    /** Directed links (tx id, rx id) that decoded frames in the last 2 s. */
    activeLinks() {
      const now = performance.now(), N = state.ids.length, out = [];
      for (let k = 0; k < state.activeRx.length; ++k) {
        if (state.activeRx[k] && now - state.activeRx[k] < ACTIVE_MS) {
          out.push([state.ids[(k / N) | 0], state.ids[k % N]]);
        }
      }
      return out;
    },
    /** JS time per message and per drawing, in ms (mean, p95, max over the last 400). */
    perf() { return state.timings.summary(); },
  };
  Object.defineProperty(window, 'rfsitlDashboard', {
    value: Object.freeze(api), writable: false, configurable: false, enumerable: true,
  });

  // ---- start -------------------------------------------------------------------------------------------------
  layoutMatrix();
  requestDraw('map', 'matrix', 'traffic', 'spectrum', 'waterfall', 'constellation');
  connect();
})();
