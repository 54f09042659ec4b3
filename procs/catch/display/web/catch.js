// The catching system's page (paper 000, issue 14): the camera image with
// the board's outline (blue, the bottom edge thicker) and circles through
// vision's pose, the ball vision sees (green; its window of interest grey),
// the world model's ball (magenta), its predicted path (dashed) and exit
// point with 1σ along the edge (orange), the catch point in the catch plane
// (orange ring), the cup's rim on the arm (cyan), the simulator's ball
// (yellow, optional). Built on ephor_page.js.
'use strict';

const { $, fmt, esc } = ephorPage;
const canvas = $('image');
const ctx = canvas.getContext('2d');

function line(points, close) {
  if (!points || points.length < 2) return;
  ctx.beginPath();
  points.forEach(([u, v], i) => (i ? ctx.lineTo(u, v) : ctx.moveTo(u, v)));
  if (close) ctx.closePath();
  ctx.stroke();
}

function cross(p, r) {
  if (!p) return;
  const [u, v] = p;
  line([[u - r, v - r], [u + r, v + r]]);
  line([[u - r, v + r], [u + r, v - r]]);
}

function ring(p, r) {
  if (!p) return;
  ctx.beginPath();
  ctx.arc(p[0], p[1], r, 0, 2 * Math.PI);
  ctx.stroke();
}

function draw(s, image) {
  if (s.frame.width > 0 && (canvas.width !== s.frame.width || canvas.height !== s.frame.height)) {
    canvas.width = s.frame.width;
    canvas.height = s.frame.height;
  }
  ctx.setLineDash([]);
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  if (image) ctx.drawImage(image, 0, 0);
  ctx.lineWidth = 1.5;
  ctx.font = '12px system-ui, sans-serif';

  const b = s.board;
  if (b && b.outline.length) {
    ctx.strokeStyle = '#3fa7ff';
    line(b.outline, true);
    ctx.lineWidth = 3;
    line(b.bottom_edge, false);
    ctx.lineWidth = 1.5;
    ctx.strokeStyle = '#ffffff';
    for (const c of b.circles_px) cross(c, 4);
  }

  const ball = s.ball;
  if (ball && $('layer-window').checked) {
    const [u0, v0, u1, v1] = ball.window;
    ctx.strokeStyle = 'rgba(200, 200, 200, 0.6)';
    ctx.setLineDash([3, 3]);
    ctx.strokeRect(u0, v0, u1 - u0, v1 - v0);
    ctx.setLineDash([]);
  }
  if (ball && ball.found) {
    ctx.strokeStyle = '#39ff7a';
    ring([ball.u, ball.v], 8);
    ctx.fillStyle = '#39ff7a';
    ctx.fillRect(ball.u_blob - 1.5, ball.v_blob - 1.5, 3, 3);  // the paper's blob centroid
  }

  const w = s.world;
  if (w && $('layer-path').checked) {
    if (w.path_px) {
      ctx.strokeStyle = '#ff5ad1';
      ctx.setLineDash([5, 4]);
      line(w.path_px, false);
      ctx.setLineDash([]);
    }
    if (w.exit_px) {
      ctx.strokeStyle = '#ff9f1a';
      ctx.lineWidth = 4;
      line(w.exit_span_px, false);
      ctx.lineWidth = 2;
      cross(w.exit_px, 7);
      ctx.fillStyle = '#ff9f1a';
      ctx.fillText('exit ' + fmt(w.exit_x_b_mm, 0) + ' ± ' + fmt(w.exit_sigma_mm, 0) + ' mm, ' +
        fmt(Math.max(w.exit_in_s, 0), 2) + ' s', w.exit_px[0] + 10, w.exit_px[1] + 16);
      ctx.lineWidth = 1.5;
    }
    if (w.catch_px) {
      ctx.strokeStyle = '#ff9f1a';
      ring(w.catch_px, 6);
    }
  }
  if (w && w.ball_px) {
    ctx.strokeStyle = '#ff5ad1';
    ring(w.ball_px, 5);
  }

  const a = s.arm;
  if (a && a.rim_px.length) {
    ctx.strokeStyle = '#00e5ff';
    ctx.lineWidth = 2;
    line(a.rim_px, true);
    ctx.lineWidth = 1.5;
    cross(a.cup_px, 3);
  }

  if ($('layer-truth').checked && s.truth && s.truth.ball_px) {
    const [u, v] = s.truth.ball_px;
    ctx.strokeStyle = '#ffd400';
    ctx.strokeRect(u - 5, v - 5, 10, 10);
  }
  canvas.dataset.updates = String(window.ephorDisplay.updates + 1);
  updatePanels(s);
}

