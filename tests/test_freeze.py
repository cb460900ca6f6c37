"""freeze=True (dr.freeze replays of the path loop) renders what the unfrozen loop renders, in a
process with one scene, as the integrator's documentation promises; the frozen functions take the
scene's variables in the scene's place (frozen.py), taken again when a scene loaded since is
missing from them, and the scene itself where they cannot serve."""
from __future__ import annotations

import json
import subprocess
import sys

import drjit as dr
import mitsuba as mi
import numpy as np

import hybrid_integrator as hi
from hybrid_integrator.frozen import FrozenScene
from conftest import DEFAULT_SCENE, ROOT

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
frozen = hi.api.renderer(scene).frozen
out["inputs"] = integrator.last_result.stats.frozen_inputs
out["snapshot"] = [frozen.taken, len(frozen.variables.handles), frozen.variables.visits]
out["read"] = [len(f.read) for f in hi.api.renderer(scene)._frozen.values()]
print(json.dumps(out))
"""


def _in_fresh_process(code: str, timeout: int) -> list[str]:
    """The lines ``code`` prints, run by a new Python process (one whose Dr.Jit registry holds no
    other scene, BSDF or recording); its failure fails the test with its error's end."""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout)
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout.strip().splitlines()


def test_frozen_path_loop_matches_unfrozen():
    out = json.loads(_in_fresh_process(SCRIPT, 600)[-1])
    recordings = out.pop("recordings")
    assert recordings == [recordings[0]] * len(recordings), recordings
    # one snapshot of the scene's variables served every frame, each variable once, and the pass
    # took only the part of it that its recording reads
    assert out.pop("inputs") == "read set"
    taken, handles, visits = out.pop("snapshot")
    assert taken == 1 and 0 < handles < visits
    read = out.pop("read")
    assert read and all(0 < n < handles for n in read), (read, handles)
    for (plain_sum, plain_rays), (frozen_sum, frozen_rays) in zip(out["False"], out["True"]):
        assert plain_rays == frozen_rays
        assert abs(plain_sum - frozen_sum) <= 1e-4 * abs(plain_sum)


def _ray(x):
    """The rays of ``x`` (in [0, 1)) into the test scene from its camera's place."""
    return mi.Ray3f(mi.Point3f(0, 0, 3.9), dr.normalize(mi.Vector3f(x - 0.5, 0.1, -1)))


def _shade(scene, x):
    """Rays into the scene along ``x`` (in [0, 1)) and the BSDF of what they hit: virtual calls
    over shapes and BSDFs."""
    si = scene.ray_intersect(_ray(x))
    value = si.bsdf().eval(mi.BSDFContext(), si, si.to_local(dr.normalize(mi.Vector3f(0, 1, 1))), si.is_valid())
    return dr.select(si.is_valid(), si.t + value.x, 0.0) + x


def test_a_scene_loaded_after_the_snapshot_has_it_taken_again():
    """A frozen function recorded after another scene was loaded meets that scene's instances in
    its virtual calls, which the first snapshot lacks: it is taken again, once, and the functions
    compute what the unfrozen code computes."""
    scene = hi.load_scene(DEFAULT_SCENE, resx=32, resy=24)
    frozen = FrozenScene(scene)
    x = dr.arange(mi.Float, 64) / 64
    first = frozen.freeze(_shade)
    assert dr.all(first(x) == _shade(scene, x)) and frozen.taken == 1
    later = hi.load_scene(ROOT / "scenes" / "showcase.xml")
    second = frozen.freeze(lambda scene, x: _shade(scene, x) * 2.0)
    for _ in range(3):
        assert dr.all(second(x) == _shade(scene, x) * 2.0) and dr.all(first(x) == _shade(scene, x))
    assert frozen.taken == 2 and frozen.inputs == "variables" and later.shapes()


def _distance(scene, x):
    """What ``_shade`` traces, without the BSDF: no BSDF variable is read."""
    return scene.ray_intersect(_ray(x)).t + x


def test_a_recording_that_reads_beyond_the_read_set_takes_the_whole_snapshot():
    """A frozen function passes the part of the snapshot its first recording read; a later
    recording (another configuration: a Python argument) that reads more is told so by Dr.Jit,
    and the function takes the whole snapshot from then on, computing what the unfrozen code
    computes."""
    scene = hi.load_scene(DEFAULT_SCENE, resx=32, resy=24)
    frozen = FrozenScene(scene)
    fn = frozen.freeze(lambda scene, x, bsdf: _shade(scene, x) if bsdf else _distance(scene, x))
    x = dr.arange(mi.Float, 64) / 64
    for _ in range(3):
        assert dr.allclose(fn(x, False), _distance(scene, x))
    assert fn.inputs == "read set" and 0 < len(fn.read) < len(frozen.variables.handles) and not fn.missed
    for _ in range(3):
        assert dr.allclose(fn(x, True), _shade(scene, x)) and dr.allclose(fn(x, False), _distance(scene, x))
    assert fn.inputs == "variables" and fn.missed.startswith("record()")  # what Dr.Jit said


def test_a_scene_the_snapshot_cannot_take_is_walked_whole():
    """A scene variable attached to Dr.Jit's AD graph has no plain handle: the functions take the
    scene itself (counted as ``scene``) and still compute what the unfrozen code computes."""
    scene = hi.load_scene(DEFAULT_SCENE, resx=32, resy=24)
    params = mi.traverse(scene)
    dr.enable_grad(params["greenwall.bsdf.reflectance.value"])
    params.update()
    frozen = FrozenScene(scene)
    shade = frozen.freeze(_shade)
    x = dr.arange(mi.Float, 64) / 64
    for _ in range(3):
        assert dr.allclose(shade(x), _shade(scene, x))
    assert frozen.inputs == "scene" and frozen.variables is None


