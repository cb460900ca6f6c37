"""The headless OpenGL context of the raster stage (paper §3.1, §7).

One standalone context per process, made through EGL so that no display server is needed: Mesa's
llvmpipe on a CPU machine, the NVIDIA driver on a GPU machine. moderngl's default (X11/GLX)
backend fails headless, hence ``backend='egl'``.
"""
from __future__ import annotations

import ctypes
import functools
import importlib.resources
import platform

import moderngl

from ..errors import RasterContextError

#: Debian packages that provide a headless EGL + OpenGL driver on a machine without a GPU
SYSTEM_PACKAGES = "libegl1 libgl1 libgl1-mesa-dri"

#: the oldest OpenGL the raster stage needs: 4.5 for ``glClipControl`` (reversed-Z depth, below)
REQUIRED_GL = 450


#: ``EGL_NV_device_cuda``: the CUDA device number of an EGL device
_EGL_CUDA_DEVICE_NV = 0x323A


def _proc_address(name: str) -> int | None:
    """``eglGetProcAddress(name)``: the address of an EGL or OpenGL entry point (None: the driver
    has none). Raises ``OSError`` where there is no ``libEGL``."""
    egl = ctypes.CDLL("libEGL.so.1")
    egl.eglGetProcAddress.restype = ctypes.c_void_p
    egl.eglGetProcAddress.argtypes = [ctypes.c_char_p]
    return egl.eglGetProcAddress(name.encode())


def egl_device_of_cuda(ordinal: int = 0) -> int | None:
    """Index of the EGL device that is CUDA device ``ordinal`` (Dr.Jit's is 0), or None where EGL
    cannot say (Mesa, no ``EGL_NV_device_cuda``).

    EGL enumerates GPUs in its own order and ignores ``CUDA_VISIBLE_DEVICES`` (which Ray sets per
    worker), so on a machine with several GPUs EGL device 0 may be another GPU than Dr.Jit's: the
    raster stage would then draw on a GPU that its interop cannot read (CUDA–GL interop needs the
    GL context on the CUDA device) and share that GPU with another worker."""
    try:
        query, attribute = (_proc_address(name) for name in ("eglQueryDevicesEXT", "eglQueryDeviceAttribEXT"))
    except OSError:
        return None
    if not query or not attribute:
        return None
    query = ctypes.CFUNCTYPE(ctypes.c_uint, ctypes.c_int, ctypes.POINTER(ctypes.c_void_p),
                             ctypes.POINTER(ctypes.c_int))(query)
    attribute = ctypes.CFUNCTYPE(ctypes.c_uint, ctypes.c_void_p, ctypes.c_int,
                                 ctypes.POINTER(ctypes.c_ssize_t))(attribute)  # EGLAttrib is intptr_t
    devices, count = (ctypes.c_void_p * 32)(), ctypes.c_int(0)
    if not query(32, devices, ctypes.byref(count)):
        return None
    for index in range(count.value):
        number = ctypes.c_ssize_t(-1)
        if attribute(devices[index], _EGL_CUDA_DEVICE_NV, ctypes.byref(number)) and number.value == ordinal:
            return index
    return None


@functools.lru_cache(maxsize=1)
def gl_context() -> moderngl.Context:
    """Return the process's headless OpenGL context, creating it on first use: with a CUDA variant
    on the EGL device of Dr.Jit's CUDA device (:func:`egl_device_of_cuda`), otherwise on EGL's
    first device (``GLCONTEXT_DEVICE_INDEX`` overrides both).

    Raises :class:`RasterContextError`, naming the system packages to install, when EGL or an
    OpenGL driver is missing, or when the driver is older than OpenGL 3.3."""
    import mitsuba as mi

    device = egl_device_of_cuda() if mi.variant() and mi.variant().startswith("cuda") else None
    try:
        ctx = moderngl.create_standalone_context(backend="egl", require=REQUIRED_GL,
                                                 **({} if device is None else {"device_index": device}))
    except Exception as exc:  # moderngl/glcontext raise plain Exceptions with the EGL reason
        raise RasterContextError(
            f"cannot create a headless OpenGL {REQUIRED_GL // 100}.{REQUIRED_GL % 100 // 10} context "
            f"through EGL ({exc}). On Debian/Ubuntu install the system packages: apt-get install "
            f"{SYSTEM_PACKAGES}") from exc
    return ctx


def max_target_side(ctx: moderngl.Context) -> int:
    """The most pixels per side of a render target this context draws: its textures',
    renderbuffers' and viewports' limits (16384 on Mesa's llvmpipe)."""
    info = ctx.info
    return min(info["GL_MAX_TEXTURE_SIZE"], info["GL_MAX_RENDERBUFFER_SIZE"], *info["GL_MAX_VIEWPORT_DIMS"])


def shader_source(name: str) -> str:
    """The GLSL source of ``raster/shaders/NAME``."""
    return importlib.resources.files(__package__).joinpath("shaders", name).read_text()


def renderer_name() -> str:
    """The OpenGL renderer string (e.g. 'llvmpipe (LLVM 15.0.6, 256 bits)'), for reports."""
    return gl_context().info["GL_RENDERER"]


