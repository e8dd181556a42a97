"""filmsplat vs Blender Cycles on the same bubble of spheres: time to equal quality.

Not part of the test suite. Set-up (once; see README.md beside this file):

    python3 -m venv /work/peers-venv
    /work/peers-venv/bin/pip install bpy pysplashsurf colour-science numpy OpenEXR

Run (the numbers in the README):

    /work/peers-venv/bin/python benches/peers/cycles_bubble.py --particles 200000 \
        --size 320x240 --out /tmp/peers-cycles

What it does (the reasoning is in README.md):
1. `filmsplat sample bubble` writes the cloud (positions, normals, thickness rh in nm, radius).
2. One lat-long environment (a studio: soft boxes over a grey gradient) is written as an EXR that
   both renderers light the scene with, in the same orientation.
3. Both render the particles as spheres of the same radius with a free-standing soap film
   (n = 1.33, thickness per particle) from the same camera at increasing sample counts, and once
   with many samples (another seed) as each renderer's converged reference. Cycles: see
   cycles_worker.py (analytic spheres, box filter 1 px, bounces = --max-depth).
4. Every render is a whole process, timed from start to exit: filmsplat's (load, build,
   render, write) and Cycles' (Python + bpy start-up, scene set-up, BVH build, render, write).
   The runs are interleaved (filmsplat and Cycles alternate, ladder after ladder) --repeats
   times; the table shows medians of wall and CPU (user + system) seconds.
5. Quality: mean / 95th-percentile CIEDE2000 against the renderer's own converged reference,
   over the whole image and over the film's pixels only (where the converged filmsplat
   image's coverage, its alpha, is >= 0.5). Time to mean ΔE00 1 is interpolated log-log between
   the sample counts that bracket it ('≤' : reached at the first count, '~' : extrapolated).
"""
import argparse
import json
import os
import subprocess
import sys


sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import peers_common as pc  # noqa: E402


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--particles", type=int, default=200000)
    ap.add_argument("--size", default="480x270")
    ap.add_argument("--out", default="/tmp/filmsplat-peers")
    ap.add_argument("--filmsplat", default=pc.DEFAULT_FILMSPLAT, help="filmsplat binary")
    ap.add_argument("--filmsplat-spp", default="1,4,16,64")
    ap.add_argument("--cycles-spp", default="16,64,256,1024")
    ap.add_argument("--filmsplat-ref-spp", type=int, default=256)
    ap.add_argument("--cycles-ref-spp", type=int, default=8192)
    ap.add_argument("--radius-scale", type=float, default=0.5)
    ap.add_argument("--ior", type=float, default=1.33)
    ap.add_argument("--max-depth", type=int, default=12,
                    help="filmsplat --max-depth; Cycles' total, glossy and transmission bounces")
    ap.add_argument("--transparent-bounces", type=int, default=0,
                    help="Cycles' transparent bounces (back faces); 0: --max-depth")
    ap.add_argument("--shading", default="lut")
    ap.add_argument("--roulette", default="0",
                    help="comma-separated filmsplat --roulette values to time (0: the full ray "
                         "tree); the reference is always rendered without roulette")
    ap.add_argument("--repeats", type=int, default=3, help="interleaved runs; medians reported")
    ap.add_argument("--threads", type=int, default=0,
                    help="threads for both renderers (0: all cores)")
    ap.add_argument("--reuse-refs", action="store_true",
                    help="keep converged references already in --out (same settings!)")
    ap.add_argument("--png", default="", help="also write a side-by-side PNG of the converged "
                                              "renders and the ΔE-1 runs here")
    return ap.parse_args()


def fs_run(args, ply, env, camera, size, spp, rr, tag, seed=None):
    exr = os.path.join(args.out, f"filmsplat{tag}_{spp}.exr")
    png = os.path.join(args.out, f"filmsplat{tag}_{spp}.png")
    extra = ["--env", env, "--primitive", "sphere", "--radius-scale", str(args.radius_scale),
             "--shading", args.shading, "--max-depth", str(args.max_depth),
             "--ior", str(args.ior), "--roulette", str(rr)]
    if seed is not None:
        extra += ["--seed", str(seed)]
    cmd = pc.filmsplat_cmd(args.filmsplat, [ply], camera, size, spp, exr, png, extra)
    return cmd, exr


