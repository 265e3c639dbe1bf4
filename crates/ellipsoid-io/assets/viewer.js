// ellipsoid viewer (inlined into the page by ellipsoid_io::viewer). World frame: z up,
// metres; body pose R = Rz(phi) Rx(theta) Rz(psi) (paper eq. 1), G at (x, y, z).
// `window.ellipsoidViewer` is the page's interface for tests and scripting.
const D = JSON.parse(document.getElementById('data').textContent);
const $ = (id) => document.getElementById(id);
const fail = (msg) => { $('error').textContent = String(msg); console.error(msg); };
// Whatever stops the page says so on it (a module that throws would leave it blank),
// unless a more precise message is already there.
const stopped = (why) => { if (!$('error').textContent) fail(`the viewer stopped: ${why}`); };
window.addEventListener('error', (e) => stopped(e.message));
window.addEventListener('unhandledrejection', (e) => stopped(e.reason));

function f32(b64) {
  const bin = atob(b64);
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
  return new Float32Array(bytes.buffer);
}

// three.js from the inlined text, as a module (a blob URL: no network).
const src = $('three-src').textContent;
const THREE = await import(URL.createObjectURL(new Blob([src], { type: 'text/javascript' })));

let now = 0, dirty = true;
const F = {};
for (const k of ['t', 'x', 'y', 'z', 'theta', 'phi', 'psi', 'cx', 'cy', 'mode']) if (D.frames[k]) F[k] = f32(D.frames[k]);
// A body with contact spheres: its surfaces (the ellipsoid, then the spheres) and, per
// pose, which touch the plane (bit k for surface k).
const S = D.surfaces || null;
if (S) F.touch = f32(S.touch);
const N = D.frames.n;
const T0 = D.t0, T1 = D.t1;
now = T0;
const shape = D.shape || null;
const semi = shape ? shape.semi_axes : null;
const gOff = shape ? shape.com_offset : [0, 0, 0];
// Unknown body: a sphere whose radius is the mean height of G (so it touches the plane).
const radius0 = (() => { let s = 0; for (let i = 0; i < N; i++) s += F.z[i]; return Math.max(s / N, 1e-6); })();
const A = semi || [radius0, radius0, radius0];
const L = Math.max(A[0], A[1], A[2]);

$('info').textContent = `${D.rows.toLocaleString('en')} samples, t = ${T0.toPrecision(4)} … ${T1.toPrecision(4)} s` + (D.status ? `, ${D.status}` : '') + (N < D.rows ? ` (${N.toLocaleString('en')} poses shown)` : '');
if (!shape) $('note').textContent = D.shape_note + ' — drawn as a sphere; G\'s path shown instead of the contact point.';
else if (!D.contact) $('note').textContent = 'contact point unknown: G\'s path shown.';

// ---------------------------------------------------------------- scene
// Without WebGL there is no 3-D view, and only it is lost: the pose is still computed
// (the HUD), and the plots, the event list and the controls need no WebGL.
const host = $('scene');
let renderer = null;
try {
  renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
} catch (e) {
  fail(`WebGL is not available in this browser (${e.message || e}), so the 3-D view cannot be drawn (the plots, the event list and the controls work without it): enable hardware acceleration or WebGL, or open the page in another browser.`);
}
if (renderer) {
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  host.appendChild(renderer.domElement);
}
const scene = new THREE.Scene();
scene.background = new THREE.Color(0xdfe6ee);
const camera = new THREE.PerspectiveCamera(35, 1, L / 200, L * 5000);
camera.up.set(0, 0, 1);
scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 2.0));
const sun = new THREE.DirectionalLight(0xffffff, 1.6);
sun.position.set(-3, -2, 6);
scene.add(sun);

