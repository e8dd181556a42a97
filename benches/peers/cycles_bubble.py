"""filmsplat vs Blender Cycles on the same bubble: time to equal quality.

Not part of the test suite. Needs: `pip install bpy colour-science numpy OpenEXR` (Blender as a Python
module, here bpy 5.0.1 with Cycles on the CPU) and a release build of filmsplat.

    cargo build --release
    python3 benches/peers/cycles_bubble.py --particles 200000 --size 480x270 --out /tmp/peers

What it does (see benches/peers/README.md for the reasoning):
1. `filmsplat sample bubble` writes the cloud (positions, normals, thickness rh in nm, radius).
2. One lat-long environment (a studio: soft boxes over a grey gradient) is written as an EXR
   that both renderers light the scene with, in the same orientation.
3. Both render the particles as spheres of the same radius with a free-standing soap film
   (n = 1.33, thickness per particle) from the same camera, at increasing sample counts, and
   once more with many samples as each renderer's converged reference.
   Cycles: points via Geometry Nodes (Mesh to Points), Principled BSDF with Thin Film
   Thickness/IOR from the `rh` attribute, base IOR 1 and full transmission (a film between air
   and air), back faces transparent (one film crossing per sphere, as in filmsplat).
4. For each run: wall time of the whole render (load and BVH build included for both) and mean /
   95th-percentile CIEDE2000 against its own converged reference, plus the difference between
   the two converged references. Prints a Markdown table and writes PNGs.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FILMSPLAT = os.path.join(ROOT, "target", "release", "filmsplat")


def read_ply(path):
    """Binary little-endian PLY of float32 vertex properties (what `filmsplat sample` writes)."""
    with open(path, "rb") as f:
        names, n = [], 0
        while True:
            line = f.readline().decode().strip()
            if line.startswith("element vertex"):
                n = int(line.split()[2])
            elif line.startswith("property float"):
                names.append(line.split()[2])
            elif line == "end_header":
                break
        data = np.frombuffer(f.read(4 * n * len(names)), dtype="<f4").reshape(n, len(names))
    return {k: data[:, i].astype(np.float64) for i, k in enumerate(names)}


# filmsplat is y-up, Blender z-up: Blender (X, Y, Z) = filmsplat (-z, -x, y), a proper rotation
# under which both renderers' lat-long conventions agree (Blender's probed with a u/v-coded map:
# +X at u = 0.5, +Y at u = 0.25, up at the top row):
#   filmsplat: u = atan2(x, -z) / 2pi + 0.5, v_top = acos(y) / pi
#   Blender:   u = 0.5 - atan2(Y, X) / 2pi,  v_top = acos(Z) / pi
def to_blender(p):
    p = np.asarray(p, dtype=np.float64)
    return np.stack([-p[..., 2], -p[..., 0], p[..., 1]], axis=-1)


def studio_env(d):
    """Radiance of the test environment for unit directions d (filmsplat coordinates, y-up)."""
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    sky = 0.25 + 0.35 * np.clip(y, 0, 1)
    floor = 0.06 + 0.0 * y
    base = np.where(y > 0, sky, floor)
    rgb = np.stack([base * 0.95, base, base * 1.08], axis=-1)

    def softbox(centre, size, power, tint):
        c = np.asarray(centre, dtype=np.float64)
        c /= np.linalg.norm(c)
        cosang = np.clip(d @ c, -1, 1)
        ang = np.arccos(cosang)
        w = 1.0 / (1.0 + np.exp((ang - size) / 0.02))
        return w[..., None] * power * np.asarray(tint)

    rgb += softbox([0.6, 0.7, 0.8], 0.35, 6.0, [1.0, 0.98, 0.95])
    rgb += softbox([-0.9, 0.4, 0.3], 0.25, 3.0, [0.9, 0.95, 1.0])
    rgb += softbox([0.1, 0.2, -1.0], 0.4, 2.0, [1.0, 1.0, 1.0])
    return rgb


def write_env(path, width=1024):
    """Writes the environment as a linear float EXR (with OpenEXR: saving through bpy would
    apply Blender's display encoding to a generated image)."""
    import OpenEXR

    h = width // 2
    j, i = np.mgrid[0:h, 0:width].astype(np.float64)  # top row first
    u = (i + 0.5) / width
    theta = (j + 0.5) / h * math.pi
    phi = (u - 0.5) * 2 * math.pi
    # filmsplat: u = atan2(x, -z)/2pi + 0.5, y = cos(theta)
    s = np.sin(theta)
    d = np.stack([s * np.sin(phi), np.cos(theta), -s * np.cos(phi)], axis=-1)
    rgb = studio_env(d).astype(np.float32)
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, {"RGB": rgb}) as f:
        f.write(path)


