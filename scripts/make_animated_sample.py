#!/usr/bin/env python3
"""Writes content/animated/moving_parts.gltf: a small animated glTF 2.0 scene for gazetrace.

One 4-second looping animation moves, over a static floor lit by a directional light (so every
shadow moves too):
  - a red box sliding along x (translation, LINEAR),
  - a blue paddle turning about y (rotation, CUBICSPLINE with zero tangents: it eases in and out
    of each quarter turn),
  - a green bar of two joints bending at its middle (a skin: joints, inverse bind matrices and
    4 weights a vertex; the tip joint's rotation is LINEAR),
  - a yellow block whose top rises and sinks (one morph target on POSITION, its weight LINEAR).
The camera is a node of the file. Everything is one file: the buffer is a base64 data: URI.

Usage: python3 scripts/make_animated_sample.py [OUTPUT]   (python3 standard library only)
"""
import base64
import json
import math
import os
import struct
import sys

DURATION = 4.0


class Writer:
    """One buffer, its bufferViews and accessors, appended one at a time."""

    def __init__(self):
        self.bin = bytearray()
        self.views = []
        self.accessors = []

    def _view(self, data, target=None):
        while len(self.bin) % 4:
            self.bin.append(0)
        view = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if target:
            view["target"] = target
        self.bin += data
        self.views.append(view)
        return len(self.views) - 1

    def floats(self, rows, kind, target=None, bounds=False):
        width = len(rows[0]) if isinstance(rows[0], (list, tuple)) else 1
        flat = [v for r in rows for v in (r if width > 1 else [r])]
        acc = {"bufferView": self._view(struct.pack("<%df" % len(flat), *flat), target),
               "componentType": 5126, "count": len(rows), "type": kind}
        if bounds:  # POSITION and animation inputs must carry min and max (glTF 2.0, 5.1.5)
            cols = [flat[i::width] for i in range(width)]
            acc["min"] = [min(c) for c in cols]
            acc["max"] = [max(c) for c in cols]
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def ushorts(self, values, kind, target=None):
        count = len(values) // {"SCALAR": 1, "VEC4": 4}[kind]
        self.accessors.append({"bufferView": self._view(struct.pack("<%dH" % len(values), *values),
                                                        target),
                               "componentType": 5123, "count": count, "type": kind})
        return len(self.accessors) - 1

    def ubytes(self, values, kind, normalized=False):
        self.accessors.append({"bufferView": self._view(bytes(values)), "componentType": 5121,
                               "count": len(values) // 4, "type": kind})
        if normalized:
            self.accessors[-1]["normalized"] = True
        return len(self.accessors) - 1


def box(lo, hi, segments_y=1):
    """A box's faces with outward normals: positions, normals, triangle indices. Its sides are
    cut into `segments_y` rows so that a skin can bend them."""
    pos, nrm, idx = [], [], []

    def quad_grid(corner, u, v, n, rows):
        base = len(pos)
        for r in range(rows + 1):
            for c in range(2):
                pos.append(tuple(corner[i] + c * u[i] + r / rows * v[i] for i in range(3)))
                nrm.append(n)
        for r in range(rows):
            a = base + 2 * r
            idx.extend([a, a + 1, a + 3, a, a + 3, a + 2])

    (x0, y0, z0), (x1, y1, z1) = lo, hi
    dx, dy, dz = x1 - x0, y1 - y0, z1 - z0
    quad_grid((x0, y0, z1), (dx, 0, 0), (0, dy, 0), (0, 0, 1), segments_y)   # +z
    quad_grid((x1, y0, z0), (-dx, 0, 0), (0, dy, 0), (0, 0, -1), segments_y)  # -z
    quad_grid((x1, y0, z1), (0, 0, -dz), (0, dy, 0), (1, 0, 0), segments_y)   # +x
    quad_grid((x0, y0, z0), (0, 0, dz), (0, dy, 0), (-1, 0, 0), segments_y)   # -x
    quad_grid((x0, y1, z1), (dx, 0, 0), (0, 0, -dz), (0, 1, 0), 1)            # +y
    quad_grid((x0, y0, z0), (dx, 0, 0), (0, 0, dz), (0, -1, 0), 1)            # -y
    return pos, nrm, idx


def mesh(w, name, pos, nrm, idx, material, extra=None, targets=None, weights=None):
    attributes = {"POSITION": w.floats(pos, "VEC3", 34962, bounds=True),
                  "NORMAL": w.floats(nrm, "VEC3", 34962)}
    attributes.update(extra or {})
    prim = {"attributes": attributes, "indices": w.ushorts(idx, "SCALAR", 34963),
            "material": material}
    if targets:
        prim["targets"] = targets
    m = {"name": name, "primitives": [prim]}
    if weights:
        m["weights"] = weights
    return m


def quat_y(angle):
    return [0.0, math.sin(angle / 2), 0.0, math.cos(angle / 2)]


def quat_z(angle):
    return [0.0, 0.0, math.sin(angle / 2), math.cos(angle / 2)]


def quat_x(angle):
    return [math.sin(angle / 2), 0.0, 0.0, math.cos(angle / 2)]


def quat_mul(a, b):
    """Hamilton product a * b of (x, y, z, w) quaternions: b's rotation first."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return [aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz]


def sampler(w, times, values, kind, interpolation="LINEAR"):
    return {"input": w.floats(times, "SCALAR", bounds=True),
            "output": w.floats(values, kind), "interpolation": interpolation}


def build():
    w = Writer()
    colour = lambda name, rgb: {"name": name, "pbrMetallicRoughness": {
        "baseColorFactor": rgb + [1.0], "metallicFactor": 0.0, "roughnessFactor": 0.8}}
    materials = [colour("floor", [0.75, 0.75, 0.72]), colour("red", [0.8, 0.1, 0.08]),
                 colour("blue", [0.1, 0.25, 0.8]), colour("green", [0.1, 0.6, 0.15]),
                 colour("yellow", [0.85, 0.7, 0.1])]
    meshes = []
    meshes.append(mesh(w, "floor", *box((-5, -0.1, -4), (5, 0, 4)), 0))
    meshes.append(mesh(w, "sliding_box", *box((-0.4, 0, -0.4), (0.4, 0.8, 0.4)), 1))
    meshes.append(mesh(w, "paddle", *box((-0.8, -0.1, -0.2), (0.8, 0.1, 0.2)), 2))

    # The bar stands 2 units tall at x = -2, z = -1.5, bound to a root joint at its foot and a
    # tip joint at its middle; weights blend linearly over y in [0.6, 1.4].
    pos, nrm, idx = box((-2.15, 0, -1.65), (-1.85, 2, -1.35), segments_y=10)
    joints, weights = [], []
    for p in pos:
        tip = min(1.0, max(0.0, (p[1] - 0.6) / 0.8))
        b = round(255 * tip)
        joints += [0, 1, 0, 0]
        weights += [255 - b, b, 0, 0]
    skin_attrs = {"JOINTS_0": w.ubytes(joints, "VEC4"),
                  "WEIGHTS_0": w.ubytes(weights, "VEC4", normalized=True)}
    meshes.append(mesh(w, "bending_bar", pos, nrm, idx, 3, skin_attrs))

    # The block's top face and the upper ends of its sides rise by 0.9 with the target.
    pos, nrm, idx = box((1.5, 0, -2.2), (2.3, 0.5, -1.4))
    rise = [(0.0, 0.9 if p[1] > 0.25 else 0.0, 0.0) for p in pos]
    target = {"POSITION": w.floats(rise, "VEC3", bounds=True)}
    meshes.append(mesh(w, "rising_block", pos, nrm, idx, 4, targets=[target], weights=[0.0]))

    inverse_bind = [[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 2, 0, 1.5, 1],
                    [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 2, -1, 1.5, 1]]
    skins = [{"name": "bar", "joints": [4, 5],
              "inverseBindMatrices": w.floats(inverse_bind, "MAT4")}]

    nodes = [
        {"name": "floor", "mesh": 0},
        {"name": "sliding_box", "mesh": 1, "translation": [-2.5, 0, 1]},
        {"name": "paddle", "mesh": 2, "translation": [0, 1.2, -0.5]},
        {"name": "bending_bar", "mesh": 3, "skin": 0},
        {"name": "bar_root", "translation": [-2, 0, -1.5], "children": [5]},
        {"name": "bar_tip", "translation": [0, 1, 0]},
        {"name": "rising_block", "mesh": 4},
        # The sun shines along its node's -Z, pitched 55 degrees down and turned to travel
        # towards the camera and to its right (+Z, +X): the shadows fall there, in view.
        {"name": "sun",
         "rotation": quat_mul(quat_y(math.radians(-145)), quat_x(math.radians(-55))),
         "extensions": {"KHR_lights_punctual": {"light": 0}}},
        # The camera looks down -Z from (0, 3.2, 7.5) at (0, 0.6, -0.5).
        {"name": "camera", "camera": 0, "translation": [0, 3.2, 7.5],
         "rotation": quat_x(-math.atan2(3.2 - 0.6, 8.0))},
    ]

    times = [DURATION * k / 4 for k in range(5)]
    slide = [[-2.5, 0, 1], [2.5, 0, 1], [-2.5, 0, 1], [2.5, 0, 1], [-2.5, 0, 1]]
    # CUBICSPLINE: per key an in-tangent, the value, an out-tangent (zero: ease in and out).
    turn = []
    for k in range(5):
        turn += [[0, 0, 0, 0], quat_y(k * math.pi / 2), [0, 0, 0, 0]]
    bend_times = [DURATION * k / 8 for k in range(9)]
    bend = [quat_z(math.radians(a)) for a in (0, 35, 60, 35, 0, -35, -60, -35, 0)]
    grow = [0.0, 1.0, 0.0, 1.0, 0.0]
    samplers = [sampler(w, times, slide, "VEC3"),
                sampler(w, times, turn, "VEC4", "CUBICSPLINE"),
                sampler(w, bend_times, bend, "VEC4"),
                sampler(w, times, grow, "SCALAR")]
    channels = [{"sampler": 0, "target": {"node": 1, "path": "translation"}},
                {"sampler": 1, "target": {"node": 2, "path": "rotation"}},
                {"sampler": 2, "target": {"node": 5, "path": "rotation"}},
                {"sampler": 3, "target": {"node": 6, "path": "weights"}}]

    doc = {
        "asset": {"version": "2.0",
                  "generator": "gazetrace scripts/make_animated_sample.py"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": "sun", "type": "directional", "color": [1.0, 0.96, 0.9],
             "intensity": 3.0}]}},
        "scene": 0,
        "scenes": [{"name": "moving_parts", "nodes": [0, 1, 2, 3, 4, 6, 7, 8]}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "skins": skins,
        "cameras": [{"type": "perspective",
                     "perspective": {"yfov": 0.8, "znear": 0.05, "aspectRatio": 16 / 9}}],
        "animations": [{"name": "moving_parts", "samplers": samplers, "channels": channels}],
        "accessors": w.accessors,
        "bufferViews": w.views,
        "buffers": [{"byteLength": len(w.bin),
                     "uri": "data:application/octet-stream;base64," +
                            base64.b64encode(bytes(w.bin)).decode("ascii")}],
    }
    return doc


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "content", "animated",
                                                             "moving_parts.gltf")
    os.makedirs(os.path.dirname(out), exist_ok=True)
    with open(out, "w", encoding="utf-8") as f:
        json.dump(build(), f, indent=1)
        f.write("\n")
    print(out, os.path.getsize(out), "bytes")


if __name__ == "__main__":
    main()
