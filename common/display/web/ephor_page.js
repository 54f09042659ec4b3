// Shared script of the system pages (sphere, catch) served by DisplayServer:
// the poll loop (/api/state and, with a camera, /api/frame.jpg every 50 ms
// at most), the scheduler's task table (#tasks), the message rates (#rates),
// the updates/s figure (#updates-per-s), the STOP / release buttons
// (button[data-cmd]) and POST /api/cmd. A page calls
//   ephorPage.start({ camera: true|false, draw(state, image) { ... } })
// No build step, no libraries.
'use strict';

const ephorPage = (() => {
  const PERIOD_MS = 50;  // one update every 50 ms at most: up to 20 updates/s
  const $ = (id) => document.getElementById(id);
  // Exposed for tests and curious users: what the newest draw showed.
  window.ephorDisplay = { updates: 0, state: null, updatesPerS: 0, imagesPerS: 0 };
  let image = null;  // newest camera image (ImageBitmap)
  let imageIndex = -1;
  const updateTimes = [];
  const imageTimes = [];

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

  function fmt(x, digits) { return Number(x).toFixed(digits); }

  function esc(s) {
    return String(s).replace(/[&<>"']/g, (ch) => '&#' + ch.charCodeAt(0) + ';');
  }

  function updateTables(s) {
    const tasks = $('tasks');
    if (tasks) {
      const rows = [];
      for (const h of s.sched) {
        for (const t of h.tasks) {
          const bad = t.deadline_misses > 0 || !t.alive;
          rows.push('<tr' + (bad ? ' class="bad"' : '') + '><td>' + esc(h.host) + '</td><td>' +
            esc(t.process) + '</td><td>' + esc(t.task) + '</td><td>' + (t.cpu < 0 ? 'any' : t.cpu) +
            '</td><td>' + esc(t.policy.replace('SCHED_', '')) + '</td><td>' + t.priority + '</td><td>' +
            (t.periodic ? fmt(t.period_us / 1000, 1) : 'trig') + '</td><td>' + fmt(t.exec_p50_us, 0) +
            ' / ' + fmt(t.exec_p99_us, 0) + ' / ' + fmt(t.exec_max_us, 0) + '</td><td>' +
            fmt(t.jitter_p50_us, 0) + ' / ' + fmt(t.jitter_p99_us, 0) + ' / ' + fmt(t.jitter_max_us, 0) +
            '</td><td>' + t.jobs + '</td><td>' + t.deadline_misses + '</td><td>' + (t.rt ? 'yes' : 'no') +
            '</td></tr>');
        }
      }
      tasks.tBodies[0].innerHTML = rows.join('') ||
        '<tr><td colspan="12">no scheduler status heard (EPHOR_SCHED_STATUS)</td></tr>';
    }
    const rates = $('rates');
    if (rates) {
      rates.tBodies[0].innerHTML = Object.entries(s.rates_hz)
        .map(([c, hz]) => '<tr><td>' + esc(c) + '</td><td>' + fmt(hz, 1) + '</td></tr>').join('');
    }
    const ups = $('updates-per-s');
    if (ups) {
      ups.textContent = fmt(window.ephorDisplay.updatesPerS, 1) +
        (imageTimes.length || imageIndex >= 0 ? ' (images ' + fmt(window.ephorDisplay.imagesPerS, 1) + ')' : '');
    }
    const stop = $('btn-estop');
    if (stop && s.controls) {
      stop.classList.toggle('paused', s.controls.estop);  // lit while the stop is held
      stop.textContent = s.controls.estop ? 'STOPPED' : 'STOP arm';
    }
  }

  async function send(params) {
    const q = new URLSearchParams(params);
    const r = await fetch('api/cmd?' + q.toString(), { method: 'POST' });
    const body = await r.json().catch(() => ({}));
    const m = $('message');
    if (m) m.textContent = r.ok ? '' : 'refused: ' + (body.error || 'HTTP ' + r.status);
    return r.ok;
  }

  function start(page) {
    for (const b of document.querySelectorAll('button[data-cmd]')) {
      b.addEventListener('click', () => send({ cmd: b.dataset.cmd, value: b.dataset.value }));
    }
    async function loop() {
      const t0 = performance.now();
      try {
        const [s, img] = await Promise.all([fetchState(), page.camera ? fetchFrame() : null]);
        if (img) {
          if (image) image.close();
          image = img;
        }
        window.ephorDisplay.state = s;
        await page.draw(s, image);
        updateTables(s);
        const now = performance.now();
        updateTimes.push(now);
        while (updateTimes.length && updateTimes[0] < now - 2000) updateTimes.shift();
        while (imageTimes.length && imageTimes[0] < now - 2000) imageTimes.shift();
        window.ephorDisplay.updatesPerS = updateTimes.length / 2;
        window.ephorDisplay.imagesPerS = imageTimes.length / 2;
        window.ephorDisplay.updates++;
      } catch (e) {
        const line = document.querySelector('.status-line');
        if (line) line.textContent = 'no connection to the display: ' + e.message;
      }
      setTimeout(loop, Math.max(0, PERIOD_MS - (performance.now() - t0)));
    }
    loop();
  }

  return { start, send, fmt, esc, $ };
})();
