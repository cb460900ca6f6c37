"""Stop 65's probe of scenes edited through ``mi.traverse`` between two hybrid frames (llvm_ad_rgb,
64×48, the hybrid at 64 spp without the denoiser, ``path`` at 256): a 5 000-triangle mesh's
vertices moved, an analytic sphere moved by its ``to_world``, the floor raised, a point light ×3,
a reflectance ×0.2. Per edit, the mean absolute error of the frame after it against ``path``
after it, over path's mean, and of the same frame after ``hi.forget(scene)`` (the noise). Then
what the check that finds geometry edits costs a frame: ``raster.geometry.geometry_key`` of the
dining room (18 shapes once batched), where ../shared/scenes holds it.

    .venv/bin/python docs/results/gpu/issue10/stop65/traverse_edits.py
    # before: a copy of this file run in a checkout of 0f468d3 (it imports the package beside it)
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[5]))

import mitsuba as mi  # noqa: E402
import numpy as np  # noqa: E402

mi.set_variant("llvm_ad_rgb")
import hybrid_integrator as hi  # noqa: E402
from hybrid_integrator.procedural import sphere_mesh  # noqa: E402
from hybrid_integrator.stability import diffuse, floor, load, scene, sensor  # noqa: E402

hi.register()
T = mi.Transform4f


def shapes(mesh: bool) -> dict:
    ball = ({"type": "ply", "filename": str(sphere_mesh(5000)), "to_world": mi.ScalarTransform4f().scale(0.7)} if mesh
            else {"type": "sphere", "radius": 0.8})
    return {"floor": floor(), "ball": ball | {"bsdf": diffuse((0.7, 0.3, 0.2))}}


def moved_vertices(params):
    params["ball.vertex_positions"] = mi.Float((np.array(params["ball.vertex_positions"]).reshape(-1, 3) + [0.8, 0, 0]).ravel())


EDITS = {
    "mesh vertices moved by 0.8": (True, moved_vertices),
    "analytic sphere moved by 0.8": (False, lambda p: p.__setitem__("ball.to_world", T().translate([0.8, 0, 0]) @ p["ball.to_world"])),
    "floor raised by 0.3": (False, lambda p: p.__setitem__("floor.to_world", T().translate([0, 0.3, 0]) @ p["floor.to_world"])),
    "point light x3": (False, lambda p: p.__setitem__("light.intensity.value", p["light.intensity.value"] * 3.0)),
    "ball reflectance x0.2": (False, lambda p: p.__setitem__("ball.bsdf.reflectance.value", p["ball.bsdf.reflectance.value"] * 0.2)),
}

for name, (mesh, edit) in EDITS.items():
    s = load(scene(shapes(mesh), sensor(res=(64, 48))))
    hi.render(s, spp=64, seed=1, denoise=False)
    params = mi.traverse(s)
    edit(params)
    params.update()
    after = hi.render(s, spp=64, seed=1, denoise=False)
    truth = np.array(mi.render(s, integrator=mi.load_dict({"type": "path"}), spp=256, seed=1))[..., :3]
    hi.forget(s)
    forgotten = np.array(hi.render(s, spp=64, seed=1, denoise=False).image)[..., :3]
    error = lambda image: float(np.abs(image - truth).mean() / truth.mean())  # noqa: E731
    print(f"{name}: error {error(np.array(after.image)[..., :3]):.3f}, after forget {error(forgotten):.3f}, "
          f"geometry_reloads {getattr(after.stats, 'geometry_reloads', '(none before stop 65)')}")

dining = Path(__file__).resolve().parents[5].parent / "shared/scenes/dining-room"
if dining.is_dir():
    import timeit

    from hybrid_integrator.raster.geometry import geometry_key

    room = hi.load_scene(Path(__file__).resolve().parents[5] / "scenes/dining_room.xml", dining_dir=str(dining), resx=64, resy=36)
    seconds = timeit.timeit(lambda: geometry_key(room), number=1000) / 1000
    print(f"geometry_key of the dining room ({len(room.shapes())} shapes): {seconds * 1e6:.1f} µs")
