"""What stop 67's probes of the trace stage's time share (reload_mode.py, rebuild_mode.py,
load_order.py; imported after they set the variant): a bench scene loaded with the command line's
NAME=VALUE pairs, and the median trace stage of 20 frames after 3 from its sensor's pose."""
import statistics

import hybrid_integrator as hi
from hybrid_integrator.bench import load_bench_scene
from hybrid_integrator.raster.camera import sensor_to_world


def load(path: str, pairs: list[str]):
    """The scene at ``path`` given the ``NAME=VALUE`` pairs, and its sensor's camera."""
    scene, _ = load_bench_scene(path, dict(kv.split("=", 1) for kv in pairs))
    return scene, sensor_to_world(scene.sensors()[0])


def trace_stage_ms(scene, camera) -> float:
    """The median device time of the trace stage over 20 frames, after 3 that compile and record."""
    hi.render_sequence(scene, [camera] * 3, layers=False)
    frames = hi.render_sequence(scene, [camera] * 20, layers=False)
    return statistics.median(f.stats.times_ms["trace"] for f in frames)
