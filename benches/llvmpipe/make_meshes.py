#!/usr/bin/env python3
"""Write the large benchmark meshes as OBJ files, so that Phosphor and llvmpipe read the same file.

The meshes are UV spheres: a single vertex at each pole, `rings - 1` circles of `segments`
vertices between them, fans of triangles at the poles and two triangles per quad elsewhere, so
a sphere has 2 * segments * (rings - 1) triangles. Every triangle winds counter-clockwise seen
from outside (outward right-hand normal), the orientation OpenGL and Phosphor treat as front.
The files hold only `v` and `f` lines (no `vn`, no `s`): both renderers then compute S1's
normals, averaged over the faces sharing each position.

Standard library only; the output is byte-identical from run to run, and a file that is
already there with the expected header is left alone.

    python3 benches/llvmpipe/make_meshes.py                 # the two default spheres
    python3 benches/llvmpipe/make_meshes.py --out-dir DIR --sphere 64x32
"""

import argparse
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
DEFAULT_DIR = os.path.join(REPO, "target", "llvmpipe", "meshes")

# About 65 k triangles (the size of the bunny) and about 820 k (sub-pixel triangles at 720p).
DEFAULT_SPHERES = ["256x128", "640x640"]


def sphere_triangle_count(segments, rings):
    return 2 * segments * (rings - 1)


def header(segments, rings):
    return (
        f"# UV sphere, radius 1, {segments} segments x {rings} rings, "
        f"{sphere_triangle_count(segments, rings)} triangles (benches/llvmpipe/make_meshes.py)\n"
    )


def sphere_lines(segments, rings):
    """Yields the OBJ text of the sphere, line by line (1-based indices)."""
    yield header(segments, rings)
    # Vertex 1 is the north pole (+Y), then circle k = 1..rings-1 from north to south,
    # then the south pole. Longitude grows from +Z towards +X, so (north, k, k+1 in longitude)
    # is counter-clockwise from outside.
    yield "v 0 1 0\n"
    for k in range(1, rings):
        polar = math.pi * k / rings
        y, r = math.cos(polar), math.sin(polar)
        for j in range(segments):
            azimuth = 2.0 * math.pi * j / segments
            x, z = r * math.sin(azimuth), r * math.cos(azimuth)
            yield f"v {x:.9g} {y:.9g} {z:.9g}\n"
    yield "v 0 -1 0\n"

    north = 1
    south = 2 + (rings - 1) * segments

    def on_circle(k, j):
        return 2 + (k - 1) * segments + (j % segments)

    for j in range(segments):
        yield f"f {north} {on_circle(1, j)} {on_circle(1, j + 1)}\n"
    for k in range(1, rings - 1):
        for j in range(segments):
            a, b = on_circle(k, j), on_circle(k, j + 1)
            c, d = on_circle(k + 1, j), on_circle(k + 1, j + 1)
            yield f"f {a} {c} {d}\n"
            yield f"f {a} {d} {b}\n"
    for j in range(segments):
        yield f"f {south} {on_circle(rings - 1, j + 1)} {on_circle(rings - 1, j)}\n"


def parse_sphere(text):
    try:
        segments, rings = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected SEGMENTSxRINGS, e.g. 256x128, got `{text}`")
    if segments < 3 or rings < 2:
        raise argparse.ArgumentTypeError(f"need at least 3 segments and 2 rings, got `{text}`")
    return segments, rings


def write_sphere(out_dir, segments, rings):
    path = os.path.join(out_dir, f"sphere_{segments}x{rings}.obj")
    try:
        with open(path, encoding="ascii") as fh:
            if fh.readline() == header(segments, rings):
                return path, False
    except (OSError, UnicodeDecodeError):
        pass
    # Written beside the target and renamed, so an interrupted run leaves no half file.
    partial = path + ".partial"
    with open(partial, "w", encoding="ascii") as fh:
        fh.writelines(sphere_lines(segments, rings))
    os.replace(partial, path)
    return path, True


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out-dir", default=DEFAULT_DIR,
                    help="where the OBJ files go (default: target/llvmpipe/meshes in the repository)")
    ap.add_argument("--sphere", action="append", type=parse_sphere, metavar="SEGMENTSxRINGS",
                    help=f"a UV sphere to write; repeatable (default: {' '.join(DEFAULT_SPHERES)})")
    args = ap.parse_args()
    spheres = args.sphere or [parse_sphere(s) for s in DEFAULT_SPHERES]
    try:
        os.makedirs(args.out_dir, exist_ok=True)
        for segments, rings in spheres:
            path, written = write_sphere(args.out_dir, segments, rings)
            state = "written" if written else "up to date"
            print(f"{path} triangles={sphere_triangle_count(segments, rings)} {state}")
    except OSError as err:
        print(f"error: {err.filename or args.out_dir}: {err.strerror}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
