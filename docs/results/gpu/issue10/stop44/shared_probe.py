"""Stop 44's probe: can OpenGL write into memory that CUDA allocated (VMM, exported as a POSIX file
descriptor, imported with GL_EXT_memory_object_fd), and what does a frame's handoff cost that way
against the registered texture's map / copy / unmap?  Run on the device:
    python3 docs/results/gpu/issue10/stop44/shared_probe.py
"""
import ctypes
import os
import time

import mitsuba as mi

mi.set_variant("cuda_ad_rgb")
import drjit as dr  # noqa: E402
import moderngl  # noqa: E402
import numpy as np  # noqa: E402

from hybrid_integrator.raster import interop  # noqa: E402
from hybrid_integrator.raster.context import _proc_address, gl_context  # noqa: E402

W, H = 1280, 720
N = W * H
ctx = gl_context()
print("GL:", ctx.info["GL_RENDERER"], ctx.info["GL_VERSION"])
print("extensions:", sorted(e for e in ctx.extensions if "memory_object" in e or "semaphore" in e))
driver = interop._Driver()
lib = driver.lib


class Location(ctypes.Structure):
    _fields_ = [("type", ctypes.c_int), ("id", ctypes.c_int)]


class AllocFlags(ctypes.Structure):
    _fields_ = [("compressionType", ctypes.c_ubyte), ("gpuDirectRDMACapable", ctypes.c_ubyte),
                ("usage", ctypes.c_ushort), ("reserved", ctypes.c_ubyte * 4)]


class Prop(ctypes.Structure):
    _fields_ = [("type", ctypes.c_int), ("requestedHandleTypes", ctypes.c_int), ("location", Location),
                ("win32HandleMetaData", ctypes.c_void_p), ("allocFlags", AllocFlags)]


class Access(ctypes.Structure):
    _fields_ = [("location", Location), ("flags", ctypes.c_int)]


