#!/usr/bin/env python3
"""Time Mesa's llvmpipe drawing the standard scene S1, headless through EGL.

llvmpipe is the CPU OpenGL driver a Linux machine without a GPU falls back to, so it is the
yardstick for a CPU rasterizer. This program draws a mesh in S1 exactly as `phosphor bench
--mesh FILE.obj` does (same normalization, normals, camera, lights and equations) and prints
one line per measurement that begins like `phosphor bench`'s:

    MODE median_ms=X min_ms=Y max_ms=Z frames=N renderer=llvmpipe mesh=NAME triangles=T size=WxH threads=N cull=off|on

Run it through `run.sh` beside it, which installs Mesa and the Python packages first.
"""

import argparse
import math
import os
import struct
import sys
import time
import zlib

MODES = ("fill", "flat", "gouraud", "phong")

# ------------------------------------------------------------------------------------------
# S1's constants. The camera looks from +Z at the origin; the mesh is normalized into the unit
# ball; intensity I = ka Ia + sum_i Il_i / (1 + d_i) (kd max(N.L, 0) + ks max(R.V, 0)^ns),
# the specular term dropped where N.L <= 0, clamped to [0, 1] when written (gouraud: at the
# vertices).

S1_EYE = (0.0, 0.0, 3.0)
S1_FOV_Y_DEG = 45.0
S1_NEAR, S1_FAR = 0.1, 10.0

S1_LIGHTING_GLSL = """
const vec3 S1_EYE = vec3(0.0, 0.0, 3.0);
const vec3 S1_KA_IA = vec3(0.1);            // ka = 0.1, white ambient light of intensity 1
const vec3 S1_KD = vec3(0.8, 0.6, 0.4);
const vec3 S1_KS = vec3(0.5);
const float S1_SHININESS = 32.0;
const vec3 S1_LIGHT_POSITION[3] = vec3[3](
    vec3(2.0, 2.0, 2.0), vec3(-2.0, 1.0, 1.0), vec3(0.0, -2.0, 2.0));
const vec3 S1_LIGHT_INTENSITY[3] = vec3[3](
    vec3(3.0, 3.0, 3.0), vec3(2.0, 2.0, 2.4), vec3(1.2, 1.2, 1.2));

// Unclamped intensity at surface point p with normal n (any length). A normal too short to
// normalize gets the ambient term only, as in Phosphor, so no NaN reaches the framebuffer.
vec3 s1_intensity(vec3 p, vec3 n) {
    float n_len_sq = dot(n, n);
    if (n_len_sq < 1e-20) {
        return S1_KA_IA;
    }
    vec3 normal = n * inversesqrt(n_len_sq);
    vec3 to_eye = normalize(S1_EYE - p);
    vec3 sum = S1_KA_IA;
    for (int i = 0; i < 3; ++i) {
        vec3 to_light = S1_LIGHT_POSITION[i] - p;
        float d = length(to_light);
        vec3 l = to_light / d;
        float n_dot_l = dot(normal, l);
        if (n_dot_l > 0.0) {
            vec3 r = 2.0 * n_dot_l * normal - l;
            float r_dot_v = max(dot(r, to_eye), 0.0);
            sum += S1_LIGHT_INTENSITY[i] / (1.0 + d)
                * (S1_KD * n_dot_l + S1_KS * pow(r_dot_v, S1_SHININESS));
        }
    }
    return sum;
}
"""

