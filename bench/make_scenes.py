#!/usr/bin/python3
"""Writes the benchmark and stability scenes from the fetched real models (bench/fetch_scenes.sh).

Run with Debian's interpreter: /usr/bin/python3 bench/make_scenes.py [SCENES_DIR]  (numpy only).

Every real model is normalised (centred, resting on y = 0, 2 units tall or long) and set on a
2-triangle ground quad, so shadows have a receiver; nothing else is added. The models of other
kinds (UNSEEN: a tree, two ships, two game levels) are written as they are, without a ground,
as NAME.gltf: they shadow themselves. Scaling is done the
honest way, and every scene name says which: `bunny_subN` are N levels of midpoint subdivision of
the scan (each triangle split into 4: the same surface, 4^N times the triangles, like the paper's
levels of one model), `fence_field` and `engine_row` are glTF nodes that instance ONE mesh. The
stability scenes (see bench/stability.sh) come with view files (camera, light, light size).
Idempotent: a scene whose .gltf exists is not written again (delete the folder to rebuild).
"""
import json
import math
import os
import struct
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "scenes")
OUT = os.path.join(SCENES, "generated")


# ---------------------------------------------------------------------------------------- readers

def read_obj(path):
    """Vertices and fan-triangulated faces of an OBJ (v / f lines; v/vt/vn and negative indices)."""
    verts, tris = [], []
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                verts.append([float(x) for x in parts[1:4]])
            elif parts[0] == "f":
                ids = []
                for p in parts[1:]:
                    i = int(p.split("/")[0])
                    ids.append(i - 1 if i > 0 else len(verts) + i)
                for k in range(1, len(ids) - 1):
                    tris.append([ids[0], ids[k], ids[k + 1]])
    return np.array(verts, dtype=np.float64), np.array(tris, dtype=np.int64)


def _quat_matrix(q):
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def _node_matrix(node):
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T  # glTF is column-major
    m = np.eye(4)
    m[:3, :3] = _quat_matrix(node.get("rotation", [0, 0, 0, 1])) * np.array(node.get("scale", [1, 1, 1]))
    m[:3, 3] = node.get("translation", [0, 0, 0])
    return m


def read_glb(path, skip=()):
    """All triangle primitives of a binary glTF's default scene, flattened to world space, but for
    the subtrees of nodes named in `skip`."""
    data = open(path, "rb").read()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    if magic != b"glTF" or version != 2 or length != len(data):
        raise SystemExit(f"make_scenes: {path} is not a complete glTF 2.0 binary")
    off, doc, binary = 12, None, b""
    while off < len(data):
        clen, ctype = struct.unpack_from("<II", data, off)
        chunk = data[off + 8: off + 8 + clen]
        if ctype == 0x4E4F534A:
            doc = json.loads(chunk.decode("utf-8"))
        elif ctype == 0x004E4942:
            binary = chunk
        off += 8 + clen
    sizes = {5121: 1, 5123: 2, 5125: 4, 5126: 4}
    kinds = {5121: np.uint8, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}
    comps = {"SCALAR": 1, "VEC3": 3}

    def accessor(i):
        acc = doc["accessors"][i]
        view = doc["bufferViews"][acc["bufferView"]]
        n, ct = comps[acc["type"]], acc["componentType"]
        elem = n * sizes[ct]
        stride = view.get("byteStride", elem)
        start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
        raw = np.frombuffer(binary, dtype=np.uint8, count=stride * (acc["count"] - 1) + elem, offset=start)
        rows = np.lib.stride_tricks.as_strided(raw, shape=(acc["count"], elem), strides=(stride, 1))
        return np.ascontiguousarray(rows).view(kinds[ct]).reshape(acc["count"], n)

    positions, triangles, base = [], [], 0

    def visit(index, parent):
        nonlocal base
        node = doc["nodes"][index]
        if node.get("name") in skip:
            return
        world = parent @ _node_matrix(node)
        if "mesh" in node:
            for prim in doc["meshes"][node["mesh"]]["primitives"]:
                if prim.get("mode", 4) != 4 or "POSITION" not in prim["attributes"]:
                    continue
                p = accessor(prim["attributes"]["POSITION"]).astype(np.float64)
                p = p @ world[:3, :3].T + world[:3, 3]
                idx = (accessor(prim["indices"]).reshape(-1) if "indices" in prim else np.arange(len(p)))
                positions.append(p)
                triangles.append(idx.astype(np.int64).reshape(-1, 3) + base)
                base += len(p)
        for child in node.get("children", []):
            visit(child, world)

    scene = doc.get("scenes", [{"nodes": list(range(len(doc["nodes"])))}])[doc.get("scene", 0)]
    for root in scene["nodes"]:
        visit(root, np.eye(4))
    return np.concatenate(positions), np.concatenate(triangles)


