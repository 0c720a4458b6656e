// A small plot of demand (blue) and actual (orange) over the last samples.
const DEMAND = '#2855a6';
const ACTUAL = '#c04000';

export function drawPlot(canvas, samples, demandKey, actualKey) {
  const dpr = window.devicePixelRatio || 1;
  const w = canvas.clientWidth || 220;
  const h = canvas.clientHeight || 110;
  if (canvas.width !== Math.round(w * dpr)) { canvas.width = Math.round(w * dpr); canvas.height = Math.round(h * dpr); }
  const g = canvas.getContext('2d');
  g.setTransform(dpr, 0, 0, dpr, 0, 0);
  g.clearRect(0, 0, w, h);
  const values = samples.flatMap((s) => [s[demandKey], s[actualKey]]).filter((v) => typeof v === 'number');
  if (values.length === 0) { g.fillStyle = '#888'; g.fillText('no data', 8, 16); return; }
  let lo = Math.min(...values); let hi = Math.max(...values);
  if (hi - lo < 1e-9) { hi += 1; lo -= 1; }
  const pad = 14;
  const x = (i) => (i / Math.max(samples.length - 1, 1)) * (w - 2);
  const y = (v) => pad + (1 - (v - lo) / (hi - lo)) * (h - 2 * pad);
  g.strokeStyle = '#e3e7eb'; g.beginPath(); g.moveTo(0, y(0)); g.lineTo(w, y(0)); g.stroke();
  for (const [key, colour] of [[demandKey, DEMAND], [actualKey, ACTUAL]]) {
    g.strokeStyle = colour; g.lineWidth = 1.5; g.beginPath();
    let started = false;
    samples.forEach((s, i) => {
      if (typeof s[key] !== 'number') return;
      if (started) g.lineTo(x(i), y(s[key])); else { g.moveTo(x(i), y(s[key])); started = true; }
    });
    g.stroke();
  }
  g.fillStyle = '#555'; g.font = '10px sans-serif';
  g.fillText(String(hi), 2, 10); g.fillText(String(lo), 2, h - 3);
}
