"""Stop 44's second probe: the shared buffer ordered on the GPU through EGL syncs, not the host.
GL -> CUDA: an EGL fence after OpenGL's pass, made a CUDA event (cuEventCreateFromEGLSync) that
Dr.Jit's stream waits for; CUDA -> GL: a CUDA event at the frame's end made an EGL sync
(EGL_NV_cuda_event) that OpenGL's context waits for on the GPU (eglWaitSync) before the pass drawn
ahead. Checks the order both ways, then times a frame-like loop (pass drawn ahead, copy, ~1 ms of
CUDA work, hand back, one synchronization) against the registered texture's map / copy / unmap.
    python3 docs/results/gpu/issue10/stop44/egl_probe.py
"""
import ctypes
import time

import mitsuba as mi

mi.set_variant("cuda_ad_rgb")
import drjit as dr  # noqa: E402
import moderngl  # noqa: E402
import numpy as np  # noqa: E402

from hybrid_integrator.raster import interop  # noqa: E402
from hybrid_integrator.raster.context import gl_context, gl_flush  # noqa: E402

W, H = 1280, 720
N = W * H
ctx = gl_context()
egl = ctypes.CDLL("libEGL.so.1")
egl.eglGetCurrentDisplay.restype = ctypes.c_void_p
egl.eglQueryString.restype, egl.eglQueryString.argtypes = ctypes.c_char_p, [ctypes.c_void_p, ctypes.c_int]
egl.eglCreateSync.restype, egl.eglCreateSync.argtypes = ctypes.c_void_p, [ctypes.c_void_p, ctypes.c_uint, ctypes.POINTER(ctypes.c_ssize_t)]
egl.eglWaitSync.restype, egl.eglWaitSync.argtypes = ctypes.c_uint, [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_int]
egl.eglDestroySync.restype, egl.eglDestroySync.argtypes = ctypes.c_uint, [ctypes.c_void_p, ctypes.c_void_p]
egl.eglGetError.restype = ctypes.c_int
dpy = egl.eglGetCurrentDisplay()
ext = egl.eglQueryString(dpy, 0x3055).decode().split()  # EGL_EXTENSIONS
print("EGL:", [e for e in ext if "sync" in e.lower() or "cuda" in e.lower()])
SYNC_FENCE, SYNC_CUDA_EVENT, CUDA_EVENT_HANDLE, NONE = 0x30F9, 0x323C, 0x323B, 0x3038

driver, glm = interop._Driver(), interop._GLMemory()
shared = interop.SharedBuffer(ctx, driver, glm, 4 * N)
stream, call = driver.stream, driver.call


def egl_fence():
    sync = egl.eglCreateSync(dpy, SYNC_FENCE, (ctypes.c_ssize_t * 1)(NONE))
    if not sync:
        raise RuntimeError(f"eglCreateSync(fence) failed: {egl.eglGetError():#x}")
    return sync


def cuda_waits_for(sync):
    event = ctypes.c_void_p()
    call("cuEventCreateFromEGLSync", ctypes.byref(event), ctypes.c_void_p(sync), ctypes.c_uint(0))
    call("cuStreamWaitEvent", stream, event, ctypes.c_uint(0))
    call("cuEventDestroy_v2", event)


END = ctypes.c_void_p()
call("cuEventCreate", ctypes.byref(END), ctypes.c_uint(2))


def gl_waits_for_cuda():
    call("cuEventRecord", END, stream)
    sync = egl.eglCreateSync(dpy, SYNC_CUDA_EVENT, (ctypes.c_ssize_t * 3)(CUDA_EVENT_HANDLE, END.value, NONE))
    if not sync:
        raise RuntimeError(f"eglCreateSync(cuda event) failed: {egl.eglGetError():#x}")
    if not egl.eglWaitSync(dpy, sync, 0):
        raise RuntimeError(f"eglWaitSync failed: {egl.eglGetError():#x}")
    return sync


