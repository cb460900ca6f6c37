"""Use and misuse (issue 12): what a user sees for bad files, bad arguments, unwritable outputs,
an interrupted write, the API before a variant; the same seed gives the same image; memory stays
flat over many frames."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import mitsuba as mi
import numpy as np
import pytest

import hybrid_integrator as hi
from hybrid_integrator.io import atomic_path, write_exr
from hybrid_integrator.raster.camera import sensor_to_world, transform_matrix
from conftest import DEFAULT_SCENE, ROOT, load

SMALL = ["-D", "resx=16", "-D", "resy=12"]


def cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "hybrid_integrator.cli", *args], capture_output=True, text=True,
                          cwd=ROOT, timeout=300)


def _files(tmp_path: Path) -> dict[str, Path]:
    (tmp_path / "malformed.xml").write_text("<scene version='3.0.0'><shape")
    return {"missing": tmp_path / "nope.xml", "directory": tmp_path, "malformed": tmp_path / "malformed.xml"}


@pytest.mark.parametrize("kind,message", [("missing", "scene file not found"), ("directory", "is a directory"),
                                          ("malformed", "Parsing of XML file")])
def test_bad_scene_files_are_one_line_errors(tmp_path, kind, message):
    done = cli("render", str(_files(tmp_path)[kind]), "-o", str(tmp_path / "o.exr"))
    assert done.returncode == 2 and message in done.stderr and "Traceback" not in done.stderr


@pytest.mark.parametrize("args,message", [
    (["-o", "/proc/no/such/dir/o.exr"], "No such file or directory"),
    (["--spp", "-3"], "spp=-3 is impossible"),
    (["--budget-ms", "nan"], "budget_ms=nan is impossible"),
    (["--variant", "scalar_rgb"], "not supported"),
    (["--variant", "cuda_mono_polarized_nope"], "not available"),
], ids=["unwritable output", "negative spp", "NaN budget", "scalar variant", "unknown variant"])
def test_bad_arguments_are_one_line_errors(tmp_path, args, message):
    args = args if "-o" in args else [*args, "-o", str(tmp_path / "o.exr")]
    done = cli("render", str(DEFAULT_SCENE), *SMALL, *args)
    assert done.returncode == 2 and message in done.stderr, done.stderr[-2000:]
    assert "Traceback" not in done.stderr


def test_no_egl_driver_names_the_packages(tmp_path):
    """Without an EGL driver (glvnd pointed at no vendor) the user sees one line naming the system
    packages to install, and no output file."""
    import os

    out = tmp_path / "x.exr"
    done = subprocess.run([sys.executable, "-m", "hybrid_integrator.cli", "render", str(DEFAULT_SCENE), *SMALL, "-o", str(out)],
                          capture_output=True, text=True, cwd=ROOT, timeout=300,
                          env={**os.environ, "__EGL_VENDOR_LIBRARY_FILENAMES": str(tmp_path / "no-vendor.json")})
    assert done.returncode != 0 and "apt-get install libegl1" in done.stderr
    assert "Traceback" not in done.stderr and not out.exists()


def test_api_before_a_variant_says_what_to_do():
    code = "import hybrid_integrator as hi\ntry:\n hi.load_scene('scenes/default.xml')\nexcept hi.HybridError as e:\n print(e)"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert "mi.set_variant" in done.stdout


def test_an_interrupted_write_leaves_no_file(tmp_path):
    target = tmp_path / "frame.exr"
    with pytest.raises(KeyboardInterrupt):
        with atomic_path(target) as tmp:
            tmp.write_bytes(b"half a frame")
            raise KeyboardInterrupt
    assert list(tmp_path.iterdir()) == []
    write_exr(target, {"Y": np.ones((2, 3), np.float32)})
    assert [p.name for p in tmp_path.iterdir()] == ["frame.exr"]


def test_the_same_seed_gives_the_same_image():
    scene = load(DEFAULT_SCENE, resx=64, resy=48)
    a, b = (np.array(hi.render(scene, spp=2, seed=11).image) for _ in range(2))
    c = np.array(hi.render(scene, spp=2, seed=12).image)
    assert np.array_equal(a, b) and not np.array_equal(a, c)


def _rss_mb() -> float:
    return int(Path("/proc/self/statm").read_text().split()[1]) * 4096 / 2**20


def test_memory_is_flat_over_500_frames():
    """Host memory after 500 frames of a camera path (selection, budget and history carried) grows
    by at most 5 % over its level after the warm-up frames."""
    scene = load(DEFAULT_SCENE, resx=48, resy=36)
    start = transform_matrix(sensor_to_world(scene.sensors()[0]))
    origin, target = start[:3, 3], start[:3, 3] + start[:3, 2]
    cameras = hi.camera_path([(origin, target), (origin + [0.5, 0.2, 0.0], target)], 500)
    integrator = hi.api._integrator({"budget_ms": 5.0, "temporal": True})
    params = mi.traverse(scene.sensors()[0])
    levels = []
    try:
        for k, camera in enumerate(cameras):
            params["to_world"] = camera
            params.update()
            integrator.render_result(scene, seed=k, spp=1, layers=False)
            if k in (50, 499):
                levels.append(_rss_mb())
    finally:
        params["to_world"] = mi.ScalarTransform4f(start)
        params.update()
    assert levels[1] <= 1.05 * levels[0], levels
