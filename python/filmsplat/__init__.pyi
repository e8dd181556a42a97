"""Type stubs of filmsplat. Units: positions, radii and depths in scene units; thickness and
wavelengths in nanometres; angles in degrees; sizes in pixels."""

import os
from typing import Any, Callable, Iterable, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

_Path = Union[str, "os.PathLike[str]"]
_Floats = npt.ArrayLike
_Progress = Union[None, bool, Callable[[int, int], Any]]

__version__: str

class Cloud:
    """A thin-film particle cloud; arrays (float32 or float64, any strides) are copied once."""

    def __init__(
        self,
        positions: _Floats,
        normals: Optional[_Floats] = None,
        thickness_nm: Optional[_Floats] = None,
        radius: Optional[_Floats] = None,
        attributes: Optional[Mapping[str, _Floats]] = None,
    ) -> None: ...
    @property
    def positions(self) -> npt.NDArray[np.float32]:
        """Particle centres, scene units, (N, 3)."""
    @property
    def normals(self) -> Optional[npt.NDArray[np.float32]]:
        """Film normals (N, 3), or None."""
    @property
    def thickness_nm(self) -> Optional[npt.NDArray[np.float32]]:
        """Film thickness, nm, (N,), or None."""
    @property
    def radius(self) -> Optional[npt.NDArray[np.float32]]:
        """Splat radius, scene units, (N,), or None."""
    @property
    def attributes(self) -> dict[str, npt.NDArray[np.float32]]:
        """Every other per-particle attribute by name, (N,) each."""
    def __len__(self) -> int: ...

class Image:
    """A rendered image, a view, or the chart."""

    @property
    def width(self) -> int:
        """Width, pixels."""
    @property
    def height(self) -> int:
        """Height, pixels."""
    @property
    def view(self) -> str:
        """"shaded", "thickness", "normal", "depth", "particle-id", "coverage" or "chart"."""
    @property
    def rgb(self) -> npt.NDArray[np.float32]:
        """Linear RGB, (H, W, 3), top row first."""
    @property
    def alpha(self) -> Optional[npt.NDArray[np.float32]]:
        """Fraction of each pixel's samples that hit a film, (H, W); None for views."""
    @property
    def layers(self) -> dict[str, npt.NDArray[np.float32]]:
        """depth (scene units), normal (H, W, 3), thickness (nm), hits (splats blended) at the
        first crossing; empty for views."""
    @property
    def rays(self) -> int:
        """Rays traced (0 for views)."""
    def to_srgb8(self) -> npt.NDArray[np.uint8]:
        """The displayed picture, sRGB-encoded (H, W, 3), as the CLI's PNG."""
    def save(self, path: _Path) -> None:
        """Writes .png (display) or .exr (linear RGBA + layers) with the CLI's writers."""
    def _repr_png_(self) -> bytes: ...

class Scene:
    """Particles turned into geometry once, rendered as often as asked."""

    def __init__(
        self,
        clouds: Union[Cloud, Sequence[Cloud], _Path, None],
        primitive: str = "disk",
        preset: str = "balanced",
        environment: Union[None, str, _Path, Mapping[str, Any]] = None,
        lights: Iterable[Mapping[str, Any]] = (),
        props: Iterable[Mapping[str, Any]] = (),
        **knobs: Any,
    ) -> None: ...
    @classmethod
    def from_file(cls, path: _Path) -> "Scene":
        """The scene of a scene file (TOML)."""
    @property
    def particles(self) -> int: ...
    @property
    def notes(self) -> list[str]: ...
    @property
    def size(self) -> Tuple[int, int]:
        """(width, height), pixels."""
    @property
    def build_seconds(self) -> dict[str, float]:
        """Seconds for load, estimate and build."""
    def render(
        self,
        camera: Optional[Mapping[str, Any]] = None,
        size: Optional[Tuple[int, int]] = None,
        spp: Optional[int] = None,
        view: Optional[str] = None,
        seed: Optional[int] = None,
        progress: _Progress = None,
        orbit: Optional[float] = None,
    ) -> Image:
        """Renders (GIL released, all cores; Ctrl-C raises KeyboardInterrupt)."""

def read(
    path: _Path,
    thickness_attr: Optional[str] = None,
    thickness_unit: Optional[str] = None,
    normal_attr: Optional[str] = None,
    radius_attr: Optional[str] = None,
) -> Cloud:
    """Reads any particle file or frame folder the CLI reads; thickness in nm."""

def film(
    thickness_nm: _Floats, angle_deg: _Floats, wavelength_nm: _Floats, ior: float = 1.33
) -> dict[str, npt.NDArray[np.float64]]:
    """R, T, Rs, Rp of a film (air | ior | air), broadcasting like numpy."""

def film_rgb(
    thickness_nm: _Floats, angle_deg: _Floats, ior: float = 1.33
) -> npt.NDArray[np.float64]:
    """Linear sRGB colour of D65 light reflected by a film; shape (..., 3)."""

def chart(
    path: Optional[_Path] = None,
    max_thickness_nm: float = 1500.0,
    ior: float = 1.33,
    max_angle_deg: float = 89.0,
    size: Tuple[int, int] = (1600, 900),
) -> Image:
    """The interference colour chart."""

def compare(
    a: str, b: str, input: _Path, output: _Path = "compare.png", **options: Any
) -> dict[str, Any]:
    """The metrics dict of ``filmsplat compare A B INPUT --json``."""

def movie(
    input: _Path,
    output: _Path = "movie.mp4",
    frames: Union[str, range, Tuple[int, int]] = "0..24",
    fps: Optional[float] = None,
    crf: Optional[int] = None,
    progress: bool = True,
    **options: Any,
) -> str:
    """Renders a sequence into a movie (.mp4 H.264 or .webm VP9) with ffmpeg; returns its path."""

def cli(*args: _Path) -> str:
    """Runs the filmsplat command line in-process; returns its stdout."""

def orbit(angle_deg: float, elevation: float = 0.3, fov: Optional[float] = None) -> dict[str, Any]:
    """A camera dict circling the scene about +y, for turntables."""
