"""Stop 41 on the GPU: frames whose visibility buffer the frame before drew ahead (interop, the
unmap behind the frame's work on a stream of its own) against frames that draw their own, as
tests/test_objects.py's two raster_ahead tests do on the CPU (where there is no interop): a still
camera over four seeds, and a camera path of four frames; many_objects and default.xml at
640×360, 1 spp, no denoiser. Prints the largest difference per frame and what each frame used;
saves the drawn-ahead images to the .npz of argv[1] (to compare two trees)."""
import sys

import mitsuba as mi
import numpy as np

mi.set_variant(sys.argv[2] if len(sys.argv) > 2 else "cuda_ad_rgb")
import hybrid_integrator as hi  # noqa: E402
from hybrid_integrator.raster.camera import sensor_to_world, transform_matrix  # noqa: E402

out, worst = {}, 0.0
for name in ("scenes/many_objects.xml", "scenes/default.xml"):
    scene = hi.load_scene(name, resx=640, resy=360)
    props = dict(spp=1, denoise=False, learn_ambient=False)
    still = {ahead: [hi.render(scene, seed=s, raster_ahead=ahead, **props) for s in range(4)] for ahead in ("off", "on")}
    start = transform_matrix(sensor_to_world(scene.sensors()[0]))
    eye, target = start[:3, 3], start[:3, 3] + start[:3, 2]
    cameras = hi.camera_path([(eye, target), (eye + [0.1, 0.05, 0.0], target)], 4)
    path = {ahead: hi.render_sequence(scene, cameras, raster_ahead=ahead, layers=False, **props) for ahead in ("off", "on")}
    for kind, runs in (("still", still), ("path", path)):
        for k, (own, drawn) in enumerate(zip(runs["off"], runs["on"])):
            diff = float(np.abs(np.array(own.image) - np.array(drawn.image)).max())
            worst = max(worst, diff)
            out[f"{name} {kind} {k}"] = np.array(drawn.image)
            print(f"{name} {kind} frame {k}: max|own - drawn ahead| {diff:.3g}, drawn ahead / discarded "
                  f"{drawn.stats.raster_ahead} / {drawn.stats.raster_discarded}, readback {drawn.stats.readback}", flush=True)
print(f"largest difference {worst:.3g}")
np.savez(sys.argv[1], **out)
