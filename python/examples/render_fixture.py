"""Renders a fixture scene by penumbra wedges and exactly, compares the two, and writes both
as EXR files: `python python/examples/render_fixture.py [OUT_DIR]` from the repository's root."""

import os
import sys
from pathlib import Path

import penumbra as pb

root = Path(__file__).resolve().parents[2]
out = Path(sys.argv[1] if len(sys.argv) > 1 else "out")
out.mkdir(parents=True, exist_ok=True)

scene = pb.Scene.load(root / "fixtures" / "scenes" / "spot.toml")
if os.environ.get("PENUMBRA_EXAMPLE_SMALL"):
    scene = scene.with_size(80, 60)
wedges = scene.render("wedges-blend", backend="cpu")
exact = scene.render("depth-complexity", samples=256, backend="cpu")
c = pb.compare(wedges, exact)
print(f"{scene}: wedges-blend against depth-complexity: MAE {c['mae']:.4f}, "
      f"penumbra MAE {c['penumbra_mae']:.4f} over {c['penumbra_pixels']} penumbra pixels")
pb.write_exr(out / "spot-wedges.exr", wedges)
pb.write_exr(out / "spot-exact.exr", exact)
print(f"wrote {out / 'spot-wedges.exr'} and {out / 'spot-exact.exr'}")
