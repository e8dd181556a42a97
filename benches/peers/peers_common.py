"""Shared parts of the peer comparisons (benches/peers/): files, the environment, timing of whole
processes, CIEDE2000 over the whole image and over the film's pixels, time-to-quality
interpolation, and the Cycles scene (world, camera, render settings, thin-film material).

Not part of the test suite; see README.md beside this file.
"""
import math
import os
import subprocess
import sys
import time

import warnings

import numpy as np

warnings.filterwarnings("ignore", module="colour")  # "Matplotlib related API not available"
HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
# The release binary the coordinator measures with; --filmsplat overrides it.
DEFAULT_FILMSPLAT = "/work/main/target/release/filmsplat"
if not os.path.exists(DEFAULT_FILMSPLAT):
    DEFAULT_FILMSPLAT = os.path.join(ROOT, "target", "release", "filmsplat")


# ----------------------------------------------------------------------------------------------
# Files


def read_ply(path):
    """Binary little-endian PLY of float32 vertex properties (what `filmsplat sample` and
    `filmsplat convert` write)."""
    with open(path, "rb") as f:
        names, n = [], 0
        while True:
            line = f.readline().decode().strip()
            if line.startswith("element vertex"):
                n = int(line.split()[2])
            elif line.startswith("property float"):
                names.append(line.split()[2])
            elif line == "end_header":
                break
        data = np.frombuffer(f.read(4 * n * len(names)), dtype="<f4").reshape(n, len(names))
    return {k: data[:, i].astype(np.float64) for i, k in enumerate(names)}


def positions(cloud):
    return np.stack([cloud["x"], cloud["y"], cloud["z"]], axis=-1)


# filmsplat is y-up, Blender z-up: Blender (X, Y, Z) = filmsplat (-z, -x, y), a proper rotation
# under which both renderers' lat-long conventions agree (Blender's probed with a u/v-coded map:
# +X at u = 0.5, +Y at u = 0.25, up at the top row):
#   filmsplat: u = atan2(x, -z) / 2pi + 0.5, v_top = acos(y) / pi
#   Blender:   u = 0.5 - atan2(Y, X) / 2pi,  v_top = acos(Z) / pi
def to_blender(p):
    p = np.asarray(p, dtype=np.float64)
    return np.stack([-p[..., 2], -p[..., 0], p[..., 1]], axis=-1)


def studio_env(d):
    """Radiance of the test environment for unit directions d (filmsplat coordinates, y-up)."""
    y = d[..., 1]
    sky = 0.25 + 0.35 * np.clip(y, 0, 1)
    floor = 0.06 + 0.0 * y
    base = np.where(y > 0, sky, floor)
    rgb = np.stack([base * 0.95, base, base * 1.08], axis=-1)

    def softbox(centre, size, power, tint):
        c = np.asarray(centre, dtype=np.float64)
        c /= np.linalg.norm(c)
        ang = np.arccos(np.clip(d @ c, -1, 1))
        w = 1.0 / (1.0 + np.exp((ang - size) / 0.02))
        return w[..., None] * power * np.asarray(tint)

    rgb += softbox([0.6, 0.7, 0.8], 0.35, 6.0, [1.0, 0.98, 0.95])
    rgb += softbox([-0.9, 0.4, 0.3], 0.25, 3.0, [0.9, 0.95, 1.0])
    rgb += softbox([0.1, 0.2, -1.0], 0.4, 2.0, [1.0, 1.0, 1.0])
    return rgb


def write_env(path, width=1024):
    """Writes the environment as a linear float EXR (with OpenEXR: saving through bpy would
    apply Blender's display encoding to a generated image)."""
    import OpenEXR

    h = width // 2
    j, i = np.mgrid[0:h, 0:width].astype(np.float64)  # top row first
    u = (i + 0.5) / width
    theta = (j + 0.5) / h * math.pi
    phi = (u - 0.5) * 2 * math.pi
    # filmsplat: u = atan2(x, -z)/2pi + 0.5, y = cos(theta)
    s = np.sin(theta)
    d = np.stack([s * np.sin(phi), np.cos(theta), -s * np.cos(phi)], axis=-1)
    rgb = studio_env(d).astype(np.float32)
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, {"RGB": rgb}) as f:
        f.write(path)


def read_exr(path):
    """(RGB, alpha) of an EXR, top row first (OpenEXR's Python bindings: bpy treats filmsplat's
    multi-layer EXR as a multilayer render and exposes no pixels). Alpha is None without one."""
    import OpenEXR

    with OpenEXR.File(path) as f:
        ch = f.channels()
        if "RGBA" in ch:
            px = ch["RGBA"].pixels.astype(np.float64)
            return px[..., :3], px[..., 3]
        return ch["RGB"].pixels.astype(np.float64), None


# ----------------------------------------------------------------------------------------------
# Quality


def delta_e_map(a, b):
    """Per-pixel CIEDE2000 between two linear sRGB images (clipped to [0, 1], D65)."""
    import colour

    def lab(rgb):
        xyz = np.clip(rgb, 0, 1) @ np.array(
            [[0.4124564, 0.3575761, 0.1804375],
             [0.2126729, 0.7151522, 0.0721750],
             [0.0193339, 0.1191920, 0.9503041]]).T
        return colour.XYZ_to_Lab(xyz, colour.XYZ_to_xy(np.array([0.95047, 1.0, 1.08883])))

    return colour.delta_E(lab(a), lab(b), method="CIE 2000")