def read_bsp(path, patch_steps=4):
    """The drawn surfaces of a Quake III level (IBSP 46): polygons and meshes as they are, curved
    patches tessellated (patch_steps per 3x3 Bezier patch), sky, nodraw and liquids (light goes
    through them) left out. Brush geometry as the game draws it: T-junctions, coplanar faces and all."""
    data = open(path, "rb").read()
    magic, version = struct.unpack_from("<4si", data, 0)
    if magic != b"IBSP" or version != 46:
        raise SystemExit(f"make_scenes: {path} is not a Quake III BSP (IBSP 46)")
    lumps = [struct.unpack_from("<ii", data, 8 + 8 * i) for i in range(17)]

    def lump(i, dtype):
        off, length = lumps[i]
        return np.frombuffer(data, dtype=dtype, count=length // dtype.itemsize, offset=off)

    textures = lump(1, np.dtype([("name", "S64"), ("flags", "<i4"), ("contents", "<i4")]))
    verts = lump(10, np.dtype([("pos", "<f4", 3), ("uv", "<f4", 4), ("normal", "<f4", 3), ("rgba", "u1", 4)]))
    meshverts = lump(11, np.dtype("<i4"))
    faces = lump(13, np.dtype([("texture", "<i4"), ("effect", "<i4"), ("type", "<i4"), ("vertex", "<i4"),
                               ("n_vertexes", "<i4"), ("meshvert", "<i4"), ("n_meshverts", "<i4"),
                               ("lightmap", "<i4", 5), ("lightmap_geometry", "<f4", 12), ("size", "<i4", 2)]))
    pos = verts["pos"].astype(np.float64)
    skip_flags, skip_contents = 0x4 | 0x80, 8 | 16 | 32 | 64  # sky, nodraw; lava, slime, water, fog
    t = np.linspace(0.0, 1.0, patch_steps + 1)
    bezier = np.stack([(1 - t) ** 2, 2 * t * (1 - t), t ** 2], axis=1)
    n = patch_steps + 1
    q = (np.arange(patch_steps)[:, None] * n + np.arange(patch_steps)[None, :]).reshape(-1)
    quads = np.stack([q, q + n, q + n + 1, q + 1], axis=1)
    out_pos, out_tris, base = [pos], [], len(pos)
    for f in faces:
        tex = textures[f["texture"]]
        if tex["flags"] & skip_flags or tex["contents"] & skip_contents:
            continue
        if f["type"] in (1, 3):  # polygon, mesh: triangles through meshverts, clockwise in Quake
            idx = f["vertex"] + meshverts[f["meshvert"]: f["meshvert"] + f["n_meshverts"]]
            out_tris.append(idx.reshape(-1, 3)[:, [0, 2, 1]])
        elif f["type"] == 2:  # patch: a grid of biquadratic Bezier patches sharing their borders
            w, h = f["size"]
            grid = pos[f["vertex"]: f["vertex"] + w * h].reshape(h, w, 3)
            for py in range(0, h - 1, 2):
                for px in range(0, w - 1, 2):
                    out_pos.append(np.einsum("ia,jb,abk->ijk", bezier, bezier, grid[py:py + 3, px:px + 3]).reshape(-1, 3))
                    out_tris.append(np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]]) + base)
                    base += n * n
    return np.concatenate(out_pos), np.concatenate(out_tris).astype(np.int64)


def only_used(pos, tris):
    """Drops the vertices no triangle uses (they would widen the bounds)."""
    used, remap = np.unique(tris, return_inverse=True)
    return pos[used], remap.reshape(tris.shape)


# ------------------------------------------------------------------------------------- geometry

def normalise(pos, up_rotation=None, size=2.0):
    """Rotates to y-up, scales the largest extent to `size`, centres x/z and rests it on y = 0."""
    if up_rotation is not None:
        pos = pos @ np.array(up_rotation, dtype=np.float64).T
    lo, hi = pos.min(axis=0), pos.max(axis=0)
    pos = (pos - [(lo[0] + hi[0]) / 2, lo[1], (lo[2] + hi[2]) / 2]) * (size / float((hi - lo).max()))
    return pos


