"""Shared helpers: the repository's fixtures, the `penumbra` command built by the Rust tests,
and scene files rewritten to a smaller image."""

import os
import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
FIXTURES = ROOT / "fixtures" / "scenes"


def fixture_names():
    return sorted(p.stem for p in FIXTURES.glob("*.toml"))


@pytest.fixture(scope="session")
def cli():
    """The `penumbra` command: $PENUMBRA_BIN, else the one `cargo test` or `cargo build`
    left in target/ (built here if there is none)."""
    given = os.environ.get("PENUMBRA_BIN")
    if given:
        return given
    for profile in ("debug", "release"):
        p = ROOT / "target" / profile / "penumbra"
        if p.exists():
            return str(p)
    subprocess.run(["cargo", "build", "-p", "penumbra-tools"], cwd=ROOT, check=True)
    return str(ROOT / "target" / "debug" / "penumbra")


def small_scene(src: Path, dest_dir: Path, width: int, height: int) -> Path:
    """A copy of the scene file `src` in `dest_dir` seen at `width` x `height` pixels, its
    mesh files named by absolute paths."""
    text = src.read_text()
    text = re.sub(r"(?m)^width = \d+", f"width = {width}", text)
    text = re.sub(r"(?m)^height = \d+", f"height = {height}", text)

    def absolute(m):
        return f'{m.group(1)} = "{(src.parent / m.group(2)).resolve()}"'

    text = re.sub(r'(?m)^(obj|gltf|ply) = "([^"]+)"', absolute, text)
    dest = dest_dir / src.name
    dest.write_text(text)
    return dest
