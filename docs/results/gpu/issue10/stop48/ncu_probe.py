"""The two megakernels under Nsight Compute (stop 48): one render of Mitsuba's ``path`` at 1 spp
(``max_depth`` -1, as the hybrid's) and two all-candidates hybrid frames (no denoiser), for
``ncu -k regex:raygen`` to profile their OptiX launches (run.sh's ``ncu`` mode).

    ncu -k regex:raygen --section LaunchStats … python3 docs/results/gpu/issue10/stop48/ncu_probe.py SCENE.xml -D …
"""
import argparse


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("scene")
    parser.add_argument("-D", dest="defines", action="append", default=[])
    args = parser.parse_args()
    import drjit as dr
    import mitsuba as mi
    mi.set_variant("cuda_ad_rgb")
    import hybrid_integrator as hi
    from hybrid_integrator.bench import load_bench_scene

    scene, _ = load_bench_scene(args.scene, dict(d.split("=", 1) for d in args.defines))
    dr.eval(mi.render(scene, integrator=mi.load_dict({"type": "path", "max_depth": -1}), spp=1, seed=1))
    dr.sync_thread()
    for _ in range(2):
        hi.render(scene, layers=False, denoise=False)


if __name__ == "__main__":
    main()
