"""``hybrid bench`` end to end on a tiny scene: every field of the report is there and sane, and
the tables and charts are written (the measurements themselves are benchmarks, in docs/)."""
import json
import math
import subprocess
import sys
from dataclasses import fields

import pytest

from conftest import DEFAULT_SCENE
from hybrid_integrator.bench import FIELDS, Measurement

TINY = ["-D", "resx=48", "-D", "resy=32", "--frames", "1", "--gt-spp", "8", "--max-path-spp", "2", "--budgets", "0", "0.5"]


def bench(*args, cwd=None):
    done = subprocess.run([sys.executable, "-m", "hybrid_integrator.cli", "bench", *args], capture_output=True, text=True,
                          cwd=cwd)
    return done


def test_bench_report_has_every_field(tmp_path):
    done = bench(str(DEFAULT_SCENE), *TINY, "-o", str(tmp_path))
    assert done.returncode == 0, done.stderr[-2000:]
    (report,) = json.loads((tmp_path / "bench.json").read_text())
    assert set(FIELDS) <= set(report)
    names = [m["method"] for m in report["methods"]]
    assert names == ["raster", "hybrid", "rt-baseline", "hybrid@0%", "hybrid@50%", "hybrid, no denoiser",
                     "hybrid, denoiser 'high'", "hybrid 2 spp", "hybrid 4 spp", "hybrid 2 spp, denoiser 'high'",
                     "hybrid+history", "hybrid+history@1", "hybrid+history@2",
                     "hybrid+history, 8 paths/hit", "hybrid+history, 8 paths/hit@1", "hybrid+history, 8 paths/hit@2",
                     "path@1spp", "path@2spp", "path@1spp, mi.render", "path@equal-time", "path@history-time",
                     "path+denoiser@history-time", "path@history-time, 8 paths/hit",
                     "path+denoiser@history-time, 8 paths/hit", "path+denoiser@1spp", "path+denoiser@2spp",
                     "path+denoiser@4spp", "path+denoiser 'fast'@1spp"]
    by_name = {m["method"]: m for m in report["methods"]}
    for name in ("hybrid+history", "hybrid+history, 8 paths/hit"):  # all frames, and the first ones
        assert [by_name[f"{name}{at}"]["frames_accumulated"] for at in ("@1", "@2", "")] == [1, 2, report["frames"] + 3]
    # eight paths per hit: as many pixels, eight times the rays, more time per frame
    one, eight = by_name["hybrid+history"], by_name["hybrid+history, 8 paths/hit"]
    assert one["pixels_traced"] == eight["pixels_traced"] and eight["secondary_rays"] > 6 * one["secondary_rays"]
    assert by_name["path@history-time, 8 paths/hit"]["spp"] >= by_name["path@history-time"]["spp"]
    # each history's rivals: path raw and path + the denoiser the history's frames have, at one spp
    for suffix in ("", ", 8 paths/hit"):
        raw, denoised = by_name[f"path@history-time{suffix}"], by_name[f"path+denoiser@history-time{suffix}"]
        assert raw["spp"] == denoised["spp"] and denoised["kind"] == "path+denoiser"
    # the path curve is replayed from a recording: the same frames as mi.render's (their error the
    # same, to the film's atomic sums); both times in Table 3
    plain, frozen = by_name["path@1spp, mi.render"], by_name["path@1spp"]
    assert frozen["flip"] == pytest.approx(plain["flip"], abs=1e-4) and frozen["time_ms"] == report["path_1spp_frozen_ms"]
    assert plain["time_ms"] == report["path_1spp_ms"]
    # the denoiser at 'fast' is another filter than at 'high': another image of the same 1-spp path
    assert by_name["path+denoiser 'fast'@1spp"]["rel_mse"] != by_name["path+denoiser@1spp"]["rel_mse"]
    assert f"| {report['path_1spp_ms']:.2f} | {report['path_1spp_frozen_ms']:.2f} |" in (tmp_path / "bench.md").read_text()
    for m in report["methods"]:
        assert set(m) == {f.name for f in fields(Measurement)}
        assert m["time_ms"] > 0 and 0 < m["flip"] < 1 and math.isfinite(m["rel_mse"]) and m["delta_e2000"] >= 0
    hybrid = next(m for m in report["methods"] if m["method"] == "hybrid")
    assert set(hybrid["stages_ms"]) >= {"raster", "lighting", "select", "trace", "compose", "total"}
    # timed without the kernel history (stage_times=False): the stages of DR, the hybrid and the
    # RT baseline from frames of their own, a budget's from its frames, the other rows' not timed
    assert all(by_name[name]["stages_ms"]["trace"] >= 0 for name in ("raster", "rt-baseline", "hybrid@50%"))
    assert hybrid["stages_ms"]["trace"] > 0 and by_name["hybrid, no denoiser"]["stages_ms"] == {}
    assert hybrid["secondary_rays"] > 0
    # the baseline traces the same pixels from camera rays: same image, same error
    rt = next(m for m in report["methods"] if m["method"] == "rt-baseline")
    assert rt["pixels_traced"] == hybrid["pixels_traced"] and rt["flip"] == pytest.approx(hybrid["flip"], abs=2e-3)
    assert report["gain"] == pytest.approx(report["rt_ms"] / report["hybrid_ms"])
    # the paired Gain: one ratio per measured frame, its median between its quartiles, in the table
    paired = report["gain_paired"]
    assert paired["pairs"] == report["frames"] and paired["q25"] <= paired["median"] <= paired["q75"]
    assert paired["hybrid_ms"] > 0 and paired["rt_ms"] > 0 and 0.2 < paired["median"] < 5
    assert f"{paired['median']:.3f} [{paired['q25']:.3f}, {paired['q75']:.3f}]" in (tmp_path / "bench.md").read_text()
    # with two frames in flight: turns of five frames, four measured (rounds of the frames asked for)
    flight = report["gain_in_flight"]
    assert flight["pairs"] == -(-report["frames"] // 4) and flight["hybrid_ms"] > 0 and flight["rt_ms"] > 0
    assert f"{flight['median']:.3f} ({flight['hybrid_ms']:.2f} / {flight['rt_ms']:.2f})" in (tmp_path / "bench.md").read_text()
    assert report["name"] == "default" and report["triangles"] == 10264 and report["width"] == 48 and report["height"] == 32
    assert report["command"].startswith("hybrid bench ")
    assert (tmp_path / "default.png").stat().st_size > 0 and "Table 3 layout" in (tmp_path / "bench.md").read_text()


def test_bench_without_accuracy_writes_times_and_no_chart(tmp_path):
    """``--no-accuracy`` (the speed benchmarks of issue 10): times and tables, no errors, and no
    time–FLIP chart to draw."""
    done = bench(str(DEFAULT_SCENE), *TINY, "--no-accuracy", "-o", str(tmp_path))
    assert done.returncode == 0, done.stderr[-2000:]
    (report,) = json.loads((tmp_path / "bench.json").read_text())
    assert report["dr_ms"] > 0 and report["hybrid_ms"] > 0 and all(math.isnan(m["flip"]) for m in report["methods"])
    assert "Table 3 layout" in (tmp_path / "bench.md").read_text() and not (tmp_path / "default.png").exists()
    # the host's speed at the scene's start and end (bench.host_loops), in the report and its table
    host = report["host_loop_ms"]
    assert all(0 < host[at]["min_ms"] <= host[at]["median_ms"] < 50 for at in ("start", "end"))
    assert f"default {host['start']['min_ms']:.3f} / {host['start']['median_ms']:.3f}" in (tmp_path / "bench.md").read_text()


def test_bench_hands_an_option_turned_off_to_its_child(tmp_path):
    """A boolean integrator option turned off (``--no-stage-times``) reaches the bench's child
    process as that flag, not as ``--stage-times False`` (which the child's parser refused: the
    bench of every scene failed); with it, the budget's frames time every ``--timing-interval``-th."""
    from hybrid_integrator.cli import _bench_options, _parser

    args = _parser().parse_args(["bench", str(DEFAULT_SCENE), "--no-stage-times", "--no-denoise", "--timing-interval", "2"])
    options = _bench_options(args)
    assert {"--no-stage-times", "--no-denoise"} <= set(options) and "False" not in options
    assert options[options.index("--timing-interval") + 1] == "2"
    done = bench(str(DEFAULT_SCENE), *TINY, "--no-accuracy", "--no-stage-times", "--timing-interval", "2",
                 "-o", str(tmp_path))
    assert done.returncode == 0, done.stderr[-2000:]
    (report,) = json.loads((tmp_path / "bench.json").read_text())
    assert "--no-stage-times" in report["command"] and report["hybrid_ms"] > 0


def test_bench_scaling_by_triangles(tmp_path):
    out = tmp_path / "triangles"
    done = bench("--scaling", "triangles", "--values", "2000", "8000", "-D", "resx=48", "-D", "resy=32",
                 "--frames", "1", "-o", str(out))
    assert done.returncode == 0, done.stderr[-2000:]
    result = json.loads(out.with_suffix(".json").read_text())
    tris = [p["triangles"] for p in result["points"]]
    assert tris[0] < tris[1] and abs(tris[1] - 8000) < 0.1 * 8000
    assert all(p["hybrid_ms"] > 0 and p["rt_ms"] > 0 for p in result["points"])
    assert out.with_suffix(".png").is_file() and out.with_suffix(".md").is_file()


def test_bench_jobs_on_ray_keep_their_order(tmp_path):
    """``--ray``: the points run as Ray tasks (a local instance, one CPU each) and come back in the
    order asked for, each measured."""
    out = tmp_path / "triangles"
    done = bench("--scaling", "triangles", "--values", "8000", "2000", "-D", "resx=48", "-D", "resy=32",
                 "--frames", "1", "--ray", "-o", str(out))
    assert done.returncode == 0, done.stderr[-2000:]
    points = json.loads(out.with_suffix(".json").read_text())["points"]
    assert [round(p["triangles"], -3) for p in points] == [8000, 2000]
    assert all(p["hybrid_ms"] > 0 and p["rt_ms"] > 0 for p in points)


@pytest.mark.parametrize("args, message", [(["procedural:10"], "triangles=10 must lie in"),
                                           (["procedural:abc"], "'abc' is not a number of triangles"),
                                           ([str(DEFAULT_SCENE), "--max-path-spp", "0"], "bench: max_path_spp=0 must be >= 1"),
                                           # a negative fraction ran as 1e-6 ms, reported as 'hybrid@-50%'
                                           ([str(DEFAULT_SCENE), "--budgets", "0.5", "-0.5", "nan"],
                                            "bench: budgets [-0.5, nan] must be fractions >= 0"),
                                           (["--scaling", "triangles"], "needs --values"),
                                           (["--scaling", "resolution", "--values", "1280by720"],
                                            "['1280by720'] are not resolutions WxH"),
                                           ([], "at least one scene")])
def test_bench_bad_input(tmp_path, args, message):
    done = bench(*args, "--frames", "1", "-o", str(tmp_path / "x"))
    assert done.returncode != 0 and message in done.stderr


def test_each_scene_gets_the_parameters_it_names():
    """``-D`` goes to the scenes that name the parameter, by its whole name: ``$res`` is not
    ``$resx`` (Mitsuba refuses a parameter a file does not use)."""
    from hybrid_integrator.bench import load_bench_scene

    params = {"resx": "40", "resy": "30", "res": "24", "integrator": "path"}
    scene, name = load_bench_scene(str(DEFAULT_SCENE), params)
    assert name == "default" and tuple(scene.sensors()[0].film().size()) == (40, 30)
    from conftest import SHARED_SCENES

    scene, _ = load_bench_scene(str(SHARED_SCENES / "cbox/cbox_spheres_analytic.xml"), params)
    assert tuple(scene.sensors()[0].film().size()) == (24, 24)


def test_frames_in_turn_along_a_camera_path():
    """Along a camera path, every side renders round k from pose k (the warm-up rounds' too), the
    pairs are formed from the measured rounds, the sensor's own pose comes back after, and too few
    poses for the rounds is a clear error. By blocks, every side moves along the path frame by
    frame: the j-th frame of round k from pose k·block + j (``bench.turn_poses`` of them)."""
    import mitsuba as mi
    import numpy as np

    import hybrid_integrator as hi
    from hybrid_integrator.bench import frames_in_turn, paired_ratio, turn_poses
    from hybrid_integrator.errors import HybridError
    from hybrid_integrator.raster.camera import transform_matrix

    scene = hi.load_scene(DEFAULT_SCENE, resx=32, resy=24)
    params = mi.traverse(scene.sensors()[0])
    before = transform_matrix(params["to_world"])
    cameras = hi.camera_path([((0, 0, 3.9), (0, 0, 0)), ((0.6, 0.2, 3.0), (0.1, -0.2, 0))], 4)
    seen = {"raster": [], "raytrace": []}  # the sensor's pose at each side's frames
    times = frames_in_turn(scene, {"raster": {"denoise": False}, "raytrace": {"denoise": False, "primary": "raytrace"}},
                           frames=2, spp=1, seed=0, warmup=2, cameras=cameras,
                           before=lambda name: seen[name].append(transform_matrix(params["to_world"])))
    assert [len(times[side]) for side in ("raster", "raytrace")] == [2, 2]
    for side in seen:
        assert [np.allclose(m, transform_matrix(c)) for m, c in zip(seen[side], cameras)] == [True] * 4
    assert np.array_equal(transform_matrix(params["to_world"]), before)
    paired = paired_ratio(times, "raytrace", "raster")
    assert paired["pairs"] == 2 and paired["q25"] <= paired["median"] <= paired["q75"] and paired["raster_ms"] > 0
    with pytest.raises(HybridError, match="3 camera poses for 4 rounds"):
        frames_in_turn(scene, {"raster": {}}, frames=2, spp=1, seed=0, warmup=2, cameras=cameras[:3])
    # by blocks of 3 (the first of each not measured): 1 warm-up round and 1 measured round, 6 poses
    assert turn_poses(2, warmup=1, block=3) == 6
    cameras = hi.camera_path([((0, 0, 3.9), (0, 0, 0)), ((0.6, 0.2, 3.0), (0.1, -0.2, 0))], 6)
    seen = {"raster": [], "raytrace": []}
    measured = []  # what ``after`` is given: each measured frame's side, pose and result
    times = frames_in_turn(scene, {"raster": {"denoise": False}, "raytrace": {"denoise": False, "primary": "raytrace"}},
                           frames=2, spp=1, seed=0, warmup=1, block=3, cameras=cameras,
                           before=lambda name: seen[name].append(transform_matrix(params["to_world"])),
                           after=lambda name, at, result: measured.append((name, at, result.stats.times_ms)))
    assert [len(times[side]) for side in ("raster", "raytrace")] == [2, 2]
    # the measured round is the second (poses 3-5), its first frame not measured
    assert sorted((name, at) for name, at, _ in measured) == [("raster", 4), ("raster", 5), ("raytrace", 4), ("raytrace", 5)]
    assert all(any(t is entry for t in times[name]) for name, _, entry in measured)
    for side in seen:
        assert [np.allclose(m, transform_matrix(c)) for m, c in zip(seen[side], cameras)] == [True] * 6
    with pytest.raises(HybridError, match="5 camera poses for 2 rounds of 3 frames"):
        frames_in_turn(scene, {"raster": {}}, frames=2, spp=1, seed=0, warmup=1, block=3, cameras=cameras[:5])


def test_frames_in_turn_take_the_hosts_speed_and_ratios_split_by_it():
    """With ``host_speed`` each measured frame carries the host loop's time before it
    (``bench.host_loop_ms``), and ``paired_ratio_by_host`` gives the paired ratio apart for the
    rounds on a fast host (every frame's loop within ``FAST_HOST`` × the fastest) and on a slow
    one; ``paired_ratio``'s ``keep`` counts only the rounds it names."""
    import hybrid_integrator as hi
    from hybrid_integrator.bench import FAST_HOST, frames_in_turn, host_loop_ms, paired_ratio, paired_ratio_by_host

    assert 0 < host_loop_ms() < 50
    scene = hi.load_scene(DEFAULT_SCENE, resx=32, resy=24)
    times = frames_in_turn(scene, {"raster": {"denoise": False}, "raytrace": {"denoise": False, "primary": "raytrace"}},
                           frames=3, spp=1, seed=0, warmup=1, host_speed=True)
    assert all(len(v) == 3 and all(t["host_loop"] > 0 and t["total"] > 0 for t in v) for v in times.values())
    split = paired_ratio_by_host(times, "raytrace", "raster")
    # a busy host may leave no round fast (both frames' loops within FAST_HOST x the fastest)
    pairs = {label: (split[label] or {"pairs": 0})["pairs"] for label in ("fast", "slow")}
    assert pairs["fast"] + pairs["slow"] == 3 and split["fast_share"] == pairs["fast"] / 3
    # rounds of 2 measured frames (block 3): round 0 fast on both sides, round 1 slow on one frame
    frame = lambda total, loop: {"total": total, "host_loop": loop}
    made = {"rt": [frame(8.0, 0.10), frame(8.0, 0.11), frame(8.0, 0.10), frame(8.0, 0.10)],
            "budget": [frame(4.0, 0.10), frame(4.0, 0.12), frame(6.0, 0.10), frame(6.0, 0.10 * FAST_HOST + 0.01)]}
    split = paired_ratio_by_host(made, "rt", "budget", block=3)
    assert split["fast_share"] == 0.5 and split["fastest_loop_ms"] == 0.10
    assert split["fast"]["median"] == 2.0 and split["slow"]["median"] == 8.0 / 6.0
    assert split["fast"]["pairs"] == split["slow"]["pairs"] == 1 and split["slow"]["budget_ms"] == 6.0
    assert paired_ratio(made, "rt", "budget", block=3, keep=[False, True]) == split["slow"]
    assert paired_ratio_by_host({k: v[:2] for k, v in made.items()}, "rt", "budget", block=3)["slow"] is None


def test_turn_scene_takes_the_parameters_its_file_uses_and_its_camera_path():
    """``bench.turn_scene`` (the GPU probes' set-up): the scene loaded with the parameters its file
    uses, its camera path where it has one (``NAME_path.json``), else None, and the hybrid's median
    trace time with every candidate traced."""
    from hybrid_integrator.bench import path_cameras, turn_scene

    ready = turn_scene(str(DEFAULT_SCENE), {"resx": "32", "resy": "24", "sponza_dir": "unused"}, 4)
    assert ready.cameras is None and ready.name == DEFAULT_SCENE.stem
    assert ready.scene.sensors()[0].film().size().x == 32 and ready.all_candidates_trace_ms > 0
    many = DEFAULT_SCENE.parent / "many_objects.xml"
    assert len(path_cameras(many, 3)) == 3 and path_cameras(DEFAULT_SCENE, 3) is None
