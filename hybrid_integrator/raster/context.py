"""The headless OpenGL context of the raster stage (paper §3.1, §7).

One standalone context per process, made through EGL so that no display server is needed: Mesa's
llvmpipe on a CPU machine, the NVIDIA driver on a GPU machine. moderngl's default (X11/GLX)
backend fails headless, hence ``backend='egl'``.
"""
from __future__ import annotations

import functools
import platform

import moderngl

from ..errors import RasterContextError

#: Debian packages that provide a headless EGL + OpenGL driver on a machine without a GPU
SYSTEM_PACKAGES = "libegl1 libgl1 libgl1-mesa-dri"

#: the oldest OpenGL the raster shaders are written for (integer targets, geometry shaders)
REQUIRED_GL = 330


@functools.lru_cache(maxsize=1)
def gl_context() -> moderngl.Context:
    """Return the process's headless OpenGL context, creating it on first use.

    Raises :class:`RasterContextError`, naming the system packages to install, when EGL or an
    OpenGL driver is missing, or when the driver is older than OpenGL 3.3."""
    try:
        ctx = moderngl.create_standalone_context(backend="egl", require=REQUIRED_GL)
    except Exception as exc:  # moderngl/glcontext raise plain Exceptions with the EGL reason
        raise RasterContextError(
            f"cannot create a headless OpenGL {REQUIRED_GL // 100}.{REQUIRED_GL % 100 // 10} context "
            f"through EGL ({exc}). On Debian/Ubuntu install the system packages: apt-get install "
            f"{SYSTEM_PACKAGES}") from exc
    return ctx


def renderer_name() -> str:
    """The OpenGL renderer string (e.g. 'llvmpipe (LLVM 15.0.6, 256 bits)'), for reports."""
    return gl_context().info["GL_RENDERER"]


def machine() -> dict[str, str]:
    """What a measurement ran on: Mitsuba variant, OpenGL renderer, CPU (for reports)."""
    import mitsuba as mi

    return {"variant": mi.variant(), "gl_renderer": renderer_name(), "cpu": platform.processor() or platform.machine()}
