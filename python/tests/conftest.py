"""Shared paths and small scenes for the filmsplat Python tests (64x48 renders)."""

import pathlib

import pytest

import filmsplat

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data"
SHELL = DATA / "splishsplash_sphere_shell.ply"


@pytest.fixture(scope="session")
def shell_cloud():
    return filmsplat.read(SHELL)


@pytest.fixture(scope="session")
def shell_scene(shell_cloud):
    return filmsplat.Scene(shell_cloud, width=64, height=48)
