// The sphere system's page (paper 002, issue 15): the newest half-second
// raster as points (azimuth right, elevation up) coloured by range, the
// locator's estimate (magenta cross), the guidance's filtered sphere (cyan:
// its outline, 1σ ellipse solid, 3σ dashed; the σ across the line of sight
// is mm at tens of metres, so the ellipses are small until close), the
// ground truth (yellow), and the approach plot. Built on ephor_page.js.
'use strict';

const { $, fmt } = ephorPage;
// Near (bright) to far (dark): bins 0..7 of the raster's foreground ranges.
const RANGE_COLOURS = ['#fde725', '#b5de2b', '#6ece58', '#35b779', '#1f9e89', '#26828e', '#31688e', '#443983'];
const BACKGROUND_COLOUR = '#5a5a5a';
const raster = $('raster');
const rctx = raster.getContext('2d');
const plot = $('approach');
const pctx = plot.getContext('2d');

let scan = null;          // newest /api/scan
let scanLoading = false;

async function loadScan() {
  scanLoading = true;
  try {
    const r = await fetch('api/scan', { cache: 'no-store' });
    if (r.ok) scan = await r.json();
  } finally {
    scanLoading = false;
  }
}

function legend(s) {
  const sc = s.scan;
  if (!sc) return;
  const lo = sc.range_lo_m, hi = sc.range_hi_m;
  $('legend').innerHTML = 'near ' + RANGE_COLOURS.map((c) => '<span style="background:' + c + '"></span>').join('') +
    ' far · ' + fmt(lo, 2) + '–' + fmt(hi, 2) + ' m · <span style="background:' + BACKGROUND_COLOUR +
    '"></span> background';
}

// Canvas position of (azimuth, elevation) in degrees within ±half.
function toCanvas(az, el, half) {
  const w = raster.width, h = raster.height;
  return [w / 2 + az / half * (w / 2), h / 2 - el / half * (h / 2)];
}

function ellipse(u, v, rx, ry, dash) {
  rctx.setLineDash(dash);
  rctx.beginPath();
  rctx.ellipse(u, v, Math.max(rx, 0.5), Math.max(ry, 0.5), 0, 0, 2 * Math.PI);
  rctx.stroke();
  rctx.setLineDash([]);
}

function drawRaster(s) {
  const w = raster.width, h = raster.height;
  rctx.clearRect(0, 0, w, h);
  const half = 1.1 * Math.max((scan && scan.half_extent_deg) || (s.scan && s.scan.half_extent_deg) || 1, 0.05);
  const pxPerDeg = w / 2 / half;
  // The frame (the scanned square) and the boresight.
  rctx.strokeStyle = '#3a3f47';
  rctx.lineWidth = 1;
  const [x0, y0] = toCanvas(-half / 1.1, half / 1.1, half);
  rctx.strokeRect(x0, y0, 2 * half / 1.1 * pxPerDeg, 2 * half / 1.1 * pxPerDeg);
  rctx.beginPath();
  rctx.moveTo(w / 2 - 6, h / 2); rctx.lineTo(w / 2 + 6, h / 2);
  rctx.moveTo(w / 2, h / 2 - 6); rctx.lineTo(w / 2, h / 2 + 6);
  rctx.stroke();

  let points = 0;
  if (scan) {
    // Pulses are 0.1 deg apart along a line: squares about that wide.
    const size = Math.min(Math.max(0.1 * pxPerDeg, 2), 8);
    for (const [az, el, , bin] of scan.points) {
      const [u, v] = toCanvas(az, el, half);
      rctx.fillStyle = bin < 0 ? BACKGROUND_COLOUR : RANGE_COLOURS[bin];
      rctx.fillRect(u - size / 2, v - size / 2, size, size);
      points++;
    }
  }
  window.ephorDisplay.points = points;
  raster.dataset.points = String(points);
  raster.dataset.window = String(scan ? scan.window : -1);

  rctx.lineWidth = 1.5;
  if ($('layer-truth').checked && s.truth) {
    const t = s.truth;
    const [u, v] = toCanvas(t.azimuth_deg, t.elevation_deg, half);
    rctx.strokeStyle = '#ffd400';
    ellipse(u, v, t.radius_deg * pxPerDeg, t.radius_deg * pxPerDeg, [2, 3]);
  }
  const g = s.guidance;
  if (g && g.tracking) {
    const [u, v] = toCanvas(g.azimuth_deg, g.elevation_deg, half);
    rctx.strokeStyle = '#00e5ff';
    ellipse(u, v, g.radius_deg * pxPerDeg, g.radius_deg * pxPerDeg, []);
    ellipse(u, v, g.sigma_deg[0] * pxPerDeg, g.sigma_deg[1] * pxPerDeg, []);
    if ($('layer-sigma3').checked) ellipse(u, v, 3 * g.sigma_deg[0] * pxPerDeg, 3 * g.sigma_deg[1] * pxPerDeg, [4, 3]);
  }
  const e = s.estimate;
  if ($('layer-estimate').checked && e && e.ok && e.position_m) {
    const [u, v] = toCanvas(e.azimuth_deg, e.elevation_deg, half);
    rctx.strokeStyle = '#ff5ad1';
    rctx.beginPath();
    rctx.moveTo(u - 7, v - 7); rctx.lineTo(u + 7, v + 7);
    rctx.moveTo(u - 7, v + 7); rctx.lineTo(u + 7, v - 7);
    rctx.stroke();
  }
  rctx.fillStyle = '#9aa4b1';
  rctx.font = '12px system-ui, sans-serif';
  rctx.fillText('±' + fmt(half / 1.1, 3) + '°', 8, 16);
}