# Per mode: (vertex shader, fragment shader). Every vertex shader gets the view-projection
# matrix `view_proj`; positions are already normalized (world = model space in S1).
SHADERS = {
    # Coverage and depth test only: the cost of the rasterizer without any lighting.
    "fill": (
        """#version 330
uniform mat4 view_proj;
in vec3 in_position;
void main() { gl_Position = view_proj * vec4(in_position, 1.0); }
""",
        """#version 330
out vec4 out_colour;
void main() { out_colour = vec4(0.8, 0.6, 0.4, 1.0); }
""",
    ),
    # Once per triangle, at its centroid with its face normal. OpenGL has no per-primitive
    # attribute, so each corner carries the triangle's centroid and normal (unindexed draw)
    # and the colour reaches the fragments through a `flat` varying.
    "flat": (
        """#version 330
uniform mat4 view_proj;
in vec3 in_position;
in vec3 in_face_normal;
in vec3 in_centroid;
flat out vec3 colour;
""" + S1_LIGHTING_GLSL + """
void main() {
    colour = s1_intensity(in_centroid, in_face_normal);
    gl_Position = view_proj * vec4(in_position, 1.0);
}
""",
        """#version 330
flat in vec3 colour;
out vec4 out_colour;
void main() { out_colour = vec4(clamp(colour, 0.0, 1.0), 1.0); }
""",
    ),
    # Gouraud 1971: lit per vertex, intensities interpolated (perspective-correct). Clamped at
    # the vertex, as Phosphor does, so that what is interpolated is what can be displayed.
    "gouraud": (
        """#version 330
uniform mat4 view_proj;
in vec3 in_position;
in vec3 in_normal;
out vec3 colour;
""" + S1_LIGHTING_GLSL + """
void main() {
    colour = min(s1_intensity(in_position, in_normal), vec3(1.0));
    gl_Position = view_proj * vec4(in_position, 1.0);
}
""",
        """#version 330
in vec3 colour;
out vec4 out_colour;
void main() { out_colour = vec4(clamp(colour, 0.0, 1.0), 1.0); }
""",
    ),
    # Phong 1975: normal and position interpolated, lit per pixel.
    "phong": (
        """#version 330
uniform mat4 view_proj;
in vec3 in_position;
in vec3 in_normal;
out vec3 surface_point;
out vec3 surface_normal;
void main() {
    surface_point = in_position;
    surface_normal = in_normal;
    gl_Position = view_proj * vec4(in_position, 1.0);
}
""",
        """#version 330
in vec3 surface_point;
in vec3 surface_normal;
out vec4 out_colour;
""" + S1_LIGHTING_GLSL + """
void main() { out_colour = vec4(clamp(s1_intensity(surface_point, surface_normal), 0.0, 1.0), 1.0); }
""",
    ),
}


class InputError(Exception):
    """A bad file or environment: printed as one `error:` line, exit code 1."""


# ------------------------------------------------------------------------------------------
# Mesh: OBJ reading, S1's normalization and normals.


def read_obj(path):
    """Positions (V, 3) float64 and triangles (T, 3) int64 of an OBJ file.

    Polygons are split into fans; `v`/`f` are the only statements used. Also returns whether the
    file has `vn` or smoothing-group lines, which Phosphor honours and this program does not.
    """
    import numpy as np

    positions, corners = [], []
    has_own_normals = False
    try:
        fh = open(path, encoding="utf-8", errors="replace")
    except OSError as err:
        raise InputError(f"{path}: {err.strerror}") from None
    with fh:
        for line_no, line in enumerate(fh, 1):
            fields = line.split()
            if not fields:
                continue
            tag = fields[0]
            if tag == "v":
                try:
                    x, y, z = float(fields[1]), float(fields[2]), float(fields[3])
                except (IndexError, ValueError):
                    raise InputError(f"{path}:{line_no}: `v` needs three numbers") from None
                if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(z)):
                    raise InputError(f"{path}:{line_no}: vertex coordinate is not finite")
                positions.append((x, y, z))
            elif tag == "f":
                if len(fields) < 4:
                    raise InputError(f"{path}:{line_no}: `f` needs at least three vertices")
                face = []
                for token in fields[1:]:
                    try:
                        i = int(token.split("/", 1)[0])
                    except ValueError:
                        raise InputError(f"{path}:{line_no}: bad vertex index `{token}`") from None
                    i = i - 1 if i > 0 else len(positions) + i
                    if not 0 <= i < len(positions):
                        raise InputError(f"{path}:{line_no}: vertex index `{token}` out of range")
                    face.append(i)
                for k in range(1, len(face) - 1):
                    corners.append((face[0], face[k], face[k + 1]))
            elif tag == "vn" or (tag == "s" and fields[1:2] not in (["off"], ["0"])):
                has_own_normals = True
    if not corners:
        raise InputError(f"{path}: no triangles")
    return (np.asarray(positions, dtype=np.float64), np.asarray(corners, dtype=np.int64),
            has_own_normals)


