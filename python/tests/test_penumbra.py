"""The Python module against the CLI: the same frames bit for bit, arrays of the right shape and
type without copies, the CLI's messages as exceptions, compare's metrics, notebook PNGs."""
import json
import os
import subprocess

import matplotlib.image
import numpy as np
import pytest

import penumbra

CLI = os.environ.get("PENUMBRA_CLI", "build/bin/penumbra")
SQUARE = "builtin:square"


@pytest.fixture(scope="module")
def square():
    return penumbra.Scene(SQUARE)


def test_scene_loads(square):
    assert square.spec == SQUARE
    assert square.triangles > 0


def test_frames_are_numpy_arrays_that_own_the_buffers(square):
    f = penumbra.Renderer(square, res=(64, 48), srt_choice="off").render("srt")
    assert (f.width, f.height) == (64, 48)
    assert f.visibility.shape == (48, 64) and f.visibility.dtype == np.float32
    assert f.image.shape == (48, 64, 4) and f.image.dtype == np.uint8
    assert f.pip.shape == (48, 64) and f.covered.shape == (48, 64)
    assert f.visibility.base is not None  # a view of the rendered buffer, not a copy
    assert f.stats["method"] == "srt"
    lit = f.visibility[f.covered == 1]
    assert 0 < (lit > 0.5).sum() < lit.size  # the square's shadow is on the ground
    assert penumbra.Renderer(square, res=(64, 48)).render("sm").pip is None


def test_render_equals_the_cli_frame(tmp_path):
    scene = "builtin:courtyard"  # soft shadows: an area light, samples, the penumbra mask
    # Both choices off: what they take follows the device's timings, which differ from run to run.
    args = ["--scene", scene, "--res", "64x64", "--srt-choice", "off", "--tile-choice", "off", "--light-size", "0.1",
            "--spp", "4"]
    subprocess.run([CLI, "render", "--method", "srt", "--out", str(tmp_path)] + args, check=True,
                   stdout=subprocess.DEVNULL)
    f = penumbra.Renderer(scene, res=(64, 64), srt_choice="off", tile_choice="off", light_size=0.1,
                          spp=4).render("srt")
    cli_image = matplotlib.image.imread(str(tmp_path / "srt.png"))
    assert np.array_equal(np.round(cli_image * 255).astype(np.uint8), f.image)
    cli_stats = json.loads((tmp_path / "srt.stats.json").read_text())
    for key in ("pip_fraction", "rays_traced", "samples_per_pixel"):
        assert cli_stats[key] == f.stats[key], key
    assert 0 < f.stats["rays_traced"]


def test_bad_input_raises_the_cli_message(square):
    with pytest.raises(penumbra.Error, match="nosuch"):
        penumbra.Scene("builtin:nosuch")
    with pytest.raises(penumbra.Error, match="--res"):
        penumbra.Renderer(square, res="12by4")
    with pytest.raises(penumbra.Error, match="--spp"):
        penumbra.Renderer(square, spp=0)
    with pytest.raises(penumbra.Error, match="no_such_option|no-such-option"):
        penumbra.Renderer(square, no_such_option=1)
    r = penumbra.Renderer(square, res=(32, 32))
    with pytest.raises(penumbra.Error, match="unknown method"):
        r.render("nosuch")
    with pytest.raises(penumbra.Error, match="spot:1,2"):
        r.light = "spot:1,2"


def test_compare_judges_methods_against_the_reference(square):
    m = penumbra.compare(square, ["sm", "srt"], res=(64, 64), srt_choice="off")
    wrong = {row["method"]: row["error"]["wrong_pixel_fraction"] for row in m["methods"]}
    assert set(wrong) == {"sm", "srt"}
    assert wrong["srt"] <= 0.0005 and wrong["srt"] <= wrong["sm"]
    assert m["reference"]["method"] == "ref"
    assert m["scene"]["resolution"] == [64, 64]


def test_camera_and_light_move_per_frame(square):
    r = penumbra.Renderer(square, res=(48, 48))
    first = r.render("sm")
    r.light = "dir:1,-1,0"
    assert r.light.startswith("dir:")
    moved = r.render("sm")
    assert not np.array_equal(first.visibility, moved.visibility)
    camera = r.camera
    r.camera = camera
    assert r.camera == camera


def test_frames_show_in_notebooks(square):
    png = penumbra.Renderer(square, res=(16, 16)).render("sm")._repr_png_()
    assert png.startswith(b"\x89PNG\r\n\x1a\n")