function kv(rows) {
  return rows.map(([k, v]) => '<div>' + k + ' <b>' + v + '</b></div>').join('');
}

function updatePanels(s) {
  const sc = s.score;
  $('score-caught').textContent = sc ? sc.caught : '–';
  $('score-balls').textContent = sc ? sc.balls : '–';
  $('score-oracle').textContent = sc ? sc.oracle_reachable : '–';

  const w = s.world, t = s.truth, ball = s.ball;
  const rows = [];
  if (w) {
    rows.push(['world model', esc(w.status) + ' (ball ' + w.ball_id + ')' + (w.reason ? ': ' + esc(w.reason) : '')]);
    if (w.position_b_mm) {
      rows.push(['on the board', '(' + fmt(w.position_b_mm[0], 0) + ', ' + fmt(w.position_b_mm[1], 0) + ') mm, ' +
        fmt(Math.hypot(...w.velocity_b_mm_s), 0) + ' mm/s']);
    }
    if (w.exit_x_b_mm !== undefined) {
      rows.push(['exit', fmt(w.exit_x_b_mm, 0) + ' ± ' + fmt(w.exit_sigma_mm, 0) + ' mm in ' +
        fmt(w.exit_in_s, 2) + ' ± ' + fmt(w.exit_sigma_s, 2) + ' s']);
    }
    if (w.catch_point_w_mm) rows.push(['catch point W', '(' + w.catch_point_w_mm.map((x) => fmt(x, 0)).join(', ') + ') mm']);
    rows.push(['frame to prediction', fmt(w.latency_ms, 1) + ' ms']);
  } else {
    rows.push(['world model', 'nothing heard']);
  }
  if (ball) rows.push(['vision', (ball.found ? 'ball, ' + ball.area_px + ' px' : 'no ball') + ', ' + fmt(ball.exec_ms, 2) + ' ms']);
  if (t) {
    rows.push(['simulator', 'ball ' + t.ball + ' ' + t.phase]);
    if (t.last_ball >= 0) {
      rows.push(['last ball', '<span class="' + (t.last_caught ? 'good' : 'bad') + '">' + t.last_ball + ' ' +
        (t.last_caught ? 'caught' : 'missed') + '</span>' + (t.last_reason ? ': ' + esc(t.last_reason) : '') +
        (t.last_oracle_reachable ? '' : ' (out of reach)')]);
    }
  }
  $('ball-kv').innerHTML = kv(rows);

  const a = s.arm;
  $('arm-kv').innerHTML = a
    ? kv([['cup W', '(' + fmt(a.x_mm, 0) + ', ' + fmt(a.y_mm, 0) + ', ' + fmt(a.z_mm, 0) + ') mm'],
      ['motion', (a.moving ? 'moving ' : 'at rest ') + fmt(a.speed_mm_s, 0) + ' mm/s'],
      ['in the image', a.cup_px ? '(' + fmt(a.cup_px[0], 0) + ', ' + fmt(a.cup_px[1], 0) + ') px' : 'not yet (needs pose and survey)']])
    : 'no ARM_STATE heard';

  const b = s.board;
  $('board-kv').innerHTML = b
    ? kv([['pose', b.valid ? 'found, ' + fmt(b.rms_px, 2) + ' px rms' : 'not found: ' + esc(b.reason)],
      ['survey', b.surveyed ? 'incline ' + fmt(b.incline_deg, 1) + '°' : (b.survey_problem ? esc(b.survey_problem) : 'not yet')]])
    : 'no board pose heard';

  $('status-line').textContent = 'frame ' + s.frame.index + ' · ' + s.frame.width + ' × ' + s.frame.height +
    (s.controls && s.controls.estop ? ' · ARM STOPPED from this page' : '');
}

ephorPage.start({ camera: true, draw });