prop = Prop(type=1, requestedHandleTypes=1, location=Location(1, 0))  # pinned, POSIX fd, device 0
gran = ctypes.c_size_t()
with driver.current():
    driver.call_current("cuMemGetAllocationGranularity", ctypes.byref(gran), ctypes.byref(prop), 0)
    size = -(-4 * N // gran.value) * gran.value
    handle = ctypes.c_uint64()
    driver.call_current("cuMemCreate", ctypes.byref(handle), ctypes.c_size_t(size), ctypes.byref(prop), ctypes.c_uint64(0))
    fd = ctypes.c_int(-1)
    driver.call_current("cuMemExportToShareableHandle", ctypes.byref(fd), handle, 1, ctypes.c_uint64(0))
    ptr = ctypes.c_uint64()
    driver.call_current("cuMemAddressReserve", ctypes.byref(ptr), ctypes.c_size_t(size), ctypes.c_size_t(0), ctypes.c_uint64(0), ctypes.c_uint64(0))
    driver.call_current("cuMemMap", ptr, ctypes.c_size_t(size), ctypes.c_size_t(0), handle, ctypes.c_uint64(0))
    access = Access(location=Location(1, 0), flags=3)
    driver.call_current("cuMemSetAccess", ptr, ctypes.c_size_t(size), ctypes.byref(access), ctypes.c_size_t(1))
print(f"CUDA: {size} bytes at {ptr.value:#x}, fd {fd.value}")


def gl(name, restype, *argtypes):
    address = _proc_address(name)
    if not address:
        raise RuntimeError(f"no {name}")
    return ctypes.CFUNCTYPE(restype, *argtypes)(address)


u = ctypes.c_uint
glCreateMemoryObjectsEXT = gl("glCreateMemoryObjectsEXT", None, ctypes.c_int, ctypes.POINTER(u))
glImportMemoryFdEXT = gl("glImportMemoryFdEXT", None, u, ctypes.c_uint64, u, ctypes.c_int)
glCreateBuffers = gl("glCreateBuffers", None, ctypes.c_int, ctypes.POINTER(u))
glNamedBufferStorageMemEXT = gl("glNamedBufferStorageMemEXT", None, u, ctypes.c_ssize_t, u, ctypes.c_uint64)
glGetError = gl("glGetError", u)
glFenceSync = gl("glFenceSync", ctypes.c_void_p, u, u)
glClientWaitSync = gl("glClientWaitSync", u, ctypes.c_void_p, u, ctypes.c_uint64)
glDeleteSync = gl("glDeleteSync", None, ctypes.c_void_p)
glFlush = gl("glFlush", None)

memory = u()
glCreateMemoryObjectsEXT(1, ctypes.byref(memory))
glImportMemoryFdEXT(memory, size, 0x9586, fd.value)  # GL_HANDLE_TYPE_OPAQUE_FD_EXT
print("import error:", glGetError())
name = u()
glCreateBuffers(1, ctypes.byref(name))
glNamedBufferStorageMemEXT(name, size, memory, 0)
print("storage error:", glGetError())
shared = ctx.external_buffer(name.value, size)

source = """#version 450
layout(local_size_x = 256) in;
layout(std430, binding = 7) buffer Out { uint out_ids[]; };
layout(r32ui, binding = 0) writeonly uniform uimage2D target;
uniform uint seed;
uniform ivec2 size;
void main() {
    uint n = gl_GlobalInvocationID.x;
    if (n >= uint(size.x * size.y)) return;
    uint v = (n * 2654435761u) ^ seed;
    out_ids[n] = v;
    imageStore(target, ivec2(int(n) % size.x, int(n) / size.x), uvec4(v));
}"""
program = ctx.compute_shader(source)
texture = ctx.texture((W, H), 1, dtype="u4")
texture.bind_to_image(0, read=False, write=True)
shared.bind_to_storage_buffer(7)
program["size"].value = (W, H)
groups = -(-N // 256)
expected = lambda seed: (np.arange(N, dtype=np.uint64) * 2654435761 % 2**32).astype(np.uint32) ^ np.uint32(seed)


def draw(seed):
    program["seed"].value = seed
    program.run(groups)
    ctx.memory_barrier(moderngl.ALL_BARRIER_BITS)


def from_shared():
    fence = glFenceSync(0x9117, 0)  # GL_SYNC_GPU_COMMANDS_COMPLETE
    status = glClientWaitSync(fence, 1, 10**9)  # GL_SYNC_FLUSH_COMMANDS_BIT, 1 s
    glDeleteSync(fence)
    if status not in (0x911A, 0x911C):  # ALREADY_SIGNALED, CONDITION_SATISFIED
        raise RuntimeError(f"glClientWaitSync {status:#x}")
    out = dr.empty(mi.UInt32, N)
    dr.eval(out)
    driver.copy_async([(interop.device_pointer(out), ptr.value)], 4 * N)
    return out


image = interop._SharedImage(texture, driver)
for seed in (7, 12345):
    draw(seed)
    a = np.array(from_shared())
    b = np.array(image.copy(mi.UInt32))
    image.release()
    print(f"seed {seed}: shared equal {np.array_equal(a, expected(seed))}, texture equal {np.array_equal(b, expected(seed))}")

# a frame-like loop: draw, hand over, a CUDA kernel that reads it, the frame's synchronization
def loop(kind, frames=300):
    times = []
    for f in range(frames):
        t0 = time.perf_counter()
        draw(f)
        glFlush()
        if kind == "shared":
            ids = from_shared()
        else:
            ids = image.copy(mi.UInt32)
        s = dr.sum(ids * 3 + 1)
        dr.eval(s)
        dr.sync_thread()
        if kind == "texture":
            image.release()
        times.append(time.perf_counter() - t0)
    return 1e3 * np.median(times[50:])


for round_ in range(3):
    for kind in ("texture", "shared"):
        print(f"round {round_} {kind}: {loop(kind):.4f} ms per frame (median)")
print("pid", os.getpid())
