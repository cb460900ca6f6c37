"""freeze=True (dr.freeze replays of the path loop) renders what the unfrozen loop renders, in a
process with one scene, as the integrator's documentation promises."""
from __future__ import annotations

import json
import subprocess
import sys

from conftest import DEFAULT_SCENE

SCRIPT = f"""
import json, numpy as np, mitsuba as mi
import hybrid_integrator as hi
mi.set_variant("llvm_ad_rgb")
scene = hi.load_scene({str(DEFAULT_SCENE)!r}, resx=96, resy=72)
cams = hi.camera_path([((0, 0, 3.9), (0, 0, 0)), ((0.5, 0.3, 3.5), (0, -0.3, 0))], 3)
out = {{}}
for freeze in (False, True):
    frames = hi.render_sequence(scene, cams, spp=2, freeze=freeze, effects="shadow,reflection,refraction,indirect")
    out[str(freeze)] = [(float(np.array(f.image).sum()), f.stats.rays) for f in frames]
# the same path frame by frame, twice, by a new integrator: the frozen device pass replays what the
# sequences above recorded, the camera moving (it recorded again in most frames while the frame's
# small inputs were NumPy memory that Dr.Jit maps, aligned or not at random: interop.device_array)
integrator = hi.api._integrator({{"effects": "shadow,reflection,refraction,indirect"}})
params = mi.traverse(scene.sensors()[0])
recordings = []
for k, cam in enumerate(cams + cams):
    params["to_world"] = mi.ScalarTransform4f(hi.raster.camera.transform_matrix(cam))
    params.update()
    integrator.render_result(scene, seed=k, spp=2, layers=False)
    recordings.append(sum(p.n_recordings for p in hi.api.renderer(scene)._frozen.values()))
out["recordings"] = recordings
print(json.dumps(out))
"""


def test_frozen_path_loop_matches_unfrozen():
    result = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr
    out = json.loads(result.stdout.strip().splitlines()[-1])
    recordings = out.pop("recordings")
    assert recordings == [recordings[0]] * len(recordings), recordings
    for (plain_sum, plain_rays), (frozen_sum, frozen_rays) in zip(out["False"], out["True"]):
        assert plain_rays == frozen_rays
        assert abs(plain_sum - frozen_sum) <= 1e-4 * abs(plain_sum)