// Extent of the motion, for the plane and the grid.
let xmin = Infinity, xmax = -Infinity, ymin = Infinity, ymax = -Infinity;
for (let i = 0; i < N; i++) { xmin = Math.min(xmin, F.x[i]); xmax = Math.max(xmax, F.x[i]); ymin = Math.min(ymin, F.y[i]); ymax = Math.max(ymax, F.y[i]); }
const span = Math.max(xmax - xmin, ymax - ymin, 8 * L);
const cell = Math.pow(10, Math.floor(Math.log10(L * 1.2)));
const size = Math.ceil((span + 8 * L) / cell / 2) * cell * 2;
const plane = new THREE.Mesh(new THREE.PlaneGeometry(size, size), new THREE.MeshLambertMaterial({ color: 0xf7f5ee }));
plane.position.set((xmin + xmax) / 2, (ymin + ymax) / 2, 0);
scene.add(plane);
const grid = new THREE.GridHelper(size, Math.round(size / cell), 0xaaaaaa, 0xd0d0d0);
grid.rotation.x = Math.PI / 2;
grid.position.set(plane.position.x, plane.position.y, L * 1e-4);
scene.add(grid);

// The body: an ellipsoid (poles on body z) with alternating meridian sectors, an
// equatorial band and a dark cap on +z; the symmetry axis; G.
const body = new THREE.Group();
scene.add(body);
const geo = new THREE.SphereGeometry(1, 64, 40);
geo.rotateX(Math.PI / 2);
const pos = geo.getAttribute('position');
const col = new Float32Array(pos.count * 3);
const c = new THREE.Color();
for (let i = 0; i < pos.count; i++) {
  const x = pos.getX(i), y = pos.getY(i), z = pos.getZ(i);
  const sector = Math.floor(((Math.atan2(y, x) + Math.PI) / (2 * Math.PI)) * 12) % 2;
  if (Math.abs(z) < 0.12) c.set(0xe08a1e);
  else if (z > 0.93) c.set(0x303848);
  else c.set(sector ? 0x4f7cc4 : 0xe9edf3);
  col.set([c.r, c.g, c.b], 3 * i);
}
geo.setAttribute('color', new THREE.BufferAttribute(col, 3));
const mesh = new THREE.Mesh(geo, new THREE.MeshLambertMaterial({ vertexColors: true, transparent: true, opacity: 0.9 }));
mesh.scale.set(A[0], A[1], A[2]);
mesh.position.set(-gOff[0], -gOff[1], -gOff[2]);
body.add(mesh);
const axisGeo = new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(-gOff[0], -gOff[1], -gOff[2] - 1.35 * A[2]), new THREE.Vector3(-gOff[0], -gOff[1], -gOff[2] + 1.35 * A[2])]);
body.add(new THREE.Line(axisGeo, new THREE.LineBasicMaterial({ color: 0xd62728 })));
const gMark = new THREE.Mesh(new THREE.SphereGeometry(0.07 * L, 16, 12), new THREE.MeshBasicMaterial({ color: 0x111111, depthTest: false }));
gMark.renderOrder = 10;
body.add(gMark);

// The contact spheres and rims fixed in the body (centres from C0, body axes), violet and
// brown while open; a surface touching the plane is marked green (the ellipsoid by a green
// glow). A rim is its torus (a sharp edge drawn with a thin tube, 1.5 % of the body).
const SPHERE_OPEN = 0x8a5a9a, RIM_OPEN = 0x8c6d46, IN_CONTACT = 0x2ca02c, ELLIPSOID_GLOW = 0x1f6f1f;
const place = (m, c) => { m.position.set(c[0] - gOff[0], c[1] - gOff[1], c[2] - gOff[2]); body.add(m); return m; };
const spheres = S ? S.spheres.map((sp) => place(new THREE.Mesh(new THREE.SphereGeometry(sp.radius, 32, 20), new THREE.MeshLambertMaterial({ color: SPHERE_OPEN })), sp.center)) : [];
const rims = S && S.rims ? S.rims.map((rim) => place(new THREE.Mesh(new THREE.TorusGeometry(rim.radius, Math.max(rim.edge, 0.015 * L), 16, 96), new THREE.MeshLambertMaterial({ color: RIM_OPEN })), rim.center)) : [];
// Bit k of a pose's touch word is surface k of S.names: the ellipsoid (if it touches),
// the spheres, the rims.
const first = S ? (S.ellipsoid === false ? 0 : 1) : 1;
if (S) {
  const legend = document.querySelector('.legend');
  const items = [...(spheres.length ? [[SPHERE_OPEN, 'contact sphere']] : []), ...(rims.length ? [[RIM_OPEN, 'rim']] : []), [IN_CONTACT, 'surface in contact']];
  for (const [color, text] of items) {
    const item = document.createElement('span');
    item.innerHTML = `<i class="sw" style="background:#${color.toString(16).padStart(6, '0')}"></i>${text}`;
    legend.appendChild(item);
  }
}
// The surfaces touching the plane at frame i, by name.
const touching = (i) => (S ? S.names.filter((_, k) => (F.touch[i] >> k) & 1) : []);
function markContacts(i) {
  if (!S) return;
  const bits = F.touch[i];
  mesh.material.emissive.setHex(first === 1 && bits & 1 ? ELLIPSOID_GLOW : 0x000000);
  spheres.forEach((m, k) => m.material.color.setHex((bits >> (first + k)) & 1 ? IN_CONTACT : SPHERE_OPEN));
  rims.forEach((m, k) => m.material.color.setHex((bits >> (first + spheres.length + k)) & 1 ? IN_CONTACT : RIM_OPEN));
}

