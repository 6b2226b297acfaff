// Helpers shared by the end-to-end tests of rayproc serve (serve_e2e.mjs, drag_fps.mjs): start
// the server, open a page, and drag the camera the way a hand does.
import { spawn } from "node:child_process";

// `rayproc serve SCENE ARGS...` on a free port; resolves to { server, url, started } once it
// prints its address (started: seconds from spawn).
export async function startServer(rayproc, scene, serveArgs, cwd) {
  const t0 = Date.now();
  const server = spawn(rayproc, ["serve", scene, "--port", "0", ...serveArgs], { cwd });
  let serverErr = "";
  server.stderr.on("data", (d) => { serverErr += d; });
  const url = await new Promise((resolve, reject) => {
    let text = "";
    server.stdout.on("data", (d) => { text += d; const m = text.match(/http:\/\/127\.0\.0\.1:\d+\//); if (m) resolve(m[0]); });
    server.on("exit", (code) => reject(new Error("rayproc serve exited " + code + ": " + serverErr)));
    setTimeout(() => reject(new Error("rayproc serve did not start: " + serverErr)), 60000);
  });
  return { server, url, started: (Date.now() - t0) / 1000, stderr: () => serverErr };
}

// Whether the page shows the end of the refinement of the view it shows (a function for
// page.evaluate).
export function refined() {
  const r = window.rayproc.lastRefine, s = window.rayproc.state;
  return !!(r && s && r.done && r.version === s.version && window.rayproc.lastFrameVersion === s.version);
}

export async function stopServer(server) {
  if (server.exitCode !== null || server.signalCode !== null) return;
  const exited = new Promise((r) => server.on("exit", r));
  server.kill("SIGINT");
  await exited;
}

export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

// Waits until no frame has arrived for 300 ms (the preview is complete) or the still view's
// refinement has ended, at most `limitMs`.
export async function settle(page, limitMs = 30000) {
  const t0 = Date.now();
  let last = -1, since = Date.now();
  while (Date.now() - t0 < limitMs) {
    if (await page.evaluate(refined)) return;
    const n = await page.evaluate(() => window.rayproc.framesShown);
    if (n !== last) { last = n; since = Date.now(); }
    else if (Date.now() - since >= 300) return;
    await sleep(50);
  }
}

// Drags with the left button from the canvas centre for `seconds`, one mouse event every
// 1/`rate` s (a hand on a 60 Hz mouse), to and fro horizontally with a slow vertical drift
// (`amplitude` pixels). Returns the frames the page drew meanwhile and their rate.
export async function dragCamera(page, box, { seconds = 3, rate = 60, amplitude = 60, button = "left" } = {}) {
  const cx = box.x + box.width / 2, cy = box.y + box.height / 2;
  await page.mouse.move(cx, cy);
  await page.mouse.down({ button });
  const frames0 = await page.evaluate(() => window.rayproc.framesShown);
  const t0 = Date.now();
  let events = 0;
  for (;;) {
    const t = (Date.now() - t0) / 1000;
    if (t >= seconds) break;
    const phase = 2 * Math.PI * t / 1.5;
    await page.mouse.move(cx + amplitude * Math.sin(phase), cy + 0.25 * amplitude * Math.sin(phase / 3));
    events++;
    const next = t0 + events * 1000 / rate;
    if (next > Date.now()) await sleep(next - Date.now());
  }
  const elapsed = (Date.now() - t0) / 1000;
  const frames = (await page.evaluate(() => window.rayproc.framesShown)) - frames0;
  await page.mouse.up({ button });
  return { frames, seconds: elapsed, events, fps: frames / elapsed, eventRate: events / elapsed };
}
