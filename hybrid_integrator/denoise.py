"""Denoising the composed frame with its own G-buffer as guides (Open Image Denoise).

The paper composes a noise-free raster layer with ray-traced effects (§5); at one sample per pixel
those effects (soft shadows, glossy reflections, indirect light) are noisy. Real-time renderers
answer that noise with a denoiser guided by the first hit's albedo and normal, and the hybrid
has those guides *exactly and for free*: its raster G-buffer (stage 1 and 2) holds them, without
the noise a path tracer's guides carry at 1 spp from anti-aliasing and from seeing through glass.

Here the denoiser is Intel Open Image Denoise 2.5 (``pyoidn``), its ``RT`` filter in HDR mode
with ``cleanAux`` (the guides are noise-free):

- on the CUDA variants, an OIDN CUDA device bound to Dr.Jit's own CUDA stream
  (``jit_cuda_stream``) reads and writes device memory: no copy to the host and no
  synchronization; the filter runs after the frame's kernels and before its one sync. Its four
  images are device arrays made once per size, which the filter keeps (``_DeviceImages``): a
  frame copies its colour and guides in and the result out on the stream (four device copies),
  instead of wrapping new buffers and committing the filter again every frame;
- on the LLVM variants, the OIDN CPU device, on host copies of the images.

Guides, as OIDN asks: ``albedo`` is the G-buffer's diffuse albedo plus its specular colour
clamped to [0, 1] (a mirror or glass pixel is "white", so the filter keeps what it reflects or
refracts), and the colour itself on background pixels; ``normal`` is the shading normal (zero on
the background). Both are splatted with the film's filter, as the colour is.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import drjit as dr
import mitsuba as mi
import numpy as np

from .errors import HybridError

QUALITIES = ("high", "balanced", "fast")


@dataclass(frozen=True)
class Guides:
    """A frame's denoising guides, H×W×3 tensors on the device."""

    albedo: mi.TensorXf
    normal: mi.TensorXf


#: the filter's images, in this order everywhere
IMAGES = ("color", "albedo", "normal", "output")


@dataclass
class _DeviceImages:
    """The filter's four images (``IMAGES``, H×W×3 float) as device arrays that live as long as
    the filter, which is committed with them once."""

    arrays: list  # mi.Float each, kept alive: OIDN holds their addresses
    buffers: list  # OIDN shared buffers over them
    pointers: list[int]

    @staticmethod
    def make(device, f, width: int, height: int) -> "_DeviceImages":
        from .raster.interop import device_pointer

        oidn = _pyoidn()
        arrays = [dr.zeros(mi.Float, width * height * 3) for _ in IMAGES]
        dr.eval(*arrays)
        pointers = [device_pointer(a) for a in arrays]
        buffers = [oidn.Buffer.shared(device, pointer, width * height * 3 * 4) for pointer in pointers]
        for name, buffer in zip(IMAGES, buffers):
            f.set_image(name, buffer, oidn.OIDN_FORMAT_FLOAT3, width, height)
        f.commit()
        return _DeviceImages(arrays, buffers, pointers)


def _pyoidn():
    try:
        import pyoidn
    except ImportError as error:  # pragma: no cover - pyoidn is a dependency
        raise HybridError("denoise=true needs Open Image Denoise: pip install pyoidn") from error
    return pyoidn