def subdivide_midpoint(pos, tris):
    """One level of midpoint subdivision: every triangle becomes 4, edges shared through their midpoint."""
    edges = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
    unique, inverse = np.unique(edges, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    mids = len(pos) + inverse.reshape(3, -1).T  # midpoint ids of edges ab, bc, ca per triangle
    new_pos = np.concatenate([pos, 0.5 * (pos[unique[:, 0]] + pos[unique[:, 1]])])
    a, b, c = tris[:, 0], tris[:, 1], tris[:, 2]
    ab, bc, ca = mids[:, 0], mids[:, 1], mids[:, 2]
    new_tris = np.concatenate([np.stack(t, axis=1) for t in ((a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca))])
    return new_pos, new_tris


def ground(half_x, half_z, y=0.0, cx=0.0, cz=0.0):
    """A 2-triangle quad facing +y."""
    pos = np.array([[cx - half_x, y, cz - half_z], [cx + half_x, y, cz - half_z],
                    [cx + half_x, y, cz + half_z], [cx - half_x, y, cz + half_z]], dtype=np.float64)
    return pos, np.array([[0, 2, 1], [0, 3, 2]], dtype=np.int64)


def box(lo, hi):
    """An axis-aligned box, 12 triangles, outward winding."""
    lo, hi = np.array(lo, dtype=np.float64), np.array(hi, dtype=np.float64)
    pos = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return pos, np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))], dtype=np.int64)


# --------------------------------------------------------------------------------------- writer

def write_gltf(name, meshes, nodes, bin_name=None):
    """Writes OUT/name.gltf (+ name.bin unless bin_name points at an existing scene's buffer).

    meshes: list of (mesh name, positions, triangles, rgb); nodes: list of (mesh index, translation,
    y rotation in degrees). The mesh list is written into the buffer even when bin_name is given,
    in which case it must be identical to that scene's (used to translate a scene without copying).
    """
    doc = {"asset": {"version": "2.0", "generator": "penumbra bench/make_scenes.py"},
           "scene": 0, "scenes": [{"nodes": list(range(len(nodes)))}],
           "nodes": [], "meshes": [], "materials": [], "accessors": [], "bufferViews": []}
    blob = bytearray()
    for mname, pos, tris, rgb in meshes:
        p = pos.astype(np.float32)
        i = tris.astype(np.uint32)
        views = []
        for arr, target in ((p, 34962), (i, 34963)):
            views.append(len(doc["bufferViews"]))
            doc["bufferViews"].append({"buffer": 0, "byteOffset": len(blob), "byteLength": arr.nbytes, "target": target})
            blob += arr.tobytes()
            blob += b"\0" * (-len(blob) % 4)
        doc["accessors"].append({"bufferView": views[0], "componentType": 5126, "count": len(p), "type": "VEC3",
                                 "min": p.min(axis=0).tolist(), "max": p.max(axis=0).tolist()})
        doc["accessors"].append({"bufferView": views[1], "componentType": 5125, "count": i.size, "type": "SCALAR"})
        doc["materials"].append({"name": mname, "pbrMetallicRoughness": {"baseColorFactor": list(rgb) + [1.0]}})
        m = len(doc["meshes"])
        doc["meshes"].append({"name": mname, "primitives": [{"attributes": {"POSITION": 2 * m},
                                                             "indices": 2 * m + 1, "material": m}]})
    for mesh, translation, yaw in nodes:
        node = {"mesh": mesh}
        if any(translation):
            node["translation"] = [float(t) for t in translation]
        if yaw:
            h = math.radians(yaw) / 2
            node["rotation"] = [0.0, math.sin(h), 0.0, math.cos(h)]
        doc["nodes"].append(node)
    bin_file = bin_name or name + ".bin"
    doc["buffers"] = [{"uri": bin_file, "byteLength": len(blob)}]
    if bin_name is None:
        with open(os.path.join(OUT, bin_file), "wb") as f:
            f.write(blob)
    else:
        have = os.path.getsize(os.path.join(OUT, bin_name))
        if have != len(blob):
            raise SystemExit(f"make_scenes: {bin_name} has {have} bytes, expected {len(blob)}")
    with open(os.path.join(OUT, name + ".gltf"), "w") as f:
        json.dump(doc, f, indent=1)
    tris = sum(len(meshes[m][2]) for m, _, _ in nodes)
    print(f"make_scenes: {name}.gltf  {tris:,} triangles  ({len(nodes)} nodes, {len(meshes)} meshes)")
    return tris


def write_view(name, camera, light, light_size=0.0, resolution=(256, 256)):
    def v(x):
        return ",".join(repr(float(c)) for c in x)
    view = {"camera": f"{v(camera[0])}:{v(camera[1])}:{float(camera[2])!r}",
            "light": f"{light[0]}:{v(light[1])}:{v(light[2])}",
            "light_size": light_size, "resolution": list(resolution)}
    with open(os.path.join(OUT, name + ".view.json"), "w") as f:
        json.dump(view, f, indent=1)
        f.write("\n")


