// The RAMBO page (paper 001, issue 17 item 6), built on ephor_page.js: the
// camera image with the corners (yellow) and image edges (blue) the features
// process found, the image triangles the pose matched to model triangles
// (green) and the model's outline by the estimated pose (magenta); a 3-D
// view (three.js, global THREE from /lib/three.min.js) of the target at its
// estimated (magenta) and true (grey) poses in the PUMA's base frame, the
// diodes on the true target (green tagged, yellow lit, red not yet), the
// camera and the laser's beam; the planned order and the diodes' state.
'use strict';

const { $, fmt, esc } = ephorPage;
const canvas = $('image');
const ctx = canvas.getContext('2d');

// ---- the 3-D view ------------------------------------------------------
const view = $('view');
let three = null;  // { renderer, scene, cam, estimated, truth, diodes[], camera, beam }
let model = null;
let yaw = -2.4, pitch = 0.45, dist = 1500, centre = [750, 0, 200];

function matrixOf(p) {  // {r: row-major 9, t_mm: 3} -> THREE.Matrix4
  const r = p.r, t = p.t_mm;
  return new THREE.Matrix4().set(r[0], r[1], r[2], t[0], r[3], r[4], r[5], t[1],
    r[6], r[7], r[8], t[2], 0, 0, 0, 1);
}

function targetMesh(colour, opacity) {
  const pos = [];
  for (const f of model.faces) {  // a fan per (convex) face
    for (let k = 1; k + 1 < f.length; k++) {
      for (const v of [f[0], f[k], f[k + 1]]) pos.push(...model.vertices[v]);
    }
  }
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
  g.computeVertexNormals();
  const group = new THREE.Group();
  group.add(new THREE.Mesh(g, new THREE.MeshLambertMaterial({
    color: colour, transparent: opacity < 1, opacity, side: THREE.DoubleSide })));
  group.add(new THREE.LineSegments(new THREE.EdgesGeometry(g),
    new THREE.LineBasicMaterial({ color: colour })));
  group.matrixAutoUpdate = false;
  group.visible = false;
  return group;
}

function setup3d() {
  if (typeof THREE === 'undefined') {
    view.textContent = 'three.js did not load (/lib/three.min.js: Debian\'s libjs-three)';
    return;
  }
  try {
    const renderer = new THREE.WebGLRenderer({ antialias: true });
    renderer.setSize(view.clientWidth, view.clientHeight);
    renderer.setClearColor(0x101215);
    view.appendChild(renderer.domElement);
    const scene = new THREE.Scene();
    scene.add(new THREE.AmbientLight(0xffffff, 0.5));
    const sun = new THREE.DirectionalLight(0xffffff, 0.7);
    sun.position.set(1, -1, 2);
    scene.add(sun);
    scene.add(new THREE.AxesHelper(200));  // the PUMA's base: x red, y green, z blue
    const cam = new THREE.PerspectiveCamera(35, view.clientWidth / view.clientHeight, 10, 20000);
    cam.up.set(0, 0, 1);
    const estimated = targetMesh(0xff4fd8, 0.35);
    const truth = targetMesh(0xcfd6df, 0.6);
    scene.add(estimated, truth);
    const diodes = model.diodes.map((d) => {
      const m = new THREE.Mesh(new THREE.SphereGeometry(9, 12, 8),
        new THREE.MeshBasicMaterial({ color: 0xff5050 }));
      m.position.set(...d.lens_mm);
      truth.add(m);
      return m;
    });
    const camera = new THREE.Mesh(new THREE.BoxGeometry(40, 40, 40),
      new THREE.MeshBasicMaterial({ color: 0x3fa7ff }));
    camera.visible = false;
    scene.add(camera);
    const beamGeometry = new THREE.BufferGeometry();
    beamGeometry.setAttribute('position', new THREE.Float32BufferAttribute([0, 0, 0, 0, 0, 0], 3));
    const beam = new THREE.Line(beamGeometry, new THREE.LineBasicMaterial({ color: 0xff2020 }));
    beam.visible = false;
    scene.add(beam);
    // The RM-501 carrying the target (--carrier rm501): one rod per link,
    // placed from the truth's chain of points each update.
    const carrier = [60, 40, 32, 25, 12].map((r) => {
      const m = new THREE.Mesh(new THREE.CylinderGeometry(r, r, 1, 16),
        new THREE.MeshLambertMaterial({ color: 0xd08a3a }));
      m.visible = false;
      scene.add(m);
      return m;
    });
    three = { renderer, scene, cam, estimated, truth, diodes, camera, beam, carrier };
  } catch (e) {
    view.textContent = 'no WebGL here: ' + e;
  }
}

