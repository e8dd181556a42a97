"""Speed of the Python package against the CLI (issue 18): run by hand, not by CI.

    python benches/python_speed.py [--particles 1000000] [--frames 36] [--size 960x540]

Needs the package installed (`pip install ./python`). Both sides render the same generated
cloud (the bubble sample written as PLY) with the same settings:

* CLI: `filmsplat render cloud.ply -o cli.png` in this process (`filmsplat.cli`, the CLI's own
  code), or the binary given with --binary in a subprocess. Wall time of the whole command.
* Python: the cloud's arrays as fresh numpy arrays → Cloud → Scene → render → save.
* Turntable: the built scene rendered --frames times around +y (orbit), against building the
  scene once per frame (measured as one build × frames).
"""

import argparse
import os
import subprocess
import tempfile
import time

import numpy as np

import filmsplat


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--particles", type=int, default=1_000_000)
    ap.add_argument("--frames", type=int, default=36)
    ap.add_argument("--size", default="960x540")
    ap.add_argument("--binary", help="the filmsplat binary (default: the CLI in-process)")
    ap.add_argument("--repeat", type=int, default=3, help="best of N for the single renders")
    a = ap.parse_args()
    w, h = (int(v) for v in a.size.split("x"))
    tmp = tempfile.mkdtemp(prefix="filmsplat-bench-")
    ply = os.path.join(tmp, "cloud.ply")
    filmsplat.cli("sample", "bubble", "--particles", str(a.particles), "-o", ply)

    def cli_once():
        t = time.perf_counter()
        args = ["render", ply, "--size", a.size, "-o", os.path.join(tmp, "cli.png"), "--quiet"]
        if a.binary:
            subprocess.run([a.binary, *args], check=True)
        else:
            filmsplat.cli(*args)
        return time.perf_counter() - t

    loaded = filmsplat.read(ply)
    arrays = {
        "positions": np.array(loaded.positions, dtype=np.float64),
        "normals": np.array(loaded.normals),
        "thickness_nm": np.array(loaded.thickness_nm),
        "radius": np.array(loaded.radius),
    }

    def python_once():
        t = time.perf_counter()
        cloud = filmsplat.Cloud(**arrays)
        scene = filmsplat.Scene(cloud, width=w, height=h)
        scene.render(progress=False).save(os.path.join(tmp, "py.png"))
        return time.perf_counter() - t, scene

    cli = min(cli_once() for _ in range(a.repeat))
    runs = [python_once() for _ in range(a.repeat)]
    py = min(t for t, _ in runs)
    scene = runs[-1][1]
    print(f"{a.particles} particles, {a.size}: CLI {cli:.3f} s, Python from numpy {py:.3f} s "
          f"({100 * (py / cli - 1):+.1f} %)")

    build = sum(scene.build_seconds.values())
    t = time.perf_counter()
    for i in range(a.frames):
        scene.render(camera=filmsplat.orbit(360 * i / a.frames), progress=False)
    turn = time.perf_counter() - t
    print(f"turntable of {a.frames} frames: {turn:.2f} s for the renders "
          f"({turn / a.frames:.3f} s a frame); building the scene once: {build:.2f} s, "
          f"so rebuilding every frame would add {(a.frames - 1) * build:.2f} s")


if __name__ == "__main__":
    main()
