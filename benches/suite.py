"""Whole-render benchmark suite: the bubble sample at several sizes, every primitive and
shading mode, timed stage by stage through the CLI, with peak memory.

    cargo build --release
    python3 benches/suite.py [--particles 100000,1000000,4000000] [--size 1280x720]
                             [--primitives disk,sphere,mls] [--out /tmp/filmsplat-suite]

For each cloud size N it writes the cloud once (`filmsplat sample bubble`), then runs
`filmsplat render` for each primitive and shading setting at the balanced preset and parses the
CLI's summary line (load, estimate, build, render seconds, Mrays/s); `/usr/bin/time` gives the
peak resident memory. Prints a Markdown table and writes `suite.md` and `suite.png` (render time
against particle count, log-log) into the output folder. Nothing here is asserted: numbers
depend on the machine; run it on a quiet one.
"""
import argparse
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FILMSPLAT = os.path.join(ROOT, "target", "release", "filmsplat")
SUMMARY = re.compile(
    r"(?P<n>\d+) particles \((?P<geom>[^)]*)\): load (?P<load>[\d.]+) s, estimate (?P<est>[\d.]+) s, "
    r"build (?P<build>[\d.]+) s; render \d+x\d+ at \d+ spp: (?P<render>[\d.]+) s \((?P<mrays>[\d.]+) Mrays/s\)")


def run(cmd):
    """Runs cmd under /usr/bin/time; returns (stdout, peak RSS in MiB)."""
    res = subprocess.run(["/usr/bin/time", "-f", "MAXRSS %M"] + cmd, capture_output=True, text=True)
    if res.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{res.stderr}")
    rss = int(re.search(r"MAXRSS (\d+)", res.stderr).group(1)) / 1024.0
    return res.stdout, rss


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--particles", default="100000,1000000,4000000")
    ap.add_argument("--size", default="1280x720")
    ap.add_argument("--primitives", default="disk,sphere")
    ap.add_argument("--shadings", default="lut,rgb:8,rgb:16")
    ap.add_argument("--out", default="/tmp/filmsplat-suite")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for n in [int(v) for v in args.particles.split(",")]:
        ply = os.path.join(args.out, f"bubble_{n}.ply")
        if not os.path.exists(ply):
            subprocess.run([FILMSPLAT, "sample", "bubble", "--particles", str(n), "-o", ply],
                           check=True, stdout=subprocess.DEVNULL)
        for prim in args.primitives.split(","):
            for sh in args.shadings.split(","):
                mode, _, wl = sh.partition(":")
                cmd = [FILMSPLAT, "render", ply, "-o", os.path.join(args.out, f"{prim}_{n}.png"),
                       "--size", args.size, "--primitive", prim, "--shading", mode,
                       "--preset", "balanced"]
                if wl:
                    cmd += ["--wavelengths", wl]
                out, rss = run(cmd)
                m = SUMMARY.search(out)
                if not m:
                    raise SystemExit(f"no summary line in: {out}")
                row = dict(n=n, prim=prim, shading=sh, rss=rss,
                           **{k: float(m.group(k)) for k in ("load", "est", "build", "render", "mrays")})
                rows.append(row)
                print(f"{n} {prim} {sh}: {row}", file=sys.stderr)
    md = ("| particles | primitive | shading | load (s) | estimate (s) | build (s) | render (s) "
          "| Mrays/s | peak memory (MiB) | bytes/particle |\n|---|---|---|---|---|---|---|---|---|---|\n")
    for r in rows:
        md += (f"| {r['n']:,} | {r['prim']} | {r['shading']} | {r['load']:.2f} | {r['est']:.2f} | "
               f"{r['build']:.2f} | {r['render']:.2f} | {r['mrays']:.2f} | {r['rss']:.0f} | "
               f"{r['rss'] * 2**20 / r['n']:.0f} |\n")
    print(md)
    with open(os.path.join(args.out, "suite.md"), "w") as f:
        f.write(md)
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6, 4), dpi=100)
        for prim in args.primitives.split(","):
            for sh in args.shadings.split(","):
                pts = [(r["n"], r["render"]) for r in rows if r["prim"] == prim and r["shading"] == sh]
                if pts:
                    ax.plot(*zip(*pts), marker="o", label=f"{prim}, {sh}")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("particles")
        ax.set_ylabel(f"render time at {args.size}, balanced preset (s)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(args.out, "suite.png"))
    except ImportError:
        print("matplotlib not installed: no plot", file=sys.stderr)


if __name__ == "__main__":
    main()
