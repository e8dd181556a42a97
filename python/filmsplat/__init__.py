"""filmsplat: spectral thin-film rendering of SPH particle clouds, from Python.

numpy arrays in, pictures and numbers out. Units: positions, radii and depths in scene units,
film thickness and wavelengths in nanometres, angles in degrees, image sizes in pixels.

    import filmsplat
    cloud = filmsplat.read("frame.vtu")              # or filmsplat.Cloud(positions, ...)
    scene = filmsplat.Scene(cloud, preset="balanced")  # builds the geometry once
    image = scene.render(size=(960, 540))            # renders as often as asked
    image.save("frame.png")                          # or image.rgb (linear float32 H x W x 3)

Every error the CLI reports as a one-line message is raised with that message: ``ValueError``
for bad input (arguments, malformed files), ``OSError`` for files that cannot be read or
written, ``KeyboardInterrupt`` when Ctrl-C stops a render.
"""

from __future__ import annotations

import json
import math
import os
import re
from typing import Any, Callable, Iterable, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._native import Cloud, Image, __version__, read

__all__ = [
    "Cloud",
    "Image",
    "Scene",
    "chart",
    "cli",
    "compare",
    "film",
    "film_rgb",
    "movie",
    "orbit",
    "read",
]

# The scene file's keys a knob may name, by section (see samples/README.md for each key).
_KNOBS = {
    "input": (
        "cloud",
        "sample",
        "particles",
        "sample_seed",
        "time",
        "sparse",
        "thickness_attr",
        "normal_attr",
        "radius_attr",
        "repair",
        "liquid",
        "liquid_field",
    ),
    "film": (
        "ior",
        "thickness_unit",
        "thickness_scale",
        "default_thickness_nm",
        "radius_scale",
        "curvature",
        "blend",
    ),
    "camera": ("position", "look_at", "up", "fov", "from", "aperture", "focus_distance"),
    "render": (
        "width",
        "height",
        "spp",
        "max_depth",
        "min_weight",
        "roulette",
        "seed",
        "shading",
        "light_samples",
        "prop_bounces",
        "wavelengths",
        "strategy",
        "view",
        "shutter",
        "frame_time",
        "shutter_slices",
    ),
    "output": ("exposure", "tonemap", "white_balance", "gains", "contrast", "saturation"),
}
_SECTION_OF = {k: s for s, keys in _KNOBS.items() for k in keys}
# `from` is a Python keyword: `from_` names it.
_SECTION_OF["from_"] = "camera"


def _toml_value(v: Any, where: str) -> str:
    if isinstance(v, np.generic):
        v = v.item()
    if isinstance(v, np.ndarray):
        v = v.tolist()
    if isinstance(v, os.PathLike):
        v = os.fspath(v)
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x, where) for x in v) + "]"
    raise ValueError(f"{where}: {type(v).__name__} is not a number, string, bool or list")


def _toml_table(header: str, table: Mapping[str, Any]) -> str:
    lines = [header]
    for k, v in table.items():
        if v is None:
            continue
        key = "from" if k == "from_" else k
        lines.append(f"{key} = {_toml_value(v, key)}")
    return "\n".join(lines) + "\n"


def _camera_toml(camera: Optional[Mapping[str, Any]]) -> Optional[str]:
    if camera is None:
        return None
    if not isinstance(camera, Mapping):
        raise ValueError("camera: give a dict of [camera] keys, e.g. {'from': [0, 0.3, 1]}")
    return _toml_table("[camera]", camera)


def orbit(
    angle_deg: float, elevation: float = 0.3, fov: Optional[float] = None
) -> dict:
    """A camera for ``Scene.render(camera=...)`` circling the scene about +y: auto-framed
    from the direction at ``angle_deg`` degrees (0 = the default front view, +z), raised by
    ``elevation`` (the y part of the direction). For turntables."""
    a = math.radians(angle_deg)
    cam: dict = {"from": [math.sin(a), elevation, math.cos(a)]}
    if fov is not None:
        cam["fov"] = fov
    return cam


