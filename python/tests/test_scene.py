"""Scene, render and Image: statistics of 64x48 renders, the CLI's own output, errors."""

import math
import os
import signal

import numpy as np
import pytest

import filmsplat
from conftest import SHELL


def test_render_statistics_of_the_default_thickness_shell(shell_scene):
    # The shell's 12 394 particles hold one duplicate position, drawn once.
    assert shell_scene.particles == 12393
    img = shell_scene.render()
    assert (img.width, img.height, img.view) == (64, 48, "shaded")
    rgb, alpha = img.rgb, img.alpha
    assert rgb.shape == (48, 64, 3) and rgb.dtype == np.float32
    assert np.all(np.isfinite(rgb))
    assert alpha.shape == (48, 64) and 0 <= alpha.min() and alpha.max() <= 1
    # The framed shell covers the middle of the picture and not the corners.
    assert alpha[24, 32] == 1 and alpha[0, 0] == 0
    assert 0.2 < alpha.mean() < 0.9
    layers = img.layers
    assert set(layers) == {"depth", "normal", "thickness", "hits", "droplets"}
    # The shell has no droplets: its droplet share is 0 everywhere.
    assert np.all(layers["droplets"] == 0)
    hit = alpha > 0
    # Film colours can leave the sRGB gamut (negative channels); the studio light cannot.
    assert rgb[~hit].min() >= 0 and rgb[hit].mean() > 0
    # Every particle got the default thickness, so every crossing shows 500 nm.
    np.testing.assert_allclose(layers["thickness"][hit], 500, rtol=1e-5)
    assert np.all(layers["thickness"][~hit] == 0)
    assert np.all(layers["depth"][hit] > 0) and layers["normal"].shape == (48, 64, 3)
    n = np.linalg.norm(layers["normal"][alpha == 1], axis=-1)
    assert np.all(n > 0.5) and np.all(n < 1.0001)
    assert np.all(layers["hits"][hit] >= 1)
    assert img.rays > 64 * 48


def test_python_render_writes_the_same_png_as_the_cli(tmp_path, shell_cloud):
    cli_png, py_png = tmp_path / "cli.png", tmp_path / "py.png"
    filmsplat.cli("render", SHELL, "--size", "64x48", "--spp", "2", "-o", cli_png, "--quiet")
    filmsplat.Scene(shell_cloud, width=64, height=48, spp=2).render().save(py_png)
    assert py_png.read_bytes() == cli_png.read_bytes()
    # The same from the path, and a path-built scene equals a numpy-built one.
    assert filmsplat.Scene(str(SHELL), width=64, height=48, spp=2).render().rgb.tobytes() == (
        filmsplat.Scene(filmsplat.Cloud(shell_cloud.positions, radius=shell_cloud.radius), width=64, height=48, spp=2)
        .render()
        .rgb.tobytes()
    )


def test_one_build_renders_many_times(shell_scene):
    a = shell_scene.render(seed=3)
    b = shell_scene.render(seed=3)
    assert a.rgb.tobytes() == b.rgb.tobytes()
    front = shell_scene.render(camera=filmsplat.orbit(0))
    side = shell_scene.render(camera=filmsplat.orbit(90))
    assert front.rgb.tobytes() != side.rgb.tobytes()
    # orbit(0) with the default elevation differs from the default camera only in the
    # direction's x part; an explicit copy of the default is the default.
    default = shell_scene.render()
    same = shell_scene.render(camera={"from": [0.35, 0.3, 1.0]})
    assert default.rgb.tobytes() == same.rgb.tobytes()
    small = shell_scene.render(size=(32, 20), spp=1)
    assert small.rgb.shape == (20, 32, 3)


def test_orbit_turns_camera_and_studio_like_the_cli():
    # A shell symmetric about +y: rings of 8k particles from azimuth 0, so a quarter turn maps
    # it onto itself; the studio turning with the camera keeps the picture.
    rows = []
    for j in range(21):
        theta = math.pi * j / 20
        around = 1 if j in (0, 20) else 8 * max(1, math.ceil(2 * math.pi * math.sin(theta) / 0.16 / 8))
        for i in range(around):
            phi = 2 * math.pi * i / around
            rows.append([math.sin(theta) * math.sin(phi), math.cos(theta), math.sin(theta) * math.cos(phi)])
    p = np.array(rows)
    cloud = filmsplat.Cloud(p, normals=p, thickness_nm=450 + 150 * p[:, 1], radius=np.full(len(p), 0.13))
    scene = filmsplat.Scene(cloud, width=64, height=48, spp=8)
    start = scene.render().rgb
    quarter = scene.render(orbit=90).rgb
    assert np.abs(quarter - start).mean() < 0.02 * start.mean()
    # The studio is rigged to any camera, so the camera dict alone seen from the side gives the
    # orbit's picture too, within the shell's own asymmetry (a studio fixed in the world lit
    # the side view differently: more than 10 % of the mean apart).
    side = scene.render(camera=filmsplat.orbit(90)).rgb
    assert np.abs(side - quarter).mean() < 0.05 * start.mean()
    # Turning back restores the light: the same bytes as before.
    assert scene.render().rgb.tobytes() == start.tobytes()
    with pytest.raises(ValueError, match="orbit"):
        scene.render(orbit=float("nan"))


