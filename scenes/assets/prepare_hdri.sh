#!/usr/bin/env bash
# Rebuilds the HDR environment maps under scenes/assets/ (see ATTRIBUTION.md):
#   potsdamer_platz_512.exr  overcast city (the environment of scenes/mirror-sphere.toml)
#   venice_sunset_512.exr    low sun over the sea: a small, very bright source
#   studio_small_03_512.exr  photo studio: a ring light and a softbox, high contrast
# Needs npm and python3 (>= 3.9); installs numpy and OpenEXR into a throw-away virtual
# environment under the work directory, never into the repository.
#
# Source: the npm package @pmndrs/assets 1.7.0 (CC0-1.0), modules hdri/<module>.exr.js: each a
# base64 data URL of a 512×256 half-float RGB EXR (DWAB-compressed) made from a Poly Haven
# HDRI. DWAB is lossy and its ringing leaves negative texels (small ones in smooth regions,
# larger ones next to the edges of very bright sources); they are clamped to 0 (a radiance
# cannot be negative). The result is written losslessly as half-float RGB with ZIP
# compression, which the `exr` crate reads.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
work="${1:-$(mktemp -d)}"
mkdir -p "$work"
version="1.7.0"

# <module in @pmndrs/assets>:<output in scenes/assets>, named after the Poly Haven asset.
maps=(
    "city:potsdamer_platz_512.exr"
    "sunset:venice_sunset_512.exr"
    "studio:studio_small_03_512.exr"
)

cd "$work"
npm pack --silent "@pmndrs/assets@${version}" >/dev/null
args=()
for map in "${maps[@]}"; do
    module="${map%%:*}"
    output="${map#*:}"
    tar xzf "pmndrs-assets-${version}.tgz" "package/hdri/${module}.exr.js"
    args+=("$module" "$work/package/hdri/${module}.exr.js" "$here/$output")
done
python3 -m venv venv
venv/bin/pip install --quiet "numpy>=1.24" "OpenEXR==3.5.3"

# Arguments: triples of module name, source .exr.js, destination .exr.
venv/bin/python - "${args[@]}" <<'PY'
import base64, hashlib, re, sys
import numpy as np
import OpenEXR

def sha256(path):
    return hashlib.sha256(open(path, "rb").read()).hexdigest()

argv = sys.argv[1:]
for module, src, dst in zip(argv[0::3], argv[1::3], argv[2::3]):
    js = open(src, encoding="ascii").read()
    raw = base64.b64decode(re.search(r"base64,([A-Za-z0-9+/=]+)", js).group(1))
    payload = f"{module}_dwab.exr"
    open(payload, "wb").write(raw)

    with OpenEXR.File(payload) as f:
        channels = f.channels()
        rgb = channels["RGB"].pixels if "RGB" in channels else np.stack(
            [channels[c].pixels for c in "RGB"], axis=-1)
    rgb = rgb.astype(np.float32)
    assert rgb.shape == (256, 512, 3), rgb.shape
    assert np.isfinite(rgb).all()
    negative, lowest = int((rgb < 0).sum()), float(rgb.min())
    rgb = np.maximum(rgb, 0.0).astype(np.float16)

    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, {"RGB": rgb}) as out:
        out.write(dst)
    value = rgb.astype(np.float32)
    row, col = np.unravel_index(np.argmax(value.max(axis=-1)), value.shape[:2])
    print(f"wrote {dst}: 512x256 half RGB, {negative} negative values (min {lowest:.3f}) "
          f"clamped to 0, max {float(value.max()):.3f} at row {row} column {col}, "
          f"mean {float(value.mean()):.4f}\n"
          f"  sha256 {sha256(dst)}\n  payload of hdri/{module}.exr.js: sha256 {sha256(payload)}")
PY
