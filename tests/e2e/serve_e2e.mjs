// End-to-end test of rayproc serve in headless Chromium (docs/serve.md, docs/testing.md):
// loads the page, picks and moves an object, drags the camera, starts gi, cancels, downloads
// the partial image, saves the scene, and checks the saved file and the screenshots.
//   node tests/e2e/serve_e2e.mjs --rayproc build/rayproc --scene scenes/cornell-box.json --out DIR
import fs from "node:fs";
import path from "node:path";
import os from "node:os";
import puppeteer from "puppeteer-core";
import { startServer, stopServer, settle, dragCamera, refined, sleep } from "./lib.mjs";

const args = Object.fromEntries(
  process.argv.slice(2).reduce((pairs, a, i, all) => (a.startsWith("--") ? [...pairs, [a.slice(2), all[i + 1]]] : pairs), []));
const rayproc = path.resolve(args.rayproc), scene = path.resolve(args.scene), out = path.resolve(args.out);
const browserPath = args.browser || "/usr/bin/chromium";
fs.mkdirSync(out, { recursive: true });
const work = fs.mkdtempSync(path.join(out, "work-"));
// The scene at 256x256 and a 128-pixel live preview: renders stay quick in sanitizer builds, and
// a download (the render) is told from the preview by its size.
const sceneCopy = path.join(work, "scene.json");
const sceneDoc = JSON.parse(fs.readFileSync(scene, "utf8"));
sceneDoc.camera.resolution = [256, 256];
fs.writeFileSync(sceneCopy, JSON.stringify(sceneDoc, null, 1));

let failures = 0;
function check(ok, what) {
  console.log((ok ? "ok   " : "FAIL ") + what);
  if (!ok) failures++;
}

// The server, on a free port.
const { server, url } = await startServer(rayproc, sceneCopy, ["--threads", "2", "--preview-size", "128"], work);
console.log("serving " + url);

