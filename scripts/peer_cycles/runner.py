"""Runs Blender on an exported scene, reads Cycles' timings, compares images with rayproc.

Timings of one Cycles render (all in seconds):
- render_seconds: Cycles' own path-tracing time ("render_time" of the render result, written
  by Cycles into the EXR header as cycles.<view layer>.render_time). Excludes Blender's start,
  scene building and Cycles' scene synchronisation (BVH build, kernel setup). This is the
  figure compared with rayproc's wall_seconds (which also excludes loading and the BVH build).
- sync_seconds: Cycles' synchronisation time, from the same header.
- render_call_seconds: bpy.ops.render.render as timed inside Blender (sync + render + write).
- wall_seconds: the whole `blender` process, start-up included.
"""

import csv
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import time

from . import blender_script

INSTALL_HINT = ("blender not found. It is needed only for this benchmark, never to build or "
                "test rayproc. On Debian 12: `sudo apt-get install --no-install-recommends "
                "blender` (Blender 3.4.1), or set BLENDER=/path/to/blender.")


def find_blender():
    path = os.environ.get("BLENDER") or shutil.which("blender")
    if not path or not os.access(path, os.X_OK):
        raise SystemExit("peer-cycles: " + INSTALL_HINT)
    return path


def exr_header_strings(path):
    """The string attributes of an OpenEXR header (scanline, single part): name -> value."""
    out = {}
    with open(path, "rb") as f:
        data = f.read(1 << 20)
    if data[:4] != b"\x76\x2f\x31\x01":
        raise ValueError(f"{path}: not an OpenEXR file")
    pos = 8
    while pos < len(data) and data[pos] != 0:
        name_end = data.index(b"\0", pos)
        name = data[pos:name_end].decode("latin-1")
        type_end = data.index(b"\0", name_end + 1)
        kind = data[name_end + 1:type_end].decode("latin-1")
        size = struct.unpack_from("<i", data, type_end + 1)[0]
        value = data[type_end + 5:type_end + 5 + size]
        if kind == "string":
            out[name] = value.decode("utf-8", errors="replace")
        pos = type_end + 5 + size
    return out


def parse_clock(text):
    """Blender's time stamps: "SS.ff", "MM:SS.ff" or "HH:MM:SS.ff" -> seconds."""
    seconds = 0.0
    for part in text.strip().split(":"):
        seconds = seconds * 60.0 + float(part)
    return seconds


def cycles_times(exr_path):
    """render and synchronisation seconds from the Cycles metadata of a rendered EXR."""
    times = {}
    for name, value in exr_header_strings(exr_path).items():
        if not name.startswith("cycles."):
            continue
        for field in ("render_time", "synchronization_time", "total_time"):
            if name.endswith("." + field):
                times[field] = parse_clock(value)
        if name.endswith(".samples"):
            times["samples"] = value
    return times


def render(plan, output, blender=None, script_path=None, log=None):
    """Renders `plan` with Cycles into the EXR `output`; returns a dict of timings."""
    blender = blender or find_blender()
    output = os.path.abspath(output)
    text = blender_script.blender_script(plan, output)
    with tempfile.TemporaryDirectory(prefix="peer-cycles-") as tmp:
        script = script_path or os.path.join(tmp, "scene.py")
        with open(script, "w", encoding="utf-8") as f:
            f.write(text)
        if os.path.exists(output):
            os.remove(output)
        cmd = [blender, "-b", "--factory-startup", "-noaudio", "--python-exit-code", "1",
               "--python", script, "-t", str(plan["render"]["threads"])]
        t0 = time.perf_counter()
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        wall = time.perf_counter() - t0
    if log:
        with open(log, "a", encoding="utf-8") as f:
            f.write(proc.stdout)
    if proc.returncode != 0 or not os.path.isfile(output):
        tail = "\n".join(proc.stdout.splitlines()[-25:])
        raise SystemExit(f"peer-cycles: blender failed (exit {proc.returncode}):\n{tail}")
    result = {"wall_seconds": wall}
    m = re.search(r"^PEER_CYCLES_TIMES (\{.*\})$", proc.stdout, re.M)
    if m:
        result.update(json.loads(m.group(1)))
    ct = cycles_times(output)
    if "render_time" in ct:
        result["render_seconds"] = ct["render_time"]
    if "synchronization_time" in ct:
        result["sync_seconds"] = ct["synchronization_time"]
    return result


def rayproc_diff(rayproc, test, reference):
    proc = subprocess.run([rayproc, "diff", test, reference, "--json"], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True)
    if proc.returncode not in (0, 1):
        raise SystemExit(f"peer-cycles: rayproc diff failed: {proc.stderr.strip()}")
    d = json.loads(proc.stdout)
    return d["relmse"], d["rmse"]


def rayproc_render(rayproc, scene, mode, spp, plan, output, extra=()):
    """One rayproc render at the plan's resolution and threads; (wall_seconds, rays)."""
    r = plan["render"]
    with tempfile.TemporaryDirectory(prefix="peer-rayproc-") as tmp:
        stats = os.path.join(tmp, "stats.json")
        cmd = [rayproc, "render", scene, "--mode", mode, "--spp", str(spp),
               "--width", str(r["width"]), "--height", str(r["height"]),
               "--threads", str(r["threads"]), "--seed", str(r["seed"]), "-q",
               "--stats-json", stats, "-o", output, *extra]
        if mode == "path":
            cmd += ["--max-depth", str(r["max_depth"])]
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if proc.returncode != 0:
            raise SystemExit(f"peer-cycles: {' '.join(cmd)} failed: {proc.stderr.strip()}")
        with open(stats, encoding="utf-8") as f:
            s = json.load(f)
    return s["wall_seconds"], s.get("rays", 0)


