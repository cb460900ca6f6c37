"""hybrid_integrator: a hybrid rasterized + ray-traced renderer on Mitsuba 3 and Dr.Jit.

An implementation of Sabino et al., "A Hybrid GPU Rasterized and Ray Traced Rendering Pipeline for
Real Time Rendering of Per Pixel Effects" (ICEC 2012). A deferred rasterizer (moderngl, headless
EGL) resolves primary visibility into a visibility buffer / G-buffer (§3.1); Mitsuba traces the
secondary rays (§3.2).

    import mitsuba as mi; mi.set_variant("llvm_ad_rgb")
    import hybrid_integrator as hi
    gb = hi.rasterize(scene, sensor=0, offset=(0.5, 0.5), aovs=("normal", "albedo"))
"""
from .environment import pin_llvm

pin_llvm()  # before Dr.Jit's LLVM backend starts: see environment.py

from .api import camera_path, finish, rasterize, rasterizer, render, render_sequence  # noqa: E402
from .cache import forget  # noqa: E402
from .objects import SceneObjects, scene_objects  # noqa: E402
from .errors import (HybridError, RasterContextError, UnsupportedSceneError,  # noqa: E402
                     UnsupportedVariantError)
from .raster.gbuffer import AOV_CHANNELS, GBuffer  # noqa: E402
from .raster.visibility import Rasterizer, VisibilityBuffer  # noqa: E402
from .scene import load_scene  # noqa: E402
from .frames import render_frames  # noqa: E402

__all__ = ["load_scene", "rasterize", "render", "render_sequence", "finish", "render_frames", "camera_path", "register", "rasterizer", "forget",
           "scene_objects", "SceneObjects", "GBuffer", "VisibilityBuffer", "Rasterizer", "AOV_CHANNELS",
           "HybridError", "UnsupportedSceneError", "UnsupportedVariantError", "RasterContextError"]
__version__ = "0.1.0"


def register() -> None:
    """Register the ``hybrid`` integrator for the active Mitsuba variant. Importing the package
    does this for the variant set at that time; call it again after ``mi.set_variant``."""
    from .plugins.hybrid import register as _register

    _register()


def _register_for_active_variant() -> None:
    import mitsuba as mi

    if mi.variant() is not None:
        register()


_register_for_active_variant()
