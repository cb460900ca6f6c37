"""Stop 45, on the CPU: per tile of the compute raster pass, how many large triangles its last stage
keeps (a debug copy of the shader whose target holds the count; the lists are the GPU's, the
order of their entries aside).

    .venv/bin/python docs/results/gpu/issue10/stop45/kept.py sponza_mirror dining_room many_objects showcase
"""
import sys, numpy as np, mitsuba as mi
mi.set_variant("llvm_ad_rgb")
import hybrid_integrator as hi
from hybrid_integrator.raster import compute
from hybrid_integrator.raster.camera import RasterCamera
src = compute.shader_source("visibility.comp")
src = src.replace("    uint count = counts.listed;", "    uint total = 0u;\n    uint count = counts.listed;")
src = src.replace("        uint n = kept_count;\n", "        uint n = kept_count;\n        total += n;\n")
src = src.replace("        imageStore(target, p, uvec4(id));", "        imageStore(target, p, uvec4(total));")
assert src.count("total") >= 3, src.count("total")
for name in sys.argv[1:]:
    scene = mi.load_file(f"scenes/{name}.xml", resx="1280", resy="720")
    raster = hi.rasterizer(scene)
    cam = RasterCamera.from_sensor(scene.sensors()[0])
    fbo = raster.target(cam.width, cam.height)
    orig = compute.shader_source
    compute.shader_source = lambda _: src
    v = compute.ComputeVisibility(raster.ctx, raster.vertices, raster.faces, len(raster.geometry.faces))
    compute.shader_source = orig
    k = raster.read_ids(v.render(cam, (0.5, 0.5), fbo)).reshape(720, 1280)[::32, ::32]
    print(name, v.tiers(), "tiles", k.size, "kept per tile: mean", k.mean().round(1), "max", k.max(), "p90", np.percentile(k, 90), "sum", k.sum())