def cy_run(args, ply, env, camera, size, spp, seed=1):
    exr = os.path.join(args.out, f"cycles_{spp}{'_ref' if seed != 1 else ''}.exr")
    spec = {"kind": "points", "ply": ply, "radius_scale": args.radius_scale, "env": env,
            "camera": camera, "size": list(size), "spp": spp, "seed": seed,
            "threads": args.threads, "ior": args.ior, "max_depth": args.max_depth,
            "transparent_bounces": args.transparent_bounces, "out": exr}
    path = exr[:-4] + ".json"
    with open(path, "w") as f:
        json.dump(spec, f)
    return pc.cycles_cmd(pc.python_exe(), path), exr


def main():
    args = parse_args()
    print(f"start: {pc.load()}", flush=True)
    size = tuple(int(v) for v in args.size.split("x"))
    os.makedirs(args.out, exist_ok=True)
    env_vars = pc.thread_env(args.threads)
    ply = os.path.join(args.out, f"bubble_{args.particles}.ply")
    subprocess.run([args.filmsplat, "sample", "bubble", "--particles", str(args.particles),
                    "-o", ply], check=True, stdout=subprocess.DEVNULL)
    env = os.path.join(args.out, "studio_env.exr")
    pc.write_env(env)
    camera = pc.camera_for(pc.positions(pc.read_ply(ply)))

    # Converged references, another seed than the ladders (their noise must not be shared).
    fs_ref_cmd, fs_ref_exr = fs_run(args, ply, env, camera, size, args.filmsplat_ref_spp, 0.0,
                                    "_ref", seed=7)
    cy_ref_cmd, cy_ref_exr = cy_run(args, ply, env, camera, size, args.cycles_ref_spp, seed=7)
    refs = {}
    for name, cmd, exr in (("filmsplat", fs_ref_cmd, fs_ref_exr),
                           ("cycles", cy_ref_cmd, cy_ref_exr)):
        reuse = args.reuse_refs and os.path.exists(exr)
        refs[name] = (float("nan"), float("nan")) if reuse else pc.timed(cmd, env_vars)
    print(f"references: filmsplat {refs['filmsplat'][0]:.1f} s, Cycles {refs['cycles'][0]:.1f} s"
          f" wall; {pc.load()}", flush=True)

    # The ladders, interleaved: filmsplat, Cycles, filmsplat, ... repeated.
    ladders = {}
    for rr in [float(v) for v in args.roulette.split(",")]:
        name = "filmsplat" if rr == 0 else f"filmsplat, roulette {rr:g}"
        tag = "" if rr == 0 else f"_rr{rr:g}"
        ladders[name] = [(spp, *fs_run(args, ply, env, camera, size, spp, rr, tag))
                         for spp in [int(s) for s in args.filmsplat_spp.split(",")]]
    ladders["cycles"] = [(spp, *cy_run(args, ply, env, camera, size, spp))
                         for spp in [int(s) for s in args.cycles_spp.split(",")]]
    jobs = []
    for i in range(max(len(v) for v in ladders.values())):
        for name, lad in ladders.items():
            if i < len(lad):
                jobs.append((name, *lad[i]))
    times = {}
    for rep in range(args.repeats):
        for name, spp, cmd, exr in jobs:
            times.setdefault((name, spp), []).append(pc.timed(cmd, env_vars))
        print(f"repeat {rep + 1}/{args.repeats} done; {pc.load()}", flush=True)

    fs_ref, alpha = pc.read_exr(fs_ref_exr)
    cy_ref, _ = pc.read_exr(cy_ref_exr)
    mask = pc.film_mask(alpha)
    rows = []
    for name, lad in ladders.items():
        ref = cy_ref if name == "cycles" else fs_ref
        for spp, _, exr in lad:
            t = times[(name, spp)]
            q = pc.summarize(pc.delta_e_map(pc.read_exr(exr)[0], ref), mask)
            rows.append({"renderer": name, "spp": spp, "exr": exr,
                         "wall": pc.median([w for w, _ in t]),
                         "seconds": pc.median([w for w, _ in t]),  # the old key: wall
                         "cpu": pc.median([c for _, c in t]), **q})
    cross = pc.summarize(pc.delta_e_map(fs_ref, cy_ref), mask)
    summary = report(args, size, rows, cross, refs, mask)
    if args.png:
        picture(args.png, rows, summary)
    print(f"end: {pc.load()}", flush=True)


