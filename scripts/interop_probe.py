"""Probe: how the compute pass's visibility buffer reaches Dr.Jit's CUDA stream, three ways (issue 10).

``scripts/gain_anatomy.py`` found that the interop step cost the hybrid's frame more than the
OpenGL pass itself while the target was a texture: mapping it orders CUDA's copy after OpenGL's
work, and on the H200 the copy ended 0.4–0.6 ms after the map against 0.06–0.22 ms of OpenGL work.
The compute pass now leaves its visibility buffer in a storage buffer, then its serial number
(``compute.ComputeTarget``). Per scene, ``--repeats`` times in turn, this probe issues the pass
(``Rasterizer.render``) and copies its buffer onto Dr.Jit's stream:

- ``stream``: as the renderer does (``interop._SharedBuffer``): the buffer mapped, the stream
  waits on the GPU for the pass's serial number (``cuStreamWaitValue32``), then copies;
- ``fence``: an OpenGL fence after the pass; the host waits for it (``glClientWaitSync``), then the
  buffer is mapped and copied;
- ``none``: the buffer mapped and copied, waiting for nothing (the floor; not a valid result: the
  map of a buffer does not wait for OpenGL's compute writes).

Per way: the host's time from the pass's issue to the copy's issue and to the copy's end (the host
synchronized after it), medians; then, at alternating sub-pixel offsets, how many of 10 copies
equal the buffer OpenGL left (a copy made before the pass ended would not).

    python3 scripts/interop_probe.py --variant cuda_ad_rgb SCENE... -D resx=1280 -D resy=720
"""
from __future__ import annotations

import ctypes
import statistics
import time

from raster_cull_probe import arguments, rasterizers  # scripts/ is on sys.path when a script runs

GL_SYNC_GPU_COMMANDS_COMPLETE, GL_SYNC_FLUSH_COMMANDS_BIT, GL_TIMEOUT_EXPIRED = 0x9117, 0x1, 0x911B
MODES = ("stream", "fence", "none")


def main() -> None:
    import drjit as dr
    import mitsuba as mi
    import numpy as np

    args = arguments(__doc__)
    mi.set_variant(args.variant)
    from hybrid_integrator.raster.context import gl_entry, gl_flush
    from hybrid_integrator.raster.interop import _Driver, _SharedBuffer, device_pointer

    driver = _Driver()
    fence = wait = delete = None
    for name, scene, raster, camera, query in rasterizers(args):
        if fence is None:  # the context is current from the first rasterizer on
            fence = gl_entry("glFenceSync", ctypes.c_uint, ctypes.c_uint, restype=ctypes.c_void_p)
            wait = gl_entry("glClientWaitSync", ctypes.c_void_p, ctypes.c_uint, ctypes.c_uint64, restype=ctypes.c_uint)
            delete = gl_entry("glDeleteSync", ctypes.c_void_p)
        shared = _SharedBuffer(raster.render(camera, (0.5, 0.5), "compute").buffer, driver)
        nbytes = 4 * camera.width * camera.height

        def run(mode, offset=(0.5, 0.5)):
            dr.sync_thread()
            start = time.perf_counter()
            target = raster.render(camera, offset, "compute")
            sync = fence(GL_SYNC_GPU_COMMANDS_COMPLETE, 0) if mode == "fence" else None
            gl_flush()
            if mode == "stream":
                out = shared.copy(target)
            else:
                if sync is not None:
                    while wait(sync, GL_SYNC_FLUSH_COMMANDS_BIT, 10**9) == GL_TIMEOUT_EXPIRED:
                        pass
                out = dr.empty(mi.UInt32, nbytes // 4)
                dr.eval(out)
                pointer, size = ctypes.c_uint64(), ctypes.c_size_t()
                with driver.current():
                    shared._map()
                    driver.call_current("cuGraphicsResourceGetMappedPointer_v2", ctypes.byref(pointer),
                                        ctypes.byref(size), shared.resource)
                    driver.call_current("cuMemcpyDtoDAsync_v2", ctypes.c_uint64(device_pointer(out)), pointer,
                                        ctypes.c_size_t(nbytes), driver.stream)
            issued = time.perf_counter()
            shared.release()
            dr.sync_thread()
            done = time.perf_counter()
            if sync is not None:
                delete(sync)
            return (issued - start) * 1e3, (done - start) * 1e3, out, target

        rows = {m: [] for m in MODES}
        for k in range(args.repeats + 3):
            for m in MODES:
                issue, done, _, _ = run(m)
                if k >= 3:
                    rows[m].append((issue, done))
        for m in MODES:
            print(f"{name}: {m:6s} host ms from the pass's issue: copy issued {statistics.median(r[0] for r in rows[m]):.3f}, "
                  f"copy done {statistics.median(r[1] for r in rows[m]):.3f}", flush=True)
        for m in MODES:
            same = 0
            for k in range(10):
                _, _, out, target = run(m, ((0.5, 0.5), (0.25, 0.75))[k % 2])
                same += np.array_equal(np.array(out), target.read())
            print(f"{name}: {m:6s} copies equal to the buffer OpenGL left: {same} of 10", flush=True)


if __name__ == "__main__":
    main()
