"""Type stubs of penumbra's native module (re-exported by the package `penumbra`)."""

import os
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

Vec3 = Union[Sequence[float], npt.ArrayLike]
Image = npt.NDArray[np.float32]
Images = Union[Image, Dict[str, Image]]

class Camera:
    """A pinhole camera looking from `eye` at `target`, `up` the image's up, `fov_y_deg` the
    vertical field of view in degrees, and an image of `width` x `height` pixels."""

    def __init__(
        self,
        eye: Vec3,
        target: Vec3,
        up: Optional[Vec3] = None,
        fov_y_deg: float = 45.0,
        width: int = 320,
        height: int = 240,
    ) -> None: ...
    @property
    def eye(self) -> Tuple[float, float, float]:
        """The eye's position."""
    @property
    def width(self) -> int:
        """The image's width in pixels."""
    @property
    def height(self) -> int:
        """The image's height in pixels."""

class RectLight:
    """A rectangular area light: its `center`, the `normal` it emits along, a `tangent` (the
    direction of its first side) and its `size` (the two sides' lengths), named `name`."""

    def __init__(
        self,
        center: Vec3,
        normal: Vec3,
        tangent: Vec3,
        size: Tuple[float, float],
        name: Optional[str] = None,
    ) -> None: ...
    @staticmethod
    def aimed(
        center: Vec3, target: Vec3, size: Tuple[float, float], name: Optional[str] = None
    ) -> "RectLight":
        """A light at `center` facing `target`, of `size`."""
    @property
    def center(self) -> Tuple[float, float, float]:
        """The light's centre."""
    @property
    def normal(self) -> Tuple[float, float, float]:
        """The unit normal it emits along."""
    @property
    def name(self) -> Optional[str]:
        """Its name, or None."""

class DistantLight:
    """A distant light (the sun): the rectangle of directions around `direction`, its sides
    along `tangent`, spanning `angular_size` degrees, named `name`."""

    def __init__(
        self,
        direction: Vec3,
        tangent: Vec3,
        angular_size: Tuple[float, float] = (0.53, 0.53),
        name: Optional[str] = None,
    ) -> None: ...
    @staticmethod
    def sun(
        azimuth_deg: float,
        elevation_deg: float,
        angular_size_deg: float = 0.53,
        name: Optional[str] = None,
    ) -> "DistantLight":
        """The sun at `azimuth_deg` (clockwise from north, north = -z, east = +x, up = +y)
        and `elevation_deg` above the horizon."""
    @property
    def direction(self) -> Tuple[float, float, float]:
        """The unit vector towards the light."""
    @property
    def name(self) -> Optional[str]:
        """Its name, or None."""

class Mesh:
    """A triangle mesh: `vertices` (n, 3) floats, `faces` (m, 3) vertex indices."""

    def __init__(self, vertices: npt.ArrayLike, faces: npt.ArrayLike, name: str = "mesh") -> None: ...
    @staticmethod
    def from_trimesh(mesh: Any, name: Optional[str] = None) -> "Mesh":
        """The mesh of a `trimesh.Trimesh`."""
    @property
    def vertices(self) -> npt.NDArray[np.float64]:
        """Its vertices, (n, 3) float64."""
    @property
    def triangle_count(self) -> int:
        """The number of triangles."""
    @property
    def name(self) -> str:
        """Its name."""

Light = Union[RectLight, DistantLight]
MeshEntry = Union[Mesh, Tuple[Mesh, npt.ArrayLike]]

class Scene:
    """A scene: a camera, one or more lights and triangle meshes."""

    def __init__(
        self, camera: Camera, lights: Union[Light, Sequence[Light]], meshes: Sequence[MeshEntry]
    ) -> None: ...
    @staticmethod
    def load(path: Union[str, os.PathLike]) -> "Scene":
        """The scene of a scene file (TOML)."""
    def with_size(self, width: int, height: int) -> "Scene":
        """The same scene seen at `width` x `height` pixels."""
    @property
    def width(self) -> int:
        """The image's width in pixels."""
    @property
    def height(self) -> int:
        """The image's height in pixels."""
    @property
    def light_names(self) -> List[str]:
        """The lights' names, in the scene's order."""
    @property
    def triangle_count(self) -> int:
        """The number of triangles."""
    def render(
        self,
        technique: str = "wedges-blend",
        samples: int = 256,
        backend: str = "auto",
        jitter: bool = False,
        light: Optional[str] = None,
        threads: Optional[int] = None,
    ) -> Images:
        """The visibility image by `technique`: (height, width) float32, or a dict from light
        name to image for a scene of several lights. `threads`: a pool of that many threads
        of the render's own (by default renders share a thread per core)."""
    def visibility_at(
        self,
        points: npt.ArrayLike,
        normals: npt.ArrayLike,
        light: Optional[str] = None,
        samples: int = 1024,
        technique: str = "depth-complexity",
        jitter: bool = False,
        threads: Optional[int] = None,
    ) -> Union[npt.NDArray[np.float32], Dict[str, npt.NDArray[np.float32]]]:
        """The visibility of sensor points with normals: (n,) float32."""

def write_exr(path: Union[str, os.PathLike], v: Images) -> None:
    """Writes an image, or a dict of images (one channel per light), to an EXR file."""

def write_colour_map(path: Union[str, os.PathLike], values: npt.ArrayLike, unit: str = "h") -> None:
    """Writes a (height, width) array of numbers from 0 up (hours of sun) as a PNG colour map
    with a legend in `unit` ("h" or "")."""

def read_exr(path: Union[str, os.PathLike]) -> Dict[str, Image]:
    """The visibility channels of an EXR file: channel name -> (height, width) float32."""

def compare(a: npt.ArrayLike, b: npt.ArrayLike) -> Dict[str, float]:
    """Metrics of `a` against the reference `b`: all pixels and penumbra pixels."""

def techniques() -> List[str]:
    """The techniques' names."""