// Traces on the plane: the contact point (or G when it is unknown) and G's ground path.
function trace(xs, ys, color, z) {
  const p = new Float32Array(3 * N);
  for (let i = 0; i < N; i++) p.set([xs[i], ys[i], z], 3 * i);
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(p, 3));
  const line = new THREE.Line(g, new THREE.LineBasicMaterial({ color }));
  scene.add(line);
  return line;
}
const gTrace = trace(F.x, F.y, 0x999999, L * 2e-3);
const cTrace = F.cx ? trace(F.cx, F.cy, 0x1f77b4, L * 3e-3) : null;
const cMark = new THREE.Mesh(new THREE.CircleGeometry(0.08 * L, 20), new THREE.MeshBasicMaterial({ color: 0x1f77b4 }));
cMark.position.z = L * 4e-3;
cMark.visible = !!cTrace;
scene.add(cMark);

// Camera: orbits the target (G, when following) by dragging; the wheel zooms.
const cam = { az: -0.9, el: 0.42, dist: 7 * L, target: new THREE.Vector3(F.x[0], F.y[0], 0.6 * L), follow: true };
function placeCamera() {
  const ce = Math.cos(cam.el);
  camera.position.set(cam.target.x + cam.dist * ce * Math.cos(cam.az), cam.target.y + cam.dist * ce * Math.sin(cam.az), cam.target.z + cam.dist * Math.sin(cam.el));
  camera.lookAt(cam.target);
}
let drag = null;
if (renderer) {
  const el = renderer.domElement;
  el.addEventListener('pointerdown', (e) => { drag = [e.clientX, e.clientY]; el.setPointerCapture(e.pointerId); });
  el.addEventListener('pointerup', () => { drag = null; });
  el.addEventListener('pointermove', (e) => {
    if (!drag) return;
    cam.az -= (e.clientX - drag[0]) * 0.008;
    cam.el = Math.min(1.5, Math.max(-0.05, cam.el + (e.clientY - drag[1]) * 0.008));
    drag = [e.clientX, e.clientY];
    dirty = true;
  });
  el.addEventListener('wheel', (e) => { e.preventDefault(); cam.dist *= Math.exp(e.deltaY * 0.001); dirty = true; }, { passive: false });
}
$('follow').addEventListener('change', (e) => { cam.follow = e.target.checked; dirty = true; });

function resize() {
  if (!renderer) return;
  const w = host.clientWidth, h = host.clientHeight;
  renderer.setSize(w, h, false);
  camera.aspect = w / Math.max(h, 1);
  camera.updateProjectionMatrix();
  dirty = true;
}
new ResizeObserver(resize).observe(host);

