"""Sizes and values a caller chooses (issue #30, items 2 and 3): every allocation goes through
the CLI's memory allowance before anything is copied, bad values are refused where they enter,
and spp has one range (1..65536) whichever way it comes in."""

import numpy as np
import pytest

import filmsplat


def test_a_billion_row_broadcast_view_is_refused_before_any_copy():
    # 24 bytes to numpy; copying it would be 12 GB and estimating it hundreds.
    view = np.broadcast_to(np.zeros(3, dtype=np.float64), (10**9, 3))
    with pytest.raises(ValueError, match="1000000000 particles.*available"):
        filmsplat.Cloud(view)


def test_the_memory_allowance_is_the_clis(monkeypatch):
    pos = np.random.default_rng(1).normal(size=(10_000, 3))
    # The CLI's allowance override: 1 MiB holds no 10 000-particle render.
    monkeypatch.setenv("FILMSPLAT_MEMORY_LIMIT", "1M")
    with pytest.raises(ValueError, match="10000 particles"):
        filmsplat.Cloud(pos)
    monkeypatch.delenv("FILMSPLAT_MEMORY_LIMIT")
    assert len(filmsplat.Cloud(pos)) == 10_000


def test_bad_values_are_refused_when_the_cloud_is_made():
    with pytest.raises(ValueError, match="10 particles have non-finite positions"):
        filmsplat.Cloud(np.full((10, 3), np.nan))
    pos = np.random.default_rng(2).normal(size=(5, 3))
    with pytest.raises(ValueError, match="negative thickness"):
        filmsplat.Cloud(pos, thickness_nm=np.array([1, 2, -3, 4, 5.0]))
    with pytest.raises(ValueError, match="zero or negative radius"):
        filmsplat.Cloud(pos, radius=np.zeros(5))
    with pytest.raises(ValueError, match="non-finite normals"):
        filmsplat.Cloud(pos, normals=np.full((5, 3), np.inf))


@pytest.mark.parametrize("view", ["depth", "shaded"])
def test_a_huge_render_size_is_refused_before_allocating(shell_scene, view):
    # 32768 x 32768 at 88 B a pixel: 94 GB, beyond any allowance.
    with pytest.raises(ValueError, match="32768x32768.*available"):
        shell_scene.render(size=(32768, 32768), view=view)
    assert shell_scene.render(size=(8, 6), spp=1, view=view) is not None


def test_spp_has_one_range_for_every_way_in(shell_scene, shell_cloud):
    # 65537 before 2**32 - 1: code without the range fails fast on it instead of rendering
    # for hours.
    for spp in (0, 65537, 2**32 - 1):
        with pytest.raises(ValueError, match="render.spp must be between 1 and 65536"):
            shell_scene.render(size=(8, 6), spp=spp)
    with pytest.raises(ValueError, match="render.spp must be between 1 and 65536"):
        filmsplat.Scene(shell_cloud, width=8, height=6, spp=2**32 - 1)
    assert shell_scene.render(size=(8, 6), spp=1) is not None


def test_a_bad_light_is_refused_before_the_input_is_read(tmp_path):
    # The input promises four billion vertices and holds none: an error about the light
    # proves the scene was checked before the file was read (issue #31, item 1).
    (tmp_path / "huge.ply").write_text(
        "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
        "property float x\nproperty float y\nproperty float z\nend_header\n"
    )
    scene = tmp_path / "s.toml"
    scene.write_text(
        '[input]\ncloud = "huge.ply"\n[[light]]\nshape = "rect"\n'
        "position = [0, 2, 0]\nsize = [1, 1]\n"
    )
    with pytest.raises(ValueError, match=r"light 1 \(line 4\): needs radiance"):
        filmsplat.Scene.from_file(scene)
