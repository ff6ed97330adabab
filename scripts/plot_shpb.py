#!/usr/bin/env python3
"""Plots of the full-size SHPB runs for docs/validation.md, as plain SVG (no dependencies).

usage: scripts/plot_shpb.py OUT_ROOT   (OUT_ROOT/<run>/series.csv and psd.csv, as written by
`fractum run scenes/<scene>.toml --out OUT_ROOT/<run>`)
writes docs/img/shpb_stress_strain.svg and docs/img/shpb_psd.svg
"""
import csv
import math
import os
import sys

COLORS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"]


def svg_plot(path, curves, xlabel, ylabel, logx=False, title=""):
    w, h, l, r, t, b = 640, 420, 70, 170, 30, 50
    xs = [x for _, c in curves for x, _ in c]
    ys = [y for _, c in curves for _, y in c]
    fx = (lambda v: math.log10(v)) if logx else (lambda v: v)
    x0, x1 = fx(min(xs)), fx(max(xs))
    y0, y1 = 0.0, max(ys) * 1.05
    px = lambda v: l + (fx(v) - x0) / (x1 - x0) * (w - l - r)
    py = lambda v: h - b - (v - y0) / (y1 - y0) * (h - t - b)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">',
           f'<rect width="{w}" height="{h}" fill="white"/>',
           f'<text x="{w/2}" y="18" text-anchor="middle">{title}</text>',
           f'<line x1="{l}" y1="{h-b}" x2="{w-r}" y2="{h-b}" stroke="black"/>',
           f'<line x1="{l}" y1="{t}" x2="{l}" y2="{h-b}" stroke="black"/>',
           f'<text x="{(l+w-r)/2}" y="{h-12}" text-anchor="middle">{xlabel}</text>',
           f'<text x="16" y="{(t+h-b)/2}" transform="rotate(-90 16 {(t+h-b)/2})" text-anchor="middle">{ylabel}</text>']
    for k in range(6):
        yv = y0 + (y1 - y0) * k / 5
        out.append(f'<text x="{l-6}" y="{py(yv)+4}" text-anchor="end">{yv:.3g}</text>')
        xv = x0 + (x1 - x0) * k / 5
        lab = 10 ** xv if logx else xv
        out.append(f'<text x="{l + (xv-x0)/(x1-x0)*(w-l-r)}" y="{h-b+16}" text-anchor="middle">{lab:.3g}</text>')
    for n, (name, c) in enumerate(curves):
        col = COLORS[n % len(COLORS)]
        pts = " ".join(f"{px(x):.1f},{py(y):.1f}" for x, y in c)
        out.append(f'<polyline fill="none" stroke="{col}" stroke-width="1.5" points="{pts}"/>')
        out.append(f'<text x="{w-r+10}" y="{t+16*n+10}" fill="{col}">{name}</text>')
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out))


def main():
    root = sys.argv[1]
    img = os.path.join(os.path.dirname(__file__), "..", "docs", "img")
    runs = [("random, breaking", "sand"), ("random, unbreakable", "sand_off"),
            ("random same size", "mono"), ("hcp", "hcp"), ("simple cubic", "cubic"),
            ("random, 5000/s", "fast")]
    curves = []
    for label, d in runs:
        p = os.path.join(root, d, "series.csv")
        if not os.path.exists(p):
            continue
        rows = list(csv.DictReader(open(p)))
        curves.append((label, [(float(r["axial_strain"]),
                                0.5e-6 * (float(r["stress_driven"]) + float(r["stress_opposite"])))
                               for r in rows]))
    svg_plot(os.path.join(img, "shpb_stress_strain.svg"), curves, "axial strain",
             "axial stress (MPa)", title="SHPB compaction, full size")
    p = os.path.join(root, "sand", "psd.csv")
    rows = list(csv.reader(open(p)))
    head, data = rows[0], rows[1:]
    curves = [(h.replace("passing_at_strain_", "strain "),
               [(float(r[0]) * 1e3, float(r[k])) for r in data])
              for k, h in enumerate(head) if k > 0]
    svg_plot(os.path.join(img, "shpb_psd.svg"), curves, "equivalent diameter (mm)",
             "mass fraction finer", logx=True, title="shpb_sand: size distribution")


if __name__ == "__main__":
    main()
