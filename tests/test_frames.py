"""Camera paths to disk on Ray workers (issue 13, ``hybrid_integrator/frames.py``): two local
workers render the same frames as one process, each frame with its statistics, a preview, and a
resumed run renders only what is missing. The comparisons turn the learnt ambient term off: each
worker's chunk learns its own (frames.py), so untraced pixels may differ from one process's."""
from __future__ import annotations

import json

import mitsuba as mi
import numpy as np
import pytest

import hybrid_integrator as hi
from hybrid_integrator.frames import chunks, render_frames
from hybrid_integrator.io import read_exr
from hybrid_integrator.raster.camera import sensor_to_world, transform_matrix
from conftest import DEFAULT_SCENE

SMALL = dict(resx=64, resy=48)


def _cameras(n: int):
    scene = hi.load_scene(DEFAULT_SCENE, **SMALL)
    start = transform_matrix(sensor_to_world(scene.sensors()[0]))
    origin, target = start[:3, 3], start[:3, 3] + start[:3, 2]
    return hi.camera_path([(origin, target), (origin + [0.4, 0.2, 0.0], target)], n)


def _fresh_process(cameras, out, seed: int) -> dict:
    """The frames rendered by ``hybrid sequence`` in a process of their own (one worker, no Ray):
    the single-process reference. (A test process that rendered other scenes before can render
    a frame of a path differently: architecture.md, Known limits.)"""
    import subprocess
    import sys


    keys = json.dumps([transform_matrix(c).tolist() for c in cameras])
    done = subprocess.run([sys.executable, "-c", (
        "import json, sys, mitsuba as mi; mi.set_variant('llvm_ad_rgb'); import hybrid_integrator as hi; "
        "print(json.dumps(hi.render_frames(sys.argv[1], json.loads(sys.argv[2]), sys.argv[3], seed=int(sys.argv[4]), "
        "params=dict(resx=64, resy=48), learn_ambient=False)))"), str(DEFAULT_SCENE), keys, str(out), str(seed)],
        capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


@pytest.fixture(scope="module")
def ray_session():
    """One local Ray instance (two CPUs) for this module's worker tests, which ``render_frames``
    finds started. Not one per test: Ray started again in a process after ``ray.shutdown()`` can
    abort that process (ray-project/ray#31145, #20975), and a CI run of the suite was aborted
    (SIGABRT) in the second of two such sessions, the killed-worker test."""
    from hybrid_integrator.frames import start_ray

    ray = start_ray("these tests need Ray: pip install 'hybrid_integrator[ray]'", num_cpus=2)
    yield ray
    ray.shutdown()


def test_chunks_are_contiguous_and_cover_every_frame():
    parts = chunks(list(range(10)), 3)
    assert [p for c in parts for p in c] == list(range(10)) and [len(c) for c in parts] == [4, 3, 3]
    assert chunks([0, 1], 4) == [[0], [1]]


def test_two_ray_workers_render_what_one_process_renders(tmp_path, ray_session):
    cameras = _cameras(6)
    one = _fresh_process(cameras, tmp_path / "one", seed=3)
    # the workers draw each next frame's raster pass ahead (on the CPU only when asked): the same frames
    two = render_frames(DEFAULT_SCENE, cameras, tmp_path / "two", seed=3, workers=2, params=SMALL,
                        learn_ambient=False, raster_ahead="on")
    assert one["rendered"] == two["rendered"] == 6 and two["preview"] and (tmp_path / "two" / "preview.gif").is_file()
    for k in range(6):
        a, _ = read_exr(tmp_path / "one" / f"frame_{k:05d}.exr")
        b, _ = read_exr(tmp_path / "two" / f"frame_{k:05d}.exr")
        image_a, image_b = (np.stack([x[c] for c in "RGB"], -1) for x in (a, b))
        assert np.abs(image_a - image_b).mean() <= 1e-3 * image_a.mean(), k
        stats = json.loads((tmp_path / "two" / f"frame_{k:05d}.json").read_text())
        assert stats["frame"] == k and stats["width"] == 64 and stats["secondary_rays"] > 0
        # chunks [0, 1, 2] and [3, 4, 5]: a worker's first frame has nothing drawn ahead
        assert (stats["raster_ahead"], stats["raster_discarded"]) == ((0, 0) if k in (0, 3) else (1, 0)), k


def test_a_resumed_run_renders_only_missing_frames(tmp_path):
    cameras = _cameras(4)
    render_frames(DEFAULT_SCENE, cameras, tmp_path, params=SMALL, preview=False)
    for k in (1, 3):
        (tmp_path / f"frame_{k:05d}.json").unlink()
    again = render_frames(DEFAULT_SCENE, cameras, tmp_path, params=SMALL)
    assert again["rendered"] == 2 and again["skipped"] == 2 and (tmp_path / "preview.gif").is_file()
    with pytest.raises(hi.HybridError, match="workers=0"):
        render_frames(DEFAULT_SCENE, cameras, tmp_path, params=SMALL, workers=0)


def _worker_pids() -> list[int]:
    """The processes of this machine's Ray actors that render frames (their title names the class)."""
    from pathlib import Path

    pids = []
    for proc in Path("/proc").iterdir():
        try:
            if proc.name.isdigit() and b"ray::FrameRenderer" in (proc / "cmdline").read_bytes():
                pids.append(int(proc.name))
        except OSError:
            continue
    return pids


def test_a_killed_worker_loses_nothing(tmp_path, ray_session):
    """One worker process is killed while the path renders: Ray restarts it and retries its frames;
    every frame is there and equals an undisturbed run's. (Only this run's workers are candidates:
    an earlier test's may still be exiting.)"""
    import os
    import signal
    import threading
    import time

    cameras = _cameras(8)
    calm = _fresh_process(cameras, tmp_path / "calm", seed=1)
    killed, earlier = [], set(_worker_pids())

    def kill_one():
        deadline = time.time() + 120
        while time.time() < deadline and not killed:
            done = list((tmp_path / "hit").glob("frame_*.json"))
            pids = [p for p in _worker_pids() if p not in earlier]
            if len(done) >= 2 and pids:
                os.kill(pids[0], signal.SIGKILL)
                killed.append(pids[0])
            time.sleep(0.05)

    killer = threading.Thread(target=kill_one)
    killer.start()
    try:
        hit = render_frames(DEFAULT_SCENE, cameras, tmp_path / "hit", seed=1, workers=2, params=SMALL, preview=False,
                            learn_ambient=False)
    finally:
        killer.join()
    assert killed and calm["rendered"] == hit["rendered"] == 8
    for k in range(8):
        a, _ = read_exr(tmp_path / "calm" / f"frame_{k:05d}.exr")
        b, _ = read_exr(tmp_path / "hit" / f"frame_{k:05d}.exr")
        image_a, image_b = (np.stack([x[c] for c in "RGB"], -1) for x in (a, b))
        assert np.abs(image_a - image_b).mean() <= 1e-3 * image_a.mean(), k


def test_render_sequence_points_to_render_frames_for_workers():
    """``hi.render_sequence`` keeps frames in memory in this process: asked for Ray workers, it
    says which call writes frames on workers instead."""
    scene = hi.load_scene(DEFAULT_SCENE, **SMALL)
    with pytest.raises(hi.HybridError, match="render_frames"):
        hi.render_sequence(scene, _cameras(2), workers=2)


def test_gl_context_on_mesa_needs_no_cuda_device():
    """The EGL device of Dr.Jit's CUDA device is looked up only with a CUDA variant; Mesa's EGL
    names no CUDA device, so the context stays on EGL's first device."""
    from hybrid_integrator.raster.context import egl_device_of_cuda, gl_context

    assert egl_device_of_cuda() is None
    assert gl_context().info["GL_RENDERER"]


def test_workers_without_ray_say_how_to_get_it(tmp_path):
    """Ray is an optional extra: where it cannot be imported, workers > 1 is a one-line error
    naming the extra to install (workers = 1 needs no Ray)."""
    import subprocess
    import sys

    code = ("import sys; sys.modules['ray'] = None; import mitsuba as mi; mi.set_variant('llvm_ad_rgb'); "
            "import hybrid_integrator as hi; import numpy as np\n"
            "try:\n    hi.render_frames(sys.argv[1], [np.eye(4).tolist()], sys.argv[2], workers=2)\n"
            "except hi.HybridError as e:\n    print('ERROR', e)")
    done = subprocess.run([sys.executable, "-c", code, str(DEFAULT_SCENE), str(tmp_path)], capture_output=True,
                          text=True, timeout=300)
    assert "ERROR" in done.stdout and "pip install 'hybrid_integrator[ray]'" in done.stdout, done.stderr[-2000:]


def test_frames_in_flight_render_the_same_frames_and_read_their_times_later():
    """``frames_in_flight=2`` (inflight.py): a camera path renders the same images as one frame at
    a time (raster passes drawn ahead too); a frame in flight has NaN times until the next frame
    reads them (its total, device time of its span; its denoiser's; its stages stay NaN: no
    kernel history without a synchronization) and learns from its counts (its statistics); the
    path's last frame is read by render_sequence.
    A budgeted frame is rendered one at a time, and a bad value is refused."""
    import math

    from hybrid_integrator.api import _integrator

    scene = hi.load_scene(DEFAULT_SCENE, **SMALL)
    cameras = _cameras(4)
    common = dict(spp=1, seed=7, layers=False, raster_ahead="on")
    one = hi.render_sequence(scene, cameras, **common)
    two = hi.render_sequence(scene, cameras, frames_in_flight=2, **common)
    for a, b in zip(one, two):
        assert np.array_equal(np.array(a.image), np.array(b.image))
        assert not a.stats.in_flight and b.stats.in_flight and a.stats.stages_timed and not b.stats.stages_timed
        # its counts' lesson, learnt in the next frame: the same statistics (the objects' order by
        # relevance may differ: a frame in flight shades its raster layer with the ambient term
        # learnt a frame earlier, and the error it measures of the layer differs with it)
        assert (a.stats.rays, a.stats.pixels_traced) == (b.stats.rays, b.stats.pixels_traced)
        assert sorted(a.stats.selected) == sorted(b.stats.selected) and b.stats.selected
        t = b.stats.times_ms
        assert t["total"] > 0 and t["denoise"] > 0 and t["issue"] > 0 and math.isnan(t["trace"]), t
        assert math.isfinite(a.stats.times_ms["trace"])
    assert [b.stats.raster_ahead for b in two] == [a.stats.raster_ahead for a in one] == [0, 1, 1, 1]
    # a frame in flight keeps no kernel history (it could never read it): none left behind
    import drjit as dr

    dr.kernel_history_clear()
    hi.render_sequence(scene, cameras[:2], frames_in_flight=2, **common)
    assert dr.kernel_history() == []
    # a frame in flight, then one with a budget: the first's times come with the second
    integrator = _integrator(dict(frames_in_flight=2))
    first = integrator.render_result(scene, seed=1, spp=1, layers=False)
    assert first.stats.in_flight and math.isnan(first.stats.times_ms["total"])
    integrator.settings = type(integrator.settings)(frames_in_flight=2, budget_ms=50.0)
    second = integrator.render_result(scene, seed=2, spp=1, layers=False)
    assert first.stats.times_ms["total"] > 0 and not second.stats.in_flight
    assert math.isfinite(second.stats.times_ms["trace"]) and second.stats.times_ms["total"] > 0
    with pytest.raises(hi.HybridError, match="frames_in_flight=3"):
        hi.render(scene, frames_in_flight=3)
