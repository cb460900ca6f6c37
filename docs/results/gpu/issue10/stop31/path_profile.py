"""Stop 31 probe: where a moving camera's frame spends its host time (the budgeted frames of
``scripts/budget_benchmark.py``'s camera path through the 226 objects set up 0.6-0.8 ms against a
still view's 0.17-0.26). Per run (50 % budget, and the RT baseline with every candidate): 3
warm-up frames, then 40 frames with ``RasterCamera.from_sensor`` timed, then the same under
cProfile (top functions by own time).

    python3 docs/results/gpu/issue10/stop31/path_profile.py --variant cuda_ad_rgb
"""
import argparse
import cProfile
import pstats
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[5]
sys.path.insert(0, str(ROOT / "scripts"))

parser = argparse.ArgumentParser()
parser.add_argument("--variant", default="llvm_ad_rgb")
parser.add_argument("--budget", type=float, default=2.43)
args = parser.parse_args()
import mitsuba as mi

mi.set_variant(args.variant)
import hybrid_integrator as hi
from hybrid_integrator.raster import camera as cam
from budget_benchmark import path_scene

times = []
original = cam.RasterCamera.from_sensor.__func__


def timed(cls, sensor):
    start = time.perf_counter()
    out = original(cls, sensor)
    times.append((time.perf_counter() - start) * 1e3)
    return out


cam.RasterCamera.from_sensor = classmethod(timed)
scene, cameras = path_scene(hi, ROOT / "scenes/many_objects.xml", 43, resx=1280, resy=720)
for name, props in (("50 %", dict(budget_ms=args.budget)), ("RT, all", dict(primary="raytrace"))):
    hi.render_sequence(scene, cameras[:3], spp=1, layers=False, **props)
    times.clear()
    frames = hi.render_sequence(scene, cameras[3:], spp=1, layers=False, **props)
    stats = [f.stats for f in frames]
    print(f"== {name}: frame {statistics.median(s.times_ms['total'] for s in stats):.3f} ms, "
          f"from_sensor {statistics.median(times):.3f} ms per call ({len(times)} calls)")
    print("  host_ms", {k: round(statistics.median(s.host_ms[k] for s in stats), 3) for k in stats[0].host_ms})
    profile = cProfile.Profile()
    profile.enable()
    hi.render_sequence(scene, cameras[3:], spp=1, layers=False, **props)
    profile.disable()
    pstats.Stats(profile, stream=sys.stdout).sort_stats("tottime").print_stats(25)
