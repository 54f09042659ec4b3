// The light-stripe page: the cloud of the scan in hand as three.js points
// (THREE r111, global), growing as /api/cloud grows, beside the camera's
// newest image (/api/frame.jpg) and the scan's state (/api/state).
(function () {
  "use strict";
  const view = document.getElementById("view");
  const status = document.getElementById("status");
  const camera = document.getElementById("camera");
  let renderer = null, scene = null, cam = null, points = null;
  let yaw = -2.1, pitch = 0.6, dist = 650, target = [40, 0, 20];
  if (typeof THREE !== "undefined") {
    try {
      renderer = new THREE.WebGLRenderer({ antialias: true });
      renderer.setSize(view.clientWidth, view.clientHeight);
      renderer.setClearColor(0xffffff);
      view.appendChild(renderer.domElement);
      scene = new THREE.Scene();
      cam = new THREE.PerspectiveCamera(40, view.clientWidth / view.clientHeight, 1, 5000);
      cam.up.set(0, 0, 1);
      scene.add(new THREE.AxesHelper(50));
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute("position", new THREE.Float32BufferAttribute([], 3));
      geometry.setAttribute("color", new THREE.Float32BufferAttribute([], 3));
      points = new THREE.Points(geometry, new THREE.PointsMaterial({ size: 2, vertexColors: THREE.VertexColors, sizeAttenuation: false }));
      scene.add(points);
    } catch (e) {
      view.textContent = "no WebGL here: " + e;
      renderer = null;
    }
  } else {
    view.textContent = "three.js did not load (/lib/three.min.js: Debian's libjs-three)";
  }
  function place() {
    if (!cam) return;
    cam.position.set(target[0] + dist * Math.cos(pitch) * Math.cos(yaw),
                     target[1] + dist * Math.cos(pitch) * Math.sin(yaw),
                     target[2] + dist * Math.sin(pitch));
    cam.lookAt(target[0], target[1], target[2]);
    renderer.render(scene, cam);
  }
  let drag = null;
  view.addEventListener("mousedown", (e) => { drag = [e.clientX, e.clientY]; });
  window.addEventListener("mouseup", () => { drag = null; });
  window.addEventListener("mousemove", (e) => {
    if (!drag) return;
    yaw -= (e.clientX - drag[0]) * 0.01;
    pitch = Math.max(-1.4, Math.min(1.4, pitch + (e.clientY - drag[1]) * 0.01));
    drag = [e.clientX, e.clientY];
    place();
  });
  view.addEventListener("wheel", (e) => { e.preventDefault(); dist = Math.max(100, dist * (e.deltaY > 0 ? 1.1 : 0.9)); place(); });
  function colour(t) {  // blue low -> red high
    t = Math.max(0, Math.min(1, t));
    return [Math.min(1, 2 * t), 1 - Math.abs(2 * t - 1) * 0.7, Math.max(0, 1 - 2 * t)];
  }
  let shown = -1, scanId = null;
  // What tests/e2e/screenshot.mjs reads of every page.
  const t0 = Date.now();
  window.ephorDisplay = { updates: 0, images: 0, updatesPerS: 0, imagesPerS: 0 };
  camera.onload = () => { window.ephorDisplay.images++; };
  async function refresh() {
    try {
      const st = await (await fetch("/api/state")).json();
      const s = st.scan, c = st.cloud;
      status.textContent = s
        ? `scan ${s.scan_id}: ${s.state}${s.reason ? " (" + s.reason + ")" : ""}\n` +
          `stripes ${s.stripes_captured} of ${s.stripes_planned} (${s.stripes_skipped} skipped), ${s.step_mm} mm apart, ${s.height_mm} mm up\n` +
          `region (${s.region_mm[0]}, ${s.region_mm[1]}) - (${s.region_mm[2]}, ${s.region_mm[3]}) mm\n` +
          `${s.stripes_per_s.toFixed(2)} stripes/s scanned (paper: 3-4), ${s.elapsed_s.toFixed(1)} s\n` +
          `cloud: ${c.points} points from ${c.stripes} stripes${c.complete ? ", complete" + (c.path ? ": " + c.path : "") : ""}`
        : "waiting for the scan...";
      camera.src = "/api/frame.jpg?t=" + Date.now();
      if (points && c && (c.points !== shown || (s && s.scan_id !== scanId))) {
        const cl = await (await fetch("/api/cloud")).json();
        const xyz = cl.xyz;
        let zmax = 1;
        for (let i = 2; i < xyz.length; i += 3) zmax = Math.max(zmax, xyz[i]);
        const rgb = new Float32Array(xyz.length);
        for (let i = 0; i < xyz.length; i += 3) rgb.set(colour(xyz[i + 2] / zmax), i);
        points.geometry.setAttribute("position", new THREE.Float32BufferAttribute(xyz, 3));
        points.geometry.setAttribute("color", new THREE.BufferAttribute(rgb, 3));
        points.geometry.computeBoundingSphere();
        if (s && s.scan_id !== scanId) {
          scanId = s.scan_id;
          target = [(s.region_mm[0] + s.region_mm[2]) / 2, (s.region_mm[1] + s.region_mm[3]) / 2, 20];
        }
        shown = cl.points;
      }
      place();
      const d = window.ephorDisplay, s_ = (Date.now() - t0) / 1000;
      d.updates++;
      d.updatesPerS = d.updates / s_;
      d.imagesPerS = d.images / s_;
    } catch (e) {
      status.textContent = "no answer from the display: " + e;
    }
  }
  async function estop(stop) { await fetch("/api/cmd?cmd=estop&value=" + (stop ? 1 : 0), { method: "POST" }); }
  document.getElementById("stop").onclick = () => estop(true);
  document.getElementById("release").onclick = () => estop(false);
  setInterval(refresh, 500);
  refresh();
})();