def read_exr_rgb(path):
    """The RGB channels of an EXR, top row first (OpenEXR's Python bindings: bpy treats
    filmsplat's multi-layer EXR as a multilayer render and exposes no pixels)."""
    import OpenEXR

    with OpenEXR.File(path) as f:
        ch = f.channels()
        if "RGBA" in ch:
            return ch["RGBA"].pixels[..., :3].astype(np.float64)
        return ch["RGB"].pixels.astype(np.float64)


def delta_e(a, b):
    import colour

    def lab(rgb):
        xyz = np.clip(rgb, 0, 1) @ np.array(
            [[0.4124564, 0.3575761, 0.1804375],
             [0.2126729, 0.7151522, 0.0721750],
             [0.0193339, 0.1191920, 0.9503041]]).T
        return colour.XYZ_to_Lab(xyz, colour.XYZ_to_xy(np.array([0.95047, 1.0, 1.08883])))

    d = colour.delta_E(lab(a), lab(b), method="CIE 2000").ravel()
    return float(d.mean()), float(np.percentile(d, 95))


def setup_cycles(cloud, camera, env_path, size, radius_scale, ior, max_depth):
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.render.engine = "CYCLES"
    sc.cycles.device = "CPU"
    sc.render.threads_mode = "FIXED"
    sc.render.threads = os.cpu_count() or 2
    sc.render.resolution_x, sc.render.resolution_y = size
    sc.render.resolution_percentage = 100
    sc.cycles.use_adaptive_sampling = False
    sc.cycles.use_denoising = False
    sc.cycles.pixel_filter_type = "BOX"
    sc.cycles.filter_width = 1.0
    sc.cycles.max_bounces = max_depth
    sc.cycles.glossy_bounces = max_depth
    sc.cycles.transmission_bounces = max_depth
    sc.cycles.transparent_max_bounces = 4 * max_depth
    sc.cycles.diffuse_bounces = 0
    sc.cycles.caustics_reflective = True
    sc.cycles.caustics_refractive = True
    sc.cycles.blur_glossy = 0.0
    sc.cycles.sample_clamp_indirect = 0.0
    sc.view_settings.view_transform = "Standard"
    sc.view_settings.look = "None"
    sc.render.image_settings.file_format = "OPEN_EXR"
    sc.render.image_settings.color_depth = "32"
    sc.render.film_transparent = False

    # World: the same lat-long EXR.
    world = bpy.data.worlds.new("w")
    sc.world = world
    world.use_nodes = True
    nt = world.node_tree
    tex = nt.nodes.new("ShaderNodeTexEnvironment")
    tex.image = bpy.data.images.load(env_path)
    tex.interpolation = "Linear"
    bg = nt.nodes["Background"]
    nt.links.new(tex.outputs["Color"], bg.inputs["Color"])
    bg.inputs["Strength"].default_value = 1.0

    # Particles: a mesh of vertices with rh and radius, turned into points (spheres).
    pos = to_blender(np.stack([cloud["x"], cloud["y"], cloud["z"]], axis=-1))
    n = len(pos)
    me = bpy.data.meshes.new("cloud")
    me.vertices.add(n)
    me.vertices.foreach_set("co", pos.astype(np.float32).ravel())
    a = me.attributes.new("rh", "FLOAT", "POINT")
    a.data.foreach_set("value", cloud["rh"].astype(np.float32))
    r = me.attributes.new("prad", "FLOAT", "POINT")
    r.data.foreach_set("value", (radius_scale * cloud["radius"]).astype(np.float32))
    me.update()
    ob = bpy.data.objects.new("cloud", me)
    sc.collection.objects.link(ob)
    gn = bpy.data.node_groups.new("points", "GeometryNodeTree")
    gn.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    gn.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    gi = gn.nodes.new("NodeGroupInput")
    go = gn.nodes.new("NodeGroupOutput")
    m2p = gn.nodes.new("GeometryNodeMeshToPoints")
    na = gn.nodes.new("GeometryNodeInputNamedAttribute")
    na.data_type = "FLOAT"
    na.inputs["Name"].default_value = "prad"
    setmat = gn.nodes.new("GeometryNodeSetMaterial")
    gn.links.new(gi.outputs[0], m2p.inputs["Mesh"])
    gn.links.new(na.outputs["Attribute"], m2p.inputs["Radius"])
    gn.links.new(m2p.outputs["Points"], setmat.inputs["Geometry"])
    gn.links.new(setmat.outputs["Geometry"], go.inputs[0])
    mod = ob.modifiers.new("points", "NODES")
    mod.node_group = gn

    # Film: thin film (rh nm, n) over a base of IOR 1 that transmits everything = a film between
    # air and air. Back faces are transparent: one film crossing per sphere.
    mat = bpy.data.materials.new("film")
    mat.use_nodes = True
    mt = mat.node_tree
    pr = mt.nodes["Principled BSDF"]
    pr.inputs["Base Color"].default_value = (1, 1, 1, 1)
    pr.inputs["Roughness"].default_value = 0.0
    pr.inputs["IOR"].default_value = 1.0
    pr.inputs["Transmission Weight"].default_value = 1.0
    pr.inputs["Thin Film IOR"].default_value = ior
    at = mt.nodes.new("ShaderNodeAttribute")
    at.attribute_type = "GEOMETRY"
    at.attribute_name = "rh"
    mt.links.new(at.outputs["Fac"], pr.inputs["Thin Film Thickness"])
    geo = mt.nodes.new("ShaderNodeNewGeometry")
    tr = mt.nodes.new("ShaderNodeBsdfTransparent")
    mix = mt.nodes.new("ShaderNodeMixShader")
    mt.links.new(geo.outputs["Backfacing"], mix.inputs["Fac"])
    mt.links.new(pr.outputs["BSDF"], mix.inputs[1])
    mt.links.new(tr.outputs["BSDF"], mix.inputs[2])
    out = mt.nodes["Material Output"]
    mt.links.new(mix.outputs["Shader"], out.inputs["Surface"])
    setmat.inputs["Material"].default_value = mat

    # Camera: same position, target and vertical field of view.
    from mathutils import Vector

    cam = bpy.data.cameras.new("cam")
    cam.sensor_fit = "VERTICAL"
    cam.angle_y = math.radians(camera["fov"])
    cam.clip_start = 1e-3
    co = bpy.data.objects.new("cam", cam)
    sc.collection.objects.link(co)
    eye = Vector(to_blender(camera["position"]).tolist())
    target = Vector(to_blender(camera["look_at"]).tolist())
    co.location = eye
    co.rotation_euler = (target - eye).to_track_quat("-Z", "Y").to_euler()
    sc.camera = co
    return sc