function render3d() {
  if (!three) return;
  const c = three.cam;
  c.position.set(centre[0] + dist * Math.cos(pitch) * Math.cos(yaw),
    centre[1] + dist * Math.cos(pitch) * Math.sin(yaw), centre[2] + dist * Math.sin(pitch));
  c.lookAt(centre[0], centre[1], centre[2]);
  three.renderer.render(three.scene, c);
}

let drag = null;
view.addEventListener('mousedown', (e) => { drag = [e.clientX, e.clientY]; });
window.addEventListener('mouseup', () => { drag = null; });
window.addEventListener('mousemove', (e) => {
  if (!drag) return;
  yaw -= (e.clientX - drag[0]) * 0.01;
  pitch = Math.max(-1.4, Math.min(1.4, pitch + (e.clientY - drag[1]) * 0.01));
  drag = [e.clientX, e.clientY];
  render3d();
});
view.addEventListener('wheel', (e) => {
  e.preventDefault();
  dist = Math.max(300, dist * (e.deltaY > 0 ? 1.1 : 0.9));
  render3d();
});

function update3d(s) {
  if (!three) return;
  const p = s.pose;
  if (p.estimated) {
    three.estimated.matrix.copy(matrixOf(p.estimated));
    three.estimated.visible = true;
  }
  if (p.true) {
    three.truth.matrix.copy(matrixOf(p.true));
    three.truth.visible = true;
    // Between the target and the arm's reach, towards the target.
    centre = [0.8 * p.true.t_mm[0], 0.8 * p.true.t_mm[1], 0.8 * p.true.t_mm[2] + 60];
  }
  // The carrying arm's links: a unit cylinder (along y) stretched from one
  // chain point to the next.
  const chain = (p.true && p.true.carrier_mm) || [];
  three.carrier.forEach((link, k) => {
    if (k + 1 >= chain.length) { link.visible = false; return; }
    const a = new THREE.Vector3(...chain[k]), b = new THREE.Vector3(...chain[k + 1]);
    const d = new THREE.Vector3().subVectors(b, a);
    link.scale.set(1, Math.max(d.length(), 1e-3), 1);
    link.position.copy(a).addScaledVector(d, 0.5);
    link.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), d.clone().normalize());
    link.visible = true;
  });
  if (p.camera) {
    three.camera.position.set(...p.camera.t_mm);
    three.camera.visible = true;
  }
  s.diodes.forEach((d, i) => {
    if (i < three.diodes.length) {
      three.diodes[i].material.color.setHex(d.tagged ? 0x44dd66 : d.lit ? 0xffd400 : 0xff5050);
    }
  });
  if (s.laser) {
    const a = s.laser.tip_mm, b = s.laser.beam;
    const pos = three.beam.geometry.attributes.position;
    pos.setXYZ(0, a[0], a[1], a[2]);
    pos.setXYZ(1, a[0] + 400 * b[0], a[1] + 400 * b[1], a[2] + 400 * b[2]);
    pos.needsUpdate = true;
    three.beam.visible = true;
  }
  render3d();
}

// ---- the camera image ----------------------------------------------------
function drawImage(s, image) {
  const im = s.image;
  if (canvas.width !== im.width || canvas.height !== im.height) {
    canvas.width = im.width;
    canvas.height = im.height;
  }
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  if (image) ctx.drawImage(image, 0, 0);
  ctx.lineWidth = 1.5;
  ctx.fillStyle = 'rgba(68, 221, 102, 0.18)';
  ctx.strokeStyle = '#44dd66';
  for (const t of im.matched_triangles) {
    ctx.beginPath();
    ctx.moveTo(t[2], t[3]);
    ctx.lineTo(t[0], t[1]);
    ctx.lineTo(t[4], t[5]);
    ctx.closePath();
    ctx.fill();
    ctx.stroke();
  }
  ctx.strokeStyle = '#ff4fd8';
  ctx.setLineDash([5, 4]);
  for (const e of im.estimated_outline) {
    ctx.beginPath();
    ctx.moveTo(e[0], e[1]);
    ctx.lineTo(e[2], e[3]);
    ctx.stroke();
  }
  ctx.setLineDash([]);
  const f = im.features;
  if (f) {
    ctx.strokeStyle = '#3fa7ff';
    for (const [i, j] of f.edges) {
      ctx.beginPath();
      ctx.moveTo(...f.corners[i]);
      ctx.lineTo(...f.corners[j]);
      ctx.stroke();
    }
    ctx.strokeStyle = '#ffd400';
    for (const [x, y] of f.corners) {
      ctx.beginPath();
      ctx.moveTo(x - 5, y);
      ctx.lineTo(x + 5, y);
      ctx.moveTo(x, y - 5);
      ctx.lineTo(x, y + 5);
      ctx.stroke();
    }
  }
  const n = s.pose.newest;
  $('status-line').textContent = (f ? `frame ${f.frame_index} (${f.source}): ${f.corners.length} corners, ` +
    `${f.edges.length} edges, ${f.triples} triples; ` : 'no features yet; ') +
    (n ? (n.found ? `pose of frame ${n.frame_index}: ${n.matched_triangles} triangles matched, ` +
      `${n.correspondences} points fit` : `frame ${n.frame_index}: no pose: ${n.reason}`) : 'no pose yet');
}

