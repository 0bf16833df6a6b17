#!/usr/bin/env python3
"""One scan of the cohort: runs gdm, then renders the mesh; always writes
status.json and exits 0 (a failed scan is a row of the table, not a failed
job: the other scans and the aggregate go on).

    run_scan.py --params results/params/NAME.json --gdm /path/to/gdm \
        --threads N --out results/scans/NAME [--render auto|xvfb|display|off]

Writes into --out: mesh.<format>, report.json (both only when gdm succeeded:
gdm writes them atomically), picture.png, gdm.log (gdm's stderr) and
status.json: the scan, its input and arguments, gdm's exit code and message,
the wall time, and the picture's status.
"""

import argparse
import datetime
import json
import os
import signal
import socket
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def gdm_message(stderr, code):
    """gdm's own words: its `gdm: error:` lines, else the last lines it printed."""
    lines = [l.strip() for l in stderr.splitlines() if l.strip()]
    errors = [l[len("gdm: error:"):].strip() if l.startswith("gdm: error:") else l
              for l in lines if l.startswith("gdm: error:") or l.startswith("gdm:")]
    if errors:
        return " | ".join(errors)
    if code < 0:
        try:
            return "gdm was killed by signal %s" % signal.Signals(-code).name
        except ValueError:
            return "gdm was killed by signal %d" % -code
    return " | ".join(lines[-3:])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--params", required=True)
    ap.add_argument("--gdm", required=True)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--out", required=True)
    ap.add_argument("--render", default="auto", choices=("auto", "xvfb", "display", "off"))
    ap.add_argument("--time-limit", type=float, default=0, help="seconds before gdm is stopped (0 = none)")
    a = ap.parse_args()

    with open(a.params) as f:
        params = json.load(f)
    os.makedirs(a.out, exist_ok=True)
    for stale in os.listdir(a.out):  # Snakemake clears directory outputs; a manual run may not
        if stale.startswith(("mesh.", "report.json", "picture.png", "status.json", "gdm.log")):
            os.remove(os.path.join(a.out, stale))
    mesh = os.path.join(a.out, "mesh." + params["mesh_format"])
    report = os.path.join(a.out, "report.json")
    command = [a.gdm, params["input"], *params["arguments"], "--threads", str(a.threads),
               "-o", mesh, "--report", report, "--quiet"]
    status = {
        "scan": params["scan"], "group": params.get("group"), "input": params["input"],
        "arguments": params["arguments"], "command": command, "gdm_version": params.get("gdm_version"),
        "host": socket.gethostname(), "threads": a.threads,
        "started": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
    }
    job_start = start = time.monotonic()
    try:
        run = subprocess.run(command, capture_output=True, text=True, errors="replace",
                             timeout=a.time_limit or None)
        code, stderr = run.returncode, run.stderr
    except FileNotFoundError as e:
        code, stderr = 127, "gdm: error: cannot run gdm: %s" % e
    except PermissionError as e:
        code, stderr = 126, "gdm: error: cannot run gdm: %s" % e
    except subprocess.TimeoutExpired as e:
        code = 124
        stderr = (e.stderr.decode(errors="replace") if isinstance(e.stderr, bytes) else (e.stderr or ""))
        stderr += "\ngdm: error: stopped by the workflow after %g s" % a.time_limit
    status["wall_seconds"] = round(time.monotonic() - start, 3)
    with open(os.path.join(a.out, "gdm.log"), "w") as f:
        f.write(stderr)
    status["exit_code"] = code
    ok = code == 0 and os.path.exists(mesh)
    status["status"] = "ok" if ok else "failed"
    status["message"] = "" if code == 0 else gdm_message(stderr, code)
    if code == 0 and not ok:
        status["message"] = "gdm exited 0 but wrote no mesh"
    status["mesh"] = os.path.basename(mesh) if ok else None
    status["report"] = "report.json" if os.path.exists(report) else None

    status["picture"] = None
    status["picture_colour"] = params.get("picture_colour", "generation")
    status["picture_message"] = "no mesh" if not ok else ""
    if ok and a.render != "off":
        title = params["scan"]
        try:
            with open(report) as f:
                m = json.load(f)["mesh"]
            title += "  |  %d faces, %.0f mm^3" % (m["faces"], m["volume_mm3"])
        except (OSError, ValueError, KeyError):
            pass
        picture = os.path.join(a.out, "picture.png")
        render = [sys.executable, os.path.join(HERE, "render_mesh.py"), mesh, picture,
                  "--title", title, "--display", a.render, "--colour", params.get("picture_colour", "generation")]
        render_start = time.monotonic()
        r = subprocess.run(render, capture_output=True, text=True, errors="replace", timeout=600)
        status["render_seconds"] = round(time.monotonic() - render_start, 3)
        if r.returncode == 0 and os.path.exists(picture):
            status["picture"] = "picture.png"
        else:
            status["picture_message"] = "rendering failed (%d): %s" % (
                r.returncode, " | ".join(r.stderr.strip().splitlines()[-2:]))
    elif ok:
        status["picture_message"] = "rendering off"

    status["job_seconds"] = round(time.monotonic() - job_start, 3)
    tmp = os.path.join(a.out, "status.json.tmp")
    with open(tmp, "w") as f:
        json.dump(status, f, indent=1)
        f.write("\n")
    os.replace(tmp, os.path.join(a.out, "status.json"))
    print("%s: %s (exit %d) in %.2f s%s" % (params["scan"], status["status"], code, status["wall_seconds"],
                                          (": " + status["message"]) if status["message"] else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
