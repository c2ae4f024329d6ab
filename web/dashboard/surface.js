// A canvas that follows its box's CSS size at the device pixel ratio, so every
// plot draws in CSS pixels and stays sharp on high-DPI screens.
import { $ } from './dom.js';

export class Surface {
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

  /// A cleared context scaled to CSS pixels, ready for one frame.
  begin() {
    const { ctx } = this;
    ctx.setTransform(this.dpr, 0, 0, this.dpr, 0, 0);
    ctx.clearRect(0, 0, this.w, this.h);
    return ctx;
  }
}