const browser = await puppeteer.launch({
  executablePath: browserPath, headless: true,
  args: ["--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage"],
});
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1000, height: 700 });
  const pageErrors = [];
  page.on("pageerror", (e) => pageErrors.push(String(e)));
  await page.goto(url);
  const waitFor = (fn, arg, timeout = 120000) => page.waitForFunction(fn, { timeout, polling: 50 }, arg);
  // A wait that times out throws (the run fails); the checks read what the page holds after it.
  await waitFor(() => window.rayproc.state !== null && window.rayproc.framesShown > 0);
  const loaded = await page.evaluate(() => ({
    objects: window.rayproc.state.objects.length, frames: window.rayproc.framesShown }));
  check(loaded.objects > 0 && loaded.frames > 0, "the page loaded, got the state (" + loaded.objects +
        " objects) and a first frame (" + loaded.frames + " shown)");
  const canvasBox = await (await page.$("#canvas")).boundingBox();
  const shot = async (name) => {
    const file = path.join(out, name + ".png");
    await page.screenshot({ path: file, clip: canvasBox });
    return fs.readFileSync(file);
  };
  const settle = async () => { // frames stop arriving, or the refinement ended: the view is complete
    let last = -1;
    for (let i = 0; i < 100; i++) {
      if (await page.evaluate(refined)) return;
      const n = await page.evaluate(() => window.rayproc.framesShown);
      if (n === last) return;
      last = n;
      await new Promise((r) => setTimeout(r, 150));
    }
  };
  await settle();
  const first = await shot("1-loaded");

  // A second tab on the same server: it sees the first tab's edits.
  const other = await browser.newPage();
  await other.goto(url);
  await other.waitForFunction(() => window.rayproc.state !== null, { timeout: 120000, polling: 50 });
  await page.bringToFront(); // a background tab gets no animation frames: clicks would wait

  // Pick the tall box (left of centre) and move it up by 3 steps of 0.1.
  await page.mouse.click(canvasBox.x + 0.38 * canvasBox.width, canvasBox.y + 0.5 * canvasBox.height);
  await waitFor(() => window.rayproc.selected !== null);
  const picked = await page.evaluate(() => window.rayproc.state.objects[window.rayproc.selected].name);
  check(picked === "TallBox", "clicking the tall box selects it (got " + picked + ")");
  // Its box is drawn over the image where it was clicked (the click at 0.38, 0.5 is inside it;
  // a mirrored or misplaced projection would not hold it).
  const outline = await page.evaluate(() => window.rayproc.outlineBox);
  check(outline && outline[0] < 0.38 && 0.38 < outline[2] && outline[1] < 0.5 && 0.5 < outline[3] && outline[2] < 0.7,
        "the selection's box is drawn around the click (" + JSON.stringify(outline && outline.map((v) => +v.toFixed(3))) + ")");
  for (let i = 0; i < 3; i++) {
    await page.click('[data-move="0,1,0"]');
    await waitFor((n) => window.rayproc.state.undo_depth === n, i + 1);
  }
  await other.waitForFunction(() => window.rayproc.state.undo_depth === 3, { timeout: 120000, polling: 50 });
  const otherDepth = await other.evaluate(() => window.rayproc.state.undo_depth);
  check(otherDepth === 3, "a second tab sees the three edits of the first (undo depth " + otherDepth + ")");
  await other.close();
  await settle();
  const moved = await shot("2-moved");
  check(!moved.equals(first), "moving the box changes the image");

  // Drag the camera: an orbit to the right.
  const before = await page.evaluate(() => JSON.stringify(window.rayproc.state.camera.position));
  const cx = canvasBox.x + canvasBox.width / 2, cy = canvasBox.y + canvasBox.height / 2;
  await page.mouse.move(cx, cy);
  await page.mouse.down();
  for (let i = 1; i <= 10; i++) await page.mouse.move(cx + 8 * i, cy + 2 * i);
  await page.mouse.up();
  await waitFor((b) => JSON.stringify(window.rayproc.state.camera.position) !== b, before);
  await settle();
  const orbited = await shot("3-orbited");
  check(!orbited.equals(moved), "dragging the camera changes the image");
  const [frameVersion, viewVersion] =
    await page.evaluate(() => [window.rayproc.lastFrameVersion, window.rayproc.state.version]);
  check(frameVersion === viewVersion,
    "the last frame drawn is of the view shown (frame version " + frameVersion + ", state " + viewVersion + ")");

  // Orbiting stays in the box (issue 37 bug 5): from the home view a 150-pixel drag keeps most
  // of the image lit (it went through the side wall into black); Ctrl+Z undoes the drag,
  // Ctrl+Shift+Z redoes it, and Home returns to the scene file's view.
  const meanLevel = () => page.evaluate(() => {
    const c = document.getElementById("canvas");
    const d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
    let sum = 0;
    for (let i = 0; i < d.length; i += 4) sum += d[i] + d[i + 1] + d[i + 2];
    return sum / (3 * d.length / 4);
  });
  const viewOf = () => page.evaluate(() => JSON.stringify(window.rayproc.state.camera.position));
  await page.click("#home");
  await waitFor(() => JSON.stringify(window.rayproc.state.camera.position) === JSON.stringify(window.rayproc.state.home.position));
  await settle();
  const homeView = await viewOf(), homeLevel = await meanLevel();
  await page.mouse.move(cx, cy);
  await page.mouse.down();
  for (let i = 1; i <= 15; i++) { await page.mouse.move(cx + 10 * i, cy); await new Promise((r) => setTimeout(r, 20)); }
  await page.mouse.up();
  await waitFor((h) => JSON.stringify(window.rayproc.state.camera.position) !== h, homeView);
  await settle();
  const draggedView = await viewOf(), draggedLevel = await meanLevel();
  await shot("3b-orbited-150px");
  check(draggedLevel > 0.6 * homeLevel, "a 150-pixel orbit keeps the box in view: mean level " + draggedLevel.toFixed(1) +
        " against " + homeLevel.toFixed(1) + " at home");
  await page.focus("#canvas");
  await page.keyboard.down("Control"); await page.keyboard.press("z"); await page.keyboard.up("Control");
  await waitFor((h) => JSON.stringify(window.rayproc.state.camera.position) === h, homeView);
  check(true, "Ctrl+Z undoes the drag (the home view again)");
  await page.keyboard.down("Control"); await page.keyboard.down("Shift"); await page.keyboard.press("z");
  await page.keyboard.up("Shift"); await page.keyboard.up("Control");
  await waitFor((v) => JSON.stringify(window.rayproc.state.camera.position) === v, draggedView);
  check(true, "Ctrl+Shift+Z redoes it");
  await page.click("#home");
  await waitFor((h) => JSON.stringify(window.rayproc.state.camera.position) === h, homeView);
  check(true, "Home returns to the scene file's view");
  await settle();

  // gi: streams in with progress; Cancel returns to the live preview.
  // 1000 spp: passes of 16 spp, each 1.6% of the render; the image fills in tile by tile.
  await page.type("#spp", "1000");
  await page.click("#mode-gi");
  await waitFor(() => window.rayproc.rendering === true);
  await waitFor(() => window.rayproc.lastProgress && window.rayproc.lastProgress.fraction > 0.004);
  await shot("4a-gi-filling-in");
  await waitFor(() => window.rayproc.lastProgress.fraction > 0.008);
  const info = await page.$eval("#render-info", (e) => e.textContent);
  check(/ETA/.test(info) && /Mrays\/s/.test(info), "gi shows progress, ETA and rays/s (" + info + ")");
  const starting = await page.evaluate(() => window.rayproc.lastStarting);
  check(starting && starting.mode === "gi" && /photon/.test(starting.what),
        "before its passes gi says it is starting (" + JSON.stringify(starting) + ")");
  await shot("4b-gi-running");
  // During a render (issue 37 bug 4): a drag says why the view does not move, the message
  // outlives the progress that follows, and the release picks nothing; so does a refused render.
  const selectedBefore = await page.evaluate(() => window.rayproc.selected);
  const viewBefore = await viewOf();
  await page.mouse.move(canvasBox.x + 0.7 * canvasBox.width, canvasBox.y + 0.8 * canvasBox.height);
  await page.mouse.down();
  for (let i = 1; i <= 5; i++) await page.mouse.move(canvasBox.x + 0.7 * canvasBox.width + 6 * i, canvasBox.y + 0.8 * canvasBox.height);
  const progressSeen = async () => page.evaluate(() => window.rayproc.lastProgress.fraction);
  let fraction = await progressSeen();
  for (let i = 0; i < 3; i++) { await waitFor((f) => window.rayproc.lastProgress.fraction > f, fraction); fraction = await progressSeen(); }
  const dragError = await page.$eval("#error", (e) => e.textContent);
  check(/render is running/.test(dragError), "a drag during a render says why the view does not move, three progress messages later (" + dragError + ")");
  await page.mouse.up();
  await new Promise((r) => setTimeout(r, 300));
  const after = await page.evaluate(() => [window.rayproc.selected, window.rayproc.lastReply.type]);
  check(after[0] === selectedBefore && after[1] !== "picked" && (await viewOf()) === viewBefore,
        "the release after it picks nothing and the view is unchanged (selected " + after[0] + ", last reply " + after[1] + ")");
  await page.click("#mode-path");
  await waitFor(() => /already running/.test(document.getElementById("error").textContent));
  fraction = await progressSeen();
  for (let i = 0; i < 2; i++) { await waitFor((f) => window.rayproc.lastProgress.fraction > f, fraction); fraction = await progressSeen(); }
  const renderError = await page.$eval("#error", (e) => e.textContent);
  check(/already running/.test(renderError), "a refused render's error outlives the progress (" + renderError + ")");
  await page.click("#cancel");
  await waitFor(() => window.rayproc.rendering === false);
  const ended = await page.$eval("#render-info", (e) => e.textContent);
  check(/cancelled/.test(ended), "Cancel stops the render (" + ended + ")");
  const stats = await page.$eval("#stats", (e) => e.textContent);
  check(/rays/.test(stats), "the render's statistics are shown");
  const analysis = await page.$eval("#analysis", (e) => e.textContent);
  check(/skipped/.test(analysis), "the scene analysis is shown (" + analysis.split("\n")[0] + ")");
  const png = await page.evaluate(async () => {
    const r = await fetch("/image.png");
    const blob = await r.blob();
    const bitmap = await createImageBitmap(blob);
    return { status: r.status, type: r.headers.get("content-type"), width: bitmap.width, height: bitmap.height };
  });
  check(png.status === 200 && png.type === "image/png" && png.width === 256 && png.height === 256,
        "the partial render downloads as PNG, at the render's 256x256, not the 128x128 preview (" +
        png.width + "x" + png.height + ")");
  const exr = await page.evaluate(async () => {
    const r = await fetch("/image.exr");
    const bytes = new Uint8Array(await r.arrayBuffer());
    return { status: r.status, magic: Array.from(bytes.slice(0, 4)) };
  });
  check(exr.status === 200 && JSON.stringify(exr.magic) === "[118,47,49,1]", "and as EXR (its magic number)");
  await settle();
  await shot("5-after-cancel");

  // A malformed edit is refused and changes nothing.
  const depth = await page.evaluate(() => window.rayproc.state.undo_depth);
  // (lastError is cleared first: an earlier error would end the wait before the reply came.)
  await page.evaluate(() => { window.rayproc.lastError = null; window.rayproc.send({ type: "material", name: "TallBox", material: { type: "plastic" } }); });
  await waitFor(() => window.rayproc.lastError !== null);
  const error = await page.$eval("#error", (e) => e.textContent);
  check(/TallBox/.test(error), "a bad material is refused with the loader's message (" + error + ")");
  check(await page.evaluate(() => window.rayproc.state.undo_depth) === depth, "and changes nothing");

  // Save; the file is the edited scene.
  const saved = path.join(work, "saved.json");
  await page.$eval("#save-path", (e, v) => { e.value = v; }, saved);
  await page.click("#save");
  await waitFor(() => /saved/.test(document.getElementById("status").textContent));
  const doc = JSON.parse(fs.readFileSync(saved, "utf8"));
  const tall = doc.nodes[6];
  check(Array.isArray(tall.transform) && Math.abs(tall.transform[7] - 0.3) < 1e-5,
        "the saved tall box is moved up by 0.3 (" + JSON.stringify(tall.transform) + ")");
  const cam = await page.evaluate(() => window.rayproc.state.camera.position);
  check(JSON.stringify(doc.camera.position) === JSON.stringify(cam), "the saved camera is the page's");
  check(pageErrors.length === 0, "no script errors on the page (" + pageErrors.join("; ") + ")");

  // Ctrl-C to the server while a render runs: it stops promptly and cleanly.
  await page.evaluate(() => { window.rayproc.lastProgress = null; window.rayproc.send({ type: "render", mode: "path", spp: 60000 }); });
  await waitFor(() => window.rayproc.lastProgress !== null);
  const stopStart = Date.now();
  server.kill("SIGINT");
  const [code, signal] = await new Promise((r) => server.on("exit", (c, s) => r([c, s])));
  const stopSeconds = (Date.now() - stopStart) / 1000;
  check(code === 0 && stopSeconds < 15, "Ctrl-C during a render stops the server with status 0 in " + stopSeconds.toFixed(1) + " s (" + code + ", " + signal + ")");
} catch (e) {
  console.log("FAIL " + e.stack);
  failures++;
} finally {
  if (server.exitCode === null && server.signalCode === null) {
    server.kill("SIGINT");
    await new Promise((r) => server.on("exit", r));
  }
}

