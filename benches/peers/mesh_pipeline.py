"""The meshing pipeline (pysplashsurf + Cycles' thin film) vs filmsplat disks and MLS, end to end,
to equal quality.

Not part of the test suite. Set-up once (see README.md beside this file):

    python3 -m venv /work/peers-venv
    /work/peers-venv/bin/pip install bpy pysplashsurf colour-science numpy OpenEXR

Run (the numbers in the README):

    /work/peers-venv/bin/python benches/peers/mesh_pipeline.py --out /tmp/peers-mesh

The pipeline users run today, as three timed processes per frame:
1. meshing (`--mesh-worker`, a fresh Python process): read the particles, reconstruct the
   surface with pysplashsurf (SPH colour field + marching cubes; particle radius = half the
   median nearest-neighbour spacing, smoothing length 2 radii, iso 0.6, mesh clean-up, 25
   weighted Laplacian smoothing steps, as splashsurf's README recommends; cube size
   --cube-size radii, default 1, coarser than the README's 0.5), interpolate the particles'
   thickness rh onto the vertices (pysplashsurf's SPH interpolation: a normalised
   kernel-weighted average of the particles within 2 smoothing lengths), write the mesh;
2. Cycles (cycles_worker.py, a fresh process: bpy start-up, mesh import, BVH, render) with the
   Principled thin film, thickness from the vertex attribute, n = 1.33, back faces
   transparent, as cycles_bubble.py renders spheres;
against `filmsplat render FILE --primitive disk|mls` (the whole process, reading the simulator's
own file). All with one camera and one environment EXR, box pixel filter, 12 film crossings.

Quality: mean CIEDE2000 against each pipeline's own converged render (many samples, another
seed); time to mean ΔE00 1 interpolated log-log between sample counts (the mesh pipeline's
time = meshing + Cycles). Whole image and film pixels only (coverage >= 0.5 in the converged
filmsplat disk render). Runs are interleaved --repeats times; medians of wall and CPU seconds.
Writes a Markdown table and, per case, samples/images/peers_mesh_CASE.png (the three
pipelines' first runs below ΔE 1, side by side, labelled with their times).
"""
import argparse
import json
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import peers_common as pc  # noqa: E402

CASES = {
    # name: (input for filmsplat, description)
    "bubble": (None, "filmsplat sample bubble (200k particles)"),
    "shell": ("tests/data/splishsplash_sphere_shell.ply", "SPlisHSPlasH sphere shell, 12,394"),
    "melp": ("tests/data/melp/bubble/l_particles_0100.vtp", "MELP bubble frame 100, 19,995"),
}


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", default="bubble,shell", help="of: " + ",".join(CASES))
    ap.add_argument("--particles", type=int, default=200000, help="bubble size")
    ap.add_argument("--size", default="320x240")
    ap.add_argument("--out", default="/tmp/filmsplat-peers-mesh")
    ap.add_argument("--filmsplat", default=pc.DEFAULT_FILMSPLAT, help="filmsplat binary")
    ap.add_argument("--filmsplat-spp", default="1,2,4,8")
    ap.add_argument("--filmsplat-ref-spp", type=int, default=64)
    ap.add_argument("--cycles-spp", default="4,16,64,256")
    ap.add_argument("--cycles-ref-spp", type=int, default=2048)
    ap.add_argument("--cube-size", type=float, default=1.0,
                    help="marching-cubes cell, in particle radii (splashsurf's example uses 0.5: "
                         "4x the vertices; 1.0 keeps meshing cheaper, in the mesh "
                         "pipeline's favour)")
    ap.add_argument("--smoothing-length", type=float, default=2.0, help="in particle radii")
    ap.add_argument("--iso", type=float, default=0.6)
    ap.add_argument("--ior", type=float, default=1.33)
    ap.add_argument("--max-depth", type=int, default=12)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--threads", type=int, default=0, help="threads for all (0: all cores)")
    ap.add_argument("--images", default=os.path.join(pc.ROOT, "samples", "images"),
                    help="folder for peers_mesh_CASE.png ('' : none)")
    ap.add_argument("--mesh-worker", nargs=2, metavar=("PLY", "NPZ"), help=argparse.SUPPRESS)
    return ap.parse_args()


def mesh_worker(args, ply, npz):
    """Step 1 of the pipeline, run in its own timed process."""
    import pysplashsurf as ps
    from scipy.spatial import cKDTree

    c = pc.read_ply(ply)
    p = pc.positions(c)
    rh = c["rh"] if "rh" in c else np.full(len(p), 500.0)
    d, _ = cKDTree(p).query(p, k=2, workers=args.threads or -1)
    radius = 0.5 * float(np.median(d[:, 1]))
    mesh, _ = ps.reconstruction_pipeline(
        p, particle_radius=radius, smoothing_length=args.smoothing_length,
        cube_size=args.cube_size, iso_surface_threshold=args.iso,
        attributes_to_interpolate={"rh": rh}, mesh_cleanup=True, mesh_smoothing_iters=25,
        mesh_smoothing_weights=True, multi_threading=args.threads != 1)
    np.savez(npz, verts=np.asarray(mesh.mesh.vertices), tris=np.asarray(mesh.mesh.triangles),
             rh=np.asarray(mesh.point_attributes["rh"]))


