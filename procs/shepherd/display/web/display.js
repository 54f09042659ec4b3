// ephor display page: polls /api/state (JSON) and /api/frame.jpg about 16
// times a second, draws the camera image with the overlays, and sends
// controls as POST /api/cmd. No build step, no libraries.
'use strict';

const PERIOD_MS = 50;  // one update every 50 ms at most: up to 20 updates/s
const canvas = document.getElementById('field');
const ctx = canvas.getContext('2d');
const $ = (id) => document.getElementById(id);

// Exposed for tests and curious users: what the newest draw showed.
window.ephorDisplay = { circles: 0, updates: 0, state: null, updatesPerS: 0, imagesPerS: 0 };

let image = null;       // newest camera image (ImageBitmap)
let state = null;       // newest /api/state
let box = null;         // calibration box being dragged {u, v, half}
let updateTimes = [];   // for the updates/s figure
let imageTimes = [];    // new camera images, for the images/s figure
let imageIndex = -1;

async function fetchState() {
  const r = await fetch('api/state', { cache: 'no-store' });
  if (!r.ok) throw new Error('state: HTTP ' + r.status);
  return r.json();
}

async function fetchFrame() {
  const r = await fetch('api/frame.jpg', { cache: 'no-store' });
  if (r.status !== 200) return null;
  const index = Number(r.headers.get('X-Frame-Index'));
  if (index === imageIndex) return null;  // the server had no newer image
  imageIndex = index;
  imageTimes.push(performance.now());
  return createImageBitmap(await r.blob());
}

async function loop() {
  const start = performance.now();
  try {
    const [s, img] = await Promise.all([fetchState(), fetchFrame()]);
    state = s;
    if (img) {
      if (image) image.close();
      image = img;
    }
    draw();
    updateTables();
    const now = performance.now();
    updateTimes.push(now);
    while (updateTimes.length && updateTimes[0] < now - 2000) updateTimes.shift();
    window.ephorDisplay.updates++;
    while (imageTimes.length && imageTimes[0] < now - 2000) imageTimes.shift();
    window.ephorDisplay.updatesPerS = updateTimes.length / 2;
    window.ephorDisplay.imagesPerS = imageTimes.length / 2;
    canvas.dataset.updates = String(window.ephorDisplay.updates);
  } catch (e) {
    $('status-line').textContent = 'no connection to ephor-display: ' + e.message;
  }
  setTimeout(loop, Math.max(0, PERIOD_MS - (performance.now() - start)));
}

function line(points, close) {
  ctx.beginPath();
  points.forEach(([u, v], i) => (i ? ctx.lineTo(u, v) : ctx.moveTo(u, v)));
  if (close) ctx.closePath();
  ctx.stroke();
}

