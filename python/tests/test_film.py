"""film() and film_rgb() against the independent reference tables in tests/data."""

import csv

import numpy as np
import pytest

import filmsplat
from conftest import DATA


def table(name):
    with open(DATA / name) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def test_film_matches_the_transfer_matrix_reference_table():
    t = table("thinfilm_rt.csv")
    for ior in np.unique(t["ior"]):
        m = t["ior"] == ior
        got = filmsplat.film(t["thickness_nm"][m], t["angle_deg"][m], t["wavelength_nm"][m], ior=ior)
        for k in ("R", "T", "Rs", "Rp"):
            np.testing.assert_allclose(got[k], t[k][m], atol=1e-6, rtol=0, err_msg=k)


def test_film_rgb_matches_the_d65_reference_table():
    t = table("thinfilm_rgb_d65.csv")
    for ior in np.unique(t["ior"]):
        m = t["ior"] == ior
        got = filmsplat.film_rgb(t["thickness_nm"][m], t["angle_deg"][m], ior=ior)
        want = np.stack([t["r"][m], t["g"][m], t["b"][m]], axis=-1)
        np.testing.assert_allclose(got, want, atol=2e-3, rtol=0)


def test_film_broadcasts_like_numpy_and_conserves_energy():
    h = np.linspace(0, 1200, 7)[:, None, None]
    a = np.array([0.0, 30.0, 60.0, 89.0])[None, :, None]
    lam = np.linspace(380, 780, 5)
    out = filmsplat.film(h, a, lam, ior=1.4)
    for k in ("R", "T", "Rs", "Rp"):
        assert out[k].shape == (7, 4, 5) and out[k].dtype == np.float64
    np.testing.assert_allclose(out["R"] + out["T"], 1.0, atol=1e-12)
    np.testing.assert_allclose(out["R"], 0.5 * (out["Rs"] + out["Rp"]), atol=1e-12)
    # No film reflects nothing; one element equals the scalar call.
    assert np.all(out["R"][0] == 0.0)
    one = filmsplat.film(h[3, 0, 0], a[0, 2, 0], lam[1], ior=1.4)
    assert one["R"].shape == () and one["R"] == out["R"][3, 2, 1]
    rgb = filmsplat.film_rgb(h[:, 0, 0], a[0, :, 0][:, None, None])
    assert rgb.shape == (4, 1, 7, 3)


def test_normal_incidence_has_no_polarisation_and_quarter_wave_is_the_maximum():
    # A quarter-wave film (n h = λ/4) reflects the most at normal incidence:
    # R = ((n² − 1) / (n² + 1))².
    n, lam = 1.33, 550.0
    r = filmsplat.film(lam / (4 * n), 0, lam, ior=n)
    assert r["Rs"] == pytest.approx(r["Rp"], abs=1e-15)
    assert r["R"] == pytest.approx(((n * n - 1) / (n * n + 1)) ** 2, rel=1e-9)


@pytest.mark.parametrize(
    "args, message",
    [
        ((-5, 0, 500), "film:"),
        ((100, 95, 500), "film: angle 95 is outside 0..90 degrees"),
        ((100, 0, 50), "film: wavelength 50 nm is outside 100..10000 nm"),
        ((np.nan, 0, 500), "film:"),
    ],
)
def test_bad_film_input_is_a_value_error_with_the_cli_message(args, message):
    with pytest.raises(ValueError, match=message.replace(".", r"\.")):
        filmsplat.film(*args)


def test_bad_ior_and_shapes_are_value_errors():
    with pytest.raises(ValueError, match="film:"):
        filmsplat.film(100, 0, 500, ior=0.5)
    with pytest.raises(ValueError):
        filmsplat.film([1, 2], [1, 2, 3], 500)
    with pytest.raises(ValueError, match="film: angle"):
        filmsplat.film_rgb(100, -1)


def test_film_and_film_rgb_print_the_same_numbers_as_the_cli():
    rows = filmsplat.cli(
        "film", "--thickness", "0,250,1000", "--angle", "0,45,90", "--wavelengths", "400,550,700", "--ior", "1.4"
    ).splitlines()
    assert rows[0] == "thickness_nm,angle_deg,wavelength_nm,R,T,Rs,Rp"
    cli = np.array([[float(v) for v in r.split(",")] for r in rows[1:]])
    got = filmsplat.film(cli[:, 0], cli[:, 1], cli[:, 2], ior=1.4)
    for k, col in (("R", 3), ("T", 4), ("Rs", 5), ("Rp", 6)):
        np.testing.assert_array_equal(got[k], cli[:, col], err_msg=k)
    rows = filmsplat.cli("film", "--rgb", "--thickness", "0:600:150", "--angle", "0,60").splitlines()
    cli = np.array([[float(v) for v in r.split(",")] for r in rows[1:]])
    np.testing.assert_array_equal(filmsplat.film_rgb(cli[:, 0], cli[:, 1]), cli[:, 2:])