def prepare(args, name):
    """The case's input file (for filmsplat), its PLY (x y z rh radius, for the mesher) and
    the shared camera."""
    d = os.path.join(args.out, name)
    os.makedirs(d, exist_ok=True)
    src, _ = CASES[name]
    if src is None:
        src = os.path.join(d, f"bubble_{args.particles}.ply")
        subprocess.run([args.filmsplat, "sample", "bubble", "--particles", str(args.particles),
                        "-o", src], check=True, stdout=subprocess.DEVNULL)
    else:
        src = os.path.join(pc.ROOT, src)
    ply = os.path.join(d, "particles.ply")
    subprocess.run([args.filmsplat, "convert", src, "-o", ply], check=True,
                   stdout=subprocess.DEVNULL)
    return d, src, ply, pc.camera_for(pc.positions(pc.read_ply(ply)))


def jobs_for(args, d, src, ply, camera, env, size):
    """{pipeline: [(spp, [commands], exr)]} and the references, same shape."""
    npz = os.path.join(d, "mesh.npz")
    mesh_cmd = [pc.python_exe(), os.path.abspath(__file__), "--mesh-worker", ply, npz,
                "--cube-size", str(args.cube_size), "--smoothing-length",
                str(args.smoothing_length), "--iso", str(args.iso), "--threads",
                str(args.threads)]

    def fs(prim, spp, seed=None):
        tag = f"{prim}_{spp}" + ("_ref" if seed else "")
        exr, png = os.path.join(d, tag + ".exr"), os.path.join(d, tag + ".png")
        extra = ["--env", env, "--primitive", prim, "--max-depth", str(args.max_depth),
                 "--ior", str(args.ior), "--shading", "lut"]
        if seed:
            extra += ["--seed", str(seed)]
        return [pc.filmsplat_cmd(args.filmsplat, [src], camera, size, spp, exr, png, extra)], exr

    def cy(spp, seed=1):
        exr = os.path.join(d, f"mesh_cycles_{spp}" + ("_ref" if seed != 1 else "") + ".exr")
        spec = {"kind": "mesh", "mesh": npz, "env": env, "camera": camera, "size": list(size),
                "spp": spp, "seed": seed, "threads": args.threads, "ior": args.ior,
                "max_depth": args.max_depth, "transparent_bounces": 0, "out": exr}
        with open(exr[:-4] + ".json", "w") as f:
            json.dump(spec, f)
        return [pc.cycles_cmd(pc.python_exe(), exr[:-4] + ".json")], exr

    fspp = [int(s) for s in args.filmsplat_spp.split(",")]
    ladders = {"filmsplat disks": [(s, *fs("disk", s)) for s in fspp],
               "filmsplat MLS": [(s, *fs("mls", s)) for s in fspp],
               "pysplashsurf + Cycles": [(s, *cy(s)) for s in
                                         [int(v) for v in args.cycles_spp.split(",")]]}
    refs = {"filmsplat disks": fs("disk", args.filmsplat_ref_spp, seed=7),
            "filmsplat MLS": fs("mls", args.filmsplat_ref_spp, seed=7),
            "pysplashsurf + Cycles": cy(args.cycles_ref_spp, seed=7)}
    return ladders, refs, mesh_cmd


def run_case(args, name, env, size):
    d, src, ply, camera = prepare(args, name)
    ladders, refs, mesh_cmd = jobs_for(args, d, src, ply, camera, env, size)
    env_vars = pc.thread_env(args.threads)
    mesh_times = [pc.timed(mesh_cmd, env_vars)]
    nverts = len(np.load(os.path.join(d, "mesh.npz"))["verts"])
    print(f"[{name}] mesh: {nverts} vertices, {mesh_times[0][0]:.1f} s; {pc.load()}", flush=True)
    for cmds, _ in refs.values():
        for c in cmds:
            pc.timed(c, env_vars)
    print(f"[{name}] references done; {pc.load()}", flush=True)
    times = {}
    for rep in range(args.repeats):
        if rep:
            mesh_times.append(pc.timed(mesh_cmd, env_vars))
        for i in range(max(len(v) for v in ladders.values())):
            for pipe, lad in ladders.items():
                if i < len(lad):
                    spp, cmds, _ = lad[i]
                    times.setdefault((pipe, spp), []).append(pc.timed(cmds[0], env_vars))
        print(f"[{name}] repeat {rep + 1}/{args.repeats}; {pc.load()}", flush=True)
    mesh_wall = pc.median([w for w, _ in mesh_times])
    mesh_cpu = pc.median([c for _, c in mesh_times])
    ref_imgs = {p: pc.read_exr(exr) for p, (_, exr) in refs.items()}
    mask = pc.film_mask(ref_imgs["filmsplat disks"][1])
    rows = []
    for pipe, lad in ladders.items():
        extra = (mesh_wall, mesh_cpu) if pipe.startswith("pysplashsurf") else (0.0, 0.0)
        for spp, _, exr in lad:
            t = times[(pipe, spp)]
            img = pc.read_exr(exr)[0]
            q = pc.summarize(pc.delta_e_map(img, ref_imgs[pipe][0]), mask)
            rows.append({"case": name, "pipeline": pipe, "spp": spp, "exr": exr,
                         "wall": extra[0] + pc.median([w for w, _ in t]),
                         "cpu": extra[1] + pc.median([c for _, c in t]), **q})
    cross = {p: pc.summarize(pc.delta_e_map(ref_imgs[p][0], ref_imgs["filmsplat disks"][0]),
                             mask)["de_mean"] for p in refs}
    return {"case": name, "rows": rows, "mesh_wall": mesh_wall, "mesh_cpu": mesh_cpu,
            "mesh_vertices": nverts, "cross": cross, "mask": mask, "refs": ref_imgs}


