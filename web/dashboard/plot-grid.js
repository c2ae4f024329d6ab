// The horizontal grid lines of the dashboard's small time plots (traffic, link
// gain), each labelled at the left; leaves the context set for the time labels
// along the bottom (centred, hanging from their y).

/** Lines at from, from + step, ... up to `to`, at heights Y(v), from x = left to right. */
export function drawValueGrid(ctx, { from, to, step, Y, left, right, digits }) {
  ctx.strokeStyle = '#1f2833';
  ctx.fillStyle = '#8793a4';
  ctx.lineWidth = 1;
  ctx.textAlign = 'right';
  ctx.textBaseline = 'middle';
  ctx.beginPath();
  for (let v = from; v <= to + 1e-9; v += step) {
    const y = Math.round(Y(v)) + 0.5;
    ctx.moveTo(left, y); ctx.lineTo(right, y);
    ctx.fillText(Number(v.toPrecision(digits)).toString(), left - 4, y);
  }
  ctx.stroke();
  ctx.textAlign = 'center';
  ctx.textBaseline = 'top';
}