def ladder(plan, scene_name, reference, spps, csv_path, rayproc, rayproc_runs=(),
           blender=None, keep=None, out=sys.stdout):
    """The spp ladder: for each spp one Cycles render and (interleaved, back to back) one
    render per rayproc run (mode, extra arguments), each compared with `reference`. Rows are appended to csv_path as
    scene,mode,settings,seconds,rays,relmse,rmse (Cycles: seconds = Cycles' render time,
    rays = 0, Cycles does not count them)."""
    new = not os.path.exists(csv_path) or os.path.getsize(csv_path) == 0
    r = plan["render"]
    with open(csv_path, "a", newline="", encoding="utf-8") as f, \
            tempfile.TemporaryDirectory(prefix="peer-ladder-") as tmp:
        w = csv.writer(f)
        if new:
            w.writerow(["scene", "mode", "settings", "seconds", "rays", "relmse", "rmse"])
        for spp in spps:
            plan["render"]["spp"] = spp
            img = os.path.join(keep or tmp, f"cycles-{spp}.exr")
            t = render(plan, img, blender)
            rel, rmse = rayproc_diff(rayproc, img, reference)
            settings = (f"spp={spp} max_bounces={r['max_depth']} {r['width']}x{r['height']} "
                        f"threads={r['threads']} sync={t.get('sync_seconds', 0):.3f}s "
                        f"wall={t['wall_seconds']:.2f}s blender={t.get('blender', '?')}")
            w.writerow([scene_name, "cycles", settings, f"{t['render_seconds']:.4f}", 0,
                        f"{rel:.6g}", f"{rmse:.6g}"])
            f.flush()
            print(f"cycles spp={spp}: render {t['render_seconds']:.3f} s (sync "
                  f"{t.get('sync_seconds', 0):.3f} s, wall {t['wall_seconds']:.2f} s) "
                  f"relmse {rel:.5g} rmse {rmse:.5g}", file=out, flush=True)
            for k, (mode, extra) in enumerate(rayproc_runs):
                img = os.path.join(keep or tmp, f"{mode}{k}-{spp}.exr")
                secs, rays = rayproc_render(rayproc, plan["scene"], mode, spp, plan, img, extra)
                rel, rmse = rayproc_diff(rayproc, img, reference)
                settings = f"spp={spp} {r['width']}x{r['height']} threads={r['threads']}"
                if mode == "path":
                    settings += f" max_depth={r['max_depth']}"
                if extra:
                    settings += " " + " ".join(extra)
                w.writerow([scene_name, mode, settings, f"{secs:.4f}", rays, f"{rel:.6g}",
                            f"{rmse:.6g}"])
                f.flush()
                print(f"{mode} {' '.join(extra)} spp={spp}: {secs:.3f} s relmse {rel:.5g} "
                      f"rmse {rmse:.5g}",
                      file=out, flush=True)


def time_at(points, target):
    """Seconds at which relMSE first reaches `target`, interpolating log(seconds) against
    log(relmse) between the two ladder points around it (error ~ 1/time for an unbiased
    estimator). None if no point reaches it; the first point's time if it already does."""
    pts = sorted(points)
    for i, (sec, rel) in enumerate(pts):
        if rel <= target:
            if i == 0:
                return sec
            s0, r0 = pts[i - 1]
            if r0 <= rel or s0 <= 0:
                return sec
            f = (math.log(r0) - math.log(target)) / (math.log(r0) - math.log(rel))
            return math.exp(math.log(s0) + f * (math.log(sec) - math.log(s0)))
    return None


def summary(csv_path, target, out=sys.stdout):
    """Per (scene, mode): the ladder's points and the time to reach relMSE `target`; then the
    ratio of every rayproc mode's time to Cycles' time on the same scene."""
    # One series per scene, mode and settings other than the ladder's own (spp) and the
    # per-render measurements Cycles' rows carry (sync, wall).
    rows = {}
    with open(csv_path, newline="", encoding="utf-8") as f:
        for row in csv.DictReader(f):
            series = re.sub(r"\s*\b(spp|sync|wall)=\S+", "", row["settings"]).strip()
            rows.setdefault((row["scene"], row["mode"], series), []).append(
                (float(row["seconds"]), float(row["relmse"])))
    times = {}
    for key, pts in sorted(rows.items()):
        t = time_at(pts, target)
        times[key] = t
        best = min(r for _, r in pts)
        print(f"{key[0]} {key[1]} [{key[2]}]: {len(pts)} points, best relMSE {best:.4g}; time "
              f"to relMSE {target:g}: " + (f"{t:.3f} s" if t is not None else "not reached")
              + (" (the first point: an upper bound)" if t is not None and t == min(
                  p[0] for p in pts) else ""), file=out)
    for (scene, mode, series), t in sorted(times.items()):
        cycles = [v for (sc, m, _), v in times.items() if sc == scene and m == "cycles" and v]
        if mode != "cycles" and t and cycles:
            tc = cycles[0]
            print(f"{scene}: time_cycles / time_{mode} [{series}] at relMSE {target:g} = "
                  f"{tc / t:.3g}", file=out)
    return times
