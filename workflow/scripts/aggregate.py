#!/usr/bin/env python3
"""The cohort's table, plot and summary page from the scans' folders.

    aggregate.py --csv cohort.csv --html summary.html --plot volumes.svg SCAN_DIR...

Every SCAN_DIR holds the status.json of run_scan.py (and report.json, the
mesh and picture.png when gdm succeeded). One CSV row per scan, failed ones
included with gdm's exit code and message; a bar plot of the volumes
(matplotlib when present, else an SVG written here); an HTML page with the
table, the plot and every scan's picture.
"""

import argparse
import csv
import html
import json
import os
import sys

COLUMNS = [
    "scan", "group", "status", "exit_code", "message", "volume_mm3", "volume_ml", "area_mm2",
    "vertices", "faces", "cycles", "stop_reason", "valid", "closed", "manifold", "genus", "components",
    "self_intersections", "threshold", "seed_source", "gdm_seconds", "wall_seconds", "render_seconds",
    "job_seconds", "threads", "input",
    "arguments", "mesh", "report", "picture", "picture_message", "gdm_version", "host",
]


def row_of(folder):
    name = os.path.basename(os.path.normpath(folder))
    try:
        with open(os.path.join(folder, "status.json")) as f:
            s = json.load(f)
    except (OSError, ValueError) as e:
        return {"scan": name, "status": "failed", "exit_code": "", "message": "no status: %s" % e}
    row = {k: s.get(k) for k in ("scan", "group", "status", "exit_code", "message", "wall_seconds",
                                 "render_seconds", "job_seconds", "threads",
                                 "input", "picture_message", "picture_colour", "gdm_version",
                                 "host")}
    row["arguments"] = " ".join(s.get("arguments") or [])
    for key in ("mesh", "report", "picture"):
        row[key] = os.path.join(folder, s[key]) if s.get(key) else ""
    if s.get("report"):
        try:
            with open(os.path.join(folder, s["report"])) as f:
                r = json.load(f)
            m, model = r.get("mesh", {}), r.get("model", {})
            row.update({
                "volume_mm3": round(m.get("volume_mm3", 0.0), 3),
                "volume_ml": round(m.get("volume_ml", 0.0), 6),
                "area_mm2": round(m.get("area_mm2", 0.0), 3),
                "vertices": m.get("vertices"), "faces": m.get("faces"),
                "closed": m.get("closed"), "manifold": m.get("manifold"), "genus": m.get("genus"),
                "components": m.get("components"), "self_intersections": m.get("self_intersections"),
                "cycles": model.get("cycles"), "stop_reason": model.get("stop_reason"),
                "threshold": (r.get("threshold") or {}).get("value"),
                "seed_source": (r.get("seed") or {}).get("source"),
                "gdm_seconds": round(r.get("total_seconds", 0.0), 3),
            })
            row["valid"] = bool(m.get("closed") and m.get("manifold") and m.get("self_intersections") == 0
                                and m.get("components") == 1 and m.get("volume_mm3", 0) > 0)
        except (OSError, ValueError, AttributeError) as e:
            row["message"] = (row.get("message") or "") + " (report unreadable: %s)" % e
    return row


def write_csv(path, rows):
    tmp = path + ".tmp"
    with open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
        w.writeheader()
        for row in rows:
            w.writerow({k: ("" if row.get(k) is None else row.get(k)) for k in COLUMNS})
    os.replace(tmp, path)


def plot_svg_by_hand(path, names, volumes):
    """A horizontal bar chart, one bar per scan (failed scans: no bar, 'failed')."""
    bar_h, gap, left, width = 18, 6, 170, 420
    height = 40 + len(names) * (bar_h + gap) + 30
    top = max([v for v in volumes if v is not None] + [1.0])
    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" '
           'font-size="12">' % (left + width + 110, height),
           '<text x="10" y="20" font-size="14">Enclosed volume per scan (mm³)</text>']
    for i, (n, v) in enumerate(zip(names, volumes)):
        y = 36 + i * (bar_h + gap)
        out.append('<text x="%d" y="%d" text-anchor="end">%s</text>' % (left - 8, y + 13, html.escape(n)))
        if v is None:
            out.append('<text x="%d" y="%d" fill="#b00">failed</text>' % (left + 4, y + 13))
        else:
            w = max(1.0, width * v / top)
            out.append('<rect x="%d" y="%d" width="%.1f" height="%d" fill="#4a78b5"/>' % (left, y, w, bar_h))
            out.append('<text x="%.1f" y="%d">%.1f</text>' % (left + w + 4, y + 13, v))
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def plot_volumes(path, rows):
    names = [r["scan"] for r in rows]
    volumes = [r.get("volume_mm3") if r.get("status") == "ok" else None for r in rows]
    if os.environ.get("GDM_WORKFLOW_NO_MATPLOTLIB"):
        plot_svg_by_hand(path, names, volumes)
        return "svg"
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        plot_svg_by_hand(path, names, volumes)
        return "svg"
    fig, ax = plt.subplots(figsize=(7, 0.45 * len(names) + 1.4))
    ys = list(range(len(names)))
    ax.barh(ys, [v or 0 for v in volumes], color=["#4a78b5" if v is not None else "#ffffff" for v in volumes])
    top = max([v for v in volumes if v is not None] + [1.0])
    for y, v in zip(ys, volumes):
        ax.text((v or 0) + 0.01 * top, y, "%.1f" % v if v is not None else "failed", va="center",
                color="black" if v is not None else "#b00", fontsize=9)
    ax.set_yticks(ys)
    ax.set_yticklabels(names)
    ax.invert_yaxis()
    ax.set_xlabel("enclosed volume (mm³)")
    ax.set_xlim(0, top * 1.18)
    ax.set_title("gdm: volume per scan")
    fig.tight_layout()
    fig.savefig(path, format="svg", metadata={"Date": None})  # no date: same rows, same file
    plt.close(fig)
    return "matplotlib"


