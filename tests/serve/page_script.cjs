// The page's script (src/serve/page.cpp) run by node against a stand-in DOM and WebSocket, so
// its handling of the server's messages and of its buttons is tested without a browser
// (tests/serve/page_test.cpp runs it; the browser test is tests/e2e).
//   node tests/serve/page_script.cjs PAGE.html SCENARIO
// Exit status 0 when the scenario holds; otherwise it prints what failed (or the exception the
// page threw) and exits 1.
"use strict";
const fs = require("node:fs");
const vm = require("node:vm");

const [pageFile, scenario] = process.argv.slice(2);
const html = fs.readFileSync(pageFile, "utf8");
const script = html.slice(html.indexOf("<script>") + 8, html.lastIndexOf("</script>"));

// Elements: what the script reads and writes. The page's ids and data-* buttons are found in its
// HTML, so a control that is not in the page is not found here either.
function element(tag, attrs = {}) {
  return {
    tagName: tag, textContent: "", value: attrs.value || "", disabled: false, hidden: false,
    className: "", type: "", step: "", min: "", dataset: attrs.dataset || {}, children: [],
    width: 512, height: 512, onclick: null, listeners: {}, style: {}, clientWidth: 800, clientHeight: 600,
    append(...c) { this.children.push(...c); },
    set innerHTML(v) { this.children = []; },
    get innerHTML() { return ""; },
    addEventListener(type, fn) { (this.listeners[type] = this.listeners[type] || []).push(fn); },
    getContext() { return { putImageData() {}, drawImage() {}, clearRect() {}, beginPath() {}, moveTo() {}, lineTo() {}, stroke() {} }; },
    getBoundingClientRect() { return { left: 0, top: 0, width: 512, height: 512 }; },
    focus() {},
  };
}
const byId = {};
for (const m of html.matchAll(/<(\w+)([^>]*?)\sid="([^"]+)"([^>]*)>/g)) {
  const value = /value="([^"]*)"/.exec(m[2] + m[4]);
  byId[m[3]] = element(m[1], { value: value ? value[1] : "" });
}
const dataButtons = [];
for (const m of html.matchAll(/<button([^>]*)>/g)) {
  const attrs = m[1];
  if (!/\bdata-edit\b|\bdata-move=/.test(attrs)) continue;
  const id = /\sid="([^"]+)"/.exec(attrs);
  const el = id ? byId[id[1]] : element("button");
  const move = /data-move="([^"]+)"/.exec(attrs);
  if (move) el.dataset.move = move[1];
  if (/\bdata-edit\b/.test(attrs)) el.dataset.edit = "";
  if (/\bdata-select\b/.test(attrs)) el.dataset.select = "";
  dataButtons.push(el);
}
const sent = [];
let socket = null;
class FakeWebSocket { constructor() { socket = this; } send(text) { sent.push(JSON.parse(text)); } }
const windowListeners = {};
const context = {
  document: {
    activeElement: null,
    getElementById: (id) => byId[id] || null,
    createElement: (tag) => element(tag),
    querySelectorAll: (sel) => sel === "[data-move]" ? dataButtons.filter((b) => b.dataset.move)
      : sel === "[data-edit]" ? dataButtons.filter((b) => "edit" in b.dataset) : [],
  },
  location: { protocol: "http:", host: "127.0.0.1:1" },
  WebSocket: FakeWebSocket, JSON, Math, Number, Array, Object, String, parseFloat, parseInt, console,
  DataView, Uint8ClampedArray, ImageData: class { constructor(d, w, h) { this.width = w; this.height = h; } },
  createImageBitmap: () => Promise.resolve({}), performance: { now: () => clock },
  setTimeout: (fn, ms) => { timers.push({ at: clock + ms, fn }); return timers.length; },
  clearTimeout: () => {},
  addEventListener: (type, fn) => { (windowListeners[type] = windowListeners[type] || []).push(fn); },
};
// The page's clock and timers, advanced by the scenarios (advance).
let clock = 1000;
const timers = [];
function advance(ms) {
  clock += ms;
  for (let due; (due = timers.filter((t) => t.at <= clock)).length;)
    for (const t of due) { timers.splice(timers.indexOf(t), 1); t.fn(); }
}
context.window = context;
vm.createContext(context);
vm.runInContext(script, context);
socket.onopen(); // connected

