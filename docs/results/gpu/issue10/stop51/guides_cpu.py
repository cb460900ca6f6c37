"""Stop 51, CPU: does OIDN do better with the guides of the first non-delta hit (through mirrors and
glass, tinted by the specular chain; transmission where there is one) than with the G-buffer's
(white on delta surfaces)? The hybrid's own noisy frame and guides (captured at the denoiser),
denoised again with the chain's guides everywhere (``chain``) or on the delta pixels alone
(``chain_delta_only``); FLIP (mean of 4 seeds) against path at 512 spp, 320x180. The chain's
guides are taken at pixel centres, the frame's at its sub-pixel offset.

    .venv/bin/python docs/results/gpu/issue10/stop51/guides_cpu.py scenes/sponza_mirror.xml scenes/armadillo_glass.xml scenes/showcase.xml
"""
import sys, numpy as np, drjit as dr, mitsuba as mi
mi.set_variant('llvm_ad_rgb')
import hybrid_integrator as hi
from hybrid_integrator import denoise as dn
from hybrid_integrator.metrics import flip_map
from hybrid_integrator.bench import load_bench_scene
S='../shared/scenes'
params = dict(resx='320', resy='180', models_dir=f'{S}/models', sponza_dir=f'{S}/sponza-dabrovic', showcase_dir=f'{S}/cbox', dining_dir=f'{S}/dining-room')
captured = []
orig = dn.Denoiser.__call__
def capture(self, color, guides):
    captured.append((np.array(color), np.array(guides.albedo), np.array(guides.normal)))
    return orig(self, color, guides)
dn.Denoiser.__call__ = capture

def chain_guides(scene, w, h, max_chain=8):
    sensor = scene.sensors()[0]
    idx = dr.arange(mi.UInt32, w * h)
    pos = mi.Vector2f(mi.Float(idx % w) + 0.5, mi.Float(idx // w) + 0.5) / mi.Vector2f(w, h)
    ray, _ = sensor.sample_ray(0.0, 0.5, pos, mi.Point2f(0.5))
    si = scene.ray_intersect(ray)
    tint = mi.Color3f(1.0)
    albedo = mi.Color3f(0.0); normal = mi.Vector3f(0.0)
    done = mi.Bool(False)
    first_delta = None
    for k in range(max_chain):
        bsdf = si.bsdf(ray)
        valid = si.is_valid()
        flags = bsdf.flags()
        delta_only = valid & mi.has_flag(flags, mi.BSDFFlags.Delta) & ~mi.has_flag(flags, mi.BSDFFlags.Smooth)
        stop = ~done & (~valid | ~delta_only)
        if first_delta is None:
            first_delta = mi.Bool(delta_only)
        # the first non-delta hit (or the background: colour clamp as the hybrid does -> use tint only)
        a = dr.select(valid, bsdf.eval_diffuse_reflectance(si, valid), 0.0)
        albedo = dr.select(stop, dr.clip(tint * a, 0, 1), albedo)
        normal = dr.select(stop & valid, si.sh_frame.n, normal)
        # background through the chain: white (as the hybrid's guide for colour-clamped background is colour)
        albedo = dr.select(stop & ~valid, dr.clip(tint, 0, 1), albedo)
        done |= stop
        ctx = mi.BSDFContext()
        bs, wgt = bsdf.sample(ctx, si, 0.999, mi.Point2f(0.5), ~done)  # 0.999: transmission where there is one
        tint = dr.select(~done, tint * wgt, tint)
        ray = si.spawn_ray(si.to_world(bs.wo))
        si = scene.ray_intersect(ray, ~done)
    albedo = dr.select(done, albedo, dr.clip(tint, 0, 1))
    def image(v):
        return np.stack([np.array(v.x), np.array(v.y), np.array(v.z)], -1).reshape(h, w, 3)
    return image(albedo), image(normal), np.array(first_delta).reshape(h, w)

for spec in sys.argv[1:]:
    scene, name = load_bench_scene(spec, params)
    gt_scene, _ = load_bench_scene(spec, {**params})
    ref = np.array(mi.render(gt_scene, integrator=mi.load_dict({'type': 'path', 'max_depth': -1}), spp=512, seed=5))[..., :3]
    w, h = 320, 180
    ca, cn, dm = chain_guides(scene, w, h)
    print(name, 'delta pixels', dm.mean())
    res = {'current': [], 'chain': [], 'chain_delta_only': [], 'none': []}
    den = dn.Denoiser('fast')
    for seed in range(4):
        captured.clear()
        r = hi.render(scene, spp=1, seed=seed, layers=False)
        color, alb, nrm = captured[0]
        res['current'].append(flip_map(np.array(r.image)[..., :3], ref)[1])
        # chain guides only where the G-buffer's albedo is white-ish from a delta surface: use the chain everywhere
        # (for non-delta surfaces the chain's first hit is the primary hit: same albedo up to the specular term)
        out = orig(den, mi.TensorXf(color), dn.Guides(albedo=mi.TensorXf(ca.astype(np.float32)), normal=mi.TensorXf(cn.astype(np.float32))))
        res['chain'].append(flip_map(np.array(out)[..., :3], ref)[1])
        a2, n2 = alb.copy(), nrm.copy(); a2[dm] = ca[dm]; n2[dm] = cn[dm]
        out = orig(den, mi.TensorXf(color), dn.Guides(albedo=mi.TensorXf(a2.astype(np.float32)), normal=mi.TensorXf(n2.astype(np.float32))))
        res['chain_delta_only'].append(flip_map(np.array(out)[..., :3], ref)[1])
        res['none'].append(flip_map(color[..., :3], ref)[1])
    print(name, {k: round(float(np.mean(v)), 4) for k, v in res.items()}, flush=True)