def summary(res):
    out = {}
    for pipe in dict.fromkeys(r["pipeline"] for r in res["rows"]):
        rs = [r for r in res["rows"] if r["pipeline"] == pipe]
        out[pipe] = {(k, c): pc.time_to([(r[c], r[k]) for r in rs])
                     for k in ("de_mean", "de_film_mean") for c in ("wall", "cpu")}
    return out


def report(args, results):
    print("\n| case | pipeline | spp | wall (s) | CPU (s) | mean ΔE00 | film mean ΔE00 |")
    print("|---|---|---|---|---|---|---|")
    for res in results:
        for r in res["rows"]:
            print(f"| {r['case']} | {r['pipeline']} | {r['spp']} | {r['wall']:.2f} | "
                  f"{r['cpu']:.2f} | {r['de_mean']:.3f} | {r['de_film_mean']:.3f} |")
    print("\nTime to mean ΔE00 1 (end to end; the mesh pipeline incl. meshing), and the mesh "
          "pipeline's time over filmsplat's:\n")
    print("| case | pipeline | wall | CPU | film only: wall | CPU | mesh / this (wall, "
          "whole) | (CPU, whole) | (wall, film) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for res in results:
        s = summary(res)
        res["summary"] = s
        mp = s["pysplashsurf + Cycles"]
        for pipe, v in s.items():
            cells = [pc.fmt_time(*v[(k, c)]) for k in ("de_mean", "de_film_mean")
                     for c in ("wall", "cpu")]
            ratios = ["" if pipe.startswith("pysplashsurf") else
                      pc.fmt_ratio(*v[(k, c)], *mp[(k, c)])
                      for k, c in (("de_mean", "wall"), ("de_mean", "cpu"),
                                   ("de_film_mean", "wall"))]
            print(f"| {res['case']} | {pipe} | " + " | ".join(cells + ratios) + " |")
    for res in results:
        print(f"\n[{res['case']}] mesh: {res['mesh_vertices']} vertices, meshing "
              f"{res['mesh_wall']:.2f} s wall / {res['mesh_cpu']:.2f} s CPU (median); converged "
              "renders vs filmsplat disks' converged, mean ΔE00: " +
              ", ".join(f"{p} {v:.2f}" for p, v in res["cross"].items()))


def picture(args, res, size):
    """The three pipelines side by side, each at its first sample count below ΔE 1 (else its
    last), labelled with the time."""
    panels = []
    for pipe, v in res["summary"].items():
        rs = [r for r in res["rows"] if r["pipeline"] == pipe]
        pick = next((r for r in rs if r["de_mean"] <= 1.0), rs[-1])
        t, how = v[("de_mean", "wall")]
        panels.append((pc.read_exr(pick["exr"])[0],
                       [pipe, f"{pick['spp']} spp: {pick['wall']:.2f} s, dE {pick['de_mean']:.2f}",
                        f"to dE 1: {pc.fmt_time(t, how)} s"]))
    path = os.path.join(args.images, f"peers_mesh_{res['case']}.png")
    pc.side_by_side(path, panels)
    print(f"wrote {path}")


def main():
    args = parse_args()
    if args.mesh_worker:
        return mesh_worker(args, *args.mesh_worker)
    print(f"start: {pc.load()}", flush=True)
    size = tuple(int(v) for v in args.size.split("x"))
    os.makedirs(args.out, exist_ok=True)
    env = os.path.join(args.out, "studio_env.exr")
    pc.write_env(env)
    results = [run_case(args, name, env, size) for name in args.cases.split(",")]
    print(f"\n{size[0]}x{size[1]}, medians of {args.repeats} interleaved runs, threads "
          f"{args.threads or os.cpu_count()}, cube size {args.cube_size} radii")
    report(args, results)
    if args.images:
        for res in results:
            picture(args, res, size)
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump([{k: v for k, v in r.items() if k not in ("mask", "refs", "summary")}
                   for r in results], f, indent=1)
    print(f"end: {pc.load()}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
