// rfsitl live dashboard: entry point. Plain browser JavaScript as native ES
// modules, no dependencies and no build step (the emulator serves these files
// as they are): it talks to the emulator's WebSocket /ws (messages documented
// in docs/dashboard.md) and draws the map, link matrix, a link's gain over
// time, spectrum, waterfall and constellation on canvases.
//
// Each view module finds its own elements and registers its own drawing and
// input handlers when imported; this file only routes the server's messages to
// them, in one place, so the order of updates per snapshot is easy to see.
//
// Performance rules (64 nodes = 4032 directed links at 4 snapshots/s):
//   * the DOM is built once per node set; snapshots only change text nodes;
//   * drawing happens in one requestAnimationFrame per burst of messages
//     (scheduler.js);
//   * map links are batched by style so a frame strokes a few dozen paths;
//   * the matrix is one N x N ImageData scaled up by drawImage.
import { updateBusiest } from './busiest.js';
import { connect } from './connection.js';
import { onConstellation } from './constellation.js';
import { setControl, setControlRefused } from './control.js';
import { updatePhyLegend, updateUnknown } from './map-aside.js';
import './map-draw.js';
import { settleOverrides } from './map-input.js';
import { refreshMapTooltip } from './map-tooltip.js';
import { keepLinkIfKnown, showInfo as showLinkInfo } from './link-plot.js';
import { layoutMatrix, refreshMatrixTooltip } from './matrix.js';
import { requestDraw } from './scheduler.js';
import { select, updateSelectedInfo } from './selection.js';
import { recordSnapshot, setNodeIds } from './snapshot.js';
import { updateSnrRange } from './snr-scale.js';
import { onSpectrum } from './spectrum.js';
import { state } from './state.js';
import { buildTable, setCounterFields, updateTable } from './table.js';
import './test-hook.js';
import { showHello, showStatus } from './topbar.js';
import './traffic.js';

/** Adopts the node list of a hello or snapshot; a different set rebuilds the per-node views. */
function setNodes(ids) {
  if (!setNodeIds(ids)) return;
  buildTable(ids);
  if (state.selected != null && !state.indexOf.has(state.selected)) select(null);
  keepLinkIfKnown();
  layoutMatrix();
  requestDraw('map', 'matrix', 'traffic', 'link');
}

function onHello(m, text) {
  state.hello = m;
  state.helloText = text;
  showHello(m);
  setControlRefused(m.control_refused);
  setControl(!!m.control);
  setCounterFields(m.counters || []);
  setNodes(m.node_ids || []);
}

function onSnapshot(s) {
  setNodes(s.nodes.map((n) => n.id));
  recordSnapshot(s);
  if (typeof s.control === 'boolean') setControl(s.control);
  showStatus(s);
  updateSnrRange(s);
  updateTable(s.nodes);
  updatePhyLegend(s.nodes);
  updateBusiest(s);
  updateUnknown(s.nodes);
  settleOverrides(s);
  if (state.selected != null) updateSelectedInfo();
  if (state.link) showLinkInfo();
  // Tooltips under a still pointer follow the data.
  refreshMatrixTooltip();
  refreshMapTooltip();
  requestDraw('map', 'matrix', 'traffic', 'link');
}

layoutMatrix();
requestDraw('map', 'matrix', 'traffic', 'link', 'spectrum', 'waterfall', 'constellation');
connect({ hello: onHello, snapshot: onSnapshot, spectrum: onSpectrum, constellation: onConstellation });
