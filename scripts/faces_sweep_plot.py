#!/usr/bin/env python3
"""Distance-vs-faces plots from the face-budget sweep's CSV (issue 16).

    build/test/benchmark/study/gdm_benchmark_study --faces-sweep --out DIR [--fractions ...] [--sweep-cgal]
    python3 scripts/faces_sweep_plot.py DIR/faces-sweep.csv OUTDIR

writes OUTDIR/faces-<case>.svg per phantom: the mean distance to the exact
surface (voxels) against the face count, log-log, one curve per method (gdm
with a face budget, the Slicer chain at gdm's counts, CGAL Mesh_3 matched to
them when the sweep ran it). Plain SVG written here (no plotting library).
"""
import csv
import math
import os
import re
import sys

COLOURS = {"gdm": "#1f77b4", "slicer": "#ff7f0e", "cgal": "#2ca02c"}
LABELS = {"gdm": "gdm, face budget", "slicer": "Slicer chain, same faces", "cgal": "CGAL Mesh_3, matched faces"}
W, H = 640, 420
LEFT, RIGHT, TOP, BOTTOM = 70, 20, 40, 55


def decades(lo, hi):
    """Tick values: 1, 2, 5 times the powers of ten within [lo, hi]."""
    ticks = []
    for e in range(math.floor(math.log10(lo)) - 1, math.ceil(math.log10(hi)) + 1):
        for m in (1, 2, 5):
            v = m * 10.0 ** e
            if lo <= v <= hi:
                ticks.append(v)
    return ticks


def plot(case, rows, path):
    xs = [r[1] for r in rows]
    ys = [r[2] for r in rows if r[2] > 0]
    x0, x1 = min(xs) / 1.2, max(xs) * 1.2
    y0, y1 = min(ys) / 1.3, max(ys) * 1.3
    lx0, lx1, ly0, ly1 = map(math.log10, (x0, x1, y0, y1))

    def px(x):
        return LEFT + (math.log10(x) - lx0) / (lx1 - lx0) * (W - LEFT - RIGHT)

    def py(y):
        return H - BOTTOM - (math.log10(y) - ly0) / (ly1 - ly0) * (H - TOP - BOTTOM)

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
           f'<rect width="{W}" height="{H}" fill="white"/>',
           f'<text x="{W / 2}" y="22" text-anchor="middle" font-size="14">Mean distance vs faces: {case}</text>',
           f'<rect x="{LEFT}" y="{TOP}" width="{W - LEFT - RIGHT}" height="{H - TOP - BOTTOM}" fill="none" stroke="black"/>']
    for t in decades(x0, x1):
        out.append(f'<line x1="{px(t):.1f}" y1="{TOP}" x2="{px(t):.1f}" y2="{H - BOTTOM}" stroke="#ddd"/>')
        out.append(f'<text x="{px(t):.1f}" y="{H - BOTTOM + 16}" text-anchor="middle">{t:g}</text>')
    for t in decades(y0, y1):
        out.append(f'<line x1="{LEFT}" y1="{py(t):.1f}" x2="{W - RIGHT}" y2="{py(t):.1f}" stroke="#ddd"/>')
        out.append(f'<text x="{LEFT - 6}" y="{py(t) + 4:.1f}" text-anchor="end">{t:g}</text>')
    out.append(f'<text x="{(LEFT + W - RIGHT) / 2}" y="{H - 12}" text-anchor="middle">faces</text>')
    out.append(f'<text transform="translate(16 {(TOP + H - BOTTOM) / 2}) rotate(-90)" text-anchor="middle">'
               'mean distance to the exact surface (voxels)</text>')
    legend_y = TOP + 16
    for method in ("gdm", "slicer", "cgal"):
        pts = sorted((r[1], r[2]) for r in rows if r[0] == method and r[2] > 0)
        if not pts:
            continue
        colour = COLOURS[method]
        line = " ".join(f"{px(x):.1f},{py(y):.1f}" for x, y in pts)
        out.append(f'<polyline points="{line}" fill="none" stroke="{colour}" stroke-width="2"/>')
        for x, y in pts:
            out.append(f'<circle cx="{px(x):.1f}" cy="{py(y):.1f}" r="3" fill="{colour}"/>')
        out.append(f'<line x1="{W - RIGHT - 200}" y1="{legend_y}" x2="{W - RIGHT - 180}" y2="{legend_y}" '
                   f'stroke="{colour}" stroke-width="2"/>')
        out.append(f'<text x="{W - RIGHT - 175}" y="{legend_y + 4}">{LABELS[method]}</text>')
        legend_y += 16
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    by_case = {}
    with open(sys.argv[1], newline="") as f:
        for r in csv.DictReader(f):
            by_case.setdefault(r["case"], []).append((r["method"], int(r["faces"]), float(r["mean_vox"])))
    os.makedirs(sys.argv[2], exist_ok=True)
    for case, rows in by_case.items():
        if len({r[1] for r in rows if r[0] == "gdm"}) < 2:
            continue  # one budget: no curve
        slug = re.sub(r"[^a-z0-9]+", "-", case.lower()).strip("-")
        path = os.path.join(sys.argv[2], f"faces-{slug}.svg")
        plot(case, rows, path)
        print(path)


if __name__ == "__main__":
    main()