def report(args, size, rows, cross, refs, mask):
    print(f"\n{args.particles} particles, {size[0]}x{size[1]}, medians of {args.repeats} "
          f"interleaved runs, threads {args.threads or os.cpu_count()}; film pixels "
          f"{int(mask.sum()) if mask is not None else 'n/a'} of {size[0] * size[1]}\n")
    print("| renderer | spp | wall (s) | CPU (s) | mean ΔE00 | p95 ΔE00 | film mean ΔE00 | "
          "film p95 ΔE00 |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['renderer']} | {r['spp']} | {r['wall']:.2f} | {r['cpu']:.2f} | "
              f"{r['de_mean']:.3f} | {r['de_p95']:.3f} | {r['de_film_mean']:.3f} | "
              f"{r['de_film_p95']:.3f} |")
    print("\nTime to mean ΔE00 1 against the own converged render (interpolated log-log):\n")
    print("| renderer | whole image: wall | CPU | film only: wall | CPU |")
    print("|---|---|---|---|---|")
    summary = {}
    for name in dict.fromkeys(r["renderer"] for r in rows):
        rs = [r for r in rows if r["renderer"] == name]
        s = {}
        for key in ("de_mean", "de_film_mean"):
            for clock in ("wall", "cpu"):
                s[(key, clock)] = pc.time_to([(r[clock], r[key]) for r in rs])
        summary[name] = s
        cells = [pc.fmt_time(*s[(k, c)]) for k in ("de_mean", "de_film_mean")
                 for c in ("wall", "cpu")]
        print(f"| {name} | " + " | ".join(cells) + " |")
    cy = summary.get("cycles")
    if cy:
        print("\nCycles' time / filmsplat's time to ΔE00 1:\n")
        print("| filmsplat run | whole image: wall | CPU | film only: wall | CPU |")
        print("|---|---|---|---|---|")
        for name, s in summary.items():
            if name == "cycles":
                continue
            cells = [pc.fmt_ratio(*s[(k, c)], *cy[(k, c)]) for k in ("de_mean", "de_film_mean")
                     for c in ("wall", "cpu")]
            print(f"| {name} | " + " | ".join(cells) + " |")
    print(f"\nconverged filmsplat vs converged Cycles: mean ΔE00 {cross['de_mean']:.2f} "
          f"(film {cross['de_film_mean']:.2f}), p95 {cross['de_p95']:.2f}")
    print(f"references: filmsplat {args.filmsplat_ref_spp} spp {refs['filmsplat'][0]:.1f} s wall,"
          f" Cycles {args.cycles_ref_spp} spp {refs['cycles'][0]:.1f} s wall")
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump({"rows": rows, "cross_de": cross, "size": size, "particles": args.particles,
                   "repeats": args.repeats,
                   "summary": {n: {f"{k}/{c}": v for (k, c), v in s.items()}
                               for n, s in summary.items()}}, f, indent=1)
    return summary


def picture(path, rows, summary):
    """Each renderer at its first sample count below mean ΔE 1 (else its last), side by side,
    labelled with its time."""
    panels = []
    for name, s in summary.items():
        rs = [r for r in rows if r["renderer"] == name]
        pick = next((r for r in rs if r["de_mean"] <= 1.0), rs[-1])
        panels.append((pc.read_exr(pick["exr"])[0],
                       [name, f"{pick['spp']} spp: {pick['wall']:.2f} s, dE {pick['de_mean']:.2f}",
                        f"to dE 1: {pc.fmt_time(*s[('de_mean', 'wall')])} s"]))
    pc.side_by_side(path, panels)
    print(f"wrote {path}")


if __name__ == "__main__":
    sys.exit(main())