def machine() -> dict[str, str]:
    """What a measurement ran on: Mitsuba variant, OpenGL renderer, CPU model and cores (for
    reports: the host's speed shows in every frame's issue time)."""
    import os

    import mitsuba as mi

    model = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as info:
            model = next(line.split(":", 1)[1].strip() for line in info if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return {"variant": mi.variant(), "gl_renderer": renderer_name(), "cpu": f"{model}, {os.cpu_count()} threads"}


# OpenGL enums of the calls below (glcorearb.h)
_GL_LOWER_LEFT, _GL_NEGATIVE_ONE_TO_ONE, _GL_ZERO_TO_ONE = 0x8CA1, 0x935E, 0x935F
_GL_FRAMEBUFFER, _GL_RENDERBUFFER, _GL_DEPTH_ATTACHMENT = 0x8D40, 0x8D41, 0x8D00
_GL_DEPTH_COMPONENT32F, _GL_FRAMEBUFFER_COMPLETE = 0x8CAC, 0x8CD5


def gl_entry(name: str, *args, restype=None):
    """An OpenGL entry point of the current context that moderngl does not expose, as a ctypes
    function (through ``eglGetProcAddress``)."""
    address = _proc_address(name)
    if not address:
        raise RasterContextError(f"the OpenGL driver has no {name} (OpenGL 4.5 is needed)")
    return ctypes.CFUNCTYPE(restype, *args)(address)


@functools.lru_cache(maxsize=1)
def _gl_flush_entry():
    gl_context()
    return gl_entry("glFlush")


#: what Mesa 22's llvmpipe answers a timer query around the first draw call of a process (checked
#: alone: a fresh context's first ``Rasterizer.render`` by ``draw`` reads 4294967295 ns, the next
#: ones a few ms; its compute dispatches and NVIDIA's driver give times): no time at all
_NO_TIME = 0xFFFFFFFF


def gl_elapsed_ms(query) -> float:
    """The GPU time (ms) a moderngl timer query measured, or NaN where the driver gave none
    (``_NO_TIME``)."""
    ns = query.elapsed
    return float("nan") if ns >= _NO_TIME else ns * 1e-6


def gl_flush() -> None:
    """``glFlush``: hand the commands the driver has buffered to the GPU without waiting for them
    (moderngl has only ``glFinish``, which waits). A timer query's end, issued after the raster
    pass, otherwise sits in the buffer until the next call that flushes, and its time then spans
    the whole frame."""
    _gl_flush_entry()()


class DepthPrecision:
    """Reversed-Z depth with a 32-bit float depth buffer, which moderngl does not expose.

    A float depth buffer that stores ``near / z`` (1 at the near plane, → 0 at infinity; OpenGL's
    ``glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE)`` keeps it from being remapped to [−1, 1]) has
    the same *relative* precision (~1e-7) at every distance, like the ray tracer's own floats: a
    24-bit 1/z buffer loses millimetres a few metres away, and writing a linear depth from the
    fragment shader (``gl_FragDepth``) would switch off early depth testing. The few OpenGL 4.5
    entry points needed are called through ``eglGetProcAddress`` in the context moderngl made."""

    def __init__(self):
        entry = gl_entry
        u = ctypes.c_uint
        self._clip_control = entry("glClipControl", u, u)
        self._gen_renderbuffers = entry("glGenRenderbuffers", ctypes.c_int, ctypes.POINTER(u))
        self._bind_renderbuffer = entry("glBindRenderbuffer", u, u)
        self._renderbuffer_storage = entry("glRenderbufferStorage", u, u, ctypes.c_int, ctypes.c_int)
        self._bind_framebuffer = entry("glBindFramebuffer", u, u)
        self._framebuffer_renderbuffer = entry("glFramebufferRenderbuffer", u, u, u, u)
        self._check_framebuffer = entry("glCheckFramebufferStatus", u, restype=u)

    def attach_float_depth(self, framebuffer: moderngl.Framebuffer, size: tuple[int, int]) -> None:
        """Replace ``framebuffer``'s depth attachment with a 32-bit float depth buffer."""
        buffer = ctypes.c_uint()
        self._gen_renderbuffers(1, ctypes.byref(buffer))
        self._bind_renderbuffer(_GL_RENDERBUFFER, buffer.value)
        self._renderbuffer_storage(_GL_RENDERBUFFER, _GL_DEPTH_COMPONENT32F, int(size[0]), int(size[1]))
        self._bind_framebuffer(_GL_FRAMEBUFFER, framebuffer.glo)
        self._framebuffer_renderbuffer(_GL_FRAMEBUFFER, _GL_DEPTH_ATTACHMENT, _GL_RENDERBUFFER, buffer.value)
        status = self._check_framebuffer(_GL_FRAMEBUFFER)
        if status != _GL_FRAMEBUFFER_COMPLETE:
            raise RasterContextError(f"a framebuffer with a 32-bit float depth buffer is incomplete (0x{status:x})")

    def zero_to_one(self, enabled: bool) -> None:
        """Clip-space depth in [0, w] (reversed Z) or OpenGL's default [−w, w]."""
        self._clip_control(_GL_LOWER_LEFT, _GL_ZERO_TO_ONE if enabled else _GL_NEGATIVE_ONE_TO_ONE)


@functools.lru_cache(maxsize=1)
def depth_precision() -> DepthPrecision:
    """The reversed-Z helpers of the process's context (made with it)."""
    gl_context()
    return DepthPrecision()