def render_cycles(sc, spp, path):
    import bpy

    sc.cycles.samples = spp
    sc.cycles.seed = 1
    sc.render.filepath = path
    t = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    return time.perf_counter() - t


def render_filmsplat(ply, env, camera, size, spp, exr, png, args, roulette=0.0):
    cmd = [
        FILMSPLAT, "render", ply, "-o", png, "--exr", exr,
        "--primitive", "sphere", "--radius-scale", str(args.radius_scale),
        "--size", f"{size[0]}x{size[1]}", "--spp", str(spp),
        "--shading", args.shading, "--max-depth", str(args.max_depth), "--ior", str(args.ior),
        "--env", env, "--tonemap", "clamp", "-q",
        "--camera", ",".join(f"{v:.6f}" for v in camera["position"]),
        "--look-at", ",".join(f"{v:.6f}" for v in camera["look_at"]),
        "--fov", str(camera["fov"]),
        "--roulette", str(roulette),
    ]
    t = time.perf_counter()
    subprocess.run(cmd, check=True)
    return time.perf_counter() - t


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--particles", type=int, default=200000)
    ap.add_argument("--size", default="480x270")
    ap.add_argument("--out", default="/tmp/filmsplat-peers")
    ap.add_argument("--filmsplat-spp", default="1,2,4,8")
    ap.add_argument("--cycles-spp", default="16,64,256,1024")
    ap.add_argument("--filmsplat-ref-spp", type=int, default=64)
    ap.add_argument("--cycles-ref-spp", type=int, default=8192)
    ap.add_argument("--radius-scale", type=float, default=0.5)
    ap.add_argument("--ior", type=float, default=1.33)
    ap.add_argument("--max-depth", type=int, default=12)
    ap.add_argument("--shading", default="lut")
    ap.add_argument("--roulette", default="0",
                    help="comma-separated filmsplat --roulette values to time (0: the full ray "
                         "tree); the reference is always rendered without roulette")
    args = ap.parse_args()
    size = tuple(int(v) for v in args.size.split("x"))
    os.makedirs(args.out, exist_ok=True)
    ply = os.path.join(args.out, f"bubble_{args.particles}.ply")
    subprocess.run([FILMSPLAT, "sample", "bubble", "--particles", str(args.particles), "-o", ply],
                   check=True, stdout=subprocess.DEVNULL)
    cloud = read_ply(ply)
    env = os.path.join(args.out, "studio_env.exr")
    write_env(env)
    p = np.stack([cloud["x"], cloud["y"], cloud["z"]], axis=-1)
    centre = 0.5 * (p.min(0) + p.max(0))
    radius = float(np.linalg.norm(p - centre, axis=1).max())
    d = np.array([0.35, 0.3, 1.0])
    d /= np.linalg.norm(d)
    fov = 40.0
    dist = 1.15 * radius / math.sin(math.radians(fov) / 2)
    camera = {"position": (centre + dist * d).tolist(), "look_at": centre.tolist(), "fov": fov}

    rows = []
    ref_exr = os.path.join(args.out, f"filmsplat_{args.filmsplat_ref_spp}.exr")
    ref_png = os.path.join(args.out, f"filmsplat_{args.filmsplat_ref_spp}.png")
    render_filmsplat(ply, env, camera, size, args.filmsplat_ref_spp, ref_exr, ref_png, args)
    runs = {}
    for rr in [float(v) for v in args.roulette.split(",")]:
        name = "filmsplat" if rr == 0 else f"filmsplat, roulette {rr:g}"
        tag = "" if rr == 0 else f"_rr{rr:g}"
        runs[name] = {}
        for spp in [int(s) for s in args.filmsplat_spp.split(",")]:
            exr = os.path.join(args.out, f"filmsplat{tag}_{spp}.exr")
            png = os.path.join(args.out, f"filmsplat{tag}_{spp}.png")
            runs[name][spp] = (render_filmsplat(ply, env, camera, size, spp, exr, png, args, rr), exr)
    sc = setup_cycles(cloud, camera, env, size, args.radius_scale, args.ior, args.max_depth)
    cy = {}
    for spp in [int(s) for s in args.cycles_spp.split(",")] + [args.cycles_ref_spp]:
        exr = os.path.join(args.out, f"cycles_{spp}.exr")
        cy[spp] = (render_cycles(sc, spp, exr), exr)
    fs_ref = read_exr_rgb(ref_exr)
    cy_ref = read_exr_rgb(cy[args.cycles_ref_spp][1])
    del cy[args.cycles_ref_spp]
    groups = [(name, r, fs_ref) for name, r in runs.items()] + [("cycles", cy, cy_ref)]
    for name, by_spp, ref in groups:
        for spp, (secs, exr) in sorted(by_spp.items()):
            m, p95 = delta_e(read_exr_rgb(exr), ref)
            rows.append({"renderer": name, "spp": spp, "seconds": secs, "de_mean": m, "de_p95": p95})
    cross = delta_e(fs_ref, cy_ref)
    print(f"| renderer | spp | time (s) | mean ΔE00 vs own reference | p95 ΔE00 |")
    print("|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['renderer']} | {r['spp']} | {r['seconds']:.2f} | {r['de_mean']:.3f} | {r['de_p95']:.3f} |")
    print(f"\nconverged filmsplat vs converged Cycles: mean ΔE00 {cross[0]:.2f}, p95 {cross[1]:.2f}")
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump({"rows": rows, "cross_de": cross, "camera": camera, "size": size,
                   "particles": args.particles}, f, indent=1)


if __name__ == "__main__":
    sys.exit(main())
