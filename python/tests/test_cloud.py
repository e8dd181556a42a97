"""Cloud from numpy and read() of every format the CLI reads."""

import numpy as np
import pytest

import filmsplat
from conftest import DATA, SHELL


def test_cloud_copies_float64_strided_input_exactly_once_into_float32():
    rng = np.random.default_rng(1)
    big = rng.normal(size=(50, 6))
    pos = big[::2, ::2]  # non-contiguous rows and columns
    normals = np.asfortranarray(rng.normal(size=(25, 3)).astype(np.float32))
    h = np.arange(50, dtype=np.float64)[::2] * 10
    r = np.full(25, 0.1, dtype=np.float32)
    c = filmsplat.Cloud(pos, normals=normals, thickness_nm=h, radius=r, attributes={"vel": h[::-1]})
    assert len(c) == 25
    assert c.positions.dtype == np.float32 and c.positions.shape == (25, 3)
    np.testing.assert_array_equal(c.positions, pos.astype(np.float32))
    np.testing.assert_array_equal(c.normals, normals)
    np.testing.assert_array_equal(c.thickness_nm, h.astype(np.float32))
    np.testing.assert_array_equal(c.radius, r)
    np.testing.assert_array_equal(c.attributes["vel"], h[::-1].astype(np.float32))
    # A copy: changing the input afterwards does not change the cloud.
    big[:] = 0
    assert np.any(c.positions != 0)


def test_cloud_accepts_lists_and_integers_and_leaves_missing_arrays_none():
    c = filmsplat.Cloud([[0, 0, 0], [1, 2, 3]])
    np.testing.assert_array_equal(c.positions[1], [1, 2, 3])
    assert c.normals is None and c.thickness_nm is None and c.radius is None
    assert c.attributes == {}


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"positions": np.zeros((4, 2))}, r"positions must have shape \(N, 3\), got \[4, 2\]"),
        ({"positions": np.zeros(4)}, "positions must have shape"),
        ({"positions": np.zeros((4, 3)), "normals": np.zeros((3, 3))}, r"normals must have shape \(4, 3\)"),
        ({"positions": np.zeros((4, 3)), "thickness_nm": np.zeros(5)}, r"thickness_nm must have shape \(4,\)"),
        ({"positions": np.zeros((4, 3)), "radius": np.zeros((4, 1))}, "radius must have shape"),
        ({"positions": np.zeros((4, 3)), "attributes": {"a": np.zeros(2)}}, r"attributes\['a'\]"),
        ({"positions": [["a", "b", "c"]]}, "positions: not an array of numbers"),
    ],
)
def test_bad_arrays_are_value_errors(kwargs, message):
    with pytest.raises(ValueError, match=message):
        filmsplat.Cloud(**kwargs)


@pytest.mark.parametrize(
    "name, count",
    [
        ("splishsplash_sphere_shell.ply", 12394),
        ("splishsplash_sphere.bgeo", 12394),
        ("dam_break_frame_9_6859_particles.bgeo", 6859),
        ("double_dam_break_frame_26_4732_particles.vtk", 4732),
        ("fluid_250_particles.vtu", 250),
        ("free_particles_125_particles.vtk", 125),
    ],
)
def test_read_every_format(name, count):
    c = filmsplat.read(DATA / name)
    assert len(c) == count
    assert np.all(np.isfinite(c.positions))


def test_read_matches_the_cli_info_count_and_keeps_attributes():
    c = filmsplat.read(SHELL)
    assert "12394" in filmsplat.cli("info", SHELL)
    np.testing.assert_array_equal(c.radius, np.full(12394, 0.025, dtype=np.float32))
    ids = c.attributes["id"]
    assert ids.shape == (12394,) and len(np.unique(ids)) == 12394


def test_thickness_unit_and_attribute_choice(tmp_path):
    p = tmp_path / "t.csv"
    p.write_text("x,y,z,film\n0,0,0,0.5\n1,0,0,0.25\n")
    c = filmsplat.read(p, thickness_attr="film", thickness_unit="um")
    np.testing.assert_allclose(c.thickness_nm, [500, 250])
    with pytest.raises(ValueError, match="thickness unit 'furlong' is not one of nm, um, mm, m"):
        filmsplat.read(p, thickness_unit="furlong")


def test_missing_file_is_an_os_error_naming_it(tmp_path):
    missing = tmp_path / "nope.ply"
    with pytest.raises(OSError, match="nope.ply"):
        filmsplat.read(missing)


@pytest.mark.parametrize("name", ["bgeo_bad_magic.bgeo", "bgeo_truncated_0.bgeo", "bgeo_corrupt_gzip.bgeo"])
def test_malformed_files_are_value_errors_naming_the_file(name):
    with pytest.raises(ValueError, match=name):
        filmsplat.read(DATA / "malformed" / name)