def exists(name):
    return os.path.exists(os.path.join(OUT, name + ".gltf"))


# ---------------------------------------------------------------------------------------- scenes

MODEL_GREY = (0.75, 0.72, 0.68)
GROUND = (0.55, 0.6, 0.5)
# y-up rotations for sources that are z-up (x stays, z becomes y).
Z_UP = [[1, 0, 0], [0, 0, 1], [0, -1, 0]]

SOURCES = {  # name: (file under SCENES, reader, rotation to y-up, normalised size)
    "bunny": ("bunny/bunny.obj", read_obj, None, 2.0),
    "armadillo": ("armadillo/armadillo.glb", read_glb, None, 2.0),
    "engine": ("engine/2CylinderEngine.glb", read_glb, None, 2.0),
    "fzk-haus": ("fzk-haus/AC14-FZK-Haus.glb", read_glb, None, 2.0),
    "fence": ("fence/fence.obj", read_obj, None, 2.0),
}
# Real models of other kinds (issue 17), written as they are (no ground quad): NAME.gltf.
UNSEEN = {
    "maple": ("maple/japaneseMaple.obj", read_obj, None, 2.0),
    "truman": ("truman/truman.glb", lambda path: read_glb(path, skip=("Wake",)), None, 2.0),  # not the water's wake
    "sailboat": ("sailboat/SailBoatUnderSail.glb", read_glb, None, 2.0),
    "oasago2": ("openarena/oasago2.bsp", read_bsp, Z_UP, 2.0),
    "ctf_inyard": ("openarena/ctf_inyard.bsp", read_bsp, Z_UP, 2.0),
}


def load(name):
    rel, reader, up, size = SOURCES[name] if name in SOURCES else UNSEEN[name]
    pos, tris = only_used(*reader(os.path.join(SCENES, rel)))
    return normalise(pos, up, size), tris


def staged(name, pos, tris, ground_scale=1.6, out_name=None):
    """The model on a ground quad `ground_scale` times its footprint (at least 2 units each way)."""
    half = ground_scale * max(1.0, np.abs(pos[:, [0, 2]]).max())
    g = ground(half, half)
    return write_gltf(out_name or name + "_stage", [(name, pos, tris, MODEL_GREY), ("ground", g[0], g[1], GROUND)],
                      [(0, (0, 0, 0), 0), (1, (0, 0, 0), 0)])


