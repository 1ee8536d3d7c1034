#!/usr/bin/env bash
# Rebuilds scenes/assets/suzanne.glb (the real glTF asset of the scene library) and the test
# input scenes/tests/data/suzanne-draco.glb (see ATTRIBUTION.md). Needs npm and node; installs
# the glTF Transform CLI into the work directory, never into the repository.
#
# Source: the npm package @pmndrs/assets 1.7.0 (CC0-1.0), module models/suzi.glb.js: a base64
# data URL of a Draco-compressed GLB (KHR_draco_mesh_compression, required) of Blender's
# "Suzanne" monkey head, subdivided: 7,503 vertices, 14,842 triangles, POSITION + NORMAL,
# one material with default metallic-roughness values. That file is kept as it is for the
# "required extension" error test. Our loader does not decode Draco, so the vendored asset
# is the same GLB with its geometry decoded by `gltf-transform copy` (glTF Transform decodes
# Draco on read through its draco3dgltf dependency and writes plain accessors; nothing else
# changes but the generator string).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
work="${1:-$(mktemp -d)}"
mkdir -p "$work"
assets_version="1.7.0"
cli_version="4.5.1"

cd "$work"
npm pack --silent "@pmndrs/assets@${assets_version}" >/dev/null
tar xzf "pmndrs-assets-${assets_version}.tgz" package/models/suzi.glb.js package/LICENSE
node -e '
const fs = require("fs");
const js = fs.readFileSync(process.argv[1], "ascii");
const b64 = js.match(/base64,([A-Za-z0-9+\/=]+)/)[1];
fs.writeFileSync(process.argv[2], Buffer.from(b64, "base64"));
' package/models/suzi.glb.js suzanne-draco.glb

npm install --silent --no-audit --no-fund --prefix "$work/cli" "@gltf-transform/cli@${cli_version}"
"$work/cli/node_modules/.bin/gltf-transform" copy suzanne-draco.glb suzanne.glb

mkdir -p "$here/../tests/data"
cp suzanne.glb "$here/suzanne.glb"
cp suzanne-draco.glb "$here/../tests/data/suzanne-draco.glb"
sha256sum "$here/suzanne.glb" "$here/../tests/data/suzanne-draco.glb"
