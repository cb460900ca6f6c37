"""CUDA–OpenGL interop: the raster targets reach Dr.Jit without crossing the host (paper §7).

Sabino et al. share their G-buffer between OpenGL and OptiX rather than copying it through the
CPU (§7). Here the visibility pass's one target (a triangle number per pixel, an ``R32UI``
texture) is registered once with CUDA (``cuGraphicsGLRegisterImage``), mapped every pass, and its
CUDA array copied device to device into a Dr.Jit array (``cuMemcpy2DAsync``) on Dr.Jit's own CUDA
stream: OpenGL does no read of its own (a ``glReadPixels`` into a pixel buffer, the way before,
added 0.13 ms per pass to the H100's OpenGL time at 1280×720), and nothing waits on the host (mapping orders
the copy after the OpenGL commands that drew the texture, and the stream orders the kernels after
it). The texture stays mapped after the copy until the frame's work is issued
(:meth:`Readback.release`, which the renderer calls at the end of each frame, where the host waits
for the GPU, and the rasterizer before it draws or reads): unmapped right after the copy, the
unmap held up the kernels issued after it, and DR frames took 0.2–0.5 ms longer on the H100 where
the GPU, not the host, bounds them (``docs/results/gpu/issue10/unmap``). Memory both APIs share
with no map or unmap (``GL_EXT_memory_object_fd``, ordered through the host) was no faster one
frame at a time and slower in flight: the unmap also orders OpenGL's next pass behind CUDA's frame
on the GPU, which the host cannot (``docs/results/gpu/issue10/stop44``).

The copy goes through the CUDA driver API (``libcuda`` via ctypes) in the device's primary
context, which Dr.Jit's CUDA backend shares: Dr.Jit 1.5's own ``dr.cuda.register_gl_buffer``
stops the process with ``CUDA_ERROR_INVALID_CONTEXT`` on a headless EGL context. Interop is used
only with a CUDA variant and a GL driver on a CUDA device, and only after the first copy has been
checked against the host path; otherwise :class:`Readback` reads through the host, and says why
(``FrameStats.readback``).
"""
from __future__ import annotations

import contextlib
import ctypes
from pathlib import Path

import drjit as dr
import mitsuba as mi
import moderngl
import numpy as np


class _DLDevice(ctypes.Structure):
    _fields_ = [("device_type", ctypes.c_int), ("device_id", ctypes.c_int)]


class _DLDataType(ctypes.Structure):
    _fields_ = [("code", ctypes.c_uint8), ("bits", ctypes.c_uint8), ("lanes", ctypes.c_uint16)]


class _DLTensor(ctypes.Structure):
    _fields_ = [("data", ctypes.c_void_p), ("device", _DLDevice), ("ndim", ctypes.c_int), ("dtype", _DLDataType),
                ("shape", ctypes.c_void_p), ("strides", ctypes.c_void_p), ("byte_offset", ctypes.c_uint64)]


_capsule_pointer = ctypes.pythonapi.PyCapsule_GetPointer
_capsule_pointer.restype, _capsule_pointer.argtypes = ctypes.c_void_p, [ctypes.py_object, ctypes.c_char_p]


def device_pointer(array) -> int:
    """Device address of an evaluated Dr.Jit CUDA array (from its DLPack export)."""
    capsule = array.__dlpack__()  # alive while its tensor is read: its destructor frees the tensor
    tensor = _DLTensor.from_address(_capsule_pointer(capsule, b"dltensor"))
    if not tensor.data:
        raise RuntimeError("a Dr.Jit array exported no device pointer")
    return int(tensor.data) + int(tensor.byte_offset)


def drjit_stream() -> ctypes.c_void_p:
    """Dr.Jit's CUDA stream (drjit-core's ``jit_cuda_stream()``), so that the copy is ordered with
    the kernels that read it without a host synchronization; the legacy default stream (which
    waits for every other blocking stream) where the symbol cannot be found."""
    try:
        core = ctypes.CDLL(str(Path(dr.__file__).parent / "libdrjit-core.so"))
        stream = core._Z15jit_cuda_streamv  # C++ symbol of `void *jit_cuda_stream()`
    except (OSError, AttributeError):
        return ctypes.c_void_p(0)
    stream.restype = ctypes.c_void_p
    return ctypes.c_void_p(stream())


