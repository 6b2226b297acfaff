// The page rayproc serve sends (docs/serve.md): one HTML document with its style and script,
// no framework and nothing fetched from elsewhere. The script speaks Session's messages over
// the WebSocket /ws and draws the binary frames (encodeFrame) into a canvas.
#include "serve/server.h"

namespace rayproc::serve {

const char* const kPage = R"PAGE(<!doctype html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>rayproc serve</title>
<style>
  html, body { height: 100%; }
  body { margin: 0; font: 13px system-ui, sans-serif; display: flex; background: #1e1e1e; color: #ddd; }
  #view { flex: 1; display: flex; flex-direction: column; min-width: 0; height: 100vh; box-sizing: border-box; padding: 6px; }
  #stage { flex: 1; position: relative; overflow: hidden; background: #111; min-height: 120px; }
  canvas { position: absolute; background: #000; cursor: crosshair; image-rendering: auto; }
  #overlay { background: transparent; pointer-events: none; }
  canvas.pixels { image-rendering: pixelated; }
  #banner { position: absolute; left: 0; right: 0; top: 0; padding: 4px 8px; background: rgba(120, 90, 0, 0.85); color: #fff; }
  #side { width: 350px; flex: none; padding: 8px; overflow-y: auto; height: 100vh; box-sizing: border-box; background: #262626; }
  h3 { margin: 10px 0 4px; font-size: 13px; color: #fff; }
  button { margin: 2px; }
  button:disabled, input:disabled, select:disabled { opacity: 0.45; }
  input[type=number] { width: 56px; }
  #res-w, #res-h { width: 56px; }
  #status, #error, #refine { min-height: 1.2em; }
  #error { color: #ff8080; }
  #status.offline { color: #ffb060; }
  pre { white-space: pre-wrap; font-size: 11px; background: #1a1a1a; padding: 4px; max-height: 220px; overflow: auto; }
  table.stats { font-size: 11px; border-collapse: collapse; width: 100%; }
  table.stats td { padding: 1px 4px; border-bottom: 1px solid #333; }
  table.stats td:last-child { text-align: right; font-variant-numeric: tabular-nums; }
  .row { display: flex; align-items: center; gap: 4px; flex-wrap: wrap; }
  .bar { display: flex; align-items: center; gap: 10px; flex-wrap: wrap; padding: 2px 0; }
  .download { display: inline-block; padding: 2px 8px; margin: 2px; background: #3a5a8a; color: #fff; border-radius: 3px; text-decoration: none; }
  .warning { color: #ffcc66; font-size: 12px; overflow-wrap: anywhere; margin: 2px 0; }
  #progress { width: 100%; }
  .help { color: #999; font-size: 12px; }
</style>
</head>
<body>
<div id="view">
  <div class="bar">
    <span><button id="home" title="the scene file's view">Home view</button><button id="undo-view" title="Ctrl+Z">Undo</button><button
      id="redo-view" title="Ctrl+Shift+Z">Redo</button></span>
    <span title="the image on screen: fit the area, one image pixel per screen pixel, or zoom (Alt+wheel; Alt+drag or middle drag pans)">image
      <button id="zoom-fit">Fit</button><button id="zoom-1">1:1</button><button id="zoom-out">&minus;</button><button id="zoom-in">+</button>
      <span id="zoom"></span></span>
    <span title="as rayproc render --exposure and --tone-map; the PNG download follows">exposure
      <input id="exposure" type="number" min="-20" max="20" step="0.5" value="0"> tone map
      <select id="tone-map"><option>clamp</option><option>reinhard</option><option>aces</option></select></span>
  </div>
  <div class="bar">
    <span title="the scene's camera: renders are this size; the live preview is at most --preview-size on its longer side">resolution
      <input id="res-w" type="number" min="1" max="16384"> x <input id="res-h" type="number" min="1" max="16384">
      field of view <input id="fov" type="number" min="0.1" max="179" step="1">&deg;
      <button id="view-apply">Apply</button></span>
    <span id="preview-size"></span>
  </div>
  <div id="stage">
    <canvas id="canvas" width="512" height="512" tabindex="0"></canvas>
    <canvas id="overlay" width="512" height="512"></canvas>
    <div id="banner" hidden></div>
  </div>
  <div class="bar"><span id="status">connecting...</span><span id="fps"></span><span id="refine"></span></div>
  <div id="error"></div>
  <div class="help">drag: orbit - shift+drag or right drag: pan - wheel: zoom (passes the pivot) - W A S D Q E: fly - click: pick - Ctrl+Z / Ctrl+Shift+Z: undo / redo (edits and views) - Alt+wheel, Alt+drag: zoom and pan the image</div>
</div>
<div id="side">
  <h3>Render</h3>
  <div class="row">
    <button id="mode-raytrace">raytrace</button><button id="mode-gi">gi</button><button id="mode-path">path</button>
    spp <input id="spp" type="number" min="1" max="65536" placeholder="default">
    <label title="three hero wavelengths per path, as pbrt-v4 renders: the live view, its refinement and the renders (every mode)"><input id="spectral" type="checkbox"> spectral</label>
  </div>
  <div id="spp-defaults" class="help"></div>
  <div class="row"><button id="cancel" disabled>Cancel</button>
    <a class="download" href="/image.png" download="render.png">Download PNG</a> <a class="download" href="/image.exr" download="render.exr">Download EXR</a></div>
  <progress id="progress" max="1" value="0"></progress>
  <div id="render-info"></div>
  <h3>Selection</h3>
  <div id="selection">none (click the image)</div>
  <div id="read-only" hidden>This scene is read-only: only JSON scenes can be edited (the camera, renders and downloads still work).</div>
  <div class="row">move <button data-edit data-select data-move="-1,0,0">-x</button><button data-edit data-select data-move="1,0,0">+x</button>
    <button data-edit data-select data-move="0,-1,0">-y</button><button data-edit data-select data-move="0,1,0">+y</button>
    <button data-edit data-select data-move="0,0,-1">-z</button><button data-edit data-select data-move="0,0,1">+z</button>
    step <input id="step" type="number" value="0.1" step="0.05" min="-1000" max="1000"></div>
  <div class="row">rotate y <button id="rot-minus" data-edit data-select>-15&deg;</button><button id="rot-plus" data-edit data-select>+15&deg;</button>
    scale <button id="scale-down" data-edit data-select>&divide;1.1</button><button id="scale-up" data-edit data-select>&times;1.1</button></div>
  <h3>Material</h3>
  <div class="row">type <select id="mat-type">
    <option>diffuse</option><option>mirror</option><option>dielectric</option><option>glossy</option></select></div>
  <div class="row">colour <input id="mat-color" type="color" value="#b9b5ad">
    roughness <input id="mat-roughness" type="number" min="0" max="1" step="0.05" value="0.2">
    ior <input id="mat-ior" type="number" min="1" max="3" step="0.05" value="1.5"></div>
  <div class="row"><button id="mat-apply" data-edit data-select>Apply material</button></div>
  <div class="row">emission r g b <input id="emission-r" type="number" min="0" step="1" value="0"><input
    id="emission-g" type="number" min="0" step="1" value="0"><input id="emission-b" type="number" min="0" step="1" value="0">
    <button id="emission-apply" data-edit data-select>Apply emission</button></div>
  <h3>Scene</h3>
  <div class="row"><button id="undo">Undo</button><button id="redo">Redo</button> <span id="undo-depth"></span></div>
  <div class="row"><input id="save-path" value="edited.json"> <button id="save" data-edit>Save JSON</button></div>
  <div id="warnings"></div>
  <h3>Lights</h3>
  <div id="lights"></div>
  <h3>Scene analysis</h3>
  <pre id="analysis"></pre>
  <h3>Statistics of the last render</h3>
  <div id="stats"></div>
</div>
<script>
"use strict";
const canvas = document.getElementById("canvas");
const ctx2d = canvas.getContext("2d");
const $ = (id) => document.getElementById(id);
const stage = document.getElementById("stage");
let ws, state = null, camera = null, selected = null, rendering = false, online = false;
let framesShown = 0, lastFrameVersion = -1, lastFrameWidth = 0, lastFramePixels = null;
// Tests read the page through window.rayproc; refineLog, when a test sets it to [], collects
// every frame drawn ({version, width, height, pixels}) and the refine message that followed it.
window.rayproc = { get state() { return state; }, get selected() { return selected; },
                   get framesShown() { return framesShown; }, get rendering() { return rendering; },
                   get lastFrameVersion() { return lastFrameVersion; }, get lastFrameWidth() { return lastFrameWidth; },
                   get cameraMessagesSent() { return cameraMessagesSent; }, get camera() { return camera; },
                   get online() { return online; }, get imageZoom() { return effectiveZoom(); },
                   get outlineBox() { return outlineBox; },
                   send: (m) => send(m), lastReply: null, lastError: null, lastProgress: null, lastRefine: null, lastStarting: null,
                   refineLog: null, connects: 0 };

// Every message is the user's doing: an error shown stays until the next one (progress and
// other replies do not clear it).
function send(m) {
  if (!online) { showError("the server is gone: reconnecting (nothing was sent)"); return; }
  $("error").textContent = ""; ws.send(JSON.stringify(m));
}
// DOM writes only where something changed: a drag brings a state message per frame, and each
// write makes the browser lay the page out again.
function setText(id, text) { const e = $(id); if (e.textContent !== text) e.textContent = text; }
function setProp(id, key, value) { const e = $(id); if (e[key] !== value) e[key] = value; }
function sub(a, b) { return [a[0]-b[0], a[1]-b[1], a[2]-b[2]]; }
function add(a, b) { return [a[0]+b[0], a[1]+b[1], a[2]+b[2]]; }
function mul(a, s) { return [a[0]*s, a[1]*s, a[2]*s]; }
function len(a) { return Math.hypot(a[0], a[1], a[2]); }
function norm(a) { const l = len(a) || 1; return mul(a, 1/l); }
function cross(a, b) { return [a[1]*b[2]-a[2]*b[1], a[2]*b[0]-a[0]*b[2], a[0]*b[1]-a[1]*b[0]]; }

// Camera messages: at most one in flight. A move while one is unanswered only marks the view
// dirty; the latest view goes out once the frame of the previous one has been drawn (or after
// kCameraBudgetMs, should that frame never come), so the server renders views the page can show
// instead of stopping each coarse frame for the next mouse event (issue 37, bug 2).
const kCameraBudgetMs = 250;
let cameraInFlight = false, cameraDirty = false, cameraSentAt = 0, cameraAwaited = null, cameraTimer = null;
let newestFrameVersion = -1, cameraMessagesSent = 0, pendingResolution = null;
function sendCamera() { cameraDirty = true; drawOutline(); flushCamera(); }
function flushCamera() {
  if (!cameraDirty || !camera) return;
  const waited = performance.now() - cameraSentAt;
  if (cameraInFlight && waited < kCameraBudgetMs) {
    if (!cameraTimer) cameraTimer = setTimeout(() => { cameraTimer = null; flushCamera(); }, kCameraBudgetMs - waited);
    return;
  }
  cameraDirty = false; cameraInFlight = true; cameraAwaited = null; cameraSentAt = performance.now();
  cameraMessagesSent++;
  const m = {type: "camera", position: camera.position, look_at: camera.look_at, up: camera.up, fov: camera.fov};
  if (pendingResolution) { m.resolution = pendingResolution; pendingResolution = null; }
  if (gestureStarted) { m.undo_step = true; gestureStarted = false; }
  send(m);
}
// The reply to a camera message names the version its frames will carry.
function cameraAccepted(version) {
  cameraAwaited = version;
  if (newestFrameVersion >= version) cameraAnswered();
}
function cameraAnswered() { cameraInFlight = false; cameraAwaited = null; flushCamera(); }

// The connection: when the server goes, the page says so, disables what needs it and tries
// again (after 0.5 s, then up to every 4 s); the state that arrives on reconnecting is the truth.
let reconnectDelay = 500;
function connect() {
  ws = new WebSocket((location.protocol === "https:" ? "wss://" : "ws://") + location.host + "/ws");
  ws.binaryType = "arraybuffer";
  ws.onopen = () => {
    online = true; reconnectDelay = 500; window.rayproc.connects++;
    $("status").textContent = "connected"; $("status").className = ""; updateControls();
  };
  ws.onclose = () => {
    const was = online;
    online = false; cameraInFlight = false; cameraDirty = false;
    $("status").textContent = (was ? "disconnected" : "server not reachable") + ": reconnecting in " +
      (reconnectDelay / 1000).toFixed(1) + " s";
    $("status").className = "offline"; updateControls();
    setTimeout(connect, reconnectDelay);
    reconnectDelay = Math.min(4000, reconnectDelay * 2);
  };
  ws.onmessage = (ev) => {
    if (typeof ev.data !== "string") return drawFrame(ev.data);
    const m = JSON.parse(ev.data);
    window.rayproc.lastReply = m;
    if (m.type === "error") {
      window.rayproc.lastError = m.message; $("error").textContent = m.message;
      if (cameraInFlight && cameraAwaited === null) cameraAnswered(); // our camera was refused
      return;
    }
    if (m.type === "camera") cameraAccepted(m.version);
    else if (m.type === "state") showState(m);
    else if (m.type === "picked") showPick(m);
    else if (m.type === "refine") showRefine(m);
    else if (m.type === "display") showDisplay(m);
    else if (m.type === "render_begin") { rendering = true; $("progress").value = 0; updateControls();
      $("render-info").textContent = m.mode + ": starting"; }
    else if (m.type === "progress") showProgress(m);
    else if (m.type === "render_end") { rendering = false; updateControls();
      $("render-info").textContent = m.mode + (m.cancelled ? ": cancelled" : ": done") + " after " +
        m.spp + " spp, " + m.seconds.toFixed(2) + " s";
      showStats(m.stats); }
    else if (m.type === "saved") $("status").textContent = "saved " + m.path;
  };
}

function showProgress(m) {
  window.rayproc.lastProgress = m;
  if (m.phase === "starting") { // gi's photon passes and cache prepass: no pass has begun yet
    window.rayproc.lastStarting = m;
    $("render-info").textContent = m.mode + ": starting (" + m.what + ") " + m.seconds.toFixed(1) + " s";
    return;
  }
  $("progress").value = m.fraction;
  $("render-info").textContent = m.mode + ": " + (100*m.fraction).toFixed(1) + "% - " + m.seconds.toFixed(1) +
    " s - ETA " + (m.eta_seconds >= 0 ? m.eta_seconds.toFixed(1) + " s" : "?") + " - " +
    (m.rays_per_second/1e6).toFixed(2) + " Mrays/s";
}

// A still view refines toward the raytrace image (the server's raytrace passes at the preview's
// size): how far it got.
function showRefine(m) {
  window.rayproc.lastRefine = m;
  const log = window.rayproc.refineLog;
  if (log && log.length && log[log.length - 1].version === m.version && !log[log.length - 1].refine)
    log[log.length - 1].refine = m;
  $("refine").textContent = m.done ? "refined: raytrace, " + m.spp + " spp" :
    "refining toward raytrace: " + m.spp + " of " + m.of + " spp";
}

// The last render's statistics as a short table (the whole JSON is in the title).
function showStats(st) {
  const rows = [["wall time", st.wall_seconds.toFixed(2) + " s"], ["rays traced", (st.rays / 1e6).toFixed(2) + " M"],
    ["rays per second", (st.rays_per_second / 1e6).toFixed(2) + " M"], ["samples", (st.samples / 1e6).toFixed(2) + " M"],
    ["peak memory", (st.peak_memory_bytes / 1048576).toFixed(0) + " MiB"]];
  if (st.clamped_samples) rows.push(["clamped samples", String(st.clamped_samples)]);
  if (st.invalid_samples) rows.push(["invalid samples", String(st.invalid_samples)]);
  for (const [group, values] of Object.entries(st))
    if (values && typeof values === "object" && !Array.isArray(values) && group !== "stages")
      for (const [k, v] of Object.entries(values)) if (typeof v === "number")
        rows.push([group + ": " + k.replace(/_/g, " "), String(Number.isInteger(v) ? v : +v.toPrecision(4))]);
  const table = document.createElement("table"); table.className = "stats";
  for (const [k, v] of rows) {
    const tr = document.createElement("tr"), a = document.createElement("td"), b = document.createElement("td");
    a.textContent = k; b.textContent = v; tr.append(a, b); table.append(tr);
  }
  const box = $("stats"); box.innerHTML = ""; box.title = JSON.stringify(st, null, 1); box.append(table);
}

// A frame: "RPF2", width, height, frame number, version (u32 each), then RGBA (encodeFrame).
// The canvas takes the size of a full frame (the preview's, or a render's at the scene's
// resolution, so 1:1 shows every pixel of a render); a drag's coarse frames are scaled into it.
function drawFrame(buffer) {
  const head = new DataView(buffer, 0, 20);
  if (String.fromCharCode(head.getUint8(0), head.getUint8(1), head.getUint8(2), head.getUint8(3)) !== "RPF2") return;
  const w = head.getUint32(4, true), h = head.getUint32(8, true), version = head.getUint32(16, true);
  // A frame of a scene or view older than the state shown is stale: never drawn.
  if (state && version < state.version) return;
  const pixels = new Uint8ClampedArray(buffer, 20, w * h * 4);
  const img = new ImageData(pixels, w, h);
  const full = !state || (w === previewWidth() && h === previewHeight()) ||
    (w === state.camera.resolution[0] && h === state.camera.resolution[1]);
  if (full && (canvas.width !== w || canvas.height !== h)) { canvas.width = w; canvas.height = h; layout(); }
  if (w === canvas.width && h === canvas.height) ctx2d.putImageData(img, 0, 0);
  else createImageBitmap(img).then((bmp) => ctx2d.drawImage(bmp, 0, 0, canvas.width, canvas.height));
  framesShown++;
  lastFrameVersion = version; lastFrameWidth = w; lastFramePixels = pixels;
  const log = window.rayproc.refineLog;
  if (log) log.push({version, width: w, height: h, pixels: pixels.slice(), refine: null});
  showRate(w, h);
  newestFrameVersion = Math.max(newestFrameVersion, version);
  if (cameraInFlight && cameraAwaited !== null && version >= cameraAwaited) cameraAnswered();
}

// The image on the stage: fitted to it (imageZoom null) or at imageZoom CSS pixels per image
// pixel, moved by the pan. Alt+wheel zooms about the cursor; Alt+drag or a middle drag pans.
let imageZoom = null, panX = 0, panY = 0;
function fitZoom() { return Math.min(stage.clientWidth / canvas.width, stage.clientHeight / canvas.height) || 1; }
function effectiveZoom() { return imageZoom === null ? fitZoom() : imageZoom; }
function layout() {
  const z = effectiveZoom(), w = canvas.width * z, h = canvas.height * z;
  if (imageZoom === null) { panX = 0; panY = 0; }
  canvas.style.width = w + "px"; canvas.style.height = h + "px";
  canvas.style.left = ((stage.clientWidth - w) / 2 + panX) + "px";
  canvas.style.top = ((stage.clientHeight - h) / 2 + panY) + "px";
  canvas.className = z * (window.devicePixelRatio || 1) >= 2 ? "pixels" : ""; // zoomed in: crisp pixels
  for (const k of ["width", "height", "left", "top"]) overlay.style[k] = canvas.style[k];
  drawOutline();
  $("zoom").textContent = (imageZoom === null ? "fit, " : "") + Math.round(100 * z * (window.devicePixelRatio || 1)) + "%";
}
// The selection's box: its top-level object's world bounds projected with the page's camera
// (so it follows a drag at once), drawn over the image. Edges with a corner behind the camera
// are left out.
const overlay = document.getElementById("overlay");
let outlineBox = null; // the last box drawn: [x0, y0, x1, y1] in fractions of the image (tests)
function project(p) {
  const f = norm(sub(camera.look_at, camera.position)), r = norm(cross(f, camera.up)), u = cross(r, f);
  const d = sub(p, camera.position), z = dotp(d, f);
  if (z <= 1e-6) return null;
  const res = state.camera.resolution, t = Math.tan(camera.fov * Math.PI / 360);
  const x = dotp(d, r) / (z * t * res[0] / res[1]), y = dotp(d, u) / (z * t);
  return [(x + 1) / 2, (1 - y) / 2];
}
function drawOutline() {
  const w = parseFloat(overlay.style.width) || 0, h = parseFloat(overlay.style.height) || 0;
  const dpr = window.devicePixelRatio || 1;
  if (overlay.width !== Math.round(w * dpr) || overlay.height !== Math.round(h * dpr)) {
    overlay.width = Math.round(w * dpr); overlay.height = Math.round(h * dpr);
  }
  const g = overlay.getContext("2d");
  g.clearRect(0, 0, overlay.width, overlay.height);
  outlineBox = null;
  const o = state && camera && selected !== null && state.objects[selected];
  if (!o || !o.bounds) return;
  const lo = o.bounds.lo, hi = o.bounds.hi;
  const corners = [0, 1, 2, 3, 4, 5, 6, 7].map((i) => project([i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]]));
  g.strokeStyle = "#ffa020"; g.lineWidth = 1.5 * dpr; g.beginPath();
  const seen = corners.filter((c) => c);
  if (seen.length) outlineBox = [Math.min(...seen.map((c) => c[0])), Math.min(...seen.map((c) => c[1])),
                                 Math.max(...seen.map((c) => c[0])), Math.max(...seen.map((c) => c[1]))];
  for (let a = 0; a < 8; a++) for (const bit of [1, 2, 4]) {
    const b = a | bit;
    if (b === a || !corners[a] || !corners[b]) continue;
    g.moveTo(corners[a][0] * overlay.width, corners[a][1] * overlay.height);
    g.lineTo(corners[b][0] * overlay.width, corners[b][1] * overlay.height);
  }
  g.stroke();
}

// A zoom by `factor` keeping the image point under (x, y) (stage coordinates) in place.
function zoomImage(factor, x, y) {
  const z = effectiveZoom(), nz = Math.min(64, Math.max(1 / 64, z * factor));
  const cx = stage.clientWidth / 2 + panX, cy = stage.clientHeight / 2 + panY; // the image centre
  if (x === undefined) { x = stage.clientWidth / 2; y = stage.clientHeight / 2; }
  panX += (x - cx) * (1 - nz / z); panY += (y - cy) * (1 - nz / z);
  imageZoom = nz; layout();
}
window.addEventListener("resize", layout);
$("zoom-fit").onclick = () => { imageZoom = null; layout(); };
$("zoom-1").onclick = () => { imageZoom = 1 / (window.devicePixelRatio || 1); panX = 0; panY = 0; layout(); };
$("zoom-in").onclick = () => zoomImage(2);
$("zoom-out").onclick = () => zoomImage(0.5);

// The frame-rate readout: frames drawn in the last second and the last one's size (a drag's
// frames are coarse; the full-size frame follows when the view rests).
const frameTimes = [];
function showRate(w, h) {
  const now = performance.now();
  frameTimes.push(now);
  while (frameTimes.length && frameTimes[0] < now - 1000) frameTimes.shift();
  const gap = frameTimes.length > 1 ? (frameTimes[frameTimes.length - 1] - frameTimes[frameTimes.length - 2]).toFixed(0) + " ms since the last" : "";
  $("fps").textContent = w + "x" + h + ", " + frameTimes.length + " frames in the last second" + (gap ? " (" + gap + ")" : "");
}

// The live preview's size: the scene's resolution, its longer side at most --preview-size.
function previewScale() { const r = state.camera.resolution; return Math.min(1, state.preview_max_side / Math.max(r[0], r[1])); }
function previewWidth() { return Math.max(1, Math.round(state.camera.resolution[0] * previewScale())); }
function previewHeight() { return Math.max(1, Math.round(state.camera.resolution[1] * previewScale())); }

let shownLights = null, shownWarnings = null;
function showState(s) {
  state = s;
  $("spectral").checked = !!s.spectral_view;
  // The canvas has a full frame's size (drawFrame): the preview's until a frame says otherwise,
  // so the coarse frames before it have the scene's aspect.
  const r = s.camera.resolution;
  if (!((canvas.width === previewWidth() && canvas.height === previewHeight()) || (canvas.width === r[0] && canvas.height === r[1]))) {
    canvas.width = previewWidth(); canvas.height = previewHeight(); layout();
  }
  // While a view of ours is unsent or unanswered, the page's camera is ahead of the server's.
  if (!cameraInFlight && !cameraDirty) camera = JSON.parse(JSON.stringify(s.camera));
  setText("undo-depth", s.undo_depth + " to undo, " + (s.redo_depth || 0) + " to redo (edits and views)");
  setText("analysis", s.analysis.map((a) => a.modes.join(",") + ": skipped " + a.what + ": " + a.why).join("\n") || "nothing skipped");
  // Rebuilt only when they changed: a drag brings a state per frame.
  const lightsKey = JSON.stringify([s.lights, s.objects.filter((o) => o.emission), s.editable]);
  if (lightsKey !== shownLights) { shownLights = lightsKey; showLights(s); }
  showViewFields(s);
  if (s.display) showDisplay(s.display);
  const d = s.default_spp || {};
  setText("spp-defaults", "without spp: raytrace " + d.raytrace + ", gi " + d.gi + ", path " + d.path + " spp");
  // pbrt scenes are read-only: a banner says so and the edit controls are disabled.
  setProp("read-only", "hidden", s.editable);
  setProp("banner", "hidden", s.editable);
  setText("banner", "Read-only: " + s.scene + " is not a JSON scene. The camera, renders and downloads work; edits do not.");
  const warningsKey = JSON.stringify(s.warnings || []);
  if (warningsKey !== shownWarnings) {
    shownWarnings = warningsKey;
    const warnings = $("warnings"); warnings.innerHTML = "";
    (s.warnings || []).forEach((w) => { const div = document.createElement("div"); div.className = "warning"; div.textContent = w; warnings.append(div); });
  }
  rendering = s.rendering;
  updateControls();
  if (selected !== null) showSelection();
  drawOutline();
}

// What each control needs: the server (every one), an editable scene (data-edit), a selection
// (data-select), a render running (Cancel). The view and mode buttons stay enabled during a
// render: their error says why nothing happens.
function updateControls() {
  const editable = online && state && state.editable;
  document.querySelectorAll("[data-edit]").forEach((el) => {
    const off = !editable || (("select" in el.dataset) && selected === null);
    if (el.disabled !== off) el.disabled = off;
  });
  for (const id of ["mode-raytrace", "mode-gi", "mode-path", "home", "view-apply", "undo", "redo", "undo-view",
                    "redo-view", "exposure", "tone-map"]) setProp(id, "disabled", !online);
  setProp("cancel", "disabled", !online || !rendering);
  setProp("spectral", "disabled", !online || rendering); // the view's mode: not during a render
}

// The scene's lights: a JSON scene's are editable (one field per channel, so a coloured light
// keeps its colour); a pbrt scene's (the sun, the sky) are listed read-only. Emissive objects
// (area lights) follow, with a button that selects them for the emission fields.
function showLights(s) {
  const lights = $("lights"); lights.innerHTML = "";
  s.lights.forEach((l, i) => {
    const row = document.createElement("div"); row.className = "row";
    const key = ["intensity", "radiance", "irradiance"].find((k) => l[k] !== undefined);
    const bb = key && l[key] && l[key].blackbody; // shown as its RGB; setting it replaces it
    row.textContent = (l.name ? l.name + " (" + l.type + ")" : l.type) + (l.image ? " image " + l.image.split("/").pop() : "") +
      (bb ? " blackbody " + bb + " K" : "") + " ";
    if (key) {
      const rgb = Array.isArray(l[key]) ? l[key] : bb ? l[key + "_rgb"] : [l[key], l[key], l[key]];
      const inputs = rgb.map((c) => { const input = document.createElement("input"); input.type = "number";
        input.step = "0.5"; input.min = "0"; input.value = c; input.disabled = !s.editable; return input; });
      const b = document.createElement("button"); b.textContent = "set " + key; b.disabled = !s.editable;
      b.onclick = () => { const v = readRgb(inputs, key); if (v) send({type: "light", index: i, set: {[key]: v}}); };
      row.append(...inputs, b);
    }
    lights.append(row);
  });
  s.objects.filter((o) => o.emission).forEach((o) => {
    const row = document.createElement("div"); row.className = "row";
    row.textContent = (o.name || o.type) + " (emissive object) " + JSON.stringify(o.emission) + " ";
    const b = document.createElement("button"); b.textContent = "select";
    b.onclick = () => showPick({object: o.index, name: o.name});
    row.append(b);
    lights.append(row);
  });
  if (!lights.children.length) lights.textContent = "none";
}

// The resolution and field of view fields, unless the user is typing in one.
function showViewFields(s) {
  const typing = document.activeElement;
  if (typing !== $("res-w")) setProp("res-w", "value", String(s.camera.resolution[0]));
  if (typing !== $("res-h")) setProp("res-h", "value", String(s.camera.resolution[1]));
  if (typing !== $("fov")) setProp("fov", "value", String(+s.camera.fov.toFixed(3)));
  setText("preview-size", "live preview " + previewWidth() + "x" + previewHeight() +
    (s.refine ? ", refined toward raytrace while still" : ""));
}

function showDisplay(d) {
  if (document.activeElement !== $("exposure")) setProp("exposure", "value", String(d.exposure));
  setProp("tone-map", "value", d.tone_map);
}
$("exposure").onchange = () => {
  const e = parseFloat($("exposure").value);
  if (!Number.isFinite(e) || e < -20 || e > 20) { showError("exposure: expected stops in [-20, 20]"); return; }
  send({type: "display", exposure: e});
};
$("tone-map").onchange = () => send({type: "display", tone_map: $("tone-map").value});
// A new resolution or field of view: one undoable camera change.
$("view-apply").onclick = () => {
  if (!camera || refuseWhileRendering()) return;
  const w = parseInt($("res-w").value), h = parseInt($("res-h").value), fov = parseFloat($("fov").value);
  if (![w, h].every((v) => Number.isInteger(v) && v >= 1 && v <= 16384)) { showError("resolution: expected whole numbers in 1..16384"); return; }
  if (!(fov > 0 && fov < 180)) { showError("field of view: expected degrees in (0, 180)"); return; }
  camera.fov = fov; pendingResolution = [w, h]; gestureStarted = true;
  sendCamera();
};

// Three number fields as an RGB triple, or null (with the reason shown) if one is not a number >= 0.
function readRgb(inputs, what) {
  const v = inputs.map((input) => parseFloat(input.value));
  if (v.some((c) => !Number.isFinite(c) || c < 0)) { showError(what + ": expected three numbers >= 0 (r, g, b)"); return null; }
  return v;
}
function showError(text) { window.rayproc.lastError = text; $("error").textContent = text; }

let picked = null; // the last pick's reply: its name and material name the object where the state lists none
function showPick(m) {
  selected = m.object === null ? null : m.object;
  picked = m;
  showSelection();
  updateControls();
  drawOutline();
}

function showSelection() {
  if (selected === null) { $("selection").textContent = "none (click the image)"; return; }
  const o = state.objects[selected] || {};
  const name = o.name || (picked && picked.object === selected && picked.name) || o.type || "object";
  const material = o.material || (picked && picked.object === selected && picked.material);
  $("selection").textContent = "#" + selected + " " + name + (material ? " (material " + material + ")" : "");
  const mat = o.material && state.materials[o.material];
  if (mat) {
    $("mat-type").value = mat.type;
    if (mat.color) $("mat-color").value = "#" + mat.color.map((c) => Math.round(Math.min(1, c) * 255).toString(16).padStart(2, "0")).join("");
    if (mat.roughness !== undefined) $("mat-roughness").value = mat.roughness;
    if (mat.ior !== undefined) $("mat-ior").value = mat.ior;
  }
  const e = o.emission || [0, 0, 0];
  ["r", "g", "b"].forEach((c, i) => { $("emission-" + c).value = e[i]; });
}

// Orbit, pan, zoom and fly, scaled to the scene (its extent, from the state's bounds), not to
// the distance to the look-at point: a W step, a wheel notch and the orbit's pivot are the same
// share of the scene however far in the view has zoomed (issue 37, bugs 5 and 6).
const kFlyStep = 0.02;     // of the scene's extent per W A S D Q E press
const kWheelStep = 0.05;   // of the extent per wheel notch: 20 notches cross the scene
const kPivotNear = 0.1;    // a look-at point nearer than this share of the extent (pbrt's
const kPivot = 0.25;       // LookAt is often 1 unit ahead) is moved this far ahead to pivot about
const kPivotMin = 0.01;    // a dolly passes the pivot, pushing it at least this far ahead
const kOrbitPixels = 256;  // a drag this long turns the view by one field of view
function sceneSize() {
  const d = state && state.bounds ? state.bounds.extent : 0;
  return Number.isFinite(d) && d > 0 ? d : Math.max(1, len(sub(camera.look_at, camera.position)));
}
function forwardOf() { return norm(sub(camera.look_at, camera.position)); }
// The orbit's pivot: the look-at point, unless it is much nearer than the scene is large.
function pivotDistance() {
  const d = len(sub(camera.look_at, camera.position));
  if (d >= kPivotNear * sceneSize()) return d;
  camera.look_at = add(camera.position, mul(forwardOf(), kPivot * sceneSize()));
  return kPivot * sceneSize();
}
// Moves along the view; the pivot stays ahead, so a zoom can pass where it was.
function dolly(distance) {
  const forward = forwardOf(), d = pivotDistance() - distance;
  camera.position = add(camera.position, mul(forward, distance));
  camera.look_at = add(camera.position, mul(forward, Math.max(d, kPivotMin * sceneSize())));
}
// The first camera message of a gesture (a drag, a wheel burst, a key press, Home) is an undo
// step on the server (flushCamera sends it so).
let gestureStarted = false, lastWheel = 0;
// While a render runs the view cannot change: the page says so instead of doing nothing.
function refuseWhileRendering() {
  if (!rendering) return false;
  showError("a render is running: Cancel it to move the camera");
  return true;
}
let drag = null;
canvas.addEventListener("contextmenu", (e) => e.preventDefault());
canvas.addEventListener("mousedown", (e) => {
  const image = e.altKey || e.button === 1; // pans the image on the page, not the camera
  drag = {x: e.clientX, y: e.clientY, moved: false, pan: e.shiftKey || e.button === 2, image};
  if (image) e.preventDefault();
  else gestureStarted = true;
  canvas.focus();
});
window.addEventListener("mouseup", (e) => {
  // A release after a drag (even one a render refused) picks nothing.
  if (drag && !drag.moved && !drag.image && e.target === canvas) {
    const r = canvas.getBoundingClientRect();
    send({type: "pick", x: (e.clientX - r.left) / r.width, y: (e.clientY - r.top) / r.height});
  }
  drag = null;
});
window.addEventListener("mousemove", (e) => {
  if (!drag || !camera) return;
  const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
  if (Math.abs(dx) + Math.abs(dy) < 2) return;
  const first = !drag.moved;
  drag.moved = true; drag.x = e.clientX; drag.y = e.clientY;
  if (drag.image) {
    if (imageZoom === null) imageZoom = fitZoom();
    panX += dx; panY += dy; layout(); return;
  }
  if (rendering) { if (first) refuseWhileRendering(); return; }
  const dist = pivotDistance();
  const offset = sub(camera.position, camera.look_at);
  const forward = norm(mul(offset, -1));
  const right = norm(cross(forward, camera.up));
  const up = cross(right, forward);
  const fov = camera.fov * Math.PI / 180;
  if (drag.pan) {
    // The point at the pivot's depth follows the cursor.
    const s = 2 * dist * Math.tan(fov / 2) / Math.max(1, canvas.getBoundingClientRect().height);
    const move = add(mul(right, -dx * s), mul(up, dy * s));
    camera.position = add(camera.position, move); camera.look_at = add(camera.look_at, move);
  } else {
    // Orbit about the pivot: yaw about up, pitch about right (kept away from the poles); a
    // drag of kOrbitPixels turns by one field of view, so 150 pixels stay inside a room.
    const yaw = -dx * fov / kOrbitPixels, pitch = -dy * fov / kOrbitPixels;
    let o = rotate(offset, camera.up, yaw);
    const o2 = rotate(o, norm(cross(camera.up, o)), pitch);
    if (Math.abs(dotp(norm(o2), norm(camera.up))) < 0.98) o = o2;
    camera.position = add(camera.look_at, o);
  }
  sendCamera();
});
canvas.addEventListener("wheel", (e) => {
  e.preventDefault();
  if (e.altKey) { // the image, about the cursor
    const r = stage.getBoundingClientRect();
    zoomImage(e.deltaY < 0 ? 1.25 : 0.8, e.clientX - r.left, e.clientY - r.top);
    return;
  }
  if (!camera || refuseWhileRendering()) return;
  const now = performance.now();
  if (now - lastWheel > 400) gestureStarted = true;
  lastWheel = now;
  const notches = e.deltaMode === 1 ? e.deltaY / 3 : e.deltaMode === 2 ? e.deltaY : e.deltaY / 100;
  dolly(-notches * kWheelStep * sceneSize()); // wheel up (negative) moves in
  sendCamera();
}, {passive: false});
canvas.addEventListener("keydown", (e) => {
  if (e.ctrlKey || e.metaKey || e.altKey || !camera) return;
  const forward = forwardOf();
  const right = norm(cross(forward, camera.up));
  const step = kFlyStep * sceneSize();
  const keys = {w: mul(forward, step), s: mul(forward, -step), d: mul(right, step), a: mul(right, -step),
                e: mul(camera.up, step), q: mul(camera.up, -step)};
  const move = keys[e.key.toLowerCase()];
  if (!move || refuseWhileRendering()) return;
  pivotDistance(); // a near look-at point is moved ahead first, as for an orbit
  if (!e.repeat) gestureStarted = true;
  camera.position = add(camera.position, move); camera.look_at = add(camera.look_at, move);
  sendCamera();
});
// Undo and redo (edits and camera moves): the buttons, Ctrl+Z, Ctrl+Shift+Z and Ctrl+Y, except
// while typing in a field.
window.addEventListener("keydown", (e) => {
  if (!(e.ctrlKey || e.metaKey) || (e.target && /^(INPUT|SELECT|TEXTAREA)$/.test(e.target.tagName))) return;
  const k = e.key.toLowerCase();
  if (k === "z" || k === "y") { e.preventDefault(); send({type: k === "y" || e.shiftKey ? "redo" : "undo"}); }
});
function dotp(a, b) { return a[0]*b[0] + a[1]*b[1] + a[2]*b[2]; }
function rotate(v, axis, angle) { // Rodrigues
  const k = norm(axis), c = Math.cos(angle), s = Math.sin(angle);
  return add(add(mul(v, c), mul(cross(k, v), s)), mul(k, dotp(k, v) * (1 - c)));
}

// Edits need a JSON scene and a selection; otherwise the error area says why.
function canEdit() {
  if (!state || !state.editable) { showError("this scene is read-only: only JSON scenes can be edited"); return false; }
  if (selected === null) { showError("select an object first (click it in the image)"); return false; }
  return true;
}
const kMaxStep = 1000; // as the server's transform.translate
document.querySelectorAll("[data-move]").forEach((b) => b.onclick = () => {
  if (!canEdit()) return;
  const step = parseFloat($("step").value);
  if (!Number.isFinite(step) || step === 0 || Math.abs(step) > kMaxStep) {
    showError("move step: expected a number in [-" + kMaxStep + ", " + kMaxStep + "], not 0"); return;
  }
  send({type: "transform", object: selected, translate: b.dataset.move.split(",").map((v) => parseFloat(v) * step)});
});
$("rot-minus").onclick = () => canEdit() && send({type: "transform", object: selected, rotate: {angle: -15, axis: [0, 1, 0]}});
$("rot-plus").onclick = () => canEdit() && send({type: "transform", object: selected, rotate: {angle: 15, axis: [0, 1, 0]}});
$("scale-down").onclick = () => canEdit() && send({type: "transform", object: selected, scale: 1 / 1.1});
$("scale-up").onclick = () => canEdit() && send({type: "transform", object: selected, scale: 1.1});
$("mat-apply").onclick = () => {
  if (!canEdit()) return;
  const o = state.objects[selected];
  if (!o || !o.material) { showError("object #" + selected + " has no material of its own to edit"); return; }
  const hex = $("mat-color").value;
  const color = [1, 3, 5].map((i) => parseInt(hex.substr(i, 2), 16) / 255);
  const type = $("mat-type").value;
  const m = {type};
  if (type === "diffuse") m.color = color;
  if (type === "mirror") m.color = color;
  if (type === "dielectric") m.ior = parseFloat($("mat-ior").value);
  if (type === "glossy") { m.color = color; m.roughness = parseFloat($("mat-roughness").value); }
  send({type: "material", name: o.material, material: m});
};
$("emission-apply").onclick = () => {
  if (!canEdit()) return;
  const v = readRgb(["r", "g", "b"].map((c) => $("emission-" + c)), "emission");
  if (v) send({type: "emission", object: selected, emission: v});
};
$("undo").onclick = $("undo-view").onclick = () => send({type: "undo"});
$("redo").onclick = $("redo-view").onclick = () => send({type: "redo"});
// Home: the scene file's view, as one undoable camera move (a reload keeps the shared view).
$("home").onclick = () => {
  if (!state || refuseWhileRendering()) return;
  camera = Object.assign(JSON.parse(JSON.stringify(state.home)), {resolution: state.camera.resolution});
  gestureStarted = true;
  sendCamera();
};
$("save").onclick = () => send({type: "save", path: $("save-path").value});
for (const mode of ["raytrace", "gi", "path"])
  $("mode-" + mode).onclick = () => {
    const spp = parseInt($("spp").value);
    const m = Number.isFinite(spp) ? {type: "render", mode, spp} : {type: "render", mode};
    if ($("spectral").checked) m.spectral = true;
    send(m);
  };
$("cancel").onclick = () => send({type: "cancel"});
// The live view, its refinement and the renders all follow the checkbox.
$("spectral").onchange = () => send({type: "view", spectral: $("spectral").checked});
layout();
connect();
</script>
</body>
</html>
)PAGE";

} // namespace rayproc::serve