// ---- the side panel --------------------------------------------------------
function drawSide(s) {
  const ind = s.indicator;
  $('score-tagged').textContent = `${ind.tagged} of ${ind.of}`;
  $('score-poses').textContent = `${s.pose.poses_found} of ${s.pose.poses}`;
  const plan = s.plan;
  const tagged = new Set(s.diodes.filter((d) => d.tagged).map((d) => d.index));
  if (plan) {
    $('plan-status').innerHTML = `<div>status <b>${esc(plan.status)}</b></div>` +
      `<div>current <b>${plan.current ? esc(plan.current.name) : '–'}</b></div>`;
    $('order').innerHTML = plan.order.map((o) => `<li class="${plan.current && plan.current.diode === o.diode ? 'current' : ''}">` +
      `${esc(o.name)}${tagged.has(o.diode) ? ' ✓' : ''}</li>`).join('') || '<li>(nothing left to order)</li>';
    const t = plan.trajectories;
    $('plan-kv').innerHTML = `<div>reaching trajectories computed: greedy <b>${t.greedy}</b>, ` +
      `exhaustive <b>${t.exhaustive}</b>, DP <b>${t.dynamic_programming}</b></div>` +
      `<div>order's predicted time <b>${fmt(plan.order_total_s, 1)} s</b>, goals sent <b>${plan.goals_sent}</b></div>`;
  } else {
    $('plan-status').textContent = 'no plan yet';
  }
  $('diodes').tBodies[0].innerHTML = s.diodes.map((d) =>
    `<tr><td>${d.index}</td><td>${esc(d.name)}</td><td class="${d.tagged ? 'good' : ''}">` +
    `${d.tagged ? 'yes' : d.lit ? 'lit ' + fmt(ind.lit_s, 1) + ' s' : 'no'}</td>` +
    `<td>${d.beam_angle_deg === null ? '–' : fmt(d.beam_angle_deg, 1)}</td>` +
    `<td>${d.beam_offset_mm === null ? '–' : (d.beam_offset_mm > 9999 ? '–' : fmt(d.beam_offset_mm, 0))}</td></tr>`).join('');
  const e = s.pose.estimated, tr = s.pose.true, n = s.pose.newest;
  $('pose-kv').innerHTML =
    (e ? `<div>estimated (frame ${e.frame_index}${tr && tr.frame_index > e.frame_index ? ', ' + (tr.frame_index - e.frame_index) + ' frames ago' : ''}) <b>${e.t_mm.map((x) => fmt(x, 0)).join(', ')}</b> mm</div>` : '<div>no pose found yet</div>') +
    (tr ? `<div>true (frame ${tr.frame_index}) <b>${tr.t_mm.map((x) => fmt(x, 0)).join(', ')}</b> mm</div>` : '') +
    (e && e.error_mm !== null ? `<div>error <b>${fmt(e.error_mm, 1)} mm, ${fmt(e.error_deg, 2)}°</b></div>` : '') +
    (n ? `<div>newest: ${n.found ? 'found' : 'no pose'}${n.pruned ? ', pruned by the prior' : ''}, ${fmt(n.pose_ms, 2)} ms</div>` : '');
}

async function draw(s, image) {
  if (!model) {
    const r = await fetch('api/model', { cache: 'no-store' });
    if (r.ok) {
      model = await r.json();
      setup3d();
    }
  }
  drawImage(s, image);
  drawSide(s);
  update3d(s);
  window.ephorDisplay.three = three !== null;
}

ephorPage.start({ camera: true, draw });