class Denoiser:
    """One OIDN device and one filter per image size, made on first use and kept."""

    def __init__(self, quality: str = "high"):
        if quality not in QUALITIES:
            raise HybridError(f"denoise quality '{quality}' is not one of {list(QUALITIES)}")
        self.quality = quality
        self.cuda = mi.variant().startswith("cuda")
        self._device = None
        self._filters: dict[tuple[int, int], object] = {}
        self._images: dict[tuple[int, int], _DeviceImages] = {}  # CUDA: the filter's images, per size
        self._timer = None  # CUDA events around the filter (its kernels are not Dr.Jit's)
        self._host_ms = 0.0

    def _open(self):
        oidn = _pyoidn()
        if self.cuda:
            from .raster.interop import drjit_stream

            stream = oidn.device.oidn_ffi.cast("cudaStream_t", drjit_stream().value or 0)
            device = oidn.Device.__new__(oidn.Device)
            device._device = oidn.capi.oidn_Capi.oidnNewCUDADevice(oidn.device.oidn_ffi.new("int[]", [0]),
                                                                     oidn.device.oidn_ffi.new("cudaStream_t[]", [stream]), 1)
        else:
            device = oidn.Device(oidn.OIDN_DEVICE_TYPE_CPU)
        device.commit()
        self._check(device, "creating the OIDN device")
        return device

    @staticmethod
    def _check(device, what: str) -> None:
        error = device.get_error()
        if error:
            raise HybridError(f"Open Image Denoise failed {what}: {error}")

    def _filter(self, width: int, height: int):
        oidn = _pyoidn()
        if self._device is None:
            self._device = self._open()
        if (width, height) not in self._filters:
            f = oidn.Filter(self._device, oidn.OIDN_FILTER_TYPE_RT)
            f.set_bool("hdr", True)
            f.set_bool("cleanAux", True)
            f.set_quality({"high": oidn.OIDN_QUALITY_HIGH, "balanced": oidn.OIDN_QUALITY_BALANCED,
                           "fast": oidn.OIDN_QUALITY_FAST}[self.quality])
            self._filters[(width, height)] = f
        return self._filters[(width, height)]

    def __call__(self, color: mi.TensorXf, guides: Guides) -> mi.TensorXf:
        """``color`` (H×W×3, linear HDR) denoised; on the GPU, issued on Dr.Jit's stream."""
        oidn = _pyoidn()
        height, width = color.shape[0], color.shape[1]
        f = self._filter(width, height)
        if self.cuda:
            return self._denoise_on_device(f, color, guides)
        host = [np.ascontiguousarray(np.array(a, dtype=np.float32)) for a in (color, guides.albedo, guides.normal)]
        out_host = np.zeros_like(host[0])
        for name, buffer in zip(IMAGES, host + [out_host]):
            f.set_image(name, buffer, oidn.OIDN_FORMAT_FLOAT3, width, height)
        f.commit()
        start = time.perf_counter()
        f.execute()
        self._host_ms = (time.perf_counter() - start) * 1e3
        self._check(self._device, "denoising")
        return mi.TensorXf(out_host)

    def _denoise_on_device(self, f, color: mi.TensorXf, guides: Guides) -> mi.TensorXf:
        from .raster.interop import StreamTimer, device_pointer

        height, width = color.shape[0], color.shape[1]
        self._timer = self._timer or StreamTimer()
        if (width, height) not in self._images:
            self._images[(width, height)] = _DeviceImages.make(self._device, f, width, height)
        images = self._images[(width, height)]
        inputs = [color.array, guides.albedo.array, guides.normal.array]
        dr.eval(*inputs)  # issued, not waited for: the copies and the filter follow on the same stream
        nbytes = width * height * 3 * 4
        driver = self._timer.driver
        driver.copy_async(zip(images.pointers[:3], (device_pointer(a) for a in inputs)), nbytes)
        self._timer.start()
        f.execute_async()
        self._timer.stop()
        self._check(self._device, "denoising")
        out = dr.empty(mi.Float, width * height * 3)
        dr.eval(out)
        driver.copy_async([(device_pointer(out), images.pointers[3])], nbytes)  # the next frame reuses the image
        return mi.TensorXf(out, color.shape)

    def elapsed_ms(self) -> float:
        """The last call's filter time: device time on the GPU (read after the frame's
        synchronization), the host's on the CPU (where the filter runs on the host)."""
        return self._timer.elapsed_ms() if self.cuda and self._timer is not None else self._host_ms