// ---------------------------------------------------------------- poses
// The pose at time t, interpolated linearly between the two neighbouring frames
// (φ and ψ are unwrapped, so angles interpolate without jumps).
function frameAt(t) {
  let lo = 0, hi = N - 1;
  if (t <= F.t[0]) return [0, 0, 0];
  if (t >= F.t[N - 1]) return [N - 1, N - 1, 0];
  while (hi - lo > 1) { const m = (lo + hi) >> 1; if (F.t[m] <= t) lo = m; else hi = m; }
  const dt = F.t[hi] - F.t[lo];
  return [lo, hi, dt > 0 ? (t - F.t[lo]) / dt : 0];
}
const lerp = (a, i, j, s) => a[i] + (a[j] - a[i]) * s;
const qz = new THREE.Quaternion(), qx = new THREE.Quaternion(), qpsi = new THREE.Quaternion();
const Z = new THREE.Vector3(0, 0, 1), X = new THREE.Vector3(1, 0, 0);
function pose(t) {
  const [i, j, s] = frameAt(t);
  const p = { x: lerp(F.x, i, j, s), y: lerp(F.y, i, j, s), z: lerp(F.z, i, j, s), theta: lerp(F.theta, i, j, s), phi: lerp(F.phi, i, j, s), psi: lerp(F.psi, i, j, s), frame: s < 0.5 ? i : j };
  if (F.cx) { p.cx = lerp(F.cx, i, j, s); p.cy = lerp(F.cy, i, j, s); }
  return p;
}
function apply(t) {
  const p = pose(t);
  body.position.set(p.x, p.y, p.z);
  qz.setFromAxisAngle(Z, p.phi);
  qx.setFromAxisAngle(X, p.theta);
  qpsi.setFromAxisAngle(Z, p.psi);
  body.quaternion.copy(qz).multiply(qx).multiply(qpsi);
  const upto = frameAt(t)[0] + 1;
  gTrace.geometry.setDrawRange(0, upto);
  if (cTrace) { cTrace.geometry.setDrawRange(0, upto); cMark.position.x = p.cx; cMark.position.y = p.cy; }
  if (cam.follow) cam.target.set(p.x, p.y, 0.6 * L);
  markContacts(p.frame);
  const mode = F.mode && D.modes.length ? D.modes[F.mode[p.frame]] : (S ? `on ${touching(p.frame).join('+') || 'nothing'}` : '');
  $('hud').textContent = `t = ${t.toFixed(4)} s   θ = ${p.theta.toFixed(4)} rad (${(p.theta * 180 / Math.PI).toFixed(2)}°)` + (mode ? `   ${mode}` : '');
  $('time').textContent = `t = ${t.toFixed(4)} s / ${T1.toFixed(4)} s`;
  return p;
}