def normalize_into_unit_ball(positions):
    """Bounding-box centre to the origin, then scaled so the farthest vertex is at distance 1."""
    import numpy as np

    centre = 0.5 * (positions.min(axis=0) + positions.max(axis=0))
    centred = positions - centre
    farthest = float(np.sqrt((centred * centred).sum(axis=1)).max())
    return centred / farthest if farthest > 0.0 else centred


def unit_rows(vectors):
    """Each row scaled to length 1; rows too short to normalize become zero."""
    import numpy as np

    length = np.linalg.norm(vectors, axis=1, keepdims=True)
    safe = np.where(length > 1e-30, length, 1.0)
    return np.where(length > 1e-30, vectors / safe, 0.0)


def s1_normals(positions, triangles):
    """(face normals, vertex normals) as S1 defines them.

    A vertex normal is the renormalized sum of the unit normals of every face touching its
    *position* (vertices repeating a position are welded, uniform weights); degenerate faces
    contribute nothing.
    """
    import numpy as np

    a, b, c = (positions[triangles[:, k]] for k in range(3))
    face_normals = unit_rows(np.cross(b - a, c - a))
    _, position_id = np.unique(positions, axis=0, return_inverse=True)
    position_id = position_id.reshape(-1)
    sums = np.zeros((position_id.max() + 1, 3))
    for corner in range(3):
        ids = position_id[triangles[:, corner]]
        for axis in range(3):
            sums[:, axis] += np.bincount(ids, weights=face_normals[:, axis], minlength=len(sums))
    return face_normals, unit_rows(sums[position_id])


# ------------------------------------------------------------------------------------------
# Camera: right-handed look-at and OpenGL's perspective, as Phosphor's S1 camera.


def s1_view_projection(aspect):
    import numpy as np

    eye = np.array(S1_EYE)
    forward = -eye / np.linalg.norm(eye)          # towards the origin
    side = np.cross(forward, (0.0, 1.0, 0.0))
    side /= np.linalg.norm(side)
    up = np.cross(side, forward)
    view = np.identity(4)
    view[0, :3], view[1, :3], view[2, :3] = side, up, -forward
    view[:3, 3] = -view[:3, :3] @ eye

    focal = 1.0 / np.tan(np.radians(S1_FOV_Y_DEG) / 2.0)
    projection = np.zeros((4, 4))
    projection[0, 0] = focal / aspect
    projection[1, 1] = focal
    projection[2, 2] = (S1_FAR + S1_NEAR) / (S1_NEAR - S1_FAR)
    projection[2, 3] = 2.0 * S1_FAR * S1_NEAR / (S1_NEAR - S1_FAR)
    projection[3, 2] = -1.0
    return projection @ view


# ------------------------------------------------------------------------------------------
# Output helpers.


def write_png(path, width, height, rgb_top_down):
    """An 8-bit RGB PNG, written beside `path` first and renamed, so no half file is left."""
    rows = b"".join(
        b"\x00" + rgb_top_down[y * width * 3:(y + 1) * width * 3] for y in range(height)
    )

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    png = (b"\x89PNG\r\n\x1a\n"
           + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
           + chunk(b"IDAT", zlib.compress(rows, 6))
           + chunk(b"IEND", b""))
    partial = path + ".partial"
    with open(partial, "wb") as fh:
        fh.write(png)
    os.replace(partial, path)


def llvmpipe_worker_threads():
    """How many rasterizer threads llvmpipe runs in this process (their names start `llvmpipe-`)."""
    count = 0
    for task in os.listdir("/proc/self/task"):
        try:
            with open(f"/proc/self/task/{task}/comm") as fh:
                count += fh.read().startswith("llvmpipe-")
        except OSError:
            pass
    return count