#: the alignment (bytes) the LLVM backend's vectors want of memory it maps (AVX-512: 16 floats)
_ALIGNMENT = 64


def device_array(dtype, values: np.ndarray):
    """A host array as a Dr.Jit array of ``dtype``, made the same way every frame. The LLVM backend
    maps a NumPy array's memory instead of copying it, and a frozen function records itself again
    whenever the alignment of such an input changes (``dr.freeze``'s documentation): NumPy's small
    arrays (a frame's camera, seeds, tables; a small visibility buffer) are aligned or not at
    random, so each is first copied into 64-byte-aligned memory, which Dr.Jit then maps. (On CUDA
    the array is copied to the device in any case.)"""
    values = np.ascontiguousarray(values)
    if dr.backend_v(dtype) == dr.JitBackend.LLVM:
        buffer = np.empty(values.nbytes + _ALIGNMENT, dtype=np.uint8)
        start = -buffer.ctypes.data % _ALIGNMENT
        aligned = buffer[start:start + values.nbytes].view(values.dtype)
        aligned[...] = values.ravel()
        values = aligned
    return dtype(values)


class _Driver:
    """The few CUDA driver calls interop needs, in the primary context of device 0 (Dr.Jit's)."""

    def __init__(self):
        self.lib = ctypes.CDLL("libcuda.so.1")
        self.context = ctypes.c_void_p()
        self._check(self.lib.cuInit(0), "cuInit")
        self._check(self.lib.cuDevicePrimaryCtxRetain(ctypes.byref(self.context), 0), "cuDevicePrimaryCtxRetain")
        dr.eval(mi.UInt32(0))  # Dr.Jit's CUDA backend (and its stream) exist from here on
        self.stream = drjit_stream()
        if self._current() is None:  # as the runtime API would on first use: a thread with no context gets this one
            self._check(self.lib.cuCtxSetCurrent(self.context), "cuCtxSetCurrent")

    def _current(self) -> int | None:
        """The calling thread's current context (None: none)."""
        context = ctypes.c_void_p()
        self._check(self.lib.cuCtxGetCurrent(ctypes.byref(context)), "cuCtxGetCurrent")
        return context.value

    @staticmethod
    def _check(code: int, call: str) -> None:
        if code != 0:
            raise RuntimeError(f"{call} returned CUDA error {code}")

    def call(self, name: str, *args) -> None:
        with self.current():
            self.call_current(name, *args)

    def call_current(self, name: str, *args) -> None:
        """A driver call where :meth:`current` has made the context current."""
        self._check(getattr(self.lib, name)(*args), name)

    def copy_async(self, pairs, nbytes: int) -> None:
        """Device-to-device copies of ``nbytes`` each, ``(destination, source)`` addresses, on
        Dr.Jit's stream: ordered after the kernels issued before them, waited for by none."""
        with self.current():
            for target, source in pairs:
                self.call_current("cuMemcpyDtoDAsync_v2", ctypes.c_uint64(target), ctypes.c_uint64(source),
                                  ctypes.c_size_t(nbytes), self.stream)

    @contextlib.contextmanager
    def current(self):
        """The primary context current on the calling thread for the calls made inside: pushed and
        popped only where another (or none) is current. The thread that made the driver has it
        current (:meth:`__init__`), and on the H200 none of a frame's groups of calls needed the push
        and the pop, which cost ~0.01 ms of host time each, ~0.1 ms per frame (docs/results/gpu/issue10/stop58)."""
        if self._current() == self.context.value:
            yield
            return
        self._check(self.lib.cuCtxPushCurrent_v2(self.context), "cuCtxPushCurrent")
        try:
            yield
        finally:
            self.lib.cuCtxPopCurrent_v2(ctypes.byref(ctypes.c_void_p()))