const receive = (m) => socket.onmessage({ data: JSON.stringify(m) });
// A frame message (encodeFrame): "RPF2", width, height, number, version, then RGBA.
function receiveFrame(version, w = 16, h = 16) {
  const buffer = new ArrayBuffer(20 + w * h * 4), head = new DataView(buffer);
  "RPF2".split("").forEach((c, i) => head.setUint8(i, c.charCodeAt(0)));
  [w, h, 1, version].forEach((v, i) => head.setUint32(4 + 4 * i, v, true));
  socket.onmessage({ data: buffer });
}
const fire = (listeners, type, e) => (listeners[type] || []).forEach((fn) => fn(Object.assign({ preventDefault() {} }, e)));
const mouse = (type, x, y, extra = {}) => fire(type === "mousedown" ? byId.canvas.listeners : windowListeners, type,
                                               Object.assign({ clientX: x, clientY: y, button: 0, target: byId.canvas }, extra));
const cameras = () => sent.filter((m) => m.type === "camera");
const click = (id) => byId[id].onclick();
let failures = 0;
function check(ok, what) { if (!ok) { console.log("FAIL " + what); failures++; } }
const lastSent = () => sent[sent.length - 1];

function state(editable, extra = {}) {
  return Object.assign({
    type: "state", scene: "s", editable, preview_max_side: 64, version: 1, undo_depth: 0, rendering: false,
    analysis: [], materials: {}, lights: [], objects: [],
    camera: { position: [0, 1, 5], look_at: [0, 1, 0], up: [0, 1, 0], fov: 40, resolution: [64, 64] },
  }, extra);
}

const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
const key = (k, extra = {}) => fire(byId.canvas.listeners, "keydown", Object.assign({ key: k, repeat: false }, extra));
const wheel = (deltaY) => fire(byId.canvas.listeners, "wheel", { deltaY, deltaMode: 0 });

