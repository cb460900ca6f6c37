"""Stop 44: which way of sharing CUDA's memory with OpenGL holds (diag2.py: a quarter of the words
changed, none right, once a scene is loaded). Each variant: a fresh allocation, a plain compute
shader writes i + 1 to every word, CUDA copies it back.
    python3 diag3.py SCENE -D ..."""
import ctypes
import sys

import mitsuba as mi

mi.set_variant("cuda_ad_rgb")
import moderngl  # noqa: E402
import numpy as np  # noqa: E402

from hybrid_integrator.raster import interop  # noqa: E402
from hybrid_integrator.raster.context import _proc_address, gl_context  # noqa: E402

N = 1280 * 720
ctx = gl_context()
driver, gl = interop._Driver(), interop._GLMemory()
parameter = ctypes.CFUNCTYPE(None, ctypes.c_uint, ctypes.c_uint, ctypes.POINTER(ctypes.c_int))(_proc_address("glMemoryObjectParameterivEXT"))
program = ctx.compute_shader("""#version 450
layout(local_size_x = 256) in;
layout(std430, binding = 7) buffer Out { uint out_ids[]; };
uniform uint n;
void main() { uint i = gl_GlobalInvocationID.x; if (i < n) out_ids[i] = i + 1u; }""")
program["n"].value = N


def variant(export_first, dedicated, nbytes=4 * N):
    loc = interop._Location(1, 0)
    prop = interop._AllocationProperties(type=1, requestedHandleTypes=1, location=loc)
    gran, fd, handle, ptr = ctypes.c_size_t(), ctypes.c_int(-1), ctypes.c_uint64(), ctypes.c_uint64()
    c = driver.call_current
    with driver.current():
        c("cuMemGetAllocationGranularity", ctypes.byref(gran), ctypes.byref(prop), 0)
        size = -(-nbytes // gran.value) * gran.value
        c("cuMemCreate", ctypes.byref(handle), ctypes.c_size_t(size), ctypes.byref(prop), ctypes.c_uint64(0))
        if export_first:
            c("cuMemExportToShareableHandle", ctypes.byref(fd), handle, 1, ctypes.c_uint64(0))
        c("cuMemAddressReserve", ctypes.byref(ptr), ctypes.c_size_t(size), ctypes.c_size_t(0), ctypes.c_uint64(0), ctypes.c_uint64(0))
        c("cuMemMap", ptr, ctypes.c_size_t(size), ctypes.c_size_t(0), handle, ctypes.c_uint64(0))
        acc = interop._AccessDescription(location=loc, flags=3)
        c("cuMemSetAccess", ptr, ctypes.c_size_t(size), ctypes.byref(acc), ctypes.c_size_t(1))
        if not export_first:
            c("cuMemExportToShareableHandle", ctypes.byref(fd), handle, 1, ctypes.c_uint64(0))
        c("cuMemsetD32_v2", ptr, ctypes.c_uint(0xDEADBEEF), ctypes.c_size_t(size // 4))
        c("cuCtxSynchronize")
    memory, name = ctypes.c_uint(), ctypes.c_uint()
    gl.create_memory_objects(1, ctypes.byref(memory))
    if dedicated:
        parameter(memory, 0x9581, ctypes.byref(ctypes.c_int(1)))  # GL_DEDICATED_MEMORY_OBJECT_EXT
    gl.import_memory_fd(memory, size, 0x9586, fd.value)
    gl.create_buffers(1, ctypes.byref(name))
    gl.buffer_storage_memory(name, size, memory, 0)
    err = gl.get_error()
    buf = ctx.external_buffer(name.value, size)
    buf.bind_to_storage_buffer(7)
    program.run(-(-N // 256))
    ctx.memory_barrier(moderngl.ALL_BARRIER_BITS)
    ctx.finish()
    host = np.empty(N, np.uint32)
    driver.call("cuMemcpyDtoH_v2", host.ctypes.data_as(ctypes.c_void_p), ptr, ctypes.c_size_t(4 * N))
    ok = np.mean(host == np.arange(1, N + 1, dtype=np.uint32))
    print(f"export first {export_first!s:5} dedicated {dedicated!s:5} size {size}: GL error {err}, right {ok:.4f}, "
          f"untouched {np.mean(host == 0xDEADBEEF):.4f}, first words {host[:4]}", flush=True)


variant(False, False)
variant(True, False)
args = sys.argv[1:]
if args:
    import hybrid_integrator as hi
    from hybrid_integrator.bench import load_bench_scene
    defines = dict(a.split("=", 1) for a in args[args.index("-D") + 1::2]) if "-D" in args else {}
    scene, _ = load_bench_scene([a for a in args if a.endswith(".xml")][0], defines)
    hi.render(scene, spp=1, denoise=False)
    print("after a scene and a frame:")
for e in (False, True):
    for d in (False, True):
        variant(e, d)
variant(False, False, 64 << 20)