// ---------------------------------------------------------------- plots
const CURSOR = 'rgb(220,0,0)';
const LINE_COLORS = ['#1f77b4', '#ff7f0e', '#2ca02c', '#9467bd', '#8c564b', '#e377c2', '#7f7f7f', '#bcbd22', '#17becf'];
const M = { left: 70, right: 10, top: 20, bottom: 34 };
// One canvas per side plot the page was made with (`--columns`, `columns=`), in order.
const plots = D.plots.map((p) => {
  const canvas = document.createElement('canvas');
  canvas.id = 'plot-' + p.name.replace('_*', '-each'); canvas.width = 360; canvas.height = 190;
  canvas.setAttribute('aria-label', p.name + ' against time');
  $('plots').appendChild(canvas);
  // A plot of one quantity per surface has `lines`, each labelled by its surface.
  const lines = p.lines ? p.lines.map((l, k) => ({ label: l.label, t: f32(l.t), v: f32(l.v), color: LINE_COLORS[k % LINE_COLORS.length] }))
    : [{ t: f32(p.t), v: f32(p.v), color: '#1f77b4' }].concat(p.t2 ? [{ t: f32(p.t2), v: f32(p.v2), color: '#2ca02c' }] : []);
  const s = { name: p.name, label: p.label, canvas, lines };
  let lo = Infinity, hi = -Infinity;
  for (const l of lines) for (const v of l.v) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
  const pad = Math.max((hi - lo) * 0.08, Math.abs(hi) * 1e-6, 1e-12);
  s.lo = lo - pad; s.hi = hi + pad;
  canvas.addEventListener('click', (e) => {
    const r = canvas.getBoundingClientRect();
    const x = (e.clientX - r.left) * canvas.width / r.width;
    seek(T0 + (x - M.left) / (canvas.width - M.left - M.right) * (T1 - T0));
  });
  return s;
});
const xOf = (canvas, t) => M.left + (T1 > T0 ? (t - T0) / (T1 - T0) : 0) * (canvas.width - M.left - M.right);
function ticks(lo, hi, n) {
  const step0 = (hi - lo) / n, mag = Math.pow(10, Math.floor(Math.log10(step0)));
  const step = [1, 2, 5, 10].map((k) => k * mag).find((s) => s >= step0) || step0;
  const out = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) out.push(Math.abs(v) < step * 1e-9 ? 0 : v);
  return out;
}
const fmt = (v) => { const a = Math.abs(v); return a !== 0 && (a < 1e-3 || a >= 1e4) ? v.toExponential(2) : String(+v.toPrecision(5)); };
function drawPlot(s, t) {
  const g = s.canvas.getContext('2d'), W = s.canvas.width, H = s.canvas.height;
  const pw = W - M.left - M.right, ph = H - M.top - M.bottom;
  const yOf = (v) => M.top + (1 - (v - s.lo) / (s.hi - s.lo)) * ph;
  g.fillStyle = '#fff'; g.fillRect(0, 0, W, H);
  g.strokeStyle = '#444'; g.lineWidth = 1; g.strokeRect(M.left + 0.5, M.top + 0.5, pw, ph);
  g.fillStyle = '#222'; g.font = '11px "DejaVu Sans", sans-serif';
  g.textAlign = 'right'; g.textBaseline = 'middle';
  for (const v of ticks(s.lo, s.hi, 4)) { const y = yOf(v); g.fillRect(M.left - 4, Math.round(y), 4, 1); g.fillText(fmt(v), M.left - 6, y); }
  g.textAlign = 'center'; g.textBaseline = 'top';
  for (const v of ticks(T0, T1, 5)) { const x = xOf(s.canvas, v); g.fillRect(Math.round(x), M.top + ph, 1, 4); g.fillText(fmt(v), x, M.top + ph + 6); }
  g.fillText('time t (s)', M.left + pw / 2, H - 13);
  g.textAlign = 'left'; g.textBaseline = 'top'; g.font = '12px "DejaVu Sans", sans-serif';
  g.fillText(s.label, M.left, 3);
  g.save(); g.beginPath(); g.rect(M.left, M.top, pw, ph); g.clip();
  for (const e of D.events) { g.fillStyle = 'rgba(120,60,160,0.55)'; g.fillRect(Math.round(xOf(s.canvas, e.t)), M.top, 1, ph); }
  const line = (ts, vs, color) => {
    g.strokeStyle = color; g.lineWidth = 1.3; g.beginPath();
    for (let i = 0; i < ts.length; i++) { const x = xOf(s.canvas, ts[i]), y = yOf(vs[i]); if (i) g.lineTo(x, y); else g.moveTo(x, y); }
    g.stroke();
  };
  for (const l of s.lines) line(l.t, l.v, l.color);
  // The legend of a plot per surface: each surface's name in its line's colour.
  let lx = M.left + pw - 4;
  g.textAlign = 'right'; g.textBaseline = 'top'; g.font = '11px "DejaVu Sans", sans-serif';
  for (const l of s.lines.filter((l) => l.label).reverse()) {
    const w = g.measureText(l.label).width;
    g.fillStyle = 'rgba(255,255,255,0.85)'; g.fillRect(lx - w - 2, M.top + 2, w + 4, 14);
    g.fillStyle = l.color; g.fillText(l.label, lx, M.top + 3);
    lx -= w + 8;
  }
  // The cursor: a 2-pixel column of exactly CURSOR, so tests can find it.
  g.fillStyle = CURSOR; g.fillRect(Math.round(xOf(s.canvas, t)) - 1, M.top + 1, 2, ph - 1);
  g.restore();
}

