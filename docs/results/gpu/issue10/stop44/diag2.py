"""Stop 44: does the compute pass write into the shared memory at all? (diag.py found garbage)
    python3 diag2.py SCENE -D ..."""
import ctypes
import sys

import mitsuba as mi

mi.set_variant("cuda_ad_rgb")
import moderngl  # noqa: E402
import numpy as np  # noqa: E402

import hybrid_integrator as hi  # noqa: E402
from hybrid_integrator.bench import load_bench_scene  # noqa: E402
from hybrid_integrator.raster.camera import RasterCamera  # noqa: E402
from hybrid_integrator.raster.context import _proc_address  # noqa: E402

args = sys.argv[1:]
defines = dict(a.split("=", 1) for a in args[args.index("-D") + 1::2]) if "-D" in args else {}
scene, name = load_bench_scene([a for a in args if a.endswith(".xml")][0], defines)
raster = hi.rasterizer(scene)
camera = RasterCamera.from_sensor(scene.sensors()[0])
N = camera.width * camera.height
get_error = ctypes.CFUNCTYPE(ctypes.c_uint)(_proc_address("glGetError"))
get_integer_i = ctypes.CFUNCTYPE(None, ctypes.c_uint, ctypes.c_uint, ctypes.POINTER(ctypes.c_int))(_proc_address("glGetIntegeri_v"))
raster.render(camera, (0.5, 0.5), "compute")
shared = raster._shared
print("errors before:", get_error())
driver = shared.driver


def fill(value):
    driver.call("cuMemsetD32_v2", ctypes.c_uint64(shared._pointer.value), ctypes.c_uint(value), ctypes.c_size_t(N))
    driver.call("cuCtxSynchronize")


def read():
    shared.fence()
    return np.array(shared.copy(mi.UInt32, N))


fill(0xDEADBEEF)
fbo = raster.render(camera, (0.5, 0.5), "compute")
raster.ctx.finish()
bound = ctypes.c_int()
get_integer_i(0x90D3, 7, ctypes.byref(bound))
print("GL error after pass:", get_error(), "; binding 7 holds", bound.value, "shared glo", shared.buffer.glo)
copied = np.array(raster._shared.copy(mi.UInt32, N))
texture = raster.read_ids(fbo)
print(f"after the pass: untouched {np.mean(copied == 0xDEADBEEF):.4f}, equal to texture {np.mean(copied == texture):.4f}")

program = raster.ctx.compute_shader("""#version 450
layout(local_size_x = 256) in;
layout(std430, binding = 7) buffer Out { uint out_ids[]; };
uniform uint n;
void main() { uint i = gl_GlobalInvocationID.x; if (i < n) out_ids[i] = i + 1u; }""")
program["n"].value = N
fill(0xDEADBEEF)
shared.buffer.bind_to_storage_buffer(7)
program.run(-(-N // 256))
raster.ctx.memory_barrier(moderngl.ALL_BARRIER_BITS)
raster.ctx.finish()
copied = read()
print(f"simple shader: equal {np.mean(copied == np.arange(1, N + 1, dtype=np.uint32)):.4f}, untouched {np.mean(copied == 0xDEADBEEF):.4f}")
fill(0xDEADBEEF)
fbo = raster.render(camera, (0.5, 0.5), "compute")  # binds again? (same size, _BOUND says bound)
raster.ctx.finish()
copied = np.array(raster._shared.copy(mi.UInt32, N)) if raster._shared.fence_pending else read()
print(f"pass after the simple shader: untouched {np.mean(copied == 0xDEADBEEF):.4f}, equal to texture {np.mean(copied == raster.read_ids(fbo)):.4f}")
