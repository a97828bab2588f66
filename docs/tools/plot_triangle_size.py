#!/usr/bin/env python3
"""Draws the triangle-size study (the output of docs/tools/triangle_size.sh) as an SVG plot:
nanoseconds per shaded pixel against pixels per triangle, both on log scales, one panel per
SIMD level and one line per mode.

    python3 docs/tools/plot_triangle_size.py study.txt > docs/triangle-size.svg

Only the Python standard library is used.
"""

import math
import sys

MODES = ["flat", "gouraud", "fast-phong:fit", "fast-phong:taylor", "phong", "reference"]
COLOURS = ["#1f77b4", "#2ca02c", "#ff7f0e", "#d62728", "#9467bd", "#7f7f7f"]
DASHES = ["", "6,3", "", "2,2", "", "8,3,2,3"]
PANEL_W, PANEL_H = 420, 300
LEFT, TOP, GAP, BOTTOM = 70, 40, 80, 60


def read(path):
    """{(simd, mode): [(px_per_triangle, ns_per_pixel)]}, sorted by pixels per triangle."""
    rows = {}
    with open(path, encoding="utf-8") as f:
        for line in f:
            cols = line.split()
            if len(cols) < 9:
                continue
            simd, mode = cols[1], cols[2]
            px, ns = float(cols[5]), float(cols[7])
            if px > 0 and ns > 0 and math.isfinite(px) and math.isfinite(ns):
                rows.setdefault((simd, mode), []).append((px, ns))
    for v in rows.values():
        v.sort()
    return rows


def decades(lo, hi):
    """Powers of ten covering [lo, hi]."""
    return range(math.floor(math.log10(lo)), math.ceil(math.log10(hi)) + 1)


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: plot_triangle_size.py STUDY.txt > plot.svg")
    rows = read(sys.argv[1])
    if not rows:
        sys.exit(f"{sys.argv[1]}: no study lines")
    xs = [p[0] for v in rows.values() for p in v]
    ys = [p[1] for v in rows.values() for p in v]
    xd, yd = list(decades(min(xs), max(xs))), list(decades(min(ys), max(ys)))
    x0, x1, y0, y1 = xd[0], xd[-1], yd[0], yd[-1]
    panels = ["baseline", "auto"]
    width = LEFT + len(panels) * (PANEL_W + GAP)
    height = TOP + PANEL_H + BOTTOM + 20 * ((len(MODES) + 2) // 3)
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
        f'font-family="sans-serif" font-size="12">',
        f'<rect width="{width}" height="{height}" fill="white"/>',
    ]
    for k, simd in enumerate(panels):
        ox = LEFT + k * (PANEL_W + GAP)

        def sx(x):
            return ox + (math.log10(x) - x0) / (x1 - x0) * PANEL_W

        def sy(y):
            return TOP + PANEL_H - (math.log10(y) - y0) / (y1 - y0) * PANEL_H

        title = "baseline SIMD (4 lanes)" if simd == "baseline" else "best SIMD (AVX2, 8 lanes)"
        out.append(
            f'<text x="{ox + PANEL_W / 2}" y="{TOP - 14}" text-anchor="middle" '
            f'font-weight="bold">{title}</text>'
        )
        out.append(
            f'<rect x="{ox}" y="{TOP}" width="{PANEL_W}" height="{PANEL_H}" '
            'fill="none" stroke="black"/>'
        )
        for d in xd:
            x = sx(10.0**d)
            out.append(f'<line x1="{x}" y1="{TOP}" x2="{x}" y2="{TOP + PANEL_H}" stroke="#ddd"/>')
            out.append(
                f'<text x="{x}" y="{TOP + PANEL_H + 16}" text-anchor="middle">{10 ** d:g}</text>'
            )
        for d in yd:
            y = sy(10.0**d)
            out.append(f'<line x1="{ox}" y1="{y}" x2="{ox + PANEL_W}" y2="{y}" stroke="#ddd"/>')
            out.append(f'<text x="{ox - 6}" y="{y + 4}" text-anchor="end">{10 ** d:g}</text>')
        out.append(
            f'<text x="{ox + PANEL_W / 2}" y="{TOP + PANEL_H + 36}" text-anchor="middle">'
            "pixels per triangle drawn</text>"
        )
        out.append(
            f'<text transform="translate({ox - 48},{TOP + PANEL_H / 2}) rotate(-90)" '
            'text-anchor="middle">ns per shaded pixel (one thread)</text>'
        )
        for mode, colour, dash in zip(MODES, COLOURS, DASHES):
            pts = rows.get((simd, mode), [])
            if not pts:
                continue
            path = " ".join(f"{sx(x):.1f},{sy(y):.1f}" for x, y in pts)
            style = f' stroke-dasharray="{dash}"' if dash else ""
            out.append(
                f'<polyline points="{path}" fill="none" stroke="{colour}" stroke-width="2"{style}/>'
            )
            for x, y in pts:
                out.append(f'<circle cx="{sx(x):.1f}" cy="{sy(y):.1f}" r="3" fill="{colour}"/>')
    ly = TOP + PANEL_H + BOTTOM
    for i, (mode, colour, dash) in enumerate(zip(MODES, COLOURS, DASHES)):
        lx = LEFT + (i % 3) * 220
        y = ly + (i // 3) * 20
        style = f' stroke-dasharray="{dash}"' if dash else ""
        out.append(
            f'<line x1="{lx}" y1="{y}" x2="{lx + 30}" y2="{y}" stroke="{colour}" '
            f'stroke-width="2"{style}/>'
        )
        out.append(f'<text x="{lx + 36}" y="{y + 4}">{mode}</text>')
    out.append("</svg>")
    print("\n".join(out))


if __name__ == "__main__":
    main()
