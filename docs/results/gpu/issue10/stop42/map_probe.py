"""Stop 42 on the GPU: the host's time to hand OpenGL's output to CUDA, a texture (what the
visibility pass writes today: ``cuGraphicsGLRegisterImage``, map, ``cuMemcpy2DAsync`` from its
array, unmap) against a storage buffer (``cuGraphicsGLRegisterBuffer``, map,
``cuGraphicsResourceGetMappedPointer``, ``cuMemcpyDtoDAsync``, unmap), 1280×720 32-bit words,
each written every round by a compute dispatch. Rounds as frames: dispatch + flush, map, copy,
a kernel standing in for the frame's work, unmap, synchronize. Each call's host time, median
of 200 rounds (the kinds taking turns at going first), in µs; and whether the copies hold what OpenGL wrote.

    source .device/prelude.sh; ln -sfn ../plugins hybrid_integrator/plugins
    python3 docs/results/gpu/issue10/stop42/map_probe.py
"""
import ctypes
import statistics
import time

import drjit as dr
import mitsuba as mi
import numpy as np

mi.set_variant("cuda_ad_rgb")
from hybrid_integrator.raster import interop  # noqa: E402
from hybrid_integrator.raster.context import gl_context, gl_flush  # noqa: E402

W, H = 1280, 720
ctx = gl_context()
texture = ctx.texture((W, H), 1, dtype="u4")
buffer = ctx.buffer(reserve=4 * W * H)
program = ctx.compute_shader("""#version 430
layout(local_size_x = 256) in;
layout(r32ui, binding = 0) writeonly uniform uimage2D target;
layout(std430, binding = 0) writeonly buffer Out { uint words[]; };
uniform uint round_;
void main() {
    uint n = gl_GlobalInvocationID.x;
    if (n >= uint(%d * %d)) return;
    words[n] = n + round_;
    imageStore(target, ivec2(int(n %% %du), int(n / %du)), uvec4(n + round_));
}""" % (W, H, W, W))
texture.bind_to_image(0, read=False, write=True)
buffer.bind_to_storage_buffer(0)
driver = interop._Driver()
image_res, buffer_res = ctypes.c_void_p(), ctypes.c_void_p()
driver.call("cuGraphicsGLRegisterImage", ctypes.byref(image_res), ctypes.c_uint(texture.glo), ctypes.c_uint(0x0DE1),
            ctypes.c_uint(1))
driver.call("cuGraphicsGLRegisterBuffer", ctypes.byref(buffer_res), ctypes.c_uint(buffer.glo), ctypes.c_uint(1))
times: dict[str, list[float]] = {}
busy = dr.arange(mi.Float, 1 << 22)


def timed(label, name, *args):
    start = time.perf_counter()
    driver.call_current(name, *args)
    times.setdefault(label, []).append((time.perf_counter() - start) * 1e6)


wrong = 0
for r in range(220):
    program["round_"].value = r
    program.run(-(-W * H // 256))
    ctx.memory_barrier()
    gl_flush()
    outs = []
    with driver.current():
        pair = (("image", image_res), ("buffer", buffer_res))
        for kind, res in (pair if r % 2 else pair[::-1]):  # each first in every other round
            out = dr.empty(mi.UInt32, W * H)
            dr.eval(out)
            timed(f"{kind} map", "cuGraphicsMapResources", 1, ctypes.byref(res), driver.stream)
            if kind == "image":
                array = ctypes.c_void_p()
                timed("image get array", "cuGraphicsSubResourceGetMappedArray", ctypes.byref(array), res, 0, 0)
                copy = interop._Memcpy2D(srcMemoryType=3, srcArray=array, dstMemoryType=2,
                                         dstDevice=interop.device_pointer(out), dstPitch=4 * W, WidthInBytes=4 * W, Height=H)
                timed("image copy", "cuMemcpy2DAsync_v2", ctypes.byref(copy), driver.stream)
            else:
                pointer, size = ctypes.c_uint64(), ctypes.c_size_t()
                timed("buffer get pointer", "cuGraphicsResourceGetMappedPointer_v2", ctypes.byref(pointer),
                      ctypes.byref(size), res)
                timed("buffer copy", "cuMemcpyDtoDAsync_v2", ctypes.c_uint64(interop.device_pointer(out)), pointer,
                      ctypes.c_size_t(4 * W * H), driver.stream)
            outs.append(out)
    work = dr.sum(dr.sin(busy * 1e-3) * dr.cos(busy))  # a frame's CUDA work after the copies
    dr.eval(work)
    with driver.current():
        for kind, res in (("image", image_res), ("buffer", buffer_res)):
            timed(f"{kind} unmap", "cuGraphicsUnmapResources", 1, ctypes.byref(res), driver.stream)
    dr.sync_thread()
    if r % 50 == 0:
        expect = np.arange(W * H, dtype=np.uint32) + r
        wrong += sum(int((np.array(o) != expect).sum()) for o in outs)
for label, values in times.items():
    print(f"{label:20s} median {statistics.median(values[20:]):7.1f} µs, p90 {np.percentile(values[20:], 90):7.1f}")
print("words that differ from what OpenGL wrote:", wrong)
