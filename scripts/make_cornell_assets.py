#!/usr/bin/env python3
"""Writes the built-in Cornell box scenes in assets/ (run from the repository root; the output is committed).

The box: walls x in [-1, 1], y in [0, 2], z in [-1, 1], open toward +z where the camera is; a 0.47 x 0.38 ceiling
light; the classic red, green and white reflectances. Every quad's front faces the inside of the box (or, for
blocks, outward) so emission and winding conventions hold.
"""
import json
import math
import os
import re


def sub(a, b): return [a[i] - b[i] for i in range(3)]
def add(a, b): return [a[i] + b[i] for i in range(3)]
def mul(a, s): return [x * s for x in a]
def dot(a, b): return sum(a[i] * b[i] for i in range(3))
def cross(a, b): return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
def r4(v): return [round(x, 4) for x in v]


def quad(corner, e1, e2, facing, material):
    if dot(cross(e1, e2), facing) < 0:
        e1, e2 = e2, e1
    return {"type": "quad", "corner": r4(corner), "edge1": r4(e1), "edge2": r4(e2), "material": material}


def walls():
    return [
        quad([-1, 0, -1], [2, 0, 0], [0, 0, 2], [0, 1, 0], "white"),     # floor
        quad([-1, 2, -1], [2, 0, 0], [0, 0, 2], [0, -1, 0], "white"),    # ceiling
        quad([-1, 0, -1], [2, 0, 0], [0, 2, 0], [0, 0, 1], "white"),     # back
        quad([-1, 0, -1], [0, 0, 2], [0, 2, 0], [1, 0, 0], "red"),       # left
        quad([1, 0, -1], [0, 0, 2], [0, 2, 0], [-1, 0, 0], "green"),     # right
        quad([-0.235, 1.98, -0.19], [0.47, 0, 0], [0, 0, 0.38], [0, -1, 0], "light"),
    ]


def block(center_xz, size, height, degrees, material):
    """An upright box standing on the floor, rotated about y; five outward-facing quads (no bottom)."""
    a = math.radians(degrees)
    ux = [math.cos(a) * size, 0, -math.sin(a) * size]
    uz = [math.sin(a) * size, 0, math.cos(a) * size]
    up = [0, height, 0]
    c = [center_xz[0], 0, center_xz[1]]
    p0 = sub(sub(c, mul(ux, 0.5)), mul(uz, 0.5))
    mid = add(c, [0, height / 2, 0])
    faces = [
        (add(p0, up), ux, uz),          # top
        (p0, ux, up),                   # -z side
        (add(p0, uz), ux, up),          # +z side
        (p0, uz, up),                   # -x side
        (add(p0, ux), uz, up),          # +x side
    ]
    out = []
    for corner, e1, e2 in faces:
        center = add(corner, mul(add(e1, e2), 0.5))
        out.append(quad(corner, e1, e2, sub(center, mid), material))
    return out


BASE_MATERIALS = {
    "white": {"type": "diffuse", "albedo": [0.725, 0.71, 0.68]},
    "red": {"type": "diffuse", "albedo": [0.63, 0.065, 0.05]},
    "green": {"type": "diffuse", "albedo": [0.14, 0.45, 0.091]},
    "light": {"type": "diffuse", "albedo": [0.78, 0.78, 0.78], "emission": [17, 12, 4]},
}
CAMERA = {"eye": [0, 1, 3.9], "target": [0, 1, 0], "up": [0, 1, 0], "fov": 40}


def scene(extra_materials, shapes):
    mats = dict(BASE_MATERIALS)
    mats.update(extra_materials)
    return {"version": 1, "camera": CAMERA, "materials": mats, "shapes": walls() + shapes}


TALL = lambda m: block([-0.33, -0.29], 0.6, 1.2, 17, m)
SHORT = lambda m: block([0.34, 0.28], 0.6, 0.6, -17, m)

SCENES = {
    "cornell": scene({}, TALL("white") + SHORT("white")),
    "cornell-glass": scene({"glass": {"type": "glass", "ior": 1.5}},
                           TALL("white") + [{"type": "sphere", "center": [0.38, 0.42, 0.3], "radius": 0.42,
                                             "material": "glass"}]),
    "cornell-mirror": scene({"mirror": {"type": "specular", "albedo": [0.95, 0.95, 0.95]}},
                            TALL("white") + [{"type": "sphere", "center": [0.38, 0.42, 0.3], "radius": 0.42,
                                              "material": "mirror"}]),
    "cornell-spheres": scene({"glass": {"type": "glass", "ior": 1.5},
                              "mirror": {"type": "specular", "albedo": [0.95, 0.95, 0.95]}},
                             [{"type": "sphere", "center": [-0.45, 0.4, -0.3], "radius": 0.4, "material": "mirror"},
                              {"type": "sphere", "center": [0.45, 0.4, 0.25], "radius": 0.4, "material": "glass"}]),
    "cornell-large-mesh": scene({"knot": {"type": "diffuse", "albedo": [0.8, 0.6, 0.3]}},
                                [{"type": "mesh", "material": "knot",
                                  "generate": {"kind": "torus-knot", "p": 2, "q": 3, "segments": 800, "sides": 64,
                                               "radius": 0.62, "tube": 0.13},
                                  "transform": {"rotate": [0, 1, 0, 20], "translate": [0, 0.765, -0.1]}}]),
}

if __name__ == "__main__":
    os.makedirs("assets", exist_ok=True)
    for name, s in SCENES.items():
        text = json.dumps(s, indent=1)
        # Numeric arrays on one line, for readable files.
        text = re.sub(r"\[\s*([-0-9.e,\s]+?)\s*\]",
                      lambda m: "[" + ", ".join(x.strip() for x in m.group(1).split(",")) + "]", text)
        with open(os.path.join("assets", name + ".json"), "w") as f:
            f.write(text + "\n")
        print("wrote assets/%s.json" % name)