def _progress_callback(progress: Any) -> Tuple[Optional[Callable[[int, int], None]], Callable[[], None]]:
    """(callback(done, total), close) for ``progress``: False → none; a callable → itself;
    None or True → a tqdm bar if tqdm is installed."""
    if progress is False:
        return None, lambda: None
    if callable(progress):
        return progress, lambda: None
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return None, lambda: None
    bar: list = []

    def update(done: int, total: int) -> None:
        if not bar:
            bar.append(tqdm(total=total, unit="tile", desc="rendering", leave=False))
        bar[0].update(done - bar[0].n)

    def close() -> None:
        if bar:
            bar[0].close()

    return update, close


CloudsLike = Union[Cloud, Sequence[Cloud], str, "os.PathLike[str]", None]


_NAME = "Scene(...)"
_LINE = re.compile(r"^Scene\(\.\.\.\): scene TOML: line (\d+): (.*)$", re.S)


def _knob_error(e: ValueError, text: str) -> ValueError:
    """A TOML error in the text built from the knobs, told by the knob: "Scene: camera.fov =
    "wide": invalid type ..." instead of a line number of text the user never saw."""
    m = _LINE.match(str(e))
    if not m:
        return e
    lines = text.splitlines()
    n = int(m.group(1))
    section = next(
        (line.strip("[]") for line in reversed(lines[: n - 1]) if line.startswith("[")), ""
    )
    return ValueError(f"Scene: {section}.{lines[n - 1]}: {m.group(2)}")