// Two panels: range (m) and offset from the boresight (cm) against scan time.
function drawApproach(s) {
  const w = plot.width, h = plot.height;
  pctx.clearRect(0, 0, w, h);
  const hist = s.history;
  const all = [...hist.truth, ...hist.guidance, ...hist.estimate];
  pctx.font = '11px system-ui, sans-serif';
  if (!all.length) {
    pctx.fillStyle = '#9aa4b1';
    pctx.fillText('no approach yet', 10, 20);
    return;
  }
  const t0 = Math.min(...all.map((x) => x[0]));
  const t1 = Math.max(t0 + 5, ...all.map((x) => x[0]));
  const left = 44, right = w - 8;
  const panels = [
    { top: 8, bottom: h / 2 - 14, col: 1, scale: 1, unit: 'range m', floor: 0,
      max: Math.max(1.2 * s.capture_distance_m, ...all.map((x) => x[1])) },
    { top: h / 2 + 6, bottom: h - 20, col: 2, scale: 100, unit: 'offset cm', floor: 0,
      max: Math.max(2, ...all.map((x) => 100 * x[2])) },
  ];
  const X = (t) => left + (t - t0) / (t1 - t0) * (right - left);
  for (const p of panels) {
    const Y = (y) => p.bottom - (y - p.floor) / (p.max - p.floor) * (p.bottom - p.top);
    pctx.strokeStyle = '#3a3f47';
    pctx.strokeRect(left, p.top, right - left, p.bottom - p.top);
    pctx.fillStyle = '#9aa4b1';
    pctx.fillText(fmt(p.max, p.max < 10 ? 1 : 0), 4, p.top + 10);
    pctx.fillText('0', 30, p.bottom);
    pctx.fillText(p.unit, left + 4, p.top + 12);
    // Capture limits: 1 m along the boresight, 2 cm from it.
    const limit = p.col === 1 ? s.capture_distance_m : 2;
    pctx.strokeStyle = '#6fdc8c';
    pctx.setLineDash([4, 4]);
    pctx.beginPath();
    pctx.moveTo(left, Y(limit)); pctx.lineTo(right, Y(limit));
    pctx.stroke();
    pctx.setLineDash([]);
    const series = [[hist.truth, '#ffd400', 'line'], [hist.guidance, '#00e5ff', 'line'], [hist.estimate, '#ff5ad1', 'dots']];
    for (const [data, colour, kind] of series) {
      if (kind === 'line' && data === hist.truth && !$('layer-truth').checked) continue;
      pctx.strokeStyle = colour;
      pctx.fillStyle = colour;
      pctx.beginPath();
      data.forEach((x, i) => {
        const u = X(x[0]), v = Y(Math.min(p.scale * x[p.col], p.max));
        if (kind === 'dots') {
          pctx.fillRect(u - 1.5, v - 1.5, 3, 3);
        } else if (i) {
          pctx.lineTo(u, v);
        } else {
          pctx.moveTo(u, v);
        }
      });
      if (kind === 'line') pctx.stroke();
    }
  }
  pctx.fillStyle = '#9aa4b1';
  pctx.fillText('scan time ' + fmt(t0, 0) + '–' + fmt(t1, 0) + ' s · yellow truth, cyan guidance, magenta estimates',
    left, h - 4);
}