def median(values):
    ordered = sorted(values)
    n = len(ordered)
    return ordered[n // 2] if n % 2 else 0.5 * (ordered[n // 2 - 1] + ordered[n // 2])


# ------------------------------------------------------------------------------------------
# Rendering.


def create_llvmpipe_context(threads):
    # llvmpipe reads LP_NUM_THREADS once, when the driver loads: it must be set before the
    # context exists, so one process measures one thread count. The other variables keep Mesa
    # on llvmpipe even where a GPU driver is installed.
    os.environ["LP_NUM_THREADS"] = str(threads)
    os.environ.setdefault("LIBGL_ALWAYS_SOFTWARE", "1")
    os.environ.setdefault("GALLIUM_DRIVER", "llvmpipe")
    mesa_vendor = "/usr/share/glvnd/egl_vendor.d/50_mesa.json"
    if os.path.exists(mesa_vendor):
        os.environ.setdefault("__EGL_VENDOR_LIBRARY_FILENAMES", mesa_vendor)
    import moderngl

    try:
        ctx = moderngl.create_standalone_context(backend="egl", require=330)
    except Exception as err:  # moderngl raises plain Exception for EGL failures
        raise InputError(f"EGL: no OpenGL 3.3 context ({err}); run through run.sh") from None
    renderer = ctx.info.get("GL_RENDERER", "?")
    if "llvmpipe" not in renderer:
        raise InputError(f"EGL: the context is `{renderer}`, not llvmpipe")
    return ctx


class MeshOnGpu:
    """A mesh's S1 vertex buffers and one vertex array per mode."""

    def __init__(self, ctx, programs, path):
        import numpy as np

        positions, triangles, has_own_normals = read_obj(path)
        if has_own_normals:
            print(f"warning: {path}: has `vn` or `s` lines; Phosphor uses them, this program "
                  "averages normals over every face (the pictures may differ)", file=sys.stderr)
        positions = normalize_into_unit_ball(positions)
        face_normals, vertex_normals = s1_normals(positions, triangles)
        self.name = os.path.splitext(os.path.basename(path))[0]
        self.triangles = len(triangles)

        interleaved = np.hstack([positions, vertex_normals]).astype("f4")
        self.buffers = [
            ctx.buffer(interleaved.tobytes()),
            ctx.buffer(triangles.astype("u4").tobytes()),
        ]
        shared, indices = self.buffers
        corners = positions[triangles].reshape(-1, 3)
        per_corner = np.hstack([
            corners,
            np.repeat(face_normals, 3, axis=0),
            np.repeat(positions[triangles].mean(axis=1), 3, axis=0),
        ]).astype("f4")
        self.buffers.append(ctx.buffer(per_corner.tobytes()))
        unindexed = self.buffers[2]
        self.arrays = {
            "fill": ctx.vertex_array(
                programs["fill"], [(shared, "3f 12x", "in_position")], indices, 4),
            "gouraud": ctx.vertex_array(
                programs["gouraud"], [(shared, "3f 3f", "in_position", "in_normal")], indices, 4),
            "phong": ctx.vertex_array(
                programs["phong"], [(shared, "3f 3f", "in_position", "in_normal")], indices, 4),
            "flat": ctx.vertex_array(
                programs["flat"],
                [(unindexed, "3f 3f 3f", "in_position", "in_face_normal", "in_centroid")]),
        }

    def release(self):
        for item in list(self.arrays.values()) + self.buffers:
            item.release()


def parse_size(text):
    try:
        width, height = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected WxH, e.g. 1280x720, got `{text}`") from None
    if not (1 <= width <= 16384 and 1 <= height <= 16384):
        raise argparse.ArgumentTypeError(f"each side must be between 1 and 16384, got `{text}`")
    return width, height


def positive(text):
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 1, got `{text}`")
    return value


def non_negative(text):
    try:
        value = int(text)
    except ValueError:
        value = -1
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 0, got `{text}`")
    return value


def parse_args(argv):
    ap = argparse.ArgumentParser(
        prog="s1_llvmpipe.py",
        description="Time Mesa's llvmpipe (headless, EGL) drawing meshes in the standard scene S1.",
        epilog="Output, one line per mesh, size and mode:\n  MODE median_ms=X min_ms=Y max_ms=Z "
               "frames=N renderer=llvmpipe mesh=NAME triangles=T size=WxH threads=N cull=off|on",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mesh", action="append", required=True, metavar="FILE.obj",
                    help="mesh to draw in S1 (repeatable)")
    ap.add_argument("--modes", nargs="+", choices=MODES, default=list(MODES), metavar="MODE",
                    help="any of fill flat gouraud phong (default: all four)")
    ap.add_argument("--size", nargs="+", type=parse_size, default=[(1920, 1080)], metavar="WxH",
                    help="image sizes (default: 1920x1080, S1's)")
    ap.add_argument("--threads", type=non_negative, default=os.cpu_count() or 1, metavar="N",
                    help="LP_NUM_THREADS: llvmpipe's rasterizer threads; 0 draws on the calling "
                         "thread (default: one per CPU)")
    ap.add_argument("--frames", type=positive, default=50, metavar="N",
                    help="timed frames per measurement (default: 50)")
    ap.add_argument("--warmup", type=non_negative, default=5, metavar="N",
                    help="untimed frames before them (default: 5)")
    ap.add_argument("--cull", action="store_true",
                    help="skip back faces (GL_CULL_FACE; S1 draws both sides)")
    ap.add_argument("--png-dir", metavar="DIR",
                    help="also write the last frame of each measurement as DIR/MESH_MODE_WxH.png "
                         "(8-bit, linear values, like `phosphor render --encoding linear`)")
    return ap.parse_args(argv)


def measure(ctx, args):
    import moderngl

    programs = {
        mode: ctx.program(vertex_shader=vertex, fragment_shader=fragment)
        for mode, (vertex, fragment) in SHADERS.items()
    }
    reported_threads = False
    for path in args.mesh:
        mesh = MeshOnGpu(ctx, programs, path)
        for width, height in args.size:
            fbo = ctx.simple_framebuffer((width, height), components=4)
            fbo.use()
            ctx.viewport = (0, 0, width, height)
            ctx.enable(moderngl.DEPTH_TEST)
            ctx.depth_func = "<"
            if args.cull:
                ctx.front_face = "ccw"
                ctx.cull_face = "back"
                ctx.enable(moderngl.CULL_FACE)
            else:
                ctx.disable(moderngl.CULL_FACE)
            # numpy is row-major, GLSL reads column-major: upload the transpose.
            matrix = s1_view_projection(width / height).T.astype("f4").tobytes()
            for program in programs.values():
                program["view_proj"].write(matrix)

            for mode in args.modes:
                array = mesh.arrays[mode]
                times_ms = []
                for frame in range(args.warmup + args.frames):
                    start = time.perf_counter()
                    fbo.clear(0.0, 0.0, 0.0, 1.0, depth=1.0)
                    array.render(moderngl.TRIANGLES)
                    ctx.finish()  # llvmpipe defers drawing until it must: time it all
                    if frame >= args.warmup:
                        times_ms.append((time.perf_counter() - start) * 1e3)
                if not reported_threads:
                    reported_threads = True
                    running = llvmpipe_worker_threads()
                    print(f"# {ctx.info.get('GL_RENDERER')}, {ctx.info.get('GL_VERSION')}, "
                          f"LP_NUM_THREADS={args.threads}, rasterizer threads running: {running}",
                          file=sys.stderr)
                    if running != args.threads:
                        print(f"warning: asked llvmpipe for {args.threads} threads, it runs "
                              f"{running}", file=sys.stderr)
                print(f"{mode} median_ms={median(times_ms):.3f} min_ms={min(times_ms):.3f} "
                      f"max_ms={max(times_ms):.3f} frames={args.frames} renderer=llvmpipe "
                      f"mesh={mesh.name} triangles={mesh.triangles} size={width}x{height} "
                      f"threads={args.threads} cull={'on' if args.cull else 'off'}", flush=True)
                if args.png_dir:
                    bottom_up = fbo.read(components=3, alignment=1)
                    row = width * 3
                    top_down = b"".join(
                        bottom_up[y * row:(y + 1) * row] for y in range(height - 1, -1, -1))
                    name = f"{mesh.name}_{mode}_{width}x{height}.png"
                    write_png(os.path.join(args.png_dir, name), width, height, top_down)
            fbo.release()
        mesh.release()


def main(argv):
    args = parse_args(argv)
    try:
        if args.png_dir:
            try:
                os.makedirs(args.png_dir, exist_ok=True)
            except OSError as err:
                raise InputError(f"{args.png_dir}: {err.strerror}") from None
        for path in args.mesh:
            if not os.path.isfile(path):
                raise InputError(f"{path}: no such file")
        ctx = create_llvmpipe_context(args.threads)
        measure(ctx, args)
    except InputError as err:
        print(f"error: {err}", file=sys.stderr)
        return 1
    except ImportError as err:
        print(f"error: Python package missing ({err.name}): run through run.sh", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