// ---------------------------------------------------------------- controls
const slider = $('slider');
slider.min = T0; slider.max = T1; slider.step = 'any';
let playing = false, speed = 0.25, last = null;
$('speed').value = '0.25';
$('speed').addEventListener('change', (e) => { speed = +e.target.value; });
function seek(t) { now = Math.min(T1, Math.max(T0, t)); slider.value = now; dirty = true; }
slider.addEventListener('input', () => { now = +slider.value; dirty = true; });
function setPlaying(on) {
  playing = on; last = null;
  if (on && now >= T1) now = T0;
  $('play').textContent = on ? '❚❚ pause' : '▶ play';
}
$('play').addEventListener('click', () => setPlaying(!playing));
window.addEventListener('keydown', (e) => { if (e.code === 'Space' && e.target.tagName !== 'SELECT') { e.preventDefault(); setPlaying(!playing); } });
if (D.events.length) {
  $('events').textContent = '';
  for (const e of D.events) {
    const b = document.createElement('button');
    b.type = 'button';
    b.textContent = `t = ${e.t.toFixed(6)} s: ${e.label}`;
    b.addEventListener('click', () => seek(e.t));
    $('events').appendChild(b);
  }
}

let frames = 0;
function render() {
  const p = apply(now);
  if (renderer) {
    placeCamera();
    renderer.render(scene, camera);
  }
  for (const s of plots) drawPlot(s, now);
  frames++;
  return p;
}
function loop(ts) {
  if (playing) {
    if (last !== null) {
      now += (ts - last) / 1000 * speed;
      if (now >= T1) { now = T1; setPlaying(false); }
      slider.value = now;
      dirty = true;
    }
    last = ts;
  }
  if (dirty) { dirty = false; render(); }
  requestAnimationFrame(loop);
}
resize();
render();
requestAnimationFrame(loop);

window.ellipsoidViewer = {
  t0: T0, t1: T1, frames: N, rows: D.rows, semiAxes: A, shapeKnown: !!shape, contactKnown: !!cTrace,
  // Whether the 3-D view is drawn (false without WebGL).
  webgl: !!renderer,
  // The body's surfaces (the ellipsoid if it touches, its contact spheres, its rims), which touch the plane
  // now, and where a sphere's centre is in the world (metres).
  surfaces: () => (S ? S.names.slice() : ['ellipsoid']),
  touching: () => touching(pose(now).frame),
  sphereCentre: (name) => { const k = S ? S.spheres.findIndex((sp) => sp.name === name) : -1; if (k < 0) return null; const v = new THREE.Vector3(); body.updateMatrixWorld(); spheres[k].getWorldPosition(v); return [v.x, v.y, v.z]; },
  // A rim's colour now (hex), and the centre of its circle in the world (metres).
  rimColour: (name) => { const k = S && S.rims ? S.rims.findIndex((r) => r.name === name) : -1; return k < 0 ? null : rims[k].material.color.getHex(); },
  rimCentre: (name) => { const k = S && S.rims ? S.rims.findIndex((r) => r.name === name) : -1; if (k < 0) return null; const v = new THREE.Vector3(); body.updateMatrixWorld(); rims[k].getWorldPosition(v); return [v.x, v.y, v.z]; },
  time: () => now,
  playing: () => playing,
  rendered: () => frames,
  seek: (t) => { seek(t); render(); },
  play: () => setPlaying(true),
  pause: () => setPlaying(false),
  setSpeed: (v) => { speed = v; },
  setCamera: (o) => { Object.assign(cam, o); dirty = true; render(); },
  pose: (t) => pose(t === undefined ? now : t),
  // Where a world point (metres) appears on the page, in CSS pixels (null without WebGL).
  project: (x, y, z) => {
    if (!renderer) return null;
    const v = new THREE.Vector3(x, y, z).project(camera);
    const r = renderer.domElement.getBoundingClientRect();
    return [r.left + (v.x + 1) / 2 * r.width, r.top + (1 - v.y) / 2 * r.height];
  },
  // The plot's box in canvas pixels and where time t falls in it.
  plotX: (name, t) => { const s = plots.find((p) => p.name === name); return s ? xOf(s.canvas, t) : null; },
};
window.ellipsoidViewer.readyAt = performance.now();
document.body.dataset.ready = '1';
