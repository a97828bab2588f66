#!/usr/bin/env python3
"""Edge error of anti-aliased renders against a reference render, in 8-bit codes.

    docs/tools/edge_error.py TRUTH.png OFF.png [CANDIDATE.png ...]

The edge pixels are those where OFF differs from TRUTH by more than 8 codes in some channel
(silhouettes and creases). For OFF and each candidate it prints the mean absolute difference
per channel against TRUTH over those pixels and over the whole image. Used for
docs/antialiasing.md. Standard library only (the PNG reader of zoom_png.py).
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from zoom_png import read_png  # noqa: E402


def flat(rows):
    return [v for row in rows for pixel in row for v in pixel]


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    truth = read_png(sys.argv[1])
    size = (len(truth[0]), len(truth))
    images = []
    for path in sys.argv[2:]:
        rows = read_png(path)
        if (len(rows[0]), len(rows)) != size:
            sys.exit(f"{path}: not {size[0]}x{size[1]} like {sys.argv[1]}")
        images.append((path, rows))
    t = flat(truth)
    off = flat(images[0][1])
    pixels = len(t) // 3
    edge = [
        p for p in range(pixels)
        if max(abs(off[3 * p + c] - t[3 * p + c]) for c in range(3)) > 8
    ]
    print(f"{len(edge)} edge pixels of {pixels}")
    for path, rows in images:
        img = flat(rows)
        on_edges = sum(abs(img[3 * p + c] - t[3 * p + c]) for p in edge for c in range(3))
        whole = sum(abs(a - b) for a, b in zip(img, t))
        print(
            f"{os.path.basename(path)}: edges {on_edges / max(1, 3 * len(edge)):.1f} codes, "
            f"whole image {whole / len(t):.3f}"
        )


if __name__ == "__main__":
    main()
