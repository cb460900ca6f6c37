"""Stop 45, on the CPU: which of ``primary.outline_ties``' tests refine a frame's pixels, on the
compute pass's visibility buffer (the GPU's refinement, ``outline="ties"``), at 1280×720: the
outline pixels, and among them the doubted ones by test (own edge, a neighbour's triangle covering
the sample, a depth tie) and the raster misses.

    .venv/bin/python docs/results/gpu/issue10/stop45/ties.py sponza_mirror dining_room many_objects
"""
import sys, numpy as np, mitsuba as mi, drjit as dr
mi.set_variant("llvm_ad_rgb")
import hybrid_integrator as hi
from hybrid_integrator import primary as P
from hybrid_integrator.raster.camera import RasterCamera
for name in sys.argv[1:]:
    scene = mi.load_file(f"scenes/{name}.xml", resx="1280", resy="720")
    raster = hi.rasterizer(scene)
    cam = RasterCamera.from_sensor(scene.sensors()[0])
    w, h = cam.width, cam.height
    off = (0.5, 0.5)
    tid = mi.UInt32(raster.read_ids(raster.render(cam, off, "compute")).astype(np.uint32))
    tables = raster.tables
    ray = P.camera_rays(scene.sensors()[0], w, h, off, differentials=True)
    record = P.resolve(tid, ray, tables)
    _, nb = P._neighbours(w, h)
    own = P._label(tid, mi.Bool(True), tables)
    outline = mi.Bool(False); drawn = []; other = []
    for inside, j in nb:
        drawn.append(dr.gather(mi.UInt32, tid, j, inside)); other.append(inside & (P._label(drawn[-1], inside, tables) != own)); outline |= other[-1]
    hit, t = record.hit, dr.select(record.hit, record.t, dr.inf)
    _, margin = P.edge_margin(ray, *P._corners(tables, tid - 1, hit))
    own_edge = outline & hit & ~(margin >= P.EDGE_TOLERANCE)
    own_nan = outline & hit & dr.isnan(margin)
    own_out = outline & hit & (margin < 0)
    covers_any = mi.Bool(False); tie_any = mi.Bool(False); covers_bg = mi.Bool(False)
    for number, differs in zip(drawn, other):
        tested = outline & differs & (number > 0)
        t_other, m2 = P.edge_margin(ray, *P._corners(tables, number - 1, tested))
        covers = ~(m2 < -P.EDGE_TOLERANCE) & ~(t_other <= 0.0) & ~(t_other >= t * (1.0 + P.DEPTH_TIE))
        tie = hit & ~(dr.abs(t_other - t) > P.DEPTH_TIE * t)
        covers_any |= tested & covers; tie_any |= tested & tie; covers_bg |= tested & covers & ~hit
    miss = record.hit & ~record.inside & ~record.proxy
    c = lambda m: int(np.count_nonzero(np.array(m)))
    total = own_edge | covers_any | tie_any | miss
    print(f"{name}: outline {c(outline)}, own edge {c(own_edge)} (NaN {c(own_nan)}, outside {c(own_out)}), "
          f"neighbour covers {c(covers_any)} (on background pixels {c(covers_bg)}), tie {c(tie_any)}, miss {c(miss)}, "
          f"all {c(total)}; covers only {c(covers_any & ~own_edge & ~tie_any & ~miss)}, tie only {c(tie_any & ~own_edge & ~covers_any & ~miss)}", flush=True)
