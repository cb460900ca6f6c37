"""Shared fixtures: the llvm_ad_rgb variant, scenes loaded once per session, sensors built on demand."""
from __future__ import annotations

from pathlib import Path

import hybrid_integrator  # pins LLVM 19 before Dr.Jit's LLVM backend starts
import mitsuba as mi
import pytest

from hybrid_integrator.raster.camera import sensor_like

mi.set_variant("llvm_ad_rgb")
hybrid_integrator.register()

ROOT = Path(__file__).resolve().parents[1]
SHARED_SCENES = ROOT.parent / "shared" / "scenes"
DEFAULT_SCENE = ROOT / "scenes" / "default.xml"

_SCENES: dict[tuple, mi.Scene] = {}


def load(path: Path, **params) -> mi.Scene:
    """Load a scene once per test session (objects kept apart: optimize=False)."""
    from hybrid_integrator.scene import load_scene

    key = (str(path), tuple(sorted(params.items())))
    if key not in _SCENES:
        if not Path(path).is_file():
            pytest.fail(f"test scene missing: {path} (../shared must sit beside the checkout)")
        _SCENES[key] = load_scene(path, **params)
    return _SCENES[key]


def make_sensor(scene: mi.Scene, width: int, height: int, fov_axis: str = "x", ppo=(0.0, 0.0)) -> mi.Sensor:
    """The scene camera's pose and x field of view with another film, fov axis or principal point."""
    return sensor_like(scene.sensors()[0], width, height, fov_axis, ppo)


@pytest.fixture(autouse=True)
def llvm_variant():
    """Every test starts (and ends) on llvm_ad_rgb, even one that switched variants (the CLI does)."""
    mi.set_variant("llvm_ad_rgb")
    yield
    mi.set_variant("llvm_ad_rgb")
    hybrid_integrator.register()


@pytest.fixture(autouse=True, scope="session")
def timed_draws():
    """One draw before any test: Mesa's llvmpipe times no draw the first in its process
    (``raster.context.gl_elapsed_ms``: the frame's ``gl`` is NaN then), so that a test's frame
    stats do not depend on whether an earlier test drew (``test_objects.py`` checks that first
    frame in a process of its own)."""
    hybrid_integrator.rasterize(load(DEFAULT_SCENE, resx=16, resy=12), method="draw")
