#!/usr/bin/env python3
"""Writes scenes/assets/uv-sphere.gltf: a unit-radius UV sphere (48 x 24 segments) with
vertex normals (the exact sphere normals) and uvs (u = phi/2pi around +Y, v = theta/pi from
the +Y pole), one clay-coloured rough dielectric material. The surface-detail silhouette
study displaces it (scenes/studies/scenes/relief-sphere.toml). Standard library only;
rerun to regenerate: python3 scenes/assets/make_uv_sphere.py"""
import base64, json, math, struct, pathlib

SEG_U, SEG_V = 48, 24
pos, nrm, uv = [], [], []
for j in range(SEG_V + 1):
    theta = math.pi * j / SEG_V
    for i in range(SEG_U + 1):
        phi = 2 * math.pi * i / SEG_U
        n = (math.sin(theta) * math.sin(phi), math.cos(theta), math.sin(theta) * math.cos(phi))
        pos.append(n); nrm.append(n); uv.append((i / SEG_U, j / SEG_V))
idx = []
row = SEG_U + 1
for j in range(SEG_V):
    for i in range(SEG_U):
        a, b, c, d = j * row + i, j * row + i + 1, (j + 1) * row + i, (j + 1) * row + i + 1
        if j > 0:
            idx += [a, c, b]
        if j < SEG_V - 1:
            idx += [b, c, d]
blob = b"".join(struct.pack("<3f", *p) for p in pos)
blob += b"".join(struct.pack("<3f", *n) for n in nrm)
blob += b"".join(struct.pack("<2f", *t) for t in uv)
off_idx = len(blob)
blob += struct.pack("<%dH" % len(idx), *idx)
n = len(pos)
doc = {
    "asset": {"version": "2.0", "generator": "verity scenes/assets/make_uv_sphere.py"},
    "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0, "name": "sphere"}],
    "materials": [{"name": "clay", "pbrMetallicRoughness": {
        "baseColorFactor": [0.7, 0.62, 0.55, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0}}],
    "meshes": [{"name": "sphere", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                                  "indices": 3, "material": 0}]}],
    "buffers": [{"byteLength": len(blob),
                 "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
    "bufferViews": [
        {"buffer": 0, "byteOffset": 0, "byteLength": 12 * n, "target": 34962},
        {"buffer": 0, "byteOffset": 12 * n, "byteLength": 12 * n, "target": 34962},
        {"buffer": 0, "byteOffset": 24 * n, "byteLength": 8 * n, "target": 34962},
        {"buffer": 0, "byteOffset": off_idx, "byteLength": 2 * len(idx), "target": 34963}],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3", "min": [-1, -1, -1], "max": [1, 1, 1]},
        {"bufferView": 1, "componentType": 5126, "count": n, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5126, "count": n, "type": "VEC2"},
        {"bufferView": 3, "componentType": 5123, "count": len(idx), "type": "SCALAR"}],
}
out = pathlib.Path(__file__).resolve().parent / "uv-sphere.gltf"
out.write_text(json.dumps(doc, separators=(",", ":")) + "\n")
print(f"wrote {out} ({n} vertices, {len(idx) // 3} triangles)")
