"""chart() and compare(): the CLI's figures and metrics from Python."""

import numpy as np
import pytest

import filmsplat
from conftest import SHELL


def test_chart_is_the_cli_chart(tmp_path):
    img = filmsplat.chart(tmp_path / "py.png", size=(400, 300), max_thickness_nm=1000)
    filmsplat.cli("chart", "-o", tmp_path / "cli.png", "--size", "400x300", "--max-thickness", "1000")
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    assert img.rgb.shape == (300, 400, 3) and img.view == "chart"
    # White background in the corner, colour inside the plot.
    assert np.all(img.rgb[0, 0] == 1.0)
    assert img.rgb.std() > 0.05


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"size": (100, 100)}, "chart: --size must be between 400x300 and 16384x16384"),
        ({"max_angle_deg": 90}, "chart: --max-angle must be 1..89.9 degrees, got 90"),
        ({"max_thickness_nm": 0}, "chart: --max-thickness must be > 0 nm"),
        ({"ior": 0.5}, "chart:"),
    ],
)
def test_bad_chart_arguments(kwargs, message):
    with pytest.raises(ValueError, match=message):
        filmsplat.chart(**kwargs)


def test_compare_returns_the_cli_json(tmp_path):
    out = tmp_path / "c.png"
    m = filmsplat.compare("disk", "sphere", SHELL, output=out, size=(64, 48), preset="preview", quiet=True)
    assert m["a"]["geometry"] == "disk" and m["b"]["geometry"] == "sphere"
    # The shell's 12 394 particles hold one duplicate position, drawn once.
    assert m["a"]["elements"] == m["b"]["elements"] == 12393
    assert -1 <= m["ssim"] <= 1 and m["identical"] is False
    assert 0 < m["delta_e"]["mean"] <= m["delta_e"]["p95"] <= m["delta_e"]["max"]
    assert m["output"] == str(out) and out.read_bytes()[:4] == b"\x89PNG"
    same = filmsplat.compare("disk", "disk", SHELL, output=out, size=(64, 48), preset="preview")
    assert same["identical"] is True and same["psnr_db"] is None and same["delta_e"]["max"] == 0


def test_compare_errors_are_value_errors(tmp_path):
    with pytest.raises(ValueError, match="cube"):
        filmsplat.compare("disk", "cube", SHELL, output=tmp_path / "c.png", size=(64, 48))
    with pytest.raises(ValueError, match="give a .png output"):
        filmsplat.compare("disk", "sphere", SHELL, output=tmp_path / "c.jpg")