def fmt(v, digits=1):
    if v is None or v == "":
        return ""
    if isinstance(v, float):
        return "%.*f" % (digits, v)
    return str(v)


def write_html(path, rows, csv_path, plot_path):
    base = os.path.dirname(os.path.abspath(path))
    rel = lambda p: html.escape(os.path.relpath(os.path.abspath(p), base)) if p else ""  # noqa: E731
    ok = [r for r in rows if r.get("status") == "ok"]
    failed = [r for r in rows if r.get("status") != "ok"]
    e = html.escape
    out = ["<!DOCTYPE html>", '<html><head><meta charset="utf-8"><title>gdm cohort</title>',
           "<style>body{font-family:sans-serif;margin:1.5em}table{border-collapse:collapse}"
           "td,th{border:1px solid #ccc;padding:3px 7px;text-align:right}td.l,th{text-align:left}"
           "tr.failed{background:#fde8e8}.pics{display:flex;flex-wrap:wrap;gap:12px}"
           "figure{margin:0}figcaption{font-size:90%}</style></head><body>",
           "<h1>gdm cohort</h1>",
           "<p>%d scans: %d meshes, %d failed. Table: <a href=\"%s\">%s</a>.</p>" % (
               len(rows), len(ok), len(failed), rel(csv_path), e(os.path.basename(csv_path)))]
    if failed:
        out.append("<h2>Failed scans</h2><table><tr><th>scan</th><th>exit code</th><th>gdm's message</th>"
                   "<th>input</th></tr>")
        for r in failed:
            out.append('<tr class="failed"><td class="l">%s</td><td>%s</td><td class="l">%s</td>'
                       '<td class="l">%s</td></tr>' % (e(r["scan"]), e(fmt(r.get("exit_code"))),
                                                       e(r.get("message") or ""), e(r.get("input") or "")))
        out.append("</table>")
    out.append("<h2>Every scan</h2><table><tr><th>scan</th><th>group</th><th>status</th><th>volume mm³</th>"
               "<th>area mm²</th><th>faces</th><th>cycles</th><th>valid</th><th>gdm s</th><th>job s</th></tr>")
    for r in rows:
        out.append('<tr class="%s"><td class="l">%s</td><td class="l">%s</td><td class="l">%s</td>' % (
            "ok" if r.get("status") == "ok" else "failed", e(r["scan"]), e(fmt(r.get("group"))),
            e(r.get("status") or "")) + "".join(
            "<td>%s</td>" % e(fmt(r.get(k))) for k in ("volume_mm3", "area_mm2", "faces", "cycles", "valid")) +
            "<td>%s</td><td>%s</td></tr>" % (e(fmt(r.get("gdm_seconds"), 2)), e(fmt(r.get("job_seconds"), 2))))
    out.append("</table>")
    out.append('<h2>Volumes</h2><img src="%s" alt="volume per scan">' % rel(plot_path))
    meaning = {"generation": "vertex generation (the deformation cycle that created each vertex)",
               "curvature": "mean curvature", "height": "height (z)"}
    colours = sorted({r.get("picture_colour") or "generation" for r in ok})
    out.append("<h2>Pictures</h2><p>Coloured by %s.</p><div class=\"pics\">" % e(
        ", ".join(meaning.get(c, c) for c in colours) or "-"))
    for r in ok:
        if r.get("picture"):
            out.append('<figure><img src="%s" width="320" alt="%s"><figcaption>%s: %s faces, %s mm³</figcaption>'
                       "</figure>" % (rel(r["picture"]), e(r["scan"]), e(r["scan"]), e(fmt(r.get("faces"))),
                                      e(fmt(r.get("volume_mm3")))))
        else:
            out.append("<figure><figcaption>%s: no picture (%s)</figcaption></figure>" % (
                e(r["scan"]), e(r.get("picture_message") or "")))
    out.append("</div></body></html>")
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(out) + "\n")
    os.replace(tmp, path)


def main():
    ap = argparse.ArgumentParser(description="The cohort's table, plot and summary page.")
    ap.add_argument("--csv", required=True)
    ap.add_argument("--html", required=True)
    ap.add_argument("--plot", required=True)
    ap.add_argument("scans", nargs="+")
    a = ap.parse_args()
    rows = [row_of(d) for d in a.scans]
    write_csv(a.csv, rows)
    how = plot_volumes(a.plot, rows)
    write_html(a.html, rows, a.csv, a.plot)
    n_ok = sum(r.get("status") == "ok" for r in rows)
    print("aggregate: %d scans, %d meshes, %d failed; plot by %s" % (len(rows), n_ok, len(rows) - n_ok, how))
    return 0


if __name__ == "__main__":
    sys.exit(main())
