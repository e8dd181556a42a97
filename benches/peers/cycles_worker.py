"""One Cycles render in a fresh process: `python cycles_worker.py SPEC.json`.

The peer scripts time this whole process (Python and bpy start-up, scene set-up, BVH build,
render, EXR write), as they time filmsplat's whole process. SPEC keys:
  kind       "points" (particles as spheres, from `ply`) or "mesh" (from `mesh`, an .npz with
             verts (n, 3), tris (m, 3) and rh (n,), filmsplat coordinates)
  ply, mesh  input file; radius_scale: factor on the PLY's `radius` (points)
  env        lat-long EXR; camera {position, look_at, fov}; size [w, h]
  spp, seed, threads (0: all cores), ior, max_depth, transparent_bounces, out (EXR)

Matched to filmsplat (see README.md):
- geometry: points are analytic spheres in Cycles (the true sphere normal, as filmsplat's
  spheres); a mesh is shaded smooth (interpolated vertex normals);
- film: Principled BSDF, base IOR 1 and full transmission (a film between air and air), thin
  film thickness from the `rh` attribute (nm) and IOR `ior`, roughness 0; back faces
  transparent, so each closed surface is one film crossing where a ray enters it;
- pixel filter: box, 1 pixel wide (filmsplat averages its samples with equal weight over the
  pixel's square, src/render/integrator.rs SubPixel);
- bounces: glossy, transmission and total = max_depth (filmsplat's most film crossings along a
  path), transparent = transparent_bounces (default max_depth: one back face per sphere
  entered), diffuse 0; no clamping, no denoising, no adaptive sampling, no glossy blur.
"""
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from peers_common import read_ply, to_blender  # noqa: E402


def render_settings(sc, spec):
    sc.render.engine = "CYCLES"
    sc.cycles.device = "CPU"
    sc.render.threads_mode = "FIXED"
    sc.render.threads = spec.get("threads") or os.cpu_count() or 2
    sc.render.resolution_x, sc.render.resolution_y = spec["size"]
    sc.render.resolution_percentage = 100
    sc.cycles.samples = spec["spp"]
    sc.cycles.seed = spec.get("seed", 1)
    sc.cycles.use_adaptive_sampling = False
    sc.cycles.use_denoising = False
    sc.cycles.pixel_filter_type = "BOX"
    sc.cycles.filter_width = 1.0
    depth = spec["max_depth"]
    sc.cycles.max_bounces = depth
    sc.cycles.glossy_bounces = depth
    sc.cycles.transmission_bounces = depth
    sc.cycles.transparent_max_bounces = spec.get("transparent_bounces") or depth
    sc.cycles.diffuse_bounces = 0
    sc.cycles.volume_bounces = 0
    sc.cycles.caustics_reflective = True
    sc.cycles.caustics_refractive = True
    sc.cycles.blur_glossy = 0.0
    sc.cycles.sample_clamp_direct = 0.0
    sc.cycles.sample_clamp_indirect = 0.0
    sc.view_settings.view_transform = "Standard"
    sc.view_settings.look = "None"
    sc.render.image_settings.file_format = "OPEN_EXR"
    sc.render.image_settings.color_depth = "32"
    sc.render.film_transparent = False


def world(bpy, sc, env_path):
    w = bpy.data.worlds.new("w")
    sc.world = w
    w.use_nodes = True
    nt = w.node_tree
    tex = nt.nodes.new("ShaderNodeTexEnvironment")
    tex.image = bpy.data.images.load(env_path)
    tex.interpolation = "Linear"
    bg = nt.nodes["Background"]
    nt.links.new(tex.outputs["Color"], bg.inputs["Color"])
    bg.inputs["Strength"].default_value = 1.0


def film_material(bpy, ior):
    """Thin film (rh nm, n = ior) over a base of IOR 1 that transmits everything = a film between
    air and air. Back faces are transparent: one film crossing per closed surface entered."""
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
    mt.links.new(mix.outputs["Shader"], mt.nodes["Material Output"].inputs["Surface"])
    return mat


def points_object(bpy, sc, spec, mat):
    """The particles as a mesh of vertices with rh and radius, turned into a point cloud by
    Geometry Nodes (Mesh to Points): Cycles intersects each point as a sphere."""
    cloud = read_ply(spec["ply"])
    pos = to_blender(np.stack([cloud["x"], cloud["y"], cloud["z"]], axis=-1))
    me = bpy.data.meshes.new("cloud")
    me.vertices.add(len(pos))
    me.vertices.foreach_set("co", pos.astype(np.float32).ravel())
    a = me.attributes.new("rh", "FLOAT", "POINT")
    a.data.foreach_set("value", cloud["rh"].astype(np.float32))
    r = me.attributes.new("prad", "FLOAT", "POINT")
    r.data.foreach_set("value", (spec["radius_scale"] * cloud["radius"]).astype(np.float32))
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
    setmat.inputs["Material"].default_value = mat
    ob.modifiers.new("points", "NODES").node_group = gn


def mesh_object(bpy, sc, spec, mat):
    """A triangle mesh with a per-vertex `rh`, shaded smooth."""
    d = np.load(spec["mesh"])
    verts = to_blender(d["verts"]).astype(np.float32)
    tris = d["tris"].astype(np.int32)
    me = bpy.data.meshes.new("surface")
    me.vertices.add(len(verts))
    me.vertices.foreach_set("co", verts.ravel())
    me.loops.add(3 * len(tris))
    me.loops.foreach_set("vertex_index", tris.ravel())
    me.polygons.add(len(tris))
    me.polygons.foreach_set("loop_start", np.arange(0, 3 * len(tris), 3, dtype=np.int32))
    me.update(calc_edges=True)
    a = me.attributes.new("rh", "FLOAT", "POINT")
    a.data.foreach_set("value", d["rh"].astype(np.float32))
    me.shade_smooth()
    me.materials.append(mat)
    ob = bpy.data.objects.new("surface", me)
    sc.collection.objects.link(ob)


def camera(bpy, sc, cam_spec):
    from mathutils import Vector

    cam = bpy.data.cameras.new("cam")
    cam.sensor_fit = "VERTICAL"
    cam.angle_y = math.radians(cam_spec["fov"])
    cam.clip_start = 1e-3
    co = bpy.data.objects.new("cam", cam)
    sc.collection.objects.link(co)
    eye = Vector(to_blender(cam_spec["position"]).tolist())
    target = Vector(to_blender(cam_spec["look_at"]).tolist())
    co.location = eye
    co.rotation_euler = (target - eye).to_track_quat("-Z", "Y").to_euler()
    sc.camera = co


def main(spec_path):
    with open(spec_path) as f:
        spec = json.load(f)
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    render_settings(sc, spec)
    world(bpy, sc, spec["env"])
    mat = film_material(bpy, spec["ior"])
    if spec["kind"] == "points":
        points_object(bpy, sc, spec, mat)
    else:
        mesh_object(bpy, sc, spec, mat)
    camera(bpy, sc, spec["camera"])
    sc.render.filepath = spec["out"]
    bpy.ops.render.render(write_still=True)


if __name__ == "__main__":
    main(sys.argv[1])