function draw() {
  const s = state;
  if (s.frame.width > 0 && (canvas.width !== s.frame.width || canvas.height !== s.frame.height)) {
    canvas.width = s.frame.width;
    canvas.height = s.frame.height;
  }
  ctx.setLineDash([]);
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  if (image) ctx.drawImage(image, 0, 0);
  ctx.lineWidth = 1.5;

  // Field boundary (table top, through the calibration).
  ctx.strokeStyle = '#3fa7ff';
  line(s.boundary, true);

  // Ground truth (optional): small squares at the true marks.
  if ($('layer-truth').checked && s.truth) {
    ctx.strokeStyle = '#ffd400';
    for (const t of s.truth.sheep) {
      if (!t.on_field) continue;
      ctx.setLineDash(t.visible ? [] : [2, 2]);
      ctx.strokeRect(t.u - 4, t.v - 4, 8, 8);
    }
    ctx.setLineDash([]);
  }

  // Blobs: circles with the blob's area (paper 3.2).
  let circles = 0;
  if (s.blobs && !s.controls.paused) {
    ctx.strokeStyle = '#39ff7a';
    for (const [u, v, r] of s.blobs.circles) {
      ctx.beginPath();
      ctx.arc(u, v, Math.max(r, 1), 0, 2 * Math.PI);
      ctx.stroke();
      circles++;
    }
  }
  window.ephorDisplay.circles = circles;
  canvas.dataset.circles = String(circles);

  // Objects: id, velocity vector (1 s), predicted path; obscured ones dashed grey.
  ctx.font = '12px system-ui, sans-serif';
  for (const o of s.objects) {
    const visible = o.state === 'visible';
    const colour = visible ? '#ff5ad1' : '#9a9a9a';
    ctx.strokeStyle = colour;
    ctx.fillStyle = colour;
    ctx.setLineDash(visible ? [] : [4, 3]);
    if ($('layer-paths').checked && o.path.length > 1) {
      ctx.globalAlpha = 0.55;
      ctx.setLineDash([3, 4]);
      line(o.path, false);
      ctx.globalAlpha = 1;
      ctx.setLineDash(visible ? [] : [4, 3]);
    }
    line([[o.u, o.v], [o.u + o.vu, o.v + o.vv]], false);
    if (!visible) {
      ctx.beginPath();
      ctx.arc(o.u, o.v, 7, 0, 2 * Math.PI);
      ctx.stroke();
    }
    ctx.fillText(String(o.id) + (visible ? '' : '?'), o.u + 8, o.v - 8);
  }
  ctx.setLineDash([]);

  // Planned intercept: a cross, with the target object's id.
  if (s.planner && s.planner.target >= 0) {
    const { u, v } = s.planner;
    ctx.strokeStyle = '#ff9f1a';
    ctx.lineWidth = 2;
    line([[u - 8, v - 8], [u + 8, v + 8]], false);
    line([[u - 8, v + 8], [u + 8, v - 8]], false);
    ctx.fillStyle = '#ff9f1a';
    ctx.fillText('→' + s.planner.target + ' ' + s.planner.time_s.toFixed(1) + ' s', u + 10, v + 14);
    ctx.lineWidth = 1.5;
  }

  // Arm: tool footprint and orientation.
  if (s.arm) {
    const { u, v, theta_rad: th, footprint_px: r } = s.arm;
    ctx.strokeStyle = '#00e5ff';
    ctx.setLineDash(s.arm.z_mm > 100 ? [5, 4] : []);  // dashed: raised (elevation plane)
    ctx.beginPath();
    ctx.arc(u, v, r, 0, 2 * Math.PI);
    ctx.stroke();
    ctx.setLineDash([]);
    line([[u - r * Math.cos(th), v - r * Math.sin(th)], [u + r * Math.cos(th), v + r * Math.sin(th)]], false);
  }

  // Calibration box.
  const b = box || (s.controls.box.visible ? s.controls.box : null);
  if ($('layer-box').checked && b) {
    ctx.strokeStyle = '#ffffff';
    ctx.strokeRect(b.u - b.half, b.v - b.half, 2 * b.half, 2 * b.half);
    ctx.fillStyle = '#ffffff';
    ctx.fillText('(' + b.u.toFixed(0) + ', ' + b.v.toFixed(0) + ')', b.u + b.half + 4, b.v);
  }

  if (s.controls.paused) {
    ctx.fillStyle = 'rgba(200, 60, 40, 0.85)';
    ctx.font = 'bold 16px system-ui, sans-serif';
    ctx.fillText('VISION PAUSED', 10, 22);
  }

  const bl = s.blobs;
  $('status-line').textContent =
    'frame ' + s.frame.index + ' · ' + (bl ? bl.mode + ', ' + bl.scan + ' scan, threshold ' + bl.threshold +
      ', ' + bl.circles.length + ' blobs, ' + bl.processing_us.toFixed(0) + ' µs' : 'no blobs yet') +
    ' · ' + s.objects.length + ' objects';
}

function fmt(x, digits) { return Number(x).toFixed(digits); }

