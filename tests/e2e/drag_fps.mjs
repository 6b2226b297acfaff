// Measures the frames per second the page of rayproc serve shows while a script drags the
// camera at 60 mouse events a second (docs/serve.md, "Measured"; issue 37 bug 2):
//   node tests/e2e/drag_fps.mjs --rayproc build/rayproc --scene SCENE [--preview-size 1024]
//        [--threads 2] [--seconds 3] [--load 2]   (--load N: a `rayproc render` of N threads beside)
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { spawn } from "node:child_process";
import puppeteer from "puppeteer-core";
import { startServer, stopServer, settle, dragCamera, sleep } from "./lib.mjs";

const args = Object.fromEntries(
  process.argv.slice(2).reduce((pairs, a, i, all) => (a.startsWith("--") ? [...pairs, [a.slice(2), all[i + 1]]] : pairs), []));
const rayproc = path.resolve(args.rayproc), scene = path.resolve(args.scene);
const work = fs.mkdtempSync(path.join(os.tmpdir(), "rayproc-drag-"));
const { server, url, started, stderr } = await startServer(rayproc, scene,
  ["--threads", args.threads || "2", "--preview-size", args["preview-size"] || "1024"], work);
let load = null;
if (args.load) // another render beside the server, as on a shared machine
  load = spawn(rayproc, ["render", scene, "--mode", "path", "--spp", "100000", "--threads", args.load,
                         "-o", path.join(work, "load.exr")], { stdio: "ignore" });
const browser = await puppeteer.launch({ executablePath: args.browser || "/usr/bin/chromium", headless: true,
                                         args: ["--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage"] });
let rc = 0;
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1400, height: 900 });
  const errors = [];
  page.on("pageerror", (e) => errors.push(String(e)));
  await page.goto(url);
  await page.waitForFunction(() => window.rayproc.state !== null && window.rayproc.framesShown > 0, { timeout: 120000, polling: 50 });
  await settle(page);
  if (load) await sleep(1000);
  const box = await (await page.$("#canvas")).boundingBox();
  const r = await dragCamera(page, box, { seconds: Number(args.seconds || 3) });
  await settle(page);
  const [frameVersion, stateVersion] = await page.evaluate(() => [window.rayproc.lastFrameVersion, window.rayproc.state.version]);
  console.log(JSON.stringify({ scene: path.basename(path.dirname(scene)) + "/" + path.basename(scene), started,
    frames: r.frames, seconds: +r.seconds.toFixed(2), fps: +r.fps.toFixed(1), mouseEventsPerSecond: +r.eventRate.toFixed(1),
    lastFrameIsFinalView: frameVersion === stateVersion, pageErrors: errors.length, load: os.loadavg()[0] }));
} catch (e) {
  console.log("FAIL " + e.stack);
  rc = 1;
} finally {
  await browser.close();
  if (load) load.kill("SIGKILL");
  await stopServer(server);
  if (process.env.TRACE) console.log(stderr());
  fs.rmSync(work, { recursive: true, force: true });
}
process.exit(rc);