function kv(rows) {
  return rows.map(([k, v]) => '<div>' + k + ' <b>' + v + '</b></div>').join('');
}

function vec(v, digits, scale) {
  return '(' + v.map((x) => fmt(x * (scale || 1), digits)).join(', ') + ')';
}

function updatePanels(s) {
  $('score-approach').textContent = s.truth ? s.truth.approach : '–';
  $('score-captured').textContent = s.approaches.captured;
  $('score-missed').textContent = s.approaches.missed;
  const g = s.guidance, t = s.truth, v = s.last_verdict;
  const rows = [];
  if (g) {
    rows.push(['guidance', g.phase + (g.tracking ? '' : ' (no track)')]);
    rows.push(['range to capture', fmt(g.range_to_capture_m, 2) + ' m']);
    rows.push(['filtered range', fmt(g.range_m, 3) + ' m, offset ' + fmt(100 * g.lateral_m, 1) + ' cm']);
    rows.push(['1σ x, y, z', vec(g.sigma_m, 1, 1000) + ' mm']);
    rows.push(['chaser velocity', vec(g.chaser_velocity_m_s, 3) + ' m/s']);
    rows.push(['estimates used / down-weighted / rejected / none',
      g.estimates_used + ' / ' + g.estimates_downweighted + ' / ' + g.estimates_rejected + ' / ' + g.no_estimates]);
  } else {
    rows.push(['guidance', 'nothing heard']);
  }
  if (t) {
    rows.push(['truth', t.phase + ': range ' + fmt(t.range_m, 3) + ' m, offset ' + fmt(100 * t.lateral_m, 1) +
      ' cm, ' + fmt(100 * t.speed_m_s, 1) + ' cm/s']);
  }
  if (v) {
    rows.push(['last verdict', '<span class="' + (v.phase === 'captured' ? 'good' : 'bad') + '">approach ' +
      v.approach + ': ' + ephorPage.esc(v.verdict) + '</span> (' + fmt(v.capture_t_s, 1) + ' s, ' +
      fmt(100 * v.capture_speed_m_s, 1) + ' cm/s, ' + fmt(100 * v.capture_offset_m, 1) + ' cm off axis)']);
  }
  $('approach-kv').innerHTML = kv(rows);
  const e = s.estimate;
  $('estimate-kv').innerHTML = !e ? 'none yet' : e.ok && e.position_m
    ? kv([['window', e.window + ' (' + e.algorithm + ', ' + e.variant + ')'],
      ['position', vec(e.position_m, 3) + ' m'],
      ['range', fmt(e.range_m, 3) + ' m, offset ' + fmt(100 * e.lateral_m, 1) + ' cm'],
      ['points / lines / missing', e.points + ' / ' + e.lines + ' / ' + e.lines_missing],
      ['CPU', fmt(e.cpu_us, 0) + ' µs'], ['windows without', e.failed]])
    : kv([['window', e.window], ['no estimate', ephorPage.esc(e.reason)]]);
  const sc = s.scan;
  $('status-line').textContent = sc
    ? 'window ' + sc.window + ': ' + sc.lines + ' lines, ' + sc.points + ' returns (' + sc.background +
      ' background), ' + sc.no_return + ' without return, frame ±' + fmt(sc.half_extent_deg, 3) + '°'
    : 'no complete raster yet (' + s.lines_heard + ' lines heard)';
}

ephorPage.start({
  camera: false,
  draw(s) {
    if (s.scan && (!scan || scan.window !== s.scan.window) && !scanLoading) loadScan();
    legend(s);
    drawRaster(s);
    drawApproach(s);
    updatePanels(s);
  },
});
