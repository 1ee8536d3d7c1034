#!/usr/bin/env python3
"""Writes scenes/assets/suzanne-camera.gltf: the vendored Suzanne (suzanne.glb, CC0, see
ATTRIBUTION.md) with a perspective camera, for scenes that take an asset's camera
(scenes/include-asset.toml, `[[include]] camera = true`).

The .gltf holds no geometry of its own: its one buffer is the file suzanne.glb itself, read
as plain bytes, and its buffer views are suzanne.glb's, moved past the GLB header and JSON
chunk to where the BIN chunk's data starts (glTF 2.0 "GLB File Format Specification":
12-byte header, then chunks of 8-byte header + data). Accessors, the mesh ("mesh") and the
material ("base") are copied unchanged; the node holding the mesh is named "suzanne"; the
camera "front" (yfov 0.7 rad, aspectRatio 1.5) sits at (0, 0.35, 3.1) looking 5.53 degrees
down, at the head's centre. Standard library only; rerun to regenerate:
python3 scenes/assets/make_suzanne_camera.py"""
import json, math, pathlib, struct

here = pathlib.Path(__file__).resolve().parent
glb = (here / "suzanne.glb").read_bytes()
magic, version, length = struct.unpack_from("<4sII", glb, 0)
assert magic == b"glTF" and version == 2 and length == len(glb)
json_len, json_type = struct.unpack_from("<I4s", glb, 12)
assert json_type == b"JSON"
src = json.loads(glb[20 : 20 + json_len])
bin_header = 20 + json_len
bin_len, bin_type = struct.unpack_from("<I4s", glb, bin_header)
assert bin_type == b"BIN\0"
bin_start = bin_header + 8
assert len(src["buffers"]) == 1 and src["buffers"][0]["byteLength"] <= bin_len

views = []
for v in src["bufferViews"]:
    v = dict(v)
    v["byteOffset"] = bin_start + v.get("byteOffset", 0)
    views.append(v)
pitch = math.atan2(-0.3, 3.1)  # look from (0, 0.35, 3.1) at (0, 0.05, 0)
doc = {
    "asset": {"version": "2.0", "generator": "verity scenes/assets/make_suzanne_camera.py"},
    "scene": 0,
    "scenes": [{"nodes": [0, 1]}],
    "nodes": [
        {"name": "suzanne", "mesh": 0},
        {
            "name": "camera",
            "camera": 0,
            "translation": [0.0, 0.35, 3.1],
            "rotation": [round(math.sin(pitch / 2), 6), 0.0, 0.0, round(math.cos(pitch / 2), 6)],
        },
    ],
    "cameras": [
        {"name": "front", "type": "perspective",
         "perspective": {"yfov": 0.7, "aspectRatio": 1.5, "znear": 0.05}}
    ],
    "materials": src["materials"],
    "meshes": src["meshes"],
    "accessors": src["accessors"],
    "bufferViews": views,
    "buffers": [{"uri": "suzanne.glb", "byteLength": bin_start + src["buffers"][0]["byteLength"]}],
}
out = here / "suzanne-camera.gltf"
out.write_text(json.dumps(doc, separators=(",", ":")) + "\n")
print(f"wrote {out} ({out.stat().st_size} bytes)")
