"""Stop 44: two processes on the CPU render the same showcase frames (160×90, undenoised): how far
apart are they?  .venv/bin/python cpu_processes.py A.npy; … B.npy; cpu_processes.py --compare A.npy B.npy"""
import sys

import numpy as np

if sys.argv[1] == "--compare":
    a, b = np.load(sys.argv[2]), np.load(sys.argv[3])
    print("max |a - b| per frame:", np.abs(a - b).max(axis=(1, 2, 3)))
    sys.exit()

import mitsuba as mi  # noqa: E402

mi.set_variant("llvm_ad_rgb")
import hybrid_integrator as hi  # noqa: E402
from hybrid_integrator.bench import load_bench_scene  # noqa: E402
from hybrid_integrator.raster.camera import sensor_to_world  # noqa: E402

scene, _ = load_bench_scene("scenes/showcase.xml", {"resx": "160", "resy": "90", "showcase_dir": "../shared/scenes/cbox"})
camera = sensor_to_world(scene.sensors()[0])
frames = hi.render_sequence(scene, [camera] * 4, seed=0, layers=False, denoise=False)
np.save(sys.argv[1], np.stack([np.array(f.image) for f in frames]))
