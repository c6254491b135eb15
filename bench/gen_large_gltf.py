#!/usr/bin/env python3
"""Writes a large glTF test scene (not committed data): an N x N grid of quads (2 N^2 triangles) on a wavy height
field, with normals and u32 indices, as OUT.glb, plus the same surface as OUT.obj for comparison.
Usage: bench/gen_large_gltf.py OUT [N]   (N = 708 gives 1,002,528 triangles)
Measure: /usr/bin/time -v build/ptview OUT.glb --frames 1 --size 64x64 --out /tmp/x.png"""
import json, math, struct, sys
from array import array

out, n = sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 708
pos, nrm, idx = array('f'), array('f'), array('I')
for j in range(n + 1):
    for i in range(n + 1):
        x, z = i / n * 2 - 1, j / n * 2 - 1
        y = 0.05 * math.sin(9 * x) * math.cos(7 * z)
        dx, dz = 0.45 * math.cos(9 * x) * math.cos(7 * z), -0.35 * math.sin(9 * x) * math.sin(7 * z)
        l = math.sqrt(dx * dx + 1 + dz * dz)
        pos.extend((x, y, z))
        nrm.extend((-dx / l, 1 / l, -dz / l))
for j in range(n):
    for i in range(n):
        a = j * (n + 1) + i
        b, c, d = a + 1, a + n + 1, a + n + 2
        idx.extend((a, c, b, b, c, d))  # counter-clockwise seen from +y
count = (n + 1) ** 2
blob = pos.tobytes() + nrm.tobytes() + idx.tobytes()
doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
       "materials": [{"name": "grey", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.7, 0.7, 1], "metallicFactor": 0}}],
       "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}],
       "accessors": [{"bufferView": 0, "componentType": 5126, "count": count, "type": "VEC3",
                      "min": [-1, -0.05, -1], "max": [1, 0.05, 1]},
                     {"bufferView": 1, "componentType": 5126, "count": count, "type": "VEC3"},
                     {"bufferView": 2, "componentType": 5125, "count": len(idx), "type": "SCALAR"}],
       "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 12 * count},
                       {"buffer": 0, "byteOffset": 12 * count, "byteLength": 12 * count},
                       {"buffer": 0, "byteOffset": 24 * count, "byteLength": 4 * len(idx)}],
       "buffers": [{"byteLength": len(blob)}]}
js = json.dumps(doc).encode()
js += b' ' * (-len(js) % 4)
blob += b'\0' * (-len(blob) % 4)
with open(out + ".glb", "wb") as f:
    f.write(b'glTF' + struct.pack('<II', 2, 28 + len(js) + len(blob)))
    f.write(struct.pack('<I', len(js)) + b'JSON' + js + struct.pack('<I', len(blob)) + b'BIN\0' + blob)
with open(out + ".obj", "w") as f:
    f.write("".join("v %.6f %.6f %.6f\n" % tuple(pos[3 * k:3 * k + 3]) for k in range(count)))
    f.write("".join("vn %.6f %.6f %.6f\n" % tuple(nrm[3 * k:3 * k + 3]) for k in range(count)))
    f.write("".join("f %d//%d %d//%d %d//%d\n" % (idx[k] + 1, idx[k] + 1, idx[k + 1] + 1, idx[k + 1] + 1,
                                                  idx[k + 2] + 1, idx[k + 2] + 1) for k in range(0, len(idx), 3)))
print(f"{out}.glb and {out}.obj: {len(idx) // 3} triangles, {count} vertices")
