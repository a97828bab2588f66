#!/usr/bin/env python3
"""How far apart two 8-bit PNG pictures of the same size are, in 8-bit codes.

    benches/llvmpipe/diff_png.py A.png B.png [--tolerance 2]

Prints the mean absolute difference per channel (R, G, B) over all pixels, the largest
difference, and the share of pixels whose three channels are all within the tolerance. Meant
for a frame of llvmpipe (s1_llvmpipe.py --png-dir) against `phosphor render --encoding linear`:
the two should agree up to rounding and rasterization rules at the silhouette.

Needs numpy (run it with the venv's python: target/llvmpipe/venv/bin/python). Reads 8-bit
grey, grey+alpha, RGB and RGBA PNGs, not interlaced; alpha is ignored.
"""

import argparse
import struct
import sys
import zlib

import numpy as np

CHANNELS = {0: 1, 2: 3, 4: 2, 6: 4}  # PNG colour type -> samples per pixel


class PngError(Exception):
    pass


def read_png_rgb(path):
    """(height, width, 3) uint8 array of an 8-bit, non-interlaced PNG."""
    with open(path, "rb") as fh:
        data = fh.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise PngError(f"{path}: not a PNG file")
    pos, idat, header = 8, [], None
    while pos + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
    if header is None:
        raise PngError(f"{path}: no IHDR chunk")
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in CHANNELS or interlace != 0:
        raise PngError(f"{path}: only 8-bit, non-interlaced grey/RGB(A) PNGs are read "
                       f"(bit depth {depth}, colour type {colour}, interlace {interlace})")
    bpp = CHANNELS[colour]
    stride = width * bpp
    try:
        raw = zlib.decompress(b"".join(idat))
    except zlib.error as err:
        raise PngError(f"{path}: corrupt image data ({err})") from None
    if len(raw) != height * (stride + 1):
        raise PngError(f"{path}: image data has {len(raw)} bytes, expected {height * (stride + 1)}")

    pixels = np.zeros((height, stride), dtype=np.uint8)
    previous = np.zeros(stride, dtype=np.int32)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        row = np.frombuffer(raw, dtype=np.uint8, count=stride, offset=y * (stride + 1) + 1)
        row = row.astype(np.int32)
        if kind == 0:
            out = row
        elif kind == 1:  # Sub: a running sum along the row, per channel
            out = np.cumsum(row.reshape(width, bpp), axis=0).reshape(-1) % 256
        elif kind == 2:  # Up
            out = (row + previous) % 256
        elif kind in (3, 4):  # Average, Paeth: each byte needs the one just decoded
            out = unfilter_sequential(kind, row.tolist(), previous.tolist(), bpp)
            out = np.asarray(out, dtype=np.int32)
        else:
            raise PngError(f"{path}: row {y} has unknown filter {kind}")
        pixels[y] = out
        previous = out
    pixels = pixels.reshape(height, width, bpp)
    if bpp < 3:
        return np.repeat(pixels[:, :, :1], 3, axis=2)
    return pixels[:, :, :3]


def unfilter_sequential(kind, row, above, bpp):
    out = [0] * len(row)
    for i, value in enumerate(row):
        left = out[i - bpp] if i >= bpp else 0
        up = above[i]
        if kind == 3:
            predictor = (left + up) // 2
        else:
            upper_left = above[i - bpp] if i >= bpp else 0
            estimate = left + up - upper_left
            d_left, d_up, d_ul = abs(estimate - left), abs(estimate - up), abs(estimate - upper_left)
            if d_left <= d_up and d_left <= d_ul:
                predictor = left
            elif d_up <= d_ul:
                predictor = up
            else:
                predictor = upper_left
        out[i] = (value + predictor) & 0xFF
    return out


def main(argv):
    ap = argparse.ArgumentParser(description="Difference of two 8-bit PNGs in 8-bit codes.")
    ap.add_argument("first")
    ap.add_argument("second")
    ap.add_argument("--tolerance", type=int, default=2, metavar="CODES",
                    help="a pixel agrees when all its channels differ by at most this (default 2)")
    args = ap.parse_args(argv)
    try:
        a, b = read_png_rgb(args.first), read_png_rgb(args.second)
    except OSError as err:
        print(f"error: {err.filename}: {err.strerror}", file=sys.stderr)
        return 1
    except PngError as err:
        print(f"error: {err}", file=sys.stderr)
        return 1
    if a.shape != b.shape:
        print(f"error: {args.second}: {b.shape[1]}x{b.shape[0]}, but {args.first} is "
              f"{a.shape[1]}x{a.shape[0]}", file=sys.stderr)
        return 1
    diff = np.abs(a.astype(np.int16) - b.astype(np.int16))
    mean = diff.reshape(-1, 3).mean(axis=0)
    within = (diff.max(axis=2) <= args.tolerance).mean()
    lit = ((a.max(axis=2) > 0) | (b.max(axis=2) > 0))
    within_lit = (diff.max(axis=2)[lit] <= args.tolerance).mean() if lit.any() else 1.0
    print(f"size={a.shape[1]}x{a.shape[0]} mean_abs_r={mean[0]:.4f} mean_abs_g={mean[1]:.4f} "
          f"mean_abs_b={mean[2]:.4f} max_abs={int(diff.max())} "
          f"within_{args.tolerance}={100.0 * within:.3f}% "
          f"within_{args.tolerance}_non_black={100.0 * within_lit:.3f}% "
          f"non_black_pixels={int(lit.sum())}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