class Scene:
    """Particles turned into geometry once, rendered as often as asked.

    ``Scene(clouds, primitive="disk", preset="balanced", environment=None, lights=(),
    props=(), **knobs)``

    * ``clouds``: a ``Cloud``, a list of them (concatenated), a particle file's path, or None
      with ``sample="bubble"`` (a built-in sample; ``particles=``, ``time=`` ...).
    * ``primitive``: "disk" (splats blended into one film), "sphere" or "mls".
    * ``preset``: "preview", "balanced" or "final".
    * ``environment``: None (the studio), "studio", "uniform", an EXR lat-long map's path, or a
      dict of ``[environment]`` keys (kind, colour, map, rotation, intensity).
    * ``lights``, ``props``: dicts of ``[[light]]`` / ``[[prop]]`` keys (shape, position, ...).
    * ``knobs``: any key of the scene file's ``[input]``, ``[film]``, ``[camera]``,
      ``[render]`` and ``[output]`` tables by its name (``ior=1.33``, ``spp=8``,
      ``width=640``, ``fov=30``, ``exposure=0.5``, ``from_=[0, 0.3, 1]`` ...; see
      samples/README.md). Lengths in scene units, thickness in nm, angles in degrees.
    * ``liquid=``: how a thin-film SPH frame's 3D particles are drawn: "auto" (the default:
      those present since the run's frame 0 ``<run>/0`` as water where packed into bodies,
      those shed later, when frame 0 holds none, as droplets), "surface" (bodies by packing
      alone) or "droplets" (every one a droplet); ``liquid_field=``: "grid" (the default) or
      "exact", how rays find the water's surface.

    Building releases the GIL; missing normals and radii are estimated here.
    """

    def __init__(
        self,
        clouds: CloudsLike,
        primitive: str = "disk",
        preset: str = "balanced",
        environment: Union[None, str, "os.PathLike[str]", Mapping[str, Any]] = None,
        lights: Iterable[Mapping[str, Any]] = (),
        props: Iterable[Mapping[str, Any]] = (),
        **knobs: Any,
    ) -> None:
        tables: dict = {s: {} for s in _KNOBS}
        tables["film"]["primitive"] = primitive
        tables["render"]["preset"] = preset
        for k, v in knobs.items():
            section = _SECTION_OF.get(k)
            if section is None:
                known = ", ".join(sorted(_SECTION_OF))
                raise ValueError(f"Scene: unknown knob '{k}' (known: {known})")
            tables[section][k] = v
        native: Optional[list] = None
        if isinstance(clouds, Cloud):
            native = [clouds]
        elif isinstance(clouds, (str, os.PathLike)):
            tables["input"]["cloud"] = os.path.abspath(os.fspath(clouds))
        elif clouds is not None:
            native = list(clouds)
            if not all(isinstance(c, Cloud) for c in native):
                raise ValueError("Scene: clouds must be Cloud objects, a path or None")
        env: dict
        if environment is None:
            env = {}
        elif isinstance(environment, Mapping):
            env = dict(environment)
        elif isinstance(environment, str) and environment in ("studio", "uniform"):
            env = {"kind": environment}
        elif isinstance(environment, (str, os.PathLike)):
            path = os.fspath(environment)
            if not path.lower().endswith(".exr"):
                raise ValueError(
                    f"environment: '{path}' is not studio, uniform or an .exr lat-long map"
                )
            env = {"kind": "map", "map": os.path.abspath(path)}
        else:
            raise ValueError("environment: give None, 'studio', 'uniform', an EXR path or a dict")
        text = "".join(_toml_table(f"[{s}]", t) for s, t in tables.items())
        text += _toml_table("[environment]", env)
        text += "".join(_toml_table("[[light]]", light) for light in lights)
        text += "".join(_toml_table("[[prop]]", prop) for prop in props)
        self._toml = text
        try:
            self._scene = _native._Scene(text, _NAME, os.getcwd(), native)
        except ValueError as e:
            raise _knob_error(e, text) from None

    @classmethod
    def from_file(cls, path: Union[str, "os.PathLike[str]"]) -> "Scene":
        """Builds the scene of a scene file (TOML; paths in it relative to its folder)."""
        self = cls.__new__(cls)
        path = os.fspath(path)
        self._toml = _native.read_text(path)
        base = os.path.dirname(os.path.abspath(path))
        self._scene = _native._Scene(self._toml, path, base, None)
        return self

    @property
    def particles(self) -> int:
        """Number of particles."""
        return self._scene.particles

    @property
    def notes(self) -> list:
        """What was estimated or repaired while building (the CLI prints these)."""
        return list(self._scene.notes)

    @property
    def size(self) -> Tuple[int, int]:
        """The scene's image size (width, height), pixels."""
        return self._scene.size

    @property
    def build_seconds(self) -> dict:
        """Seconds spent loading, estimating (normals, radii) and building the ray tree."""
        load, estimate, build = self._scene.build_seconds
        return {"load": load, "estimate": estimate, "build": build}

    def render(
        self,
        camera: Optional[Mapping[str, Any]] = None,
        size: Optional[Tuple[int, int]] = None,
        spp: Optional[int] = None,
        view: Optional[str] = None,
        seed: Optional[int] = None,
        progress: Any = None,
        orbit: Optional[float] = None,
    ) -> Image:
        """Renders the scene; re-uses the built geometry (a turntable costs renders, not
        builds).

        * ``camera``: a dict of ``[camera]`` keys replacing the scene's (``{"from": [x, y, z]}``
          auto-frames from that direction; ``position``/``look_at``/``up``/``fov`` in scene
          units and degrees; see ``orbit()``), None: the scene's.
        * ``size``: (width, height) pixels; None: the scene's (960 x 540 by default).
        * ``spp``: camera samples per pixel; None: the preset's.
        * ``view``: "shaded", "thickness", "normal", "depth", "particle-id", "coverage";
          None: the scene's (shaded).
        * ``seed``: random seed; None: the scene's (0). The same seed gives the same image.
        * ``progress``: None or True: a tqdm bar if tqdm is installed; False: none; a
          callable: called as ``progress(done_tiles, total_tiles)`` about every 0.1 s.
        * ``orbit``: degrees the camera (``camera``'s, or the auto-framed one) turns about its
          up axis around its look-at point, the studio turning with it, as ``render --orbit``
          turns frame i of N by DEG·i/N: ``[scene.render(orbit=360 * i / n) for i in
          range(n)]`` is the CLI's turntable. None or 0: not turned.

        Releases the GIL and uses all cores; Ctrl-C stops it within a tile per core and
        raises ``KeyboardInterrupt``.
        """
        callback, close = _progress_callback(progress)
        try:
            return self._scene.render(
                _camera_toml(camera), size, spp, view, seed, callback, orbit
            )
        finally:
            close()

    def __repr__(self) -> str:
        w, h = self.size
        return f"Scene({self.particles} particles, {w}x{h})"