program = ctx.compute_shader("""#version 450
layout(local_size_x = 256) in;
layout(std430, binding = 7) buffer Out { uint out_ids[]; };
layout(std430, binding = 6) buffer Seen { uint seen[]; };
layout(r32ui, binding = 0) writeonly uniform uimage2D target;
uniform uint seed;
uniform ivec2 size;
void main() {
    uint n = gl_GlobalInvocationID.x;
    if (n >= uint(size.x * size.y)) return;
    seen[n] = out_ids[n];  // what CUDA left there
    uint v = (n * 2654435761u) ^ seed;
    out_ids[n] = v;
    imageStore(target, ivec2(int(n) % size.x, int(n) / size.x), uvec4(v));
}""")
texture = ctx.texture((W, H), 1, dtype="u4")
texture.bind_to_image(0, read=False, write=True)
seen = ctx.buffer(reserve=4 * N)
seen.bind_to_storage_buffer(6)
shared.buffer.bind_to_storage_buffer(7)
program["size"].value = (W, H)
groups = -(-N // 256)
expected = lambda seed: (np.arange(N, dtype=np.uint64) * 2654435761 % 2**32).astype(np.uint32) ^ np.uint32(seed)


def draw(seed):
    program["seed"].value = seed
    program.run(groups)
    ctx.memory_barrier(moderngl.ALL_BARRIER_BITS)


def work(ids, heavy=True):
    x = mi.Float(ids) * 1e-9
    if heavy:
        for _ in range(60):
            x = dr.fma(dr.sin(x), 0.999, 0.001)
    return x


# order, GL -> CUDA: the pass, its fence, CUDA waits on the GPU and copies (no host wait)
draw(11)
fence = egl_fence()
gl_flush()
cuda_waits_for(fence)
out = dr.empty(mi.UInt32, N)
dr.eval(out)
driver.copy_async([(interop.device_pointer(out), shared._pointer.value)], 4 * N)
print("GL -> CUDA in order:", np.array_equal(np.array(out), expected(11)))
egl.eglDestroySync(dpy, fence)
# order, CUDA -> GL: a long CUDA kernel writes the buffer, GL waits on the GPU, then reads it
marker = dr.full(mi.UInt32, 77, N)
slow = mi.UInt32(work(dr.arange(mi.UInt32, N)) * 0) + marker
dr.eval(slow)  # issued, not waited for
driver.copy_async([(shared._pointer.value, interop.device_pointer(slow))], 4 * N)
sync = gl_waits_for_cuda()
draw(12)
ctx.finish()
print("CUDA -> GL in order:", bool(np.all(np.frombuffer(seen.read(), np.uint32) == 77)))
egl.eglDestroySync(dpy, sync)

image = interop._SharedImage(texture, driver)


def loop(kind, frames=200):
    times, ok = [], True
    draw(0)
    pending = egl_fence() if kind == "egl" else None
    gl_flush()
    for f in range(frames):
        dr.sync_thread()
        t0 = time.perf_counter()
        if kind == "egl":
            cuda_waits_for(pending)
            ids = dr.empty(mi.UInt32, N)
            dr.eval(ids)
            driver.copy_async([(interop.device_pointer(ids), shared._pointer.value)], 4 * N)
        else:
            ids = image.copy(mi.UInt32)
        result = work(ids)
        dr.eval(result)
        check = ids if f % 50 == 7 else None
        if kind == "egl":
            egl.eglDestroySync(dpy, pending)
            done = gl_waits_for_cuda()
        else:
            image.release()
        draw(f + 1)  # ahead
        if kind == "egl":
            pending = egl_fence()
        gl_flush()
        dr.sync_thread()
        times.append(time.perf_counter() - t0)
        if kind == "egl":
            egl.eglDestroySync(dpy, done)
        if check is not None:
            ok &= np.array_equal(np.array(check), expected(f))
    if kind == "egl":
        egl.eglDestroySync(dpy, pending)
    return 1e3 * np.median(times[20:]), ok


for round_ in range(3):
    for kind in ("texture", "egl"):
        ms, ok = loop(kind)
        print(f"round {round_} {kind}: {ms:.4f} ms per frame (median), ids right: {ok}", flush=True)