def test_views_and_srgb8(shell_scene, tmp_path):
    v = shell_scene.render(view="thickness")
    assert v.view == "thickness" and v.alpha is None and v.layers == {}
    assert v.rgb.shape == (48, 64, 3)
    img = shell_scene.render()
    s8 = img.to_srgb8()
    assert s8.dtype == np.uint8 and s8.shape == (48, 64, 3)
    # Exposure, tone curve and encoding act per channel and are monotone.
    for c in range(3):
        lin, enc = img.rgb[..., c].ravel(), s8[..., c].ravel()
        assert np.all(np.diff(enc[np.argsort(lin, kind="stable")].astype(int)) >= 0)
    png = img._repr_png_()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    img.save(tmp_path / "a.exr")
    v.save(tmp_path / "v.png")
    assert (tmp_path / "a.exr").stat().st_size > 64 * 48 * 16
    assert (tmp_path / "v.png").read_bytes()[:4] == b"\x89PNG"


def test_progress_callback_counts_tiles_up_to_the_total(shell_cloud):
    calls = []
    filmsplat.Scene(shell_cloud, width=64, height=48).render(progress=lambda d, t: calls.append((d, t)))
    assert calls[-1] == (12, 12)  # 4 x 3 tiles of 16 x 16
    assert all(d <= t for d, t in calls) and [d for d, _ in calls] == sorted(d for d, _ in calls)


def test_ctrl_c_stops_a_render_with_keyboard_interrupt(shell_cloud):
    # Big enough to be running at the first poll (0.1 s): Ctrl-C arrives from the callback.
    scene = filmsplat.Scene(shell_cloud, width=640, height=480, spp=64, preset="final")
    seen = []

    def interrupt(done, total):
        seen.append((done, total))
        os.kill(os.getpid(), signal.SIGINT)

    with pytest.raises(KeyboardInterrupt):
        scene.render(progress=interrupt)
    assert seen and seen[0][0] < seen[0][1]
    # The scene is usable again afterwards.
    assert scene.render(size=(16, 12), spp=1).rgb.shape == (12, 16, 3)


def test_a_callback_error_stops_the_render_and_propagates(shell_scene):
    def fail(done, total):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        shell_scene.render(size=(640, 480), spp=64, progress=fail)


def test_several_clouds_are_one_scene(shell_cloud):
    p = shell_cloud.positions
    left = filmsplat.Cloud(p - [1.5, 0, 0], radius=shell_cloud.radius)
    right = filmsplat.Cloud(p + [1.5, 0, 0], radius=shell_cloud.radius)
    s = filmsplat.Scene([left, right], width=64, height=48)
    # Each copy of the shell holds its one duplicate position, drawn once.
    assert s.particles == 2 * (len(p) - 1)
    with pytest.raises(ValueError, match="1 of 2 clouds have radius"):
        filmsplat.Scene([left, filmsplat.Cloud(p)])


def test_scene_from_file(tmp_path):
    f = tmp_path / "s.toml"
    f.write_text('[input]\nsample = "bubble"\nparticles = 3000\n[render]\nwidth = 64\nheight = 48\n')
    s = filmsplat.Scene.from_file(f)
    assert s.size == (64, 48) and s.particles == 3000
    assert s.render(spp=1).rgb.shape == (48, 64, 3)
    same = filmsplat.Scene(None, sample="bubble", particles=3000, width=64, height=48)
    assert same.render(spp=1).rgb.tobytes() == s.render(spp=1).rgb.tobytes()
    f.write_text('[input]\nsample = "bubble"\n\n[render]\nspps = 2\n')
    with pytest.raises(ValueError, match=r"s\.toml.*line 5.*spps"):
        filmsplat.Scene.from_file(f)
    with pytest.raises(FileNotFoundError, match="missing.toml"):
        filmsplat.Scene.from_file(tmp_path / "missing.toml")


@pytest.mark.parametrize(
    "kwargs, error, message",
    [
        ({"spps": 2}, ValueError, "Scene: unknown knob 'spps'"),
        ({"preset": "fast"}, ValueError, "render.preset"),
        ({"primitive": "cube"}, ValueError, "film.primitive"),
        ({"ior": 0.5}, ValueError, "film.ior"),
        ({"width": 0}, ValueError, "image size must be between"),
        ({"environment": "nowhere.exr"}, FileNotFoundError, "nowhere.exr"),
        ({"environment": {"kind": "sky"}}, ValueError, "environment.kind: unknown 'sky'"),
        ({"environment": "sky"}, ValueError, "environment: 'sky' is not studio, uniform or an .exr"),
        ({"lights": [{"shape": "point", "position": [0, 1, 0]}]}, ValueError, "light"),
        ({"fov": "wide"}, ValueError, r"Scene: camera\.fov = \"wide\": invalid type: string"),
    ],
)
def test_bad_scenes_raise_with_the_cli_message(shell_cloud, kwargs, error, message):
    with pytest.raises(error, match=message):
        filmsplat.Scene(shell_cloud, **kwargs)