def _flat(a: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=np.float64).ravel()


def film(
    thickness_nm: Any, angle_deg: Any, wavelength_nm: Any, ior: float = 1.33
) -> dict:
    """Reflectance and transmittance of a film (air | index ``ior`` | air), the exact Airy sum
    in float64, as ``filmsplat film`` prints them.

    ``thickness_nm`` (nm, 0..1e6), ``angle_deg`` (angle of incidence, degrees, 0..90) and
    ``wavelength_nm`` (vacuum wavelength, nm, 100..10000) broadcast like numpy. Returns a dict
    of float64 arrays of the broadcast shape: ``R`` and ``T`` (unpolarised, R + T = 1),
    ``Rs`` and ``Rp`` (s and p polarisation).
    """
    h, a, lam = np.broadcast_arrays(
        np.asarray(thickness_nm, dtype=np.float64),
        np.asarray(angle_deg, dtype=np.float64),
        np.asarray(wavelength_nm, dtype=np.float64),
    )
    shape = h.shape
    r, t, rs, rp = _native.film_rt(_flat(h), _flat(a), _flat(lam), float(ior))
    return {k: v.reshape(shape) for k, v in (("R", r), ("T", t), ("Rs", rs), ("Rp", rp))}


def film_rgb(thickness_nm: Any, angle_deg: Any, ior: float = 1.33) -> np.ndarray:
    """Colour of D65 light reflected by a film, linear sRGB (a perfect reflector is 1, 1, 1),
    the 1 nm spectral sum over 360..830 nm, as ``filmsplat film --rgb`` prints it.

    ``thickness_nm`` (nm) and ``angle_deg`` (degrees) broadcast like numpy; returns float64 of
    the broadcast shape plus a last axis of 3 (r, g, b).
    """
    h, a = np.broadcast_arrays(
        np.asarray(thickness_nm, dtype=np.float64), np.asarray(angle_deg, dtype=np.float64)
    )
    rgb = _native.film_rgb(_flat(h), _flat(a), float(ior))
    return rgb.reshape(h.shape + (3,))


def chart(
    path: Union[None, str, "os.PathLike[str]"] = None,
    max_thickness_nm: float = 1500.0,
    ior: float = 1.33,
    max_angle_deg: float = 89.0,
    size: Tuple[int, int] = (1600, 900),
) -> Image:
    """The interference colour chart (``filmsplat chart``): reflected colour against thickness
    (x, nm, 0..``max_thickness_nm``) and angle of incidence (y, degrees, 0..``max_angle_deg``,
    at most 89.9). ``size`` (width, height) pixels, at least 400 x 300. Written to ``path``
    (PNG) if given; returned as an ``Image`` either way."""
    img = _native.chart(
        float(max_thickness_nm), float(ior), float(max_angle_deg), int(size[0]), int(size[1])
    )
    if path is not None:
        img.save(path)
    return img


