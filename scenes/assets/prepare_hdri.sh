#!/usr/bin/env bash
# Rebuilds scenes/assets/potsdamer_platz_512.exr, the environment of scenes/mirror-sphere.toml
# (see ATTRIBUTION.md). Needs npm and python3 (>= 3.9); installs numpy and OpenEXR into a
# throw-away virtual environment under the work directory, never into the repository.
#
# Source: the npm package @pmndrs/assets 1.7.0 (CC0-1.0), module hdri/city.exr.js: a base64
# data URL of a 512×256 half-float RGB EXR (DWAB-compressed) made from Poly Haven's
# "Potsdamer Platz" HDRI. DWAB is lossy and its ringing leaves a few small negative texels;
# they are clamped to 0 (a radiance cannot be negative). The result is written losslessly as
# half-float RGB with ZIP compression, which the `exr` crate reads.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
work="${1:-$(mktemp -d)}"
mkdir -p "$work"
version="1.7.0"

cd "$work"
npm pack --silent "@pmndrs/assets@${version}" >/dev/null
tar xzf "pmndrs-assets-${version}.tgz" package/hdri/city.exr.js
python3 -m venv venv
venv/bin/pip install --quiet "numpy>=1.24" "OpenEXR==3.5.3"

venv/bin/python - "$work/package/hdri/city.exr.js" "$here/potsdamer_platz_512.exr" <<'PY'
import base64, re, sys
import numpy as np
import OpenEXR

src, dst = sys.argv[1], sys.argv[2]
js = open(src, encoding="ascii").read()
raw = base64.b64decode(re.search(r"base64,([A-Za-z0-9+/=]+)", js).group(1))
open("city_dwab.exr", "wb").write(raw)

with OpenEXR.File("city_dwab.exr") as f:
    channels = f.channels()
    rgb = channels["RGB"].pixels if "RGB" in channels else np.stack(
        [channels[c].pixels for c in "RGB"], axis=-1)
rgb = rgb.astype(np.float32)
assert rgb.shape == (256, 512, 3), rgb.shape
assert np.isfinite(rgb).all()
negative = int((rgb < 0).sum())
rgb = np.maximum(rgb, 0.0).astype(np.float16)

header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
with OpenEXR.File(header, {"RGB": rgb}) as out:
    out.write(dst)
print(f"wrote {dst}: 512x256 half RGB, {negative} negative values clamped to 0, "
      f"max {float(rgb.max()):.3f}, mean {float(rgb.astype(np.float32).mean()):.4f}")
PY
