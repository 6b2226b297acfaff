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
    width: 512, height: 512, onclick: null, listeners: {},
    append(...c) { this.children.push(...c); },
    set innerHTML(v) { this.children = []; },
    get innerHTML() { return ""; },
    addEventListener(type, fn) { (this.listeners[type] = this.listeners[type] || []).push(fn); },
    getContext() { return { putImageData() {}, drawImage() {} }; },
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
  dataButtons.push(el);
}
const sent = [];
let socket = null;
class FakeWebSocket { constructor() { socket = this; } send(text) { sent.push(JSON.parse(text)); } }
const windowListeners = {};
const context = {
  document: {
    getElementById: (id) => byId[id] || null,
    createElement: (tag) => element(tag),
    querySelectorAll: (sel) => sel === "[data-move]" ? dataButtons.filter((b) => b.dataset.move)
      : sel === "[data-edit]" ? dataButtons.filter((b) => "edit" in b.dataset) : [],
  },
  location: { protocol: "http:", host: "127.0.0.1:1" },
  WebSocket: FakeWebSocket, JSON, Math, Number, Array, Object, String, parseFloat, parseInt, console,
  addEventListener: (type, fn) => { (windowListeners[type] = windowListeners[type] || []).push(fn); },
};
context.window = context;
vm.createContext(context);
vm.runInContext(script, context);

const receive = (m) => socket.onmessage({ data: JSON.stringify(m) });
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

const scenarios = {
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
};

try {
  scenarios[scenario]();
} catch (e) {
  console.log("FAIL the page threw: " + (e && e.stack || e));
  failures++;
}
process.exit(failures ? 1 : 0);