// A still view refines toward the raytrace image (issue 37): the Cornell box at 128 x 128 with
// a 128-pixel preview, so the preview, its refining passes and a raytrace render of the same
// view have one size. The reference is raytrace at 4x its default spp; each frame of the view
// (the 1-spp preview, then the passes) is compared with it, and the error must fall. A camera
// move and an edit each restart the passes.
{
  const refineScene = path.join(work, "refine.json");
  const doc = JSON.parse(fs.readFileSync(scene, "utf8"));
  doc.camera.resolution = [128, 128];
  fs.writeFileSync(refineScene, JSON.stringify(doc, null, 1));
  const srv = await startServer(rayproc, refineScene, ["--threads", "2", "--preview-size", "128"], work);
  try {
    const page = await browser.newPage();
    await page.setViewport({ width: 1000, height: 700 });
    const pageErrors = [];
    page.on("pageerror", (e) => pageErrors.push(String(e)));
    await page.goto(srv.url);
    const waitFor = (fn, arg, timeout = 120000) => page.waitForFunction(fn, { timeout, polling: 50 }, arg);
    await waitFor(() => window.rayproc.state !== null && window.rayproc.framesShown > 0);
    const defaults = await page.$eval("#spp-defaults", (e) => e.textContent);
    const spp = await page.evaluate(() => window.rayproc.state.default_spp.raytrace);
    check(defaults.includes("raytrace " + spp), "the default spp are shown (" + defaults + ")");
    await page.type("#spp", String(4 * spp));
    await page.click("#mode-raytrace");
    await waitFor(() => /raytrace: done/.test(document.getElementById("render-info").textContent));
    const recordView = async (action) => {
      const before = await page.evaluate(() => window.rayproc.state.version);
      await page.evaluate(() => { window.rayproc.refineLog = []; });
      await action();
      await waitFor((v) => window.rayproc.state.version > v, before);
      await waitFor(refined);
      return page.evaluate(() => window.rayproc.state.version);
    };
    // The same view again (Home): its preview, then the passes.
    const home = await recordView(() => page.click("#home"));
    const measured = await page.evaluate(async (version) => {
      const bitmap = await createImageBitmap(await (await fetch("/image.png")).blob());
      const c = document.createElement("canvas");
      c.width = bitmap.width; c.height = bitmap.height;
      const g = c.getContext("2d");
      g.drawImage(bitmap, 0, 0);
      const ref = g.getImageData(0, 0, c.width, c.height).data;
      const rmse = (p) => { let sum = 0; for (let i = 0; i < p.length; i++) if (i % 4 !== 3) sum += (p[i] - ref[i]) ** 2; return Math.sqrt(sum / (0.75 * p.length)); };
      return window.rayproc.refineLog.filter((f) => f.version === version && f.width === c.width && f.height === c.height)
        .map((f) => ({ spp: f.refine ? f.refine.spp : 0, rmse: +rmse(f.pixels).toFixed(3) }));
    }, home);
    console.log("     refinement vs raytrace at " + 4 * spp + " spp (8-bit RMSE): " + measured.map((m) => m.spp + " spp " + m.rmse).join(", "));
    const preview = measured.find((m) => m.spp === 0), passes = measured.filter((m) => m.spp > 0);
    check(preview && passes.length >= 3 && passes[passes.length - 1].spp === spp,
          "the still view's preview is followed by raytrace passes up to " + spp + " spp (" + passes.length + " passes)");
    const first = passes[0].rmse, last = passes[passes.length - 1].rmse;
    check(preview.rmse > last && last < 0.6 * first && passes.every((m, i) => i === 0 || m.rmse <= 1.05 * passes[i - 1].rmse + 0.1),
          "its error against the raytrace render falls as it refines: preview " + preview.rmse + ", first pass " + first +
          ", last " + last);
    const refineText = await page.$eval("#refine", (e) => e.textContent);
    check(/refined: raytrace, \d+ spp/.test(refineText), "the page says the view is refined (" + refineText + ")");
    // A camera move (W) and an edit restart the passes from the first.
    await page.focus("#canvas");
    const firstPassAfter = async (version) => page.evaluate((v) => {
      const f = window.rayproc.refineLog.find((e) => e.version === v && e.refine);
      return f ? f.refine.spp : -1;
    }, version);
    const afterMove = await firstPassAfter(await recordView(() => page.keyboard.press("w")));
    const afterEdit = await firstPassAfter(await recordView(() =>
      page.evaluate(() => window.rayproc.send({ type: "transform", object: 6, translate: [0, 0.05, 0] }))));
    check(afterMove === passes[0].spp && afterEdit === passes[0].spp,
          "a camera move and an edit restart the refinement (first pass " + afterMove + " and " + afterEdit + " spp)");
    // The refined view (docs/serve.md shows it: docs/images/serve-cornell-box.png).
    await page.screenshot({ path: path.join(out, "page-cornell-box.png"), clip: { x: 0, y: 0, width: 1000, height: 700, scale: 0.75 } });
    check(pageErrors.length === 0, "no script errors while refining (" + pageErrors.join("; ") + ")");
    await page.close();
  } catch (e) {
    console.log("FAIL " + e.stack);
    failures++;
  } finally {
    await stopServer(srv.server);
  }
}

