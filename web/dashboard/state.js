// The dashboard's shared state. Imported bindings are read-only in ES modules,
// so everything more than one module reads or writes lives on this one object
// (and the test hook can expose it without each module exporting getters).
import { Timings } from './timings.js';

export const ACTIVE_MS = 2000;  // a link "carried frames recently" for this long

export const state = {
  conn: 'connecting',
  hello: null,
  helloText: null,    // the message as received, so the test hook hands out fresh copies
  snap: null,
  ids: [],            // node ids in `nodes` order
  indexOf: new Map(), // id -> index
  control: null,      // null until known
  controlRefused: null,  // why control, on for the run, is refused to this viewer (no token)
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
  hoverAt: null,      // ... and where the pointer is, to refresh the tooltip on new data
  matrixHover: null,  // [tx, rx] index
  link: null,         // [tx id, rx id]: the link whose gain is plotted (link-plot.js)
  snrHistory: null,   // every link's SNR per snapshot, the last few minutes (snapshot.js)
  mapLinks: [],       // the map's links as drawn: i, j, x1, y1, x2, y2 per pair (map-draw.js)
  matrixHoverAt: null,
  view: { cx: 0, cy: 0, scale: 10 },
  autoFit: true,
  messages: [],
  timings: new Timings(),
  specHi: 40,
};
