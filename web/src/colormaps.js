// The colour maps of the report, the same as src/raster/raster.cpp draws in the PNG pictures.
// Each takes t and returns [r, g, b] in [0, 1].

const VIRIDIS = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];

// Sequential, dark blue to yellow: distances, print order. t in [0, 1] (clamped).
export function viridis(t) {
  const s = Math.min(1, Math.max(0, Number.isFinite(t) ? t : 0)) * 4;
  const i = Math.min(3, Math.floor(s));
  const f = s - i;
  return VIRIDIS[i].map((a, k) => (a * (1 - f) + VIRIDIS[i + 1][k] * f) / 255);
}

// Cyclic of period 1: line directions, t = theta / pi.
export function cyclic(t) {
  const a = 2 * Math.PI * (Number.isFinite(t) ? t : 0);
  return [0.5 + 0.42 * Math.cos(a), 0.5 + 0.42 * Math.cos(a - (2 * Math.PI) / 3), 0.5 + 0.42 * Math.cos(a - (4 * Math.PI) / 3)];
}

// Diverging: blue at -1, white at 0, red at +1 (clamped).
export function diverging(t) {
  const blue = [59, 76, 192], white = [242, 242, 242], red = [180, 4, 38];
  const s = Math.min(1, Math.max(-1, Number.isFinite(t) ? t : 0));
  const end = s < 0 ? blue : red;
  return white.map((w, k) => (w + (end[k] - w) * Math.abs(s)) / 255);
}

export function css([r, g, b]) {
  const c = (x) => Math.round(255 * Math.min(1, Math.max(0, x)));
  return `rgb(${c(r)}, ${c(g)}, ${c(b)})`;
}