class _Memcpy2D(ctypes.Structure):
    """The driver's ``CUDA_MEMCPY2D``."""

    _fields_ = [("srcXInBytes", ctypes.c_size_t), ("srcY", ctypes.c_size_t), ("srcMemoryType", ctypes.c_int),
                ("srcHost", ctypes.c_void_p), ("srcDevice", ctypes.c_uint64), ("srcArray", ctypes.c_void_p),
                ("srcPitch", ctypes.c_size_t), ("dstXInBytes", ctypes.c_size_t), ("dstY", ctypes.c_size_t),
                ("dstMemoryType", ctypes.c_int), ("dstHost", ctypes.c_void_p), ("dstDevice", ctypes.c_uint64),
                ("dstArray", ctypes.c_void_p), ("dstPitch", ctypes.c_size_t), ("WidthInBytes", ctypes.c_size_t),
                ("Height", ctypes.c_size_t)]


class _SharedImage:
    """A GL texture registered with CUDA once, copied into a Dr.Jit array per frame."""

    _TEXTURE_2D = 0x0DE1  # GL_TEXTURE_2D
    _ARRAY, _DEVICE = 3, 2  # CU_MEMORYTYPE_ARRAY, CU_MEMORYTYPE_DEVICE

    def __init__(self, texture: moderngl.Texture, driver: _Driver):
        self.driver, self.size = driver, texture.size
        self.resource = ctypes.c_void_p()
        self.mapped = False
        driver.call("cuGraphicsGLRegisterImage", ctypes.byref(self.resource), ctypes.c_uint(texture.glo),
                    ctypes.c_uint(self._TEXTURE_2D), ctypes.c_uint(1))  # CU_GRAPHICS_REGISTER_FLAGS_READ_ONLY

    def copy(self, array_type, bytes_per_pixel: int = 4):
        """Map (unless still mapped) and copy device to device on Dr.Jit's stream, both
        asynchronous; the texture stays mapped until :meth:`release`. Mapping orders the copy after
        the OpenGL commands that drew the texture."""
        w, h = self.size
        out = dr.empty(array_type, w * h)
        dr.eval(out)
        array = ctypes.c_void_p()
        stream, call = self.driver.stream, self.driver.call_current
        row = w * bytes_per_pixel
        with self.driver.current():
            if not self.mapped:
                call("cuGraphicsMapResources", 1, ctypes.byref(self.resource), stream)
                self.mapped = True
            call("cuGraphicsSubResourceGetMappedArray", ctypes.byref(array), self.resource, 0, 0)
            copy = _Memcpy2D(srcMemoryType=self._ARRAY, srcArray=array, dstMemoryType=self._DEVICE,
                             dstDevice=device_pointer(out), dstPitch=row, WidthInBytes=row, Height=h)
            call("cuMemcpy2DAsync_v2", ctypes.byref(copy), stream)
        return out

    def release(self) -> None:
        """Unmap, on Dr.Jit's stream: OpenGL's next commands on the texture wait for the copies
        issued before."""
        if self.mapped:
            self.mapped = False
            self.driver.call("cuGraphicsUnmapResources", 1, ctypes.byref(self.resource), self.driver.stream)


class Readback:
    """The visibility pass's target as a Dr.Jit array: through interop where it works (module
    docstring), else through the host. ``mode`` says which, with the reason for the host."""

    def __init__(self):
        self.mode = "host"
        self._images: dict[int, _SharedImage] = {}  # by GL texture name
        self._driver = None
        self._verified = False
        if not mi.variant().startswith("cuda"):
            self.mode = f"host ({mi.variant()} is not a CUDA variant)"
            return
        try:
            self._driver = _Driver()
            self.mode = "cuda-gl-interop"
        except (OSError, RuntimeError) as exc:
            self.mode = f"host (no CUDA driver for interop: {exc})"

    def ids(self, fbo: moderngl.Framebuffer, host_read) -> mi.UInt32:
        """The triangle-number target of ``fbo``; ``host_read(fbo)`` is the host path
        (``Rasterizer.read_ids``, which calls :meth:`release` before OpenGL reads)."""
        if self._driver is not None:
            try:
                shared = self._interop(fbo)
                if not self._verified:  # the first copy must equal the host's, or interop is off
                    copied = np.array(shared)  # before host_read, which hands the texture back to OpenGL
                    if not np.array_equal(copied, host_read(fbo)):
                        raise RuntimeError("the interop copy differs from the host read-back")
                    self._verified = True
                return shared
            except Exception as exc:  # noqa: BLE001 - any failure of interop falls back, and says why
                self._driver, self.mode = None, f"host (interop failed: {type(exc).__name__}: {exc})"
        return device_array(mi.UInt32, host_read(fbo))

    def release(self) -> None:
        """Hand every texture copied from back to OpenGL: call before OpenGL draws into or reads
        any of them (mapped to CUDA, OpenGL's access to them is undefined)."""
        for image in self._images.values():
            image.release()

    def _interop(self, fbo: moderngl.Framebuffer) -> mi.UInt32:
        texture = fbo.color_attachments[0]
        if texture.glo not in self._images:
            self._images[texture.glo] = _SharedImage(texture, self._driver)
        return self._images[texture.glo].copy(mi.UInt32)


