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
  body { margin: 0; font: 13px system-ui, sans-serif; display: flex; background: #1e1e1e; color: #ddd; }
  #view { flex: 1; display: flex; flex-direction: column; align-items: center; padding: 8px; }
  canvas { background: #000; image-rendering: auto; cursor: crosshair; max-width: 100%; }
  #side { width: 330px; padding: 8px; overflow-y: auto; height: 100vh; box-sizing: border-box; background: #262626; }
  h3 { margin: 10px 0 4px; font-size: 13px; color: #fff; }
  button { margin: 2px; }
  input[type=number] { width: 64px; }
  #status, #error { min-height: 1.2em; }
  #error { color: #ff8080; }
  pre { white-space: pre-wrap; font-size: 11px; background: #1a1a1a; padding: 4px; max-height: 220px; overflow: auto; }
  .row { display: flex; align-items: center; gap: 4px; flex-wrap: wrap; }
  #progress { width: 100%; }
</style>
</head>
<body>
<div id="view">
  <canvas id="canvas" width="512" height="512" tabindex="0"></canvas>
  <div id="status">connecting...</div>
  <div id="fps"></div>
  <div id="error"></div>
  <div class="row"><button id="home" title="the scene file's view">Home view</button>
    <button id="undo-view" title="Ctrl+Z">Undo</button><button id="redo-view" title="Ctrl+Shift+Z">Redo</button></div>
  <div class="help">drag: orbit - shift+drag or right drag: pan - wheel: zoom (passes the pivot) - W A S D Q E: fly - click: pick - Ctrl+Z / Ctrl+Shift+Z: undo / redo (edits and views)</div>
</div>
<div id="side">
  <h3>Mode</h3>
  <div class="row">
    <button id="mode-raytrace">raytrace</button><button id="mode-gi">gi</button><button id="mode-path">path</button>
    spp <input id="spp" type="number" min="1" max="65536" placeholder="default">
  </div>
  <div class="row"><button id="cancel" disabled>Cancel</button>
    <a href="/image.png" download="render.png">PNG</a> <a href="/image.exr" download="render.exr">EXR</a></div>
  <progress id="progress" max="1" value="0"></progress>
  <div id="render-info"></div>
  <h3>Selection</h3>
  <div id="selection">none (click the image)</div>
  <div id="read-only" hidden>This scene is read-only: only JSON scenes can be edited (the camera, renders and downloads still work).</div>
  <div class="row">move <button data-edit data-move="-1,0,0">-x</button><button data-edit data-move="1,0,0">+x</button>
    <button data-edit data-move="0,-1,0">-y</button><button data-edit data-move="0,1,0">+y</button>
    <button data-edit data-move="0,0,-1">-z</button><button data-edit data-move="0,0,1">+z</button>
    step <input id="step" type="number" value="0.1" step="0.05" min="-1000" max="1000"></div>
  <div class="row">rotate y <button id="rot-minus" data-edit>-15&deg;</button><button id="rot-plus" data-edit>+15&deg;</button>
    scale <button id="scale-down" data-edit>&divide;1.1</button><button id="scale-up" data-edit>&times;1.1</button></div>
  <h3>Material</h3>
  <div class="row">type <select id="mat-type">
    <option>diffuse</option><option>mirror</option><option>dielectric</option><option>glossy</option></select></div>
  <div class="row">colour <input id="mat-color" type="color" value="#b9b5ad">
    roughness <input id="mat-roughness" type="number" min="0" max="1" step="0.05" value="0.2">
    ior <input id="mat-ior" type="number" min="1" max="3" step="0.05" value="1.5"></div>
  <div class="row"><button id="mat-apply" data-edit>Apply material</button></div>
  <div class="row">emission r g b <input id="emission-r" type="number" min="0" step="1" value="0"><input
    id="emission-g" type="number" min="0" step="1" value="0"><input id="emission-b" type="number" min="0" step="1" value="0">
    <button id="emission-apply" data-edit>Apply emission</button></div>
  <h3>Scene</h3>
  <div class="row"><button id="undo">Undo</button><button id="redo">Redo</button> <span id="undo-depth"></span></div>
  <div class="row"><input id="save-path" value="edited.json"> <button id="save" data-edit>Save JSON</button></div>
  <h3>Lights</h3>
  <div id="lights"></div>
  <h3>Scene analysis</h3>
  <pre id="analysis"></pre>
  <h3>Statistics of the last render</h3>
  <pre id="stats"></pre>
</div>
<script>
"use strict";
const canvas = document.getElementById("canvas");
const ctx2d = canvas.getContext("2d");
const $ = (id) => document.getElementById(id);
let ws, state = null, camera = null, selected = null, rendering = false;
let framesShown = 0, lastFrameVersion = -1, lastFrameWidth = 0;
window.rayproc = { get state() { return state; }, get selected() { return selected; },
                   get framesShown() { return framesShown; }, get rendering() { return rendering; },
                   get lastFrameVersion() { return lastFrameVersion; }, get lastFrameWidth() { return lastFrameWidth; },
                   get cameraMessagesSent() { return cameraMessagesSent; }, get camera() { return camera; },
                   send: (m) => send(m), lastReply: null, lastError: null, lastProgress: null };

// Every message is the user's doing: an error shown stays until the next one (progress and
// other replies do not clear it).
function send(m) { $("error").textContent = ""; ws.send(JSON.stringify(m)); }
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
let newestFrameVersion = -1, cameraMessagesSent = 0;
function sendCamera() { cameraDirty = true; flushCamera(); }
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
  if (gestureStarted) { m.undo_step = true; gestureStarted = false; }
  send(m);
}
// The reply to a camera message names the version its frames will carry.
function cameraAccepted(version) {
  cameraAwaited = version;
  if (newestFrameVersion >= version) cameraAnswered();
}
function cameraAnswered() { cameraInFlight = false; cameraAwaited = null; flushCamera(); }

function connect() {
  ws = new WebSocket((location.protocol === "https:" ? "wss://" : "ws://") + location.host + "/ws");
  ws.binaryType = "arraybuffer";
  ws.onopen = () => { $("status").textContent = "connected"; };
  ws.onclose = () => { $("status").textContent = "disconnected (reload to reconnect)"; };
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
    else if (m.type === "render_begin") { rendering = true; $("cancel").disabled = false; $("progress").value = 0;
      $("render-info").textContent = m.mode + ": starting"; }
    else if (m.type === "progress") { window.rayproc.lastProgress = m; $("progress").value = m.fraction;
      $("render-info").textContent = m.mode + ": " + (100*m.fraction).toFixed(1) + "% - " + m.seconds.toFixed(1) +
        " s - ETA " + (m.eta_seconds >= 0 ? m.eta_seconds.toFixed(1) + " s" : "?") + " - " +
        (m.rays_per_second/1e6).toFixed(2) + " Mrays/s"; }
    else if (m.type === "render_end") { rendering = false; $("cancel").disabled = true;
      $("render-info").textContent = m.mode + (m.cancelled ? ": cancelled" : ": done") + " after " +
        m.spp + " spp, " + m.seconds.toFixed(2) + " s";
      $("stats").textContent = JSON.stringify(m.stats, null, 1); }
    else if (m.type === "saved") $("status").textContent = "saved " + m.path;
  };
}

// A frame: "RPF2", width, height, frame number, version (u32 each), then RGBA (encodeFrame).
function drawFrame(buffer) {
  const head = new DataView(buffer, 0, 20);
  if (String.fromCharCode(head.getUint8(0), head.getUint8(1), head.getUint8(2), head.getUint8(3)) !== "RPF2") return;
  const w = head.getUint32(4, true), h = head.getUint32(8, true), version = head.getUint32(16, true);
  // A frame of a scene or view older than the state shown is stale: never drawn.
  if (state && version < state.version) return;
  const pixels = new Uint8ClampedArray(buffer, 20, w * h * 4);
  const img = new ImageData(pixels, w, h);
  if (state && (canvas.width !== previewWidth() || canvas.height !== previewHeight())) {
    canvas.width = previewWidth(); canvas.height = previewHeight();
  }
  if (w === canvas.width && h === canvas.height) ctx2d.putImageData(img, 0, 0);
  else createImageBitmap(img).then((bmp) => ctx2d.drawImage(bmp, 0, 0, canvas.width, canvas.height));
  framesShown++;
  lastFrameVersion = version; lastFrameWidth = w;
  showRate(w, h);
  newestFrameVersion = Math.max(newestFrameVersion, version);
  if (cameraInFlight && cameraAwaited !== null && version >= cameraAwaited) cameraAnswered();
}

// The frame-rate readout: frames drawn in the last second and the last one's size (a drag's
// frames are coarse; the full-size frame follows when the view rests).
const frameTimes = [];
function showRate(w, h) {
  const now = performance.now();
  frameTimes.push(now);
  while (frameTimes.length && frameTimes[0] < now - 1000) frameTimes.shift();
  $("fps").textContent = w + "x" + h + ", " + frameTimes.length + " frames in the last second";
}

// The canvas keeps the live preview's size; renders at the scene's resolution are scaled to it.
function previewScale() { const r = state.camera.resolution; return Math.min(1, state.preview_max_side / Math.max(r[0], r[1])); }
function previewWidth() { return Math.max(1, Math.round(state.camera.resolution[0] * previewScale())); }
function previewHeight() { return Math.max(1, Math.round(state.camera.resolution[1] * previewScale())); }

function showState(s) {
  state = s;
  // While a view of ours is unsent or unanswered, the page's camera is ahead of the server's.
  if (!cameraInFlight && !cameraDirty) camera = JSON.parse(JSON.stringify(s.camera));
  $("undo-depth").textContent = s.undo_depth + " to undo, " + (s.redo_depth || 0) + " to redo (edits and views)";
  $("analysis").textContent = s.analysis.map((a) => a.modes.join(",") + ": skipped " + a.what + ": " + a.why).join("\n") || "nothing skipped";
  const lights = $("lights"); lights.innerHTML = "";
  s.lights.forEach((l, i) => {
    const row = document.createElement("div"); row.className = "row";
    row.textContent = (l.name || l.type) + " ";
    if (l.intensity || l.radiance) {
      const key = l.intensity ? "intensity" : "radiance";
      // One field per channel: a coloured light keeps its colour (a number means grey).
      const rgb = Array.isArray(l[key]) ? l[key] : [l[key], l[key], l[key]];
      const inputs = rgb.map((c) => { const input = document.createElement("input"); input.type = "number";
        input.step = "0.5"; input.min = "0"; input.value = c; input.disabled = !s.editable; return input; });
      const b = document.createElement("button"); b.textContent = "set " + key; b.disabled = !s.editable;
      b.onclick = () => { const v = readRgb(inputs, key); if (v) send({type: "light", index: i, set: {[key]: v}}); };
      row.append(...inputs, b);
    }
    lights.append(row);
  });
  rendering = s.rendering; $("cancel").disabled = !rendering;
  // pbrt scenes are read-only: the edit controls say so instead of sending what is refused.
  $("read-only").hidden = s.editable;
  document.querySelectorAll("[data-edit]").forEach((el) => { el.disabled = !s.editable; });
  if (selected !== null) showSelection();
}

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
}

function showSelection() {
  if (selected === null) { $("selection").textContent = "none"; return; }
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
  drag = {x: e.clientX, y: e.clientY, moved: false, pan: e.shiftKey || e.button === 2};
  gestureStarted = true; canvas.focus();
});
window.addEventListener("mouseup", (e) => {
  // A release after a drag (even one a render refused) picks nothing.
  if (drag && !drag.moved && e.target === canvas) {
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
    send(Number.isFinite(spp) ? {type: "render", mode, spp} : {type: "render", mode});
  };
$("cancel").onclick = () => send({type: "cancel"});
connect();
</script>
</body>
</html>
)PAGE";

} // namespace rayproc::serve