def summarize(de, mask):
    """Mean and 95th percentile of a ΔE map over the whole image and over `mask` (the film's
    pixels)."""
    whole = de.ravel()
    film = de[mask].ravel() if mask is not None and mask.any() else whole
    return {"de_mean": float(whole.mean()), "de_p95": float(np.percentile(whole, 95)),
            "de_film_mean": float(film.mean()), "de_film_p95": float(np.percentile(film, 95))}


def film_mask(alpha, threshold=0.5):
    """The film's pixels: where at least `threshold` of the converged image's camera samples hit
    a film (filmsplat's alpha is that coverage)."""
    return None if alpha is None else alpha >= threshold


def time_to(points, target=1.0):
    """Seconds to reach mean ΔE `target`, from (seconds, ΔE) points in increasing sample count,
    interpolated log-log between the two counts that bracket it. Returns (seconds, how): how is
    '=' (interpolated), '<=' (already below at the first count: an upper bound) or '~'
    (extrapolated log-log beyond the last count)."""
    pts = [(t, d) for t, d in points if t > 0 and d > 0]
    if not pts:
        return float("nan"), "?"
    if pts[0][1] <= target:
        return pts[0][0], "<="
    for (t0, d0), (t1, d1) in zip(pts, pts[1:]):
        if d1 <= target < d0:
            f = math.log(target / d0) / math.log(d1 / d0)
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0))), "="
    if len(pts) >= 2 and pts[-1][1] < pts[-2][1] and pts[-1][0] > pts[-2][0]:
        (t0, d0), (t1, d1) = pts[-2], pts[-1]
        f = math.log(target / d0) / math.log(d1 / d0)
        return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0))), "~"
    return float("nan"), "?"


def fmt_time(t, how):
    if t != t:
        return "n/a"
    return {"=": "", "<=": "≤ ", "~": "~"}[how] + f"{t:.2f}"


def fmt_ratio(a, how_a, b, how_b):
    """b / a with its direction: a is an upper bound (≤) → the ratio is a lower bound (≥)."""
    if a != a or b != b:
        return "n/a"
    mark = "≥ " if how_a == "<=" and how_b != "<=" else ("~" if "~" in (how_a, how_b) else "")
    if how_b == "<=":
        mark = "≤ " if how_a != "<=" else "? "
    return f"{mark}{b / a:.1f}×"


# ----------------------------------------------------------------------------------------------
# Timing of whole processes


def load():
    return "load average %.2f %.2f %.2f" % os.getloadavg()


def timed(cmd, env=None):
    """Runs `cmd` as a child process; returns (wall seconds, CPU seconds = user + system of the
    child and its children). The whole process is timed: start-up, loading, build, render,
    writing."""
    t = time.perf_counter()
    p = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL)
    _, status, ru = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        raise subprocess.CalledProcessError(p.returncode, cmd)
    return wall, ru.ru_utime + ru.ru_stime


def thread_env(threads):
    """Environment for a filmsplat child limited to `threads` threads (0: all cores)."""
    env = dict(os.environ)
    if threads:
        env["RAYON_NUM_THREADS"] = str(threads)
    return env


def camera_for(p, direction=(0.35, 0.3, 1.0), fov=40.0, margin=1.15):
    """A camera looking at the cloud's bounding-box centre from `direction`, far enough that the
    bounding sphere fills the vertical field of view with `margin`."""
    centre = 0.5 * (p.min(0) + p.max(0))
    radius = float(np.linalg.norm(p - centre, axis=1).max())
    d = np.asarray(direction, dtype=np.float64)
    d /= np.linalg.norm(d)
    dist = margin * radius / math.sin(math.radians(fov) / 2)
    return {"position": (centre + dist * d).tolist(), "look_at": centre.tolist(), "fov": fov}


def filmsplat_cmd(exe, inputs, camera, size, spp, exr, png, extra):
    """`filmsplat render` with the shared camera, environment handled by `extra`."""
    return [exe, "render", *inputs, "-o", png, "--exr", exr,
            "--size", f"{size[0]}x{size[1]}", "--spp", str(spp), "--tonemap", "clamp", "-q",
            "--camera", ",".join(f"{v:.6f}" for v in camera["position"]),
            "--look-at", ",".join(f"{v:.6f}" for v in camera["look_at"]),
            "--fov", str(camera["fov"]), *extra]


def cycles_cmd(python, spec_path):
    """A fresh Python process that imports bpy, builds the scene and renders once: Blender's
    start-up is part of the time, as filmsplat's is."""
    return [python, "-W", "ignore::DeprecationWarning", os.path.join(HERE, "cycles_worker.py"),
            spec_path]


def median(xs):
    return float(np.median(np.asarray(xs, dtype=np.float64)))


def python_exe():
    return sys.executable


def side_by_side(path, panels, width=320):
    """A PNG of labelled panels: (linear RGB, [label lines]) each scaled to `width` pixels."""
    from PIL import Image, ImageDraw

    ims = []
    for rgb, lines in panels:
        c = np.clip(rgb, 0, 1)
        s = np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1 / 2.4) - 0.055)
        im = Image.fromarray((s * 255 + 0.5).astype(np.uint8))
        if im.width != width:
            im = im.resize((width, round(width * im.height / im.width)), Image.LANCZOS)
        dr = ImageDraw.Draw(im)
        dr.rectangle([0, 0, width - 1, 13 * len(lines) + 3], fill=(0, 0, 0))
        for i, line in enumerate(lines):
            dr.text((4, 2 + 13 * i), line.replace("≤", "<=").replace("Δ", "d"),
                    fill=(255, 255, 255))
        ims.append(im)
    out = Image.new("RGB", (sum(p.width for p in ims), max(p.height for p in ims)))
    x = 0
    for p in ims:
        out.paste(p, (x, 0))
        x += p.width
    out.save(path, optimize=True)
