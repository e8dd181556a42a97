"""The Python shown in README.md and docs/*.md, and the scripts in python/examples/, run as
written on small data: each ```python block is executed in a fresh namespace in a temporary
folder holding the repository's tests/ (the paths the docs use), with image sizes shrunk to
64x48 (`width=..., height=...` and `size=(..., ...)`); each example script runs as a separate
process with FILMSPLAT_EXAMPLE_SIZE=64x48."""

import os
import pathlib
import re
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
DOCS = [ROOT / "README.md"] + sorted((ROOT / "docs").glob("*.md"))
EXAMPLES = sorted((ROOT / "python" / "examples").glob("*.py"))


def python_blocks():
    """(document:line, code) of every ```python block."""
    out = []
    for doc in DOCS:
        lines = doc.read_text().splitlines()
        start = None
        for i, line in enumerate(lines):
            fence = line.strip()
            if start is None and fence == "```python":
                start = i + 1
            elif start is not None and fence == "```":
                out.append((f"{doc.relative_to(ROOT)}:{start}", "\n".join(lines[start:i])))
                start = None
    return out


def small(code):
    """The same code with every image size shrunk to 64x48."""
    code = re.sub(r"width=\d+, height=\d+", "width=64, height=48", code)
    return re.sub(r"size=\(\d+, \d+\)", "size=(64, 48)", code)


BLOCKS = python_blocks()


def test_the_docs_show_python():
    assert len(BLOCKS) >= 2, BLOCKS
    assert len(EXAMPLES) >= 1


@pytest.mark.parametrize("where,code", BLOCKS, ids=[w for w, _ in BLOCKS])
def test_python_block_runs(where, code, tmp_path, monkeypatch):
    (tmp_path / "tests").symlink_to(ROOT / "tests")
    monkeypatch.chdir(tmp_path)
    exec(compile(small(code), where, "exec"), {"__name__": "__docs__"})
    written = [p.name for p in tmp_path.iterdir() if p.suffix in (".png", ".exr")]
    for name in re.findall(r'"([\w.-]+\.(?:png|exr))"', code):
        assert name in written, f"{where}: {name} was not written ({written})"


@pytest.mark.parametrize("script", EXAMPLES, ids=[p.name for p in EXAMPLES])
def test_example_runs(script, tmp_path):
    env = dict(os.environ, FILMSPLAT_EXAMPLE_SIZE="64x48")
    done = subprocess.run(
        [sys.executable, str(script), str(tmp_path)],
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
    assert any(p.suffix == ".png" for p in tmp_path.iterdir()), done.stdout
