#!/usr/bin/env python3
"""scripts/scaling at a tiny size: 1 and 2 threads (--threads-max 2, and --threads 2, which
adds the base of 1), one repetition each, of a path render of the
Cornell box at 32x32 and a gi render at 24x24 (photon passes, cache prepass). Its table and JSON
are well formed: every phase rayproc reports appears once with a time per thread count, the
render's own phases are there, the speed-ups are the 1-thread time over each, and the serial
and busy fractions are fractions. Run by ctest (scaling_script) with the rayproc to use:
    tests/scripts/test_scaling.py build/rayproc
"""
import json
import math
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TOOL = os.path.join(ROOT, "scripts", "scaling")


def check(cond, what):
    if not cond:
        sys.exit("scaling_script: " + what)


def run_case(rayproc, mode, size, expected, extra=(), counts=("--threads-max", "2")):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "scaling.json")
        p = subprocess.run([sys.executable, TOOL, os.path.join(ROOT, "scenes", "cornell-box.json"),
                            "--rayproc", rayproc, "--mode", mode, "--spp", "1", "--width",
                            str(size), "--height", str(size), *counts,
                            "--repetitions", "1", "--json", out] + (["--", *extra] if extra else []),
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        check(p.returncode == 0, "%s: exit %d: %s" % (mode, p.returncode, p.stderr))
        with open(out) as f:
            doc = json.load(f)
    check(doc["threads"] == [1, 2], "%s: thread counts %s" % (mode, doc["threads"]))
    names = [ph["name"] for ph in doc["phases"]]
    check(len(names) == len(set(names)), "%s: a phase twice: %s" % (mode, names))
    for name in expected:
        check(name in names, "%s: no phase %s in %s" % (mode, name, names))
    for ph in doc["phases"]:
        check(ph["kind"] in ("serial", "parallel", "workers"), "%s: kind %s" % (mode, ph["kind"]))
        check(len(ph["seconds"]) == 2 and all(s >= 0 and math.isfinite(s) for s in ph["seconds"]),
              "%s: %s seconds %s" % (mode, ph["name"], ph["seconds"]))
        for s, sp in zip(ph["seconds"], ph["speedup"]):
            if sp is not None:
                check(abs(sp * s - ph["seconds"][0]) <= 1e-9 + 1e-6 * ph["seconds"][0],
                      "%s: %s speed-up %s is not t1 / t" % (mode, ph["name"], sp))
    for key in ("process_seconds", "whole_process_seconds", "whole_process_cpu_seconds"):
        check(len(doc[key]) == 2 and all(v > 0 for v in doc[key]), "%s: %s" % (mode, key))
    for key in ("serial_fraction", "workers_busy_fraction"):
        check(all(0 <= v <= 1 for v in doc[key]), "%s: %s %s" % (mode, key, doc[key]))
    # The table: a header, a row per phase with a time for each thread count, the totals.
    lines = p.stdout.splitlines()
    check(lines[0].startswith("rayproc scaling:") and lines[1].startswith("phase"),
          "%s: table header: %s" % (mode, lines[:2]))
    rows = {line.split()[0]: line for line in lines[2:] if line.strip()}
    for name in names:
        check(name in rows and rows[name].count("|") == 2, "%s: table row %s" % (mode, name))
    for label in ("process", "whole", "serial", "workers"):  # totals rows
        check(label in rows, "%s: table has no %s row" % (mode, label))


def main():
    rayproc = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "rayproc")
    common = ["scene_load", "bvh_build", "light_set", "render_passes", "film_commit",
              "between_passes", "film_resolve",
              "image_write", "other"]
    run_case(rayproc, "path", 32, common)
    # --threads: the counts given, 1 (the base) added.
    run_case(rayproc, "path", 32, common, counts=("--threads", "2"))
    run_case(rayproc, "gi", 24, common + ["photon_tracing", "photon_map_build", "cache_prepass"],
             ["--photons", "20000", "--caustic-photons", "5000"])
    print("scaling_script: ok")


if __name__ == "__main__":
    main()
