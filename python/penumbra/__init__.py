"""penumbra: physically based soft shadows from geometry.

Visibility images (the share of a light's area that each camera pixel's surface point sees)
and visibility at sensor points, as numpy arrays, by every technique of the library and
measured against the same ray-cast truth::

    import penumbra as pb
    scene = pb.Scene.load("fixtures/scenes/spot.toml")
    v = scene.render("wedges-blend")        # (height, width) float32
    exact = scene.render("depth-complexity", samples=256, backend="cpu")
    print(pb.compare(v, exact)["penumbra_mae"])
"""

from ._penumbra import (
    Camera,
    DistantLight,
    Mesh,
    RectLight,
    Scene,
    __version__,
    compare,
    read_exr,
    techniques,
    write_colour_map,
    write_exr,
)
from . import batch, study

__all__ = [
    "batch",
    "study",
    "Camera",
    "DistantLight",
    "Mesh",
    "RectLight",
    "Scene",
    "__version__",
    "compare",
    "read_exr",
    "techniques",
    "write_colour_map",
    "write_exr",
]