// A pbrt-v4 scene (the classroom when ../shared/scenes is there) at a 1024-pixel preview: a drag
// at 60 mouse events a second for 3 s shows frames at an interactive rate and ends on the final
// view (issue 37 bug 2); picks and moves throw nothing on the page.
const pbrtPreview = Number(args["pbrt-preview-size"] || 1024);
if (args["pbrt-scene"]) {
  const pbrt = await startServer(rayproc, path.resolve(args["pbrt-scene"]),
                                 ["--threads", "2", "--preview-size", String(pbrtPreview)], work);
  console.log("serving " + path.basename(args["pbrt-scene"]) + " at " + pbrt.url + " (started in " + pbrt.started.toFixed(2) + " s)");
  try {
    const page = await browser.newPage();
    await page.setViewport({ width: 1400, height: 900 });
    const pageErrors = [];
    page.on("pageerror", (e) => pageErrors.push(String(e)));
    await page.goto(pbrt.url);
    await page.waitForFunction(() => window.rayproc.state !== null && window.rayproc.framesShown > 0, { timeout: 120000, polling: 50 });
    await settle(page);
    // The page as it loaded, refining (docs/serve.md shows it: docs/images/serve-pbrt.png): the
    // full-size frame, and the first refining pass if it comes within 30 s.
    await page.waitForFunction((w) => window.rayproc.lastFrameWidth === w, { timeout: 120000, polling: 50 }, pbrtPreview);
    await page.waitForFunction(() => window.rayproc.lastRefine !== null, { timeout: 30000, polling: 100 }).catch(() => {});
    await page.screenshot({ path: path.join(out, "page-pbrt.png"), clip: { x: 0, y: 0, width: 1400, height: 900, scale: 0.5 } });
    const box = await (await page.$("#canvas")).boundingBox();
    const drag = await dragCamera(page, box, { seconds: 3, rate: 60 });
    const minFps = Number(args["min-drag-fps"] || 0);
    check(drag.fps >= minFps, "a 3 s drag at " + drag.eventRate.toFixed(0) + " mouse events/s shows " + drag.frames +
          " frames: " + drag.fps.toFixed(1) + " frames/s at preview " + pbrtPreview + " (at least " + minFps + "; load " + os.loadavg()[0].toFixed(1) + ")");
    const readout = await page.$eval("#fps", (e) => e.textContent);
    check(/x\d+, \d+ frames in the last second/.test(readout), "the page shows its frame rate (" + readout + ")");
    await settle(page);
    const end = await page.evaluate(() => ({ frame: window.rayproc.lastFrameVersion, state: window.rayproc.state.version,
      page: window.rayproc.camera, server: window.rayproc.state.camera }));
    const near = (a, b) => a.every((v, i) => Math.abs(v - b[i]) <= 1e-5 * (1 + Math.abs(v)));
    check(end.frame === end.state && near(end.page.position, end.server.position) && near(end.page.look_at, end.server.look_at),
          "the last frame is of the drag's final view (frame version " + end.frame + ", state " + end.state + ")");
    await page.waitForFunction((w) => window.rayproc.lastFrameWidth === w, { timeout: 120000, polling: 50 }, pbrtPreview);
    await page.screenshot({ path: path.join(out, "6-pbrt-after-drag.png") }); // the full-size frame
    // A pick names the object; nothing throws.
    await page.mouse.click(box.x + 0.5 * box.width, box.y + 0.7 * box.height);
    await page.waitForFunction(() => window.rayproc.lastReply && window.rayproc.lastReply.type === "picked", { timeout: 30000, polling: 50 });
    const picked0 = await page.evaluate(() => window.rayproc.lastReply);
    // Walking through the room (issue 37 bug 6): W steps 2% of the scene's extent, 20 wheel
    // notches cross it, passing the pivot, and W is no shorter after.
    const cameraNow = () => page.evaluate(() => ({ ...window.rayproc.camera, extent: window.rayproc.state.bounds.extent }));
    const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
    const walk = async () => {
      const a = await cameraNow();
      const shown = await page.evaluate(() => JSON.stringify(window.rayproc.state.camera.position));
      await page.focus("#canvas");
      await page.keyboard.press("w");
      await page.waitForFunction((p) => JSON.stringify(window.rayproc.state.camera.position) !== p, { timeout: 30000, polling: 50 }, shown);
      return dist((await cameraNow()).position, a.position) / a.extent;
    };
    const w1 = await walk();
    const beforeZoom = await cameraNow();
    await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
    for (let i = 0; i < 20; i++) { await page.mouse.wheel({ deltaY: -100 }); await new Promise((r) => setTimeout(r, 30)); }
    await settle(page);
    const zoomed = await cameraNow();
    const zoom = dist(zoomed.position, beforeZoom.position) / beforeZoom.extent;
    const passed = dist(zoomed.position, beforeZoom.position) > dist(beforeZoom.look_at, beforeZoom.position);
    const w2 = await walk();
    check(Math.abs(w1 - 0.02) < 1e-3 && Math.abs(zoom - 1) < 0.02 && passed && Math.abs(w2 - 0.02) < 1e-3,
          "W steps " + (100 * w1).toFixed(2) + "% of the scene's extent (" + beforeZoom.extent.toFixed(1) + "), 20 wheel notches " +
          (100 * zoom).toFixed(1) + "% passing the pivot (" + passed + "), W after it " + (100 * w2).toFixed(2) + "%");
    const selection = await page.$eval("#selection", (e) => e.textContent);
    // Read-only, said and shown (issue 37): the banner over the image, the edit controls
    // disabled, the picked object's name and material, the sun and the sky among the lights.
    const ro = await page.evaluate(() => ({
      banner: !document.getElementById("banner").hidden && document.getElementById("banner").textContent,
      disabled: [...document.querySelectorAll("[data-edit]")].every((b) => b.disabled),
      lights: document.getElementById("lights").textContent,
      picked: window.rayproc.lastReply && window.rayproc.lastReply.type === "picked" ? window.rayproc.lastReply : null }));
    check(/Read-only/.test(ro.banner || "") && ro.disabled, "a pbrt scene shows a read-only banner and disabled edit controls (" + ro.banner + ")");
    check(/directional/.test(ro.lights) && /environment/.test(ro.lights), "the lights panel lists the sun and the sky (" + ro.lights + ")");
    check(!!picked0 && !!picked0.material && selection.includes(picked0.material),
          "the selection names the picked object's material (" + selection + ")");
    check(pageErrors.length === 0, "no script errors on the pbrt page (" + pageErrors.join("; ") + "; selection " + selection + ")");
    await page.close();
  } catch (e) {
    console.log("FAIL " + e.stack);
    failures++;
  } finally {
    await stopServer(pbrt.server);
  }
}
await browser.close();
console.log(failures === 0 ? "serve e2e: all checks passed" : "serve e2e: " + failures + " failure(s)");
process.exit(failures === 0 ? 0 : 1);