function updateTables() {
  const s = state;
  window.ephorDisplay.state = s;
  if (s.truth) {
    $('score-on-field').textContent = s.truth.on_field;
    $('score-saves').textContent = s.truth.saves;
    $('score-escapes').textContent = s.truth.escapes;
    $('score-elapsed').textContent = fmt(s.truth.elapsed_s, 0) + ' s';
  }
  $('updates-per-s').textContent = fmt(window.ephorDisplay.updatesPerS, 1) + ' (images ' + fmt(window.ephorDisplay.imagesPerS, 1) + ')';

  const rows = [];
  for (const h of s.sched) {
    for (const t of h.tasks) {
      const bad = t.deadline_misses > 0 || !t.alive;
      rows.push('<tr' + (bad ? ' class="bad"' : '') + '><td>' + esc(h.host) + '</td><td>' + esc(t.process) +
        '</td><td>' + esc(t.task) + '</td><td>' + (t.cpu < 0 ? 'any' : t.cpu) + '</td><td>' +
        esc(t.policy.replace('SCHED_', '')) + '</td><td>' + t.priority + '</td><td>' +
        (t.periodic ? fmt(t.period_us / 1000, 1) : 'trig') + '</td><td>' + fmt(t.exec_p50_us, 0) + ' / ' +
        fmt(t.exec_p99_us, 0) + ' / ' + fmt(t.exec_max_us, 0) + '</td><td>' + fmt(t.jitter_p50_us, 0) +
        ' / ' + fmt(t.jitter_p99_us, 0) + ' / ' + fmt(t.jitter_max_us, 0) + '</td><td>' + t.jobs +
        '</td><td>' + t.deadline_misses + '</td><td>' + (t.rt ? 'yes' : 'no') + '</td></tr>');
    }
  }
  $('tasks').tBodies[0].innerHTML = rows.join('') ||
    '<tr><td colspan="12">no scheduler status heard (EPHOR_SCHED_STATUS)</td></tr>';

  $('rates').tBodies[0].innerHTML = Object.entries(s.rates_hz)
    .map(([c, hz]) => '<tr><td>' + esc(c) + '</td><td>' + fmt(hz, 1) + '</td></tr>').join('');
  const l = s.latency;
  $('latency').textContent = l.commands
    ? 'p50 ' + fmt(l.p50_ms, 1) + ' ms, p99 ' + fmt(l.p99_ms, 1) + ' ms, max ' + fmt(l.max_ms, 1) +
      ' ms over ' + l.commands + ' commands'
    : 'no arm commands yet';
  const p = s.planner;
  $('planner-line').textContent = p
    ? p.planner + ': ' + p.phase + (p.target >= 0 ? ', saving ' + p.target : '') + ', ' +
      fmt(p.planning_us, 0) + ' µs/plan'
    : 'no planner status';

  const c = s.controls;
  const pause = $('btn-pause');
  pause.textContent = c.paused ? 'resume vision' : 'pause vision';
  pause.classList.toggle('paused', c.paused);
  for (const [id, on] of [['btn-blobify', c.mode === 'blobify'], ['btn-trackify', c.mode === 'trackify'],
    ['btn-full', c.scan === 'full'], ['btn-axis', c.scan === 'axis'], ['btn-single', c.planner === 'single'],
    ['btn-multi', c.planner === 'multi'], ['btn-lookahead', c.planner === 'lookahead']]) {
    $(id).classList.toggle('active', on);
  }
  $('btn-estop').classList.toggle('paused', c.estop);  // lit while the stop is held
  $('btn-estop').textContent = c.estop ? 'STOPPED' : 'STOP arm';
  const sheep = $('sheep');
  if (document.activeElement !== sheep) sheep.value = c.sheep;
}

function esc(s) {
  return String(s).replace(/[&<>"']/g, (ch) => '&#' + ch.charCodeAt(0) + ';');
}

async function send(params) {
  const q = new URLSearchParams(params);
  const r = await fetch('api/cmd?' + q.toString(), { method: 'POST' });
  const body = await r.json().catch(() => ({}));
  $('message').textContent = r.ok ? '' : 'refused: ' + (body.error || 'HTTP ' + r.status);
  return r.ok;
}

for (const b of document.querySelectorAll('button[data-cmd]')) {
  b.addEventListener('click', () => {
    let value = b.dataset.value;
    if (b.dataset.cmd === 'pause') value = state && state.controls.paused ? 'false' : 'true';
    send({ cmd: b.dataset.cmd, value });
  });
}
$('btn-sheep').addEventListener('click', () => send({ cmd: 'sheep', value: $('sheep').value }));

// Calibration box: drag on the image while the layer is on.
function imagePos(ev) {
  const r = canvas.getBoundingClientRect();
  const clamp = (x, hi) => Math.min(Math.max(x, 0), hi);
  return [clamp((ev.clientX - r.left) * canvas.width / r.width, canvas.width - 1),
    clamp((ev.clientY - r.top) * canvas.height / r.height, canvas.height - 1)];
}
let lastBoxSend = 0;
function sendBox(final) {
  const now = performance.now();
  if (!final && now - lastBoxSend < 100) return;  // at most 10 commands/s while dragging
  lastBoxSend = now;
  send({ cmd: 'box', u: box.u.toFixed(1), v: box.v.toFixed(1), half: String(box.half) });
}
canvas.addEventListener('mousedown', (ev) => {
  if (!$('layer-box').checked) return;
  const [u, v] = imagePos(ev);
  box = { u, v, half: state ? state.controls.box.half : 12 };
  sendBox(false);
});
canvas.addEventListener('mousemove', (ev) => {
  if (!box) return;
  [box.u, box.v] = imagePos(ev);
  sendBox(false);
});
window.addEventListener('mouseup', () => {
  if (!box) return;
  sendBox(true);
  box = null;
});

loop();
