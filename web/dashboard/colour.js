// Colours: the SNR / power scale shared by the map, the matrix and the
// waterfall, and one colour per PHY type.
//
// The scale is a 256-entry lookup table built once, so per-pixel and per-link
// colouring is an array index instead of an interpolation.

/** The page background (style.css), for dimming toward it and clearing images. */
export const BG_RGB = [11, 15, 20];

const PHY_COLOURS = {
  gmsk: '#4fc3f7', 'gmsk-liquid': '#7fd8a4', ofdm: '#ffb74d', dsss: '#c792ea',
  external: '#e8e8e8',
};

// Own design: violet -> blue -> teal -> green -> gold.
const STOPS = [
  [0.00, [40, 18, 78]], [0.20, [56, 78, 186]], [0.42, [32, 152, 172]],
  [0.62, [72, 196, 112]], [0.80, [192, 222, 64]], [1.00, [255, 226, 84]],
];
export const LUT = [];      // 256 x [r, g, b]
export const LUT_CSS = [];  // 256 x 'rgb(...)'
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

/** The colour of a link that does not decode: mostly background. */
export const dimRgb = (rgb) => rgb.map((v, j) => Math.round(v * 0.34 + BG_RGB[j] * 0.66));

/** The scale as a CSS gradient, for the legends' bars. */
export const cssGradient = (dim) => {
  const parts = [];
  for (let i = 0; i <= 16; ++i) {
    const rgb = LUT[Math.round(i * 255 / 16)];
    const c = dim ? dimRgb(rgb) : rgb;
    parts.push(`rgb(${c[0]},${c[1]},${c[2]}) ${(i * 100 / 16).toFixed(1)}%`);
  }
  return `linear-gradient(to right, ${parts.join(', ')})`;
};

/** A fixed colour for the known PHYs; any other name hashes to a stable hue. */
export const phyColour = (phy) => {
  if (PHY_COLOURS[phy]) return PHY_COLOURS[phy];
  let h = 0;
  for (const ch of String(phy)) h = (h * 31 + ch.charCodeAt(0)) % 360;
  return `hsl(${h},65%,68%)`;
};