def main():
    os.makedirs(OUT, exist_ok=True)
    cache = {}

    def model(name):
        if name not in cache:
            cache[name] = load(name)
        return cache[name]

    for name in SOURCES:
        if not exists(name + "_stage"):
            staged(name, *model(name))
    for name in UNSEEN:
        if not exists(name):
            pos, tris = model(name)
            write_gltf(name, [(name, pos, tris, MODEL_GREY)], [(0, (0, 0, 0), 0)])

    # Subdivision levels of the scan: 69,666 x 4^N triangles (+2 for the ground).
    for level in (1, 2, 3):
        if exists(f"bunny_sub{level}"):
            continue
        pos, tris = model("bunny")
        for _ in range(level):
            pos, tris = subdivide_midpoint(pos, tris)
        staged("bunny", pos, tris, out_name=f"bunny_sub{level}")

    # Instanced layouts: nodes that all point at one mesh.
    if not exists("fence_field"):
        pos, tris = model("fence")
        ext = pos.max(axis=0) - pos.min(axis=0)
        rows, cols = 8, 8  # 64 sections: rows of fences, one behind the other
        dx, dz = ext[0] * 1.02, max(ext[2], 0.1) + 0.9
        nodes = [(0, ((c - (cols - 1) / 2) * dx, 0.0, (r - (rows - 1) / 2) * dz), 0) for r in range(rows) for c in range(cols)]
        g = ground(0.6 * cols * dx + 1.0, 0.6 * rows * dz + 1.0)
        write_gltf("fence_field", [("fence", pos, tris, MODEL_GREY), ("ground", g[0], g[1], GROUND)],
                   nodes + [(1, (0, 0, 0), 0)])
    if not exists("engine_row"):
        pos, tris = model("engine")
        ext = pos.max(axis=0) - pos.min(axis=0)
        per_row, rows = 4, 2  # two rows of 4 engines, each turned a little so their shadows differ
        dx, dz = ext[0] * 1.15, ext[2] * 2.5
        nodes = [(0, ((k - (per_row - 1) / 2) * dx, 0.0, (r - (rows - 1) / 2) * dz), 15.0 * (r * per_row + k))
                 for r in range(rows) for k in range(per_row)]
        g = ground(0.6 * per_row * dx + 1.0, 0.6 * rows * dz + 1.0)
        write_gltf("engine_row", [("engine", pos, tris, MODEL_GREY), ("ground", g[0], g[1], GROUND)],
                   nodes + [(1, (0, 0, 0), 0)])

    # Stability: PCSS's overlapping penumbrae, the scene of tests/test_soft_baselines.cpp
    # (PcssSingleBlockerErrorWherePenumbraeOverlap): a small square high up and a low box under a
    # disk light 1 unit wide, so the square's wide penumbra crosses the box's narrow one.
    if not exists("two_heights"):
        g = ground(4.0, 4.0)
        b = box([-3.0, 0.0, -3.0], [0.0, 2.0, 3.0])
        sq = (np.array([[-3.3, 10.0, -0.7], [-1.9, 10.0, -0.7], [-1.9, 10.0, 0.7], [-3.3, 10.0, 0.7]]),
              np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int64))
        write_gltf("two_heights", [("ground", g[0], g[1], GROUND), ("low box", b[0], b[1], MODEL_GREY),
                                   ("high square", sq[0], sq[1], MODEL_GREY)],
                   [(0, (0, 0, 0), 0), (1, (0, 0, 0), 0), (2, (0, 0, 0), 0)])
        radius = 0.5 * math.sqrt(8.0 ** 2 + 10.0 ** 2 + 8.0 ** 2)  # bounding-box half diagonal: --light-size is relative to it
        write_view("two_heights", ((4.0, 9.0, 9.0), (0.5, 0.0, 0.0), 45.0),
                   ("disk", (-4.0, 14.0, 0.0), (1.0, 0.0, 0.0)), light_size=round(1.0 / radius, 6))

    # Stability: huge coordinates. The staged bunny moved OFFSET units along x and z by a node
    # translation (the same buffer as bunny_stage), with the same camera and light moved along.
    for offset in (0.0, 1e5, 1e6):
        name = f"bunny_far{offset:.0e}".replace("+0", "").replace("+", "") if offset else "bunny_far0"
        if exists(name):
            continue
        pos, tris = model("bunny")
        half = 1.6 * max(1.0, np.abs(pos[:, [0, 2]]).max())
        g = ground(half, half)
        t = (offset, 0.0, offset)
        write_gltf(name, [("bunny", pos, tris, MODEL_GREY), ("ground", g[0], g[1], GROUND)],
                   [(0, t, 0), (1, t, 0)], bin_name="bunny_stage.bin")
        o = np.array(t)
        write_view(name, (o + (3.0, 3.2, 4.5), o + (0.0, 0.8, 0.0), 45.0), ("disk", o + (-2.5, 6.0, 1.5), o + (0.0, 0.5, 0.0)))

    # Alpha-tested content (issue 41): Sweet Home 3D's football goal, whose net is cut out of quads
    # by its texture's alpha (map_d), and its bush, whose leaves are cut-out cards; each kept as an
    # OBJ (a glTF written here would drop the cut-out) beside its textures, with a ground quad of its
    # own material library appended.
    stage_obj(os.path.join(SCENES, "goal"), "big-football-goal", "goal_stage")
    stage_obj(os.path.join(SCENES, "bush"), "bush", "bush_stage")


def stage_obj(folder, name, stage_name):
    model = os.path.join(folder, name + ".obj")
    stage = os.path.join(folder, stage_name + ".obj")
    if not os.path.exists(model) or os.path.exists(stage):
        return
    pos, _ = read_obj(model)
    lo, hi = pos.min(axis=0), pos.max(axis=0)
    c, half = (lo + hi) / 2, 0.8 * (hi - lo).max()
    y = lo[1]
    with open(os.path.join(folder, "stage.mtl"), "w") as f:
        f.write("newmtl stage_ground\nKd 0.62 0.60 0.55\nd 1.0\n")
    with open(model, encoding="utf-8", errors="replace") as f:
        text = f.read()
    corners = [(c[0] - half, c[2] - half), (c[0] + half, c[2] - half), (c[0] + half, c[2] + half), (c[0] - half, c[2] + half)]
    text += "\nmtllib stage.mtl\no stage_ground\n" + "".join(f"v {x:.6f} {y:.6f} {z:.6f}\n" for x, z in corners)
    text += "vn 0 1 0\nusemtl stage_ground\nf -4//-1 -1//-1 -2//-1 -3//-1\n"
    with open(stage + ".tmp", "w") as f:
        f.write(text)
    os.replace(stage + ".tmp", stage)

if __name__ == "__main__":
    main()
