#!/usr/bin/env python3
"""Writes scenes/bench/rock.glb: a generated "scan-like" rock of 1,310,720 triangles for the
`verity bench --vs-mitsuba` scene scenes/bench/rock-under-sky.toml (issue 26: a ~1 M-triangle
glTF mesh under an HDR environment).

The mesh is an icosphere of 8 midpoint-subdivision levels (20 * 4^8 triangles, 655,362
vertices) whose vertices are moved along the radius by a deterministic sum of 48 plane waves
over random directions (octaves of frequency 1.7 to 49 /m, amplitude falling as 1/f), so the
surface has detail at every scale down to a few triangles and the 1 M triangles are not
wasted on a smooth ball. Vertex normals are the area-weighted face normals. One glTF material
("stone", rough dielectric), overridden by the scene.

Deterministic (fixed seed, float32 output): every run writes the same bytes (SHA-256 printed).
Not committed (36 MB); scripts/setup.sh writes it. Needs numpy (the .venv has it):
    .venv/bin/python scenes/bench/make_rock.py
"""
import hashlib
import json
import pathlib
import struct
import sys

import numpy as np

LEVELS = 8


def icosphere(levels):
    t = (1.0 + 5.0 ** 0.5) / 2.0
    v = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0],
                  [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
                  [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]], dtype=np.float64)
    f = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
                  [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
                  [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
                  [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]], dtype=np.int64)
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    for _ in range(levels):
        # One new vertex per unique edge, at the edge's midpoint pushed onto the sphere.
        edges = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
        key = np.sort(edges, axis=1)
        uniq, inverse = np.unique(key, axis=0, return_inverse=True)
        mid = v[uniq[:, 0]] + v[uniq[:, 1]]
        mid /= np.linalg.norm(mid, axis=1, keepdims=True)
        m = inverse.reshape(3, -1) + len(v)
        a, b, c = f[:, 0], f[:, 1], f[:, 2]
        ab, bc, ca = m[0], m[1], m[2]
        f = np.concatenate([np.stack([a, ab, ca], 1), np.stack([b, bc, ab], 1),
                            np.stack([c, ca, bc], 1), np.stack([ab, bc, ca], 1)])
        v = np.concatenate([v, mid])
    return v, f


def main():
    v, f = icosphere(LEVELS)
    rng = np.random.default_rng(26)
    waves = 48
    dirs = rng.normal(size=(waves, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    freq = 1.7 * (1.08 ** np.arange(waves))
    phase = rng.uniform(0, 2 * np.pi, waves)
    amp = 0.06 / freq ** 1.0
    r = 1.0 + (np.sin(v @ (dirs * freq[:, None]).T + phase) * amp).sum(axis=1)
    # Flatten the bottom a little so the rock sits on the ground.
    p = v * r[:, None]
    p[:, 1] = np.maximum(p[:, 1], -0.82)
    p[:, 1] -= p[:, 1].min()
    p *= 0.6
    # Area-weighted vertex normals.
    fn = np.cross(p[f[:, 1]] - p[f[:, 0]], p[f[:, 2]] - p[f[:, 0]])
    n = np.zeros_like(p)
    for k in range(3):
        np.add.at(n, f[:, k], fn)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    pos = p.astype("<f4")
    nrm = n.astype("<f4")
    idx = f.astype("<u4")
    blob = pos.tobytes() + nrm.tobytes() + idx.tobytes()
    nv, ni = len(pos), idx.size
    doc = {
        "asset": {"version": "2.0", "generator": "verity scenes/bench/make_rock.py"},
        "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "rock"}],
        "materials": [{"name": "stone", "pbrMetallicRoughness": {
            "baseColorFactor": [0.5, 0.45, 0.4, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0}}],
        "meshes": [{"name": "rock", "primitives": [
            {"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}],
        "buffers": [{"byteLength": len(blob)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 12 * nv, "target": 34962},
            {"buffer": 0, "byteOffset": 12 * nv, "byteLength": 12 * nv, "target": 34962},
            {"buffer": 0, "byteOffset": 24 * nv, "byteLength": 4 * ni, "target": 34963}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": nv, "type": "VEC3",
             "min": pos.min(axis=0).tolist(), "max": pos.max(axis=0).tolist()},
            {"bufferView": 1, "componentType": 5126, "count": nv, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": ni, "type": "SCALAR"}],
    }
    js = json.dumps(doc, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    glb = struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(js) + 8 + len(blob))
    glb += struct.pack("<II", len(js), 0x4E4F534A) + js
    glb += struct.pack("<II", len(blob), 0x004E4942) + blob
    out = pathlib.Path(__file__).resolve().parent / "rock.glb"
    tmp = out.with_suffix(".glb.tmp")
    tmp.write_bytes(glb)
    tmp.replace(out)
    print(f"wrote {out}: {nv} vertices, {len(f)} triangles, "
          f"sha256 {hashlib.sha256(glb).hexdigest()}", file=sys.stderr)


if __name__ == "__main__":
    main()