class HostCopy:
    """32-bit words of evaluated Dr.Jit CUDA arrays copied to the host on Dr.Jit's stream, behind
    the kernels issued before them and ahead of those issued after (``cuMemcpyDtoHAsync`` into
    page-locked memory, then an event), so that the host can wait for them alone while the GPU
    goes on with later work. (Reading an array with ``np.array`` waits for everything issued.)
    The pipeline reads a frame's counts this way and learns from them while the GPU develops and
    denoises the frame (``pipeline.HybridRenderer.render``)."""

    def __init__(self):
        self.driver = _Driver()
        self.event = ctypes.c_void_p()
        self.driver.call("cuEventCreate", ctypes.byref(self.event), ctypes.c_uint(2))  # CU_EVENT_DISABLE_TIMING
        self._host, self._capacity, self._sizes = ctypes.c_void_p(), 0, []

    def start(self, arrays: list) -> None:
        """Issue the copies of ``arrays`` (UInt32, evaluated) and the event after them."""
        self._sizes = [dr.width(a) for a in arrays]
        nbytes = 4 * sum(self._sizes)
        with self.driver.current():
            if nbytes > self._capacity:
                if self._host:
                    self.driver.call_current("cuMemFreeHost", self._host)
                self.driver.call_current("cuMemAllocHost_v2", ctypes.byref(self._host), ctypes.c_size_t(nbytes))
                self._capacity = nbytes
            offset = 0
            for array, size in zip(arrays, self._sizes):
                self.driver.call_current("cuMemcpyDtoHAsync_v2", ctypes.c_void_p(self._host.value + offset),
                                         ctypes.c_uint64(device_pointer(array)), ctypes.c_size_t(4 * size),
                                         self.driver.stream)
                offset += 4 * size
            self.driver.call_current("cuEventRecord", self.event, self.driver.stream)

    def sync(self) -> None:
        """Wait for the copies issued by :meth:`start` (not for the work issued after them)."""
        self.driver.call("cuEventSynchronize", self.event)

    def wait(self) -> list[np.ndarray]:
        """:meth:`sync`, then each array's words (copies: the buffer is reused)."""
        self.sync()
        words = np.ctypeslib.as_array((ctypes.c_uint32 * sum(self._sizes)).from_address(self._host.value)).copy()
        return np.split(words, np.cumsum(self._sizes)[:-1])


class StreamTimer:
    """Device time of work issued on Dr.Jit's CUDA stream by another library (CUDA events: what
    Dr.Jit's kernel history cannot see), read after the frame's synchronization."""

    def __init__(self):
        self.driver = _Driver()
        self.events = [ctypes.c_void_p(), ctypes.c_void_p()]
        for event in self.events:
            self.driver.call("cuEventCreate", ctypes.byref(event), ctypes.c_uint(0))

    def start(self) -> None:
        self.driver.call("cuEventRecord", self.events[0], self.driver.stream)

    def stop(self) -> None:
        self.driver.call("cuEventRecord", self.events[1], self.driver.stream)

    def wait(self) -> None:
        """Wait until the work issued before :meth:`stop` is done (not the work issued after it)."""
        self.driver.call("cuEventSynchronize", self.events[1])

    def elapsed_ms(self, since: "StreamTimer | None" = None) -> float:
        """Device ms from :meth:`start` (or from ``since``'s :meth:`stop`) to :meth:`stop`."""
        ms = ctypes.c_float()
        first = self.events[0] if since is None else since.events[1]
        self.driver.call("cuEventElapsedTime", ctypes.byref(ms), first, self.events[1])
        return float(ms.value)