const scenarios = {
  // Issue 37 bug 6: in a room 20 units across whose camera looks at a point 1 unit ahead (pbrt's
  // LookAt), W moves 2% of the scene, 20 wheel notches cross it and pass the pivot, and neither
  // shrinks after zooming in; the orbit pivots a quarter of the scene ahead.
  scene_scaled_navigation() {
    const room = { lo: [-10, 0, -5], hi: [10, 5, 5], extent: 20 };
    receive(state(false, { bounds: room, camera: { position: [0, 2, 8], look_at: [0, 2, 7], up: [0, 1, 0], fov: 40, resolution: [64, 64] } }));
    const cam = () => context.window.rayproc.camera;
    let p0 = cam().position.slice();
    key("w");
    check(Math.abs(dist(cam().position, p0) - 0.4) < 1e-6, "W moves 2% of the 20-unit scene (0.4), not " + dist(cam().position, p0));
    const pivot0 = cam().look_at.slice();
    check(Math.abs(dist(cam().look_at, cam().position) - 5) < 1e-6, "the pivot is a quarter of the scene ahead (5), not " +
          dist(cam().look_at, cam().position));
    p0 = cam().position.slice();
    for (let i = 0; i < 20; i++) wheel(-100);
    check(Math.abs(dist(cam().position, p0) - 20) < 1e-6, "20 wheel notches move 20 units (the scene), not " + dist(cam().position, p0));
    check(cam().position[2] < pivot0[2], "the zoom passed the pivot (z " + cam().position[2] + " beyond " + pivot0[2] + ")");
    check(cam().look_at[2] < cam().position[2], "the pivot stays ahead of the camera");
    p0 = cam().position.slice();
    key("w");
    check(Math.abs(dist(cam().position, p0) - 0.4) < 1e-6, "after zooming in W still moves 0.4, not " + dist(cam().position, p0));
    p0 = cam().position.slice();
    wheel(100);
    check(Math.abs(dist(cam().position, p0) - 1) < 1e-6, "a notch back moves 1 unit, not " + dist(cam().position, p0));
  },
  // Issue 37 bug 5: a 150-pixel drag on the Cornell box's view (6.8 units away, 19.5 degree field
  // of view) turns the view by less than its field of view, so it stays in front of the box's open
  // side; the first camera message of a gesture is an undo step, the rest are not.
  orbit_speed() {
    receive(state(true, { bounds: { lo: [-1, 0, -1], hi: [1, 2, 1], extent: 3.46 },
      camera: { position: [0, 1, 6.8], look_at: [0, 1, 0], up: [0, 1, 0], fov: 19.5, resolution: [64, 64] } }));
    mouse("mousedown", 100, 100);
    for (let i = 1; i <= 15; i++) mouse("mousemove", 100 + 10 * i, 100);
    mouse("mouseup", 250, 100);
    const p = context.window.rayproc.camera.position;
    const angle = Math.atan2(p[0], p[2]) * 180 / Math.PI;
    check(Math.abs(angle) > 5 && Math.abs(angle) < 19.5, "a 150-pixel orbit turns 5..19.5 degrees, not " + angle.toFixed(1));
    check(cameras().length === 1 && cameras()[0].undo_step === true, "the drag's first message is an undo step");
    receive({ type: "camera", version: 2 });
    receiveFrame(2);
    check(cameras().length === 2 && !cameras()[1].undo_step, "the drag's next message is not");
    check(!sent.some((m) => m.type === "pick"), "the release after a drag picks nothing");
  },
  // Issue 37 bug 2: a drag sends at most one camera message until a frame of it arrives, then
  // the latest view; the state of an earlier view does not pull the page's camera back.
  camera_throttle() {
    receive(state(true));
    mouse("mousedown", 100, 100);
    for (let i = 1; i <= 10; i++) mouse("mousemove", 100 + 5 * i, 100);
    check(cameras().length === 1, "ten mouse moves before any frame send one camera message, not " + cameras().length);
    receive({ type: "camera", version: 2 });
    receive(state(true, { version: 2 })); // the server's view: the first move's
    for (let i = 11; i <= 20; i++) mouse("mousemove", 100 + 5 * i, 100);
    check(cameras().length === 1, "still one while its frame has not come: " + cameras().length);
    receiveFrame(1); // an older frame does not answer it
    check(cameras().length === 1, "an older frame does not release the next view");
    receiveFrame(2);
    check(cameras().length === 2, "the frame of the view releases the next: " + cameras().length);
    const second = cameras()[1].position;
    mouse("mousemove", 300, 100); // the drag goes on past where it was at the frame
    mouse("mouseup", 300, 100);
    check(cameras().length === 2, "the last move waits for the frame of the second view");
    // A stale state (of the first view) must not pull the page's camera back.
    receive(state(true, { version: 2 }));
    receive({ type: "camera", version: 3 });
    receiveFrame(3);
    check(cameras().length === 3, "the final view is sent once the second's frame arrived");
    const last = cameras()[2].position;
    check(JSON.stringify(last) !== JSON.stringify(second), "the final view is the drag's end, not the second view again");
    receive({ type: "camera", version: 4 });
    receiveFrame(4);
    // A frame that never comes (another tab changed the scene meanwhile): the view goes out anyway.
    mouse("mousedown", 300, 100);
    mouse("mousemove", 320, 100);
    mouse("mousemove", 340, 100);
    check(cameras().length === 4, "a new drag sends at once");
    advance(300);
    check(cameras().length === 5, "after the budget without a frame the latest view goes out: " + cameras().length);
  },
  // Issue 37 bug 1: a pick on a pbrt scene (no editable objects) must not throw, then or at the
  // next state (every camera move brings one), and edits say the scene is read-only.
  pbrt_pick() {
    // The state lists no objects (as the server did for pbrt scenes before issue 37): the page
    // names the object from the pick.
    const s = state(false);
    receive(s);
    receive({ type: "picked", object: 27, shape: "", material: "ChairFrame", point: [0, 0, 0] });
    check(byId.selection.textContent.includes("#27") && byId.selection.textContent.includes("ChairFrame"),
          "the selection names object 27 and its material ChairFrame: " + byId.selection.textContent);
    receive(Object.assign({}, s, { version: 2 })); // after a camera move
    check(byId.selection.textContent.includes("ChairFrame"), "the selection survives a new state");
    check(!byId["read-only"].hidden, "the read-only note shows on a pbrt scene");
    check(byId["mat-apply"].disabled, "material apply is disabled on a pbrt scene");
    const before = sent.length;
    click("mat-apply");
    click("emission-apply");
    check(sent.length === before, "no edit is sent on a read-only scene");
    check(byId.error.textContent.includes("read-only"), "the error area says the scene is read-only: " +
          byId.error.textContent);
    // The server may pick an object the state does not list: named from the pick alone.
    receive({ type: "picked", object: 99, name: "Chair", material: "Wood", point: [0, 0, 0] });
    check(byId.selection.textContent.includes("Chair"), "an unlisted object is named from the pick");
  },
  // Issue 37 bug 3: a light's and an object's emission keep their colour.
  rgb_emission() {
    receive(state(true, {
      lights: [{ type: "point", name: "bulb", position: [0, 2, 0], intensity: [17, 12, 4] }],
      objects: [{ index: 0, type: "quad", name: "lamp", emission: [17, 12, 4] }],
    }));
    const row = byId.lights.children[0];
    const inputs = row.children.filter((c) => c.type === "number");
    check(inputs.length === 3, "the light shows three fields, not " + inputs.length);
    check(inputs.map((i) => Number(i.value)).join() === "17,12,4", "the fields show 17, 12, 4");
    inputs[0].value = "8";
    row.children.find((c) => c.tagName === "button").onclick();
    check(JSON.stringify(lastSent()) === JSON.stringify({ type: "light", index: 0, set: { intensity: [8, 12, 4] } }),
          "setting red to 8 sends [8, 12, 4]: " + JSON.stringify(lastSent()));
    receive({ type: "picked", object: 0, name: "lamp", point: [0, 0, 0] });
    check(["r", "g", "b"].map((c) => byId["emission-" + c].value).join() === "17,12,4",
          "the emission fields show 17, 12, 4");
    byId["emission-g"].value = "2";
    click("emission-apply");
    check(JSON.stringify(lastSent()) === JSON.stringify({ type: "emission", object: 0, emission: [17, 2, 4] }),
          "applying sends [17, 2, 4]: " + JSON.stringify(lastSent()));
    byId["emission-b"].value = "-1";
    const before = sent.length;
    click("emission-apply");
    check(sent.length === before && byId.error.textContent.includes("emission"), "a negative channel is refused");
  },
  // Issue 37 bug 7: a move step outside the accepted range is refused with the range named.
  move_step() {
    receive(state(true, { objects: [{ index: 0, type: "sphere", name: "ball" }] }));
    receive({ type: "picked", object: 0, name: "ball", point: [0, 0, 0] });
    const up = dataButtons.find((b) => b.dataset.move === "0,1,0");
    byId.step.value = "0.5";
    up.onclick();
    check(JSON.stringify(lastSent()) === JSON.stringify({ type: "transform", object: 0, translate: [0, 0.5, 0] }),
          "a step of 0.5 moves by 0.5: " + JSON.stringify(lastSent()));
    for (const bad of ["1e9", "abc", "0"]) {
      byId.step.value = bad;
      const before = sent.length;
      up.onclick();
      check(sent.length === before, "a step of " + bad + " is not sent");
      check(byId.error.textContent.includes("1000"), "the error names the range: " + byId.error.textContent);
    }
  },
  // Issue 37's viewer: the refinement's progress, exposure and tone map, the resolution and field
  // of view, the default spp, readable statistics, controls that need a selection or the server,
  // and a reconnect when the server goes.
  viewer_controls() {
    receive(state(true, { default_spp: { raytrace: 16, gi: 8, path: 64 }, display: { exposure: 0, tone_map: "clamp" },
                          objects: [{ index: 0, type: "sphere", name: "ball", emission: [1, 2, 3] }] }));
    check(byId["spp-defaults"].textContent.includes("raytrace 16, gi 8, path 64"), "the default spp are shown: " + byId["spp-defaults"].textContent);
    check(byId["res-w"].value == 64 && byId["fov"].value == 40, "resolution and field of view are shown");
    receiveFrame(1, 64, 64);
    receive({ type: "refine", version: 1, spp: 5, of: 16, done: false });
    check(byId.refine.textContent === "refining toward raytrace: 5 of 16 spp", "the refinement's progress: " + byId.refine.textContent);
    receive({ type: "refine", version: 1, spp: 16, of: 16, done: true });
    check(byId.refine.textContent === "refined: raytrace, 16 spp", "its end: " + byId.refine.textContent);
    byId.exposure.value = "1.5";
    byId.exposure.onchange();
    check(JSON.stringify(lastSent()) === JSON.stringify({ type: "display", exposure: 1.5 }), "exposure sends display: " + JSON.stringify(lastSent()));
    byId["tone-map"].value = "aces";
    byId["tone-map"].onchange();
    check(JSON.stringify(lastSent()) === JSON.stringify({ type: "display", tone_map: "aces" }), "the tone map sends display");
    byId["res-w"].value = "320"; byId["res-h"].value = "200"; byId.fov.value = "30";
    click("view-apply");
    const cam = lastSent();
    check(cam.type === "camera" && JSON.stringify(cam.resolution) === "[320,200]" && cam.fov === 30 && cam.undo_step === true,
          "Apply sends the resolution and field of view as one undo step: " + JSON.stringify(cam));
    const moveUp = dataButtons.find((b) => b.dataset.move === "0,1,0");
    check(moveUp.disabled && byId["mat-apply"].disabled && !byId.save.disabled, "with nothing selected the selection's edits are disabled, Save is not");
    byId.lights.children[0].children.find((c) => c.tagName === "button").onclick(); // an emissive object's select
    check(!moveUp.disabled && context.window.rayproc.selected === 0, "selecting the emissive object from the lights panel enables them");
    receive({ type: "render_end", mode: "gi", cancelled: false, spp: 8, seconds: 1.5,
             stats: { wall_seconds: 1.5, rays: 3e6, rays_per_second: 2e6, samples: 1e5, peak_memory_bytes: 1 << 26, gi: { photons_stored: 12345 } } });
    const rows = byId.stats.children[0].children.map((tr) => tr.children.map((td) => td.textContent).join(" "));
    check(rows.includes("rays traced 3.00 M") && rows.includes("gi: photons stored 12345"), "statistics as a table: " + rows.join("; "));
    click("zoom-1");
    check(context.window.rayproc.imageZoom === 1, "1:1 shows one image pixel per screen pixel: " + context.window.rayproc.imageZoom);
    click("zoom-fit");
    check(Math.abs(context.window.rayproc.imageZoom - 600 / 64) < 1e-9, "Fit fills the stage: " + context.window.rayproc.imageZoom);
    // The server goes: controls are disabled, nothing is sent, and the page reconnects.
    const old = socket;
    old.onclose();
    check(byId.status.textContent.includes("reconnecting") && byId["mode-path"].disabled && byId.undo.disabled,
          "when the server goes the page says so and disables its controls: " + byId.status.textContent);
    const before = sent.length;
    click("undo");
    check(sent.length === before && byId.error.textContent.includes("reconnecting"), "a click then sends nothing and says why");
    advance(600);
    check(socket !== old, "the page connects again");
    socket.onopen();
    check(!byId["mode-path"].disabled && byId.status.textContent === "connected", "and enables its controls once connected");
  },
};

try {
  scenarios[scenario]();
} catch (e) {
  console.log("FAIL the page threw: " + (e && e.stack || e));
  failures++;
}
process.exit(failures ? 1 : 0);
