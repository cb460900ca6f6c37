"""Does setting the sensor's pose wait for the GPU? (issue 10, stop 56)

Along a camera path ``api.posed``'s ``place`` sets the sensor's ``to_world`` and calls
``params.update()`` between frames. With two frames in flight that host work runs while the GPU
still finishes the frame before; if it waits for that work, frames in flight lose their overlap
along a moving path. This probe issues a long kernel (about ``--busy`` ms of device work), then
times, on the host: ``place`` to a new pose; ``place`` and the next frame's raster camera
(``RasterCamera.from_sensor``); ``place`` with the backend synchronized first; and the busy
kernel's launch alone, for scale. A call that waits takes about the kernel's time. Since stop 56
``place`` is ``raster.camera.place_sensor``; before, Mitsuba's ``params.update()``.

    python3 docs/results/gpu/issue10/stop56/pose_wait.py --variant cuda_ad_rgb
"""
from __future__ import annotations

import argparse
import statistics
import time


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--scene", default="scenes/many_objects.xml")
    parser.add_argument("--repeats", type=int, default=30)
    parser.add_argument("--size", type=int, default=1 << 20, help="lanes of the busy kernel")
    parser.add_argument("--loops", type=int, default=20000, help="iterations per lane of the busy kernel")
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.api import posed
    from hybrid_integrator.bench import path_cameras
    from hybrid_integrator.raster.camera import RasterCamera, camera_pose

    scene = hi.load_scene(args.scene, resx=1280, resy=720)
    poses = [camera_pose(c) for c in path_cameras(args.scene, 2 * args.repeats + 2)]
    poses = poses + poses[::-1]

    def busy():
        """A kernel of some ms (a loop of ``--loops`` steps per lane), launched and not waited for."""
        x = dr.arange(mi.Float, args.size)
        i = mi.UInt32(0)

        def step(i, x):
            return i + 1, dr.fma(x, 0.999, 1.0)

        i, x = dr.while_loop((i, x), lambda i, x: i < args.loops, step)
        dr.eval(x)
        return x

    def timed(fn) -> float:
        start = time.perf_counter()
        fn()
        return (time.perf_counter() - start) * 1e3

    with posed(scene.sensors()[0]) as place:
        busy(); dr.sync_thread()  # the kernel compiled
        kernel = statistics.median(timed(lambda: (busy(), dr.sync_thread())) for _ in range(5))
        rows = {"place while the GPU is busy": [], "place after a sync": [], "launch alone": [],
                "place and camera while busy": []}
        sensor = scene.sensors()[0]
        for k in range(args.repeats):
            dr.sync_thread()
            busy()
            rows["place while the GPU is busy"].append(timed(lambda: place(poses[2 * k])))
            dr.sync_thread()
            busy()  # the frame's raster camera too, as the next frame builds it (RasterCamera.from_sensor)
            rows["place and camera while busy"].append(
                timed(lambda: (place(poses[2 * k + 1]), RasterCamera.from_sensor(sensor))))
            dr.sync_thread()
            rows["place after a sync"].append(timed(lambda: place(poses[-1 - k])))
            rows["launch alone"].append(timed(busy))
            dr.sync_thread()
    print(f"busy kernel with its sync: {kernel:.3f} ms ({args.variant})")
    for name, values in rows.items():
        print(f"{name:30s} median {statistics.median(values):.3f} ms, max {max(values):.3f} ms")


if __name__ == "__main__":
    main()