def _flags(options: Mapping[str, Any]) -> list:
    args = []
    for k, v in options.items():
        flag = "--" + k.rstrip("_").replace("_", "-")
        if v is None or v is False:
            continue
        if v is True:
            args.append(flag)
        elif k == "size" and isinstance(v, (tuple, list)):
            args += [flag, f"{int(v[0])}x{int(v[1])}"]
        elif isinstance(v, (tuple, list)):
            args += [flag, ",".join(str(x) for x in v)]
        else:
            args += [flag, os.fspath(v) if isinstance(v, os.PathLike) else str(v)]
    return args


def cli(*args: Union[str, "os.PathLike[str]"]) -> str:
    """Runs the ``filmsplat`` command line in this process (``cli("info", "frame.ply")``)
    and returns what it printed; errors raise as everywhere else. Releases the GIL."""
    return _native.run_cli([os.fspath(a) for a in args])


def _frame_range(frames: Union[str, range, Tuple[int, int]]) -> str:
    """``--frames`` text for ``"0..48"``, ``range(0, 48)`` or ``(0, 48)`` (end excluded)."""
    if isinstance(frames, str):
        return frames
    if isinstance(frames, range):
        if frames.step != 1:
            raise ValueError(f"movie: frames {frames} must have step 1")
        return f"{frames.start}..{frames.stop}"
    if isinstance(frames, (tuple, list)) and len(frames) == 2:
        return f"{int(frames[0])}..{int(frames[1])}"
    raise ValueError(f"movie: frames must be 'A..B', range(A, B) or (A, B), got {frames!r}")


def movie(
    input: Union[str, "os.PathLike[str]"],
    output: Union[str, "os.PathLike[str]"] = "movie.mp4",
    frames: Union[str, range, Tuple[int, int]] = "0..24",
    fps: Optional[float] = None,
    crf: Optional[int] = None,
    progress: bool = True,
    **options: Any,
) -> str:
    """Renders a sequence straight into a movie, in one call: ``filmsplat render INPUT
    --frames A..B -o OUTPUT``. ``input`` is a frame pattern (``"frames/{:04}.ply"``) or a
    scene file (a generated sample moves 1/fps s a frame); ``output`` a ``.mp4`` (H.264,
    yuv420p) or ``.webm`` (VP9), written whole or not at all; ``fps`` its frame rate (24),
    ``crf`` its quality (lower is better: H.264 18, VP9 31). ``options`` are the render flags
    by name, passed through (``size=(640, 360)``, ``preset="preview"``, ``frame_all=True``,
    and any flag the CLI takes, such as a camera move). Needs ``ffmpeg`` on PATH. Progress: a
    line per frame on stderr, as the CLI prints it (``progress=False``: none). Returns the
    movie's path."""
    args = ["render", os.fspath(input), "-o", os.fspath(output), "--frames", _frame_range(frames)]
    if fps is not None:
        args += ["--fps", str(fps)]
    if crf is not None:
        args += ["--crf", str(int(crf))]
    if not progress:
        args.append("--quiet")
    cli(*args, *_flags(options))
    return os.fspath(output)


def compare(
    a: str,
    b: str,
    input: Union[str, "os.PathLike[str]"],
    output: Union[str, "os.PathLike[str]"] = "compare.png",
    **options: Any,
) -> dict:
    """``filmsplat compare A B INPUT --json``: renders one scene with two geometries (disk,
    sphere, mls, mesh:FILE), writes the side-by-side figure to ``output`` (PNG) and returns
    the metrics dict the CLI prints: ``a`` and ``b`` (geometry, elements, prepare_s, mesh_s,
    meshing_s, render_s), ``psnr_db``, ``identical``, ``ssim``, ``delta_e`` (mean, p95,
    max; ΔE2000) and ``output``. ``options`` are the CLI's flags by name (``size=(64, 48)``,
    ``spp=1``, ``preset="preview"``, ``heat_max=10``, ``quiet=True`` ...)."""
    args = ["compare", a, b, os.fspath(input), "--json", "-o", os.fspath(output)]
    return json.loads(cli(*args, *_flags(options)))
