// Small DOM helpers shared by every view. Views build their elements once per
// node set and afterwards only change text and classes, so these stay minimal.

/** The first element matching `sel` under `root`. */
export const $ = (sel, root = document) => root.querySelector(sel);

/** A new element: `class`, `dataset`, then properties, else attributes; then its children. */
export const el = (tag, props = {}, ...children) => {
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

/** Writes text only when it differs: an unchanged field then costs no layout. */
export const setText = (node, text) => { if (node.textContent !== text) node.textContent = text; };