def test_an_edited_scene_renders_its_edit_once_forgotten():
    """The snapshot keeps the variables it was taken from: after an edit through ``mi.traverse``,
    ``hi.forget`` makes the next frame take the edited scene (frozen as unfrozen)."""
    scene = hi.load_scene(DEFAULT_SCENE, resx=32, resy=24)
    kw = dict(spp=1, seed=2, denoise=False)
    before = np.array(hi.render(scene, **kw).image)
    params = mi.traverse(scene)
    params["redwall.bsdf.reflectance.value"] = mi.Color3f(0.1, 0.1, 0.9)
    params.update()
    hi.forget(scene)
    after = np.array(hi.render(scene, **kw).image)
    plain = np.array(hi.render(scene, freeze=False, **kw).image)
    assert np.abs(after - before).mean() > 1e-3 and np.allclose(after, plain, rtol=1e-4, atol=1e-5)


def test_a_class_without_instances_ends_the_snapshot():
    """In a fresh process whose scene has no sensor or emitter, those classes have no registered
    instance: Dr.Jit looks every id up as null there (a lookup by id would never end), and the
    snapshot takes none of them."""
    code = ("import drjit as dr, mitsuba as mi; mi.set_variant('llvm_ad_rgb')\n"
            "from hybrid_integrator.frozen import FrozenScene\n"
            "scene = mi.load_dict({'type': 'scene', 's': {'type': 'sphere'}})\n"
            "frozen = FrozenScene(scene)\n"
            "f = frozen.freeze(lambda scene, x: x + scene.ray_intersect(mi.Ray3f(mi.Point3f(0, 0, 5), mi.Vector3f(0, 0, -1))).t)\n"
            "x = dr.arange(mi.Float, 4)\n"
            "print([float(v) for v in f(x)], [float(v) for v in f(x)], frozen.inputs)")
    line = _in_fresh_process(code, 120)[-1]
    assert line.startswith("[4.0, 5.0, 6.0, 7.0] [4.0, 5.0, 6.0, 7.0] variables"), line


def test_a_bsdf_outside_the_scene_runs_the_pass_unfrozen():
    """Dr.Jit 1.5 cannot record a virtual call that meets a BSDF registered outside the scene (a
    frozen ``mi.render`` of Mitsuba's ``path`` fails on it too): the frame's pass runs unfrozen,
    counted as ``unfrozen``, and renders what ``freeze=False`` renders; a benchmark says so instead
    of timing it as frozen; once that BSDF is deleted, a scene's pass freezes again. In a fresh
    process: the lone BSDF would be in every later recording of this one."""
    code = ("import numpy as np, mitsuba as mi; mi.set_variant('llvm_ad_rgb')\n"
            "import hybrid_integrator as hi\n"
            "lone = mi.load_dict({'type': 'diffuse'})\n"
            f"scene_file = {str(DEFAULT_SCENE)!r}\n"
            "scene = hi.load_scene(scene_file, resx=32, resy=24)\n"
            "kw = dict(spp=1, seed=2, denoise=False)\n"
            "frames = [hi.render(scene, **kw) for _ in range(2)]\n"
            "plain = np.array(hi.render(scene, freeze=False, **kw).image)\n"
            "print([f.stats.frozen_inputs for f in frames], hi.api.renderer(scene).frozen.unfrozen[:8],\n"
            "      all(np.allclose(np.array(f.image), plain, rtol=1e-4, atol=1e-5) for f in frames), float(plain.mean()) > 0)\n"
            "from hybrid_integrator.bench import bench_scene\n"
            "from hybrid_integrator.compare import timed_path\n"
            "for timed in (lambda: bench_scene(scene_file, {'resx': '32', 'resy': '24'}, frames=2, budgets=(), accuracy=False),\n"
            "              lambda: timed_path(scene, 1, 4, 0, frozen=True)):\n"
            "    try:\n"
            "        timed(); print('timed')\n"
            "    except hi.HybridError as error:\n"
            "        print(str(error).split(':')[0 if 'frozen path' in str(error) else 1].strip())\n"
            "del lone; import gc; gc.collect()\n"
            "print(hi.render(hi.load_scene(scene_file, resx=32, resy=24), **kw).stats.frozen_inputs)")
    lines = _in_fresh_process(code, 300)[-4:]
    assert lines[0] == "['unfrozen', 'unfrozen'] record() True True", lines
    # a benchmark refuses to time the fallback under the frozen frame's name: the hybrid's rows and
    # the frozen path baseline alike
    assert lines[1:3] == ["raster", "frozen path"], lines
    assert lines[3] == "read set", lines  # the BSDF deleted, a scene loaded since freezes again


def test_a_moved_camera_records_nothing_more():
    """The sensor is an input of every call, not part of the snapshot: moving it after the first
    frames (``params.update()`` gives it new variables) replays what they recorded. (In the
    snapshot too, its variables aliased the sensor's until the move, which changed the inputs'
    layout: one more recording.)"""
    scene = hi.load_scene(DEFAULT_SCENE, resx=32, resy=24)
    for seed in range(3):
        hi.render(scene, spp=1, seed=seed, denoise=False)
    renderer = hi.api.renderer(scene)
    before = sum(f.n_recordings for f in renderer._frozen.values())
    params = mi.traverse(scene.sensors()[0])
    params["to_world"] = mi.ScalarTransform4f().look_at(origin=(0.3, 0.2, 3.8), target=(0, 0, 0), up=(0, 1, 0))
    params.update()
    for seed in range(3):
        hi.render(scene, spp=1, seed=seed, denoise=False)
    assert sum(f.n_recordings for f in renderer._frozen.values()) == before