def test_bad_renders_and_bad_clouds_raise(shell_scene):
    with pytest.raises(ValueError, match="image size must be between 1x1 and 32768x32768"):
        shell_scene.render(size=(0, 10))
    with pytest.raises(ValueError, match="spp must be between 1 and 65536"):
        shell_scene.render(spp=0)
    with pytest.raises(ValueError, match="view"):
        shell_scene.render(view="x-ray")
    with pytest.raises(ValueError, match="camera.fov must be 1..170"):
        shell_scene.render(camera={"fov": 500})
    with pytest.raises(ValueError, match="Scene: no clouds given"):
        filmsplat.Scene([])
    with pytest.raises(ValueError, match="must be finite|non-finite|NaN|nan"):
        filmsplat.Scene(filmsplat.Cloud([[0, 0, 0], [np.nan, 0, 0], [1, 0, 0]]))
    img = shell_scene.render(size=(8, 6), spp=1)
    with pytest.raises(ValueError, match="output must end in .png or .exr"):
        img.save("picture.jpg")
    with pytest.raises(OSError):
        img.save("/nonexistent-folder/a.png")


def test_a_scene_renders_again_while_it_renders(shell_cloud):
    # A built scene is read only (each render takes its own camera and settings): a render
    # started from another render's progress callback, while that one is still running, runs
    # to the end and gives exactly the pixels it gives alone.
    scene = filmsplat.Scene(shell_cloud, width=640, height=480, spp=64, preset="final")
    sizes, inner = [], []

    class Enough(Exception):
        pass

    def reenter(done, total):
        sizes.append(scene.size)
        inner.append(scene.render(size=(16, 12), spp=2, camera={"fov": 30}))
        raise Enough  # stops the outer render (cancelled, as on Ctrl-C)

    with pytest.raises(Enough):
        scene.render(progress=reenter)
    assert sizes == [(640, 480)]
    alone = scene.render(size=(16, 12), spp=2, camera={"fov": 30})
    assert inner[0].rgb.tobytes() == alone.rgb.tobytes()
    assert alone.rgb.tobytes() != scene.render(size=(16, 12), spp=2).rgb.tobytes()


def test_rendering_releases_the_gil(shell_cloud):
    # A Python thread counts while the render runs, sleeping 1 ms a step (a voluntary release
    # of the GIL). Forced GIL switches are switched off, so between two progress calls (0.1 s
    # of rendering) it can advance only if the render does not hold the GIL.
    import sys
    import threading
    import time

    scene = filmsplat.Scene(shell_cloud, width=320, height=240, spp=8)
    count, stop, seen = [0], threading.Event(), []

    def counter():
        while not stop.is_set():
            count[0] += 1
            time.sleep(0.001)

    interval = sys.getswitchinterval()
    sys.setswitchinterval(1000)
    t = threading.Thread(target=counter)
    t.start()
    try:
        scene.render(progress=lambda d, total: seen.append(count[0]))
    finally:
        stop.set()
        t.join()
        sys.setswitchinterval(interval)
    assert len(seen) >= 2
    assert seen[-1] - seen[0] > 5


def test_shutter_knobs_blur_as_the_cli_does(tmp_path):
    # A square film of disks moving along +x at 1 unit/s.
    rows = [
        f"{-0.5 + 0.05 * i} {-0.5 + 0.05 * j} 0 0 0 1 0.04 400 1 0 0"
        for i in range(21)
        for j in range(21)
    ]
    head = "ply\nformat ascii 1.0\nelement vertex %d\n" % len(rows) + "".join(
        f"property float {p}\n"
        for p in ("x", "y", "z", "nx", "ny", "nz", "radius", "thickness", "velocity_x", "velocity_y", "velocity_z")
    )
    ply = tmp_path / "moving.ply"
    ply.write_text(head + "end_header\n" + "\n".join(rows) + "\n")
    cli_png, py_png, sharp_png = tmp_path / "cli.png", tmp_path / "py.png", tmp_path / "sharp.png"
    size = ("--size", "64x48", "--spp", "8", "--quiet")
    filmsplat.cli("render", ply, *size, "--shutter", "1", "--frame-time", "0.5", "-o", cli_png)
    filmsplat.Scene(str(ply), width=64, height=48, spp=8, shutter=1.0, frame_time=0.5).render().save(py_png)
    filmsplat.Scene(str(ply), width=64, height=48, spp=8).render().save(sharp_png)
    assert py_png.read_bytes() == cli_png.read_bytes()
    assert py_png.read_bytes() != sharp_png.read_bytes()
    with pytest.raises(ValueError, match="frame_time"):
        filmsplat.Scene(str(ply), width=64, height=48, spp=8, shutter=0.5)
