#!/usr/bin/env node
// Writes the example's glTF 2.0 binary (.glb): a ground quad, a cube, a metal sphere and a
// dielectric sphere, one KHR_lights_punctual point light and a perspective camera.
//
//   node make-scene.mjs OUT.glb
//
// Plain Node, no dependencies: the JSON chunk and the BIN chunk are assembled here (glTF 2.0
// §4.4 "GLB File Format Specification"). The output is deterministic: the same bytes on every
// run (every number goes through a Float32Array; Math.sin/cos are V8's fdlibm ports).
//
// Conventions (glTF 2.0 §3.4, §3.10, KHR_lights_punctual): +Y up, metres, right-handed; a
// camera looks down its node's −Z with +Y up; a point light's intensity is in candela and
// falls off with the inverse square of the distance (no `range`); base colours are linear.
// Every mesh, node and material is named; the names become Verity's shape names
// (`sphere_metal/0`, …) and three.js's object names.

import { writeFileSync } from 'node:fs';
import { pathToFileURL } from 'node:url';

// ---- The scene, in numbers ------------------------------------------------------------

/** UV-sphere tessellation: segments around the axis, rings from pole to pole. */
export const SPHERE_SEGMENTS = 64;
export const SPHERE_RINGS = 32;

const MATERIALS = [
  // name, baseColorFactor (linear RGB), metallic, roughness
  { name: 'ground_grey', color: [0.5, 0.5, 0.5], metallic: 0, roughness: 1 },
  { name: 'cube_blue', color: [0.18, 0.36, 0.72], metallic: 0, roughness: 0.8 },
  { name: 'metal_copper', color: [0.95, 0.64, 0.54], metallic: 1, roughness: 0.3 },
  { name: 'plastic_red', color: [0.75, 0.16, 0.12], metallic: 0, roughness: 0.5 },
];

const CAMERA = {
  eye: [0.35, 1.45, 3.4],
  target: [0.1, 0.45, 0],
  yfov: (40 * Math.PI) / 180,
  aspectRatio: 4 / 3,
  znear: 0.1,
  zfar: 100,
};

// The light stands behind the group, up and to the right: seen from the camera, the metal
// sphere's highlight sits near its top rim, where the view and light directions are ~114°
// apart (cos θ ≈ 0.55 at the half vector). There the single-scattering GGX lobe of roughness
// 0.3 loses a few per cent of its energy, so three.js's energy compensation is visible; a
// light beside the camera would put the highlight at cos θ ≈ 0.95, where it is ~1 %.
// 120 cd puts the lit ground near 1 (linear), away from relMSE's 0.01 regulariser.
const LIGHT = { name: 'key_light', position: [0.9, 2.8, -2.0], color: [1.0, 0.94, 0.86], intensity: 120 };

// ---- Geometry -------------------------------------------------------------------------

/** Axis-aligned quad in the y = 0 plane, front face (+Y) up, half-size h. */
function groundQuad(h) {
  const positions = [-h, 0, -h, -h, 0, h, h, 0, h, h, 0, -h];
  const normals = [0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0];
  // Counter-clockwise seen from +Y (glTF front faces wind counter-clockwise).
  const indices = [0, 1, 2, 0, 2, 3];
  return { positions, normals, indices };
}

/** Cube of side s centred on the origin, flat faces (4 vertices each, outward normals). */
function cube(s) {
  const h = s / 2;
  const positions = [];
  const normals = [];
  const indices = [];
  // Each face: normal n, and two in-plane axes u, v with u × v = n (so u, v, −u, −v corners
  // wind counter-clockwise seen from outside).
  const faces = [
    { n: [1, 0, 0], u: [0, 1, 0], v: [0, 0, 1] },
    { n: [-1, 0, 0], u: [0, 0, 1], v: [0, 1, 0] },
    { n: [0, 1, 0], u: [0, 0, 1], v: [1, 0, 0] },
    { n: [0, -1, 0], u: [1, 0, 0], v: [0, 0, 1] },
    { n: [0, 0, 1], u: [1, 0, 0], v: [0, 1, 0] },
    { n: [0, 0, -1], u: [0, 1, 0], v: [1, 0, 0] },
  ];
  for (const { n, u, v } of faces) {
    const base = positions.length / 3;
    for (const [a, b] of [[-1, -1], [1, -1], [1, 1], [-1, 1]]) {
      for (let k = 0; k < 3; k++) positions.push(h * (n[k] + a * u[k] + b * v[k]));
      normals.push(...n);
    }
    indices.push(base, base + 1, base + 2, base, base + 2, base + 3);
  }
  return { positions, normals, indices };
}

/** UV sphere of radius r centred on the origin, smooth (per-vertex, exact) normals. The
 * pole rings are triangle fans (no zero-area triangles). */
function uvSphere(r, segments, rings) {
  const positions = [];
  const normals = [];
  const indices = [];
  for (let j = 0; j <= rings; j++) {
    const theta = (j * Math.PI) / rings; // from +Y
    for (let i = 0; i <= segments; i++) {
      const phi = (i * 2 * Math.PI) / segments;
      const n = [Math.sin(theta) * Math.sin(phi), Math.cos(theta), Math.sin(theta) * Math.cos(phi)];
      if (j === 0 || j === rings) n[0] = n[2] = 0; // exact poles
      normals.push(...n);
      positions.push(r * n[0], r * n[1], r * n[2]);
    }
  }
  const row = segments + 1;
  for (let j = 0; j < rings; j++) {
    for (let i = 0; i < segments; i++) {
      const a = j * row + i; // (theta_j, phi_i)
      const b = a + 1; // (theta_j, phi_i+1)
      const c = a + row; // (theta_j+1, phi_i)
      const d = c + 1; // (theta_j+1, phi_i+1)
      // Seen from outside, increasing phi runs to the right (towards +X from +Z) and
      // increasing theta runs down, so a → c → d → b is counter-clockwise.
      if (j !== 0) indices.push(a, c, b);
      if (j !== rings - 1) indices.push(b, c, d);
    }
  }
  return { positions, normals, indices };
}

// ---- Small vector helpers -----------------------------------------------------------------

const sub = (a, b) => a.map((x, i) => x - b[i]);
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const normalize = (a) => {
  const l = Math.hypot(...a);
  return a.map((x) => x / l);
};

/** Unit quaternion [x, y, z, w] of the rotation whose matrix has columns x, y, z. */
function quatFromBasis(x, y, z) {
  const [m00, m10, m20] = x;
  const [m01, m11, m21] = y;
  const [m02, m12, m22] = z;
  const tr = m00 + m11 + m22;
  let q;
  if (tr > 0) {
    const s = Math.sqrt(tr + 1) * 2;
    q = [(m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s, s / 4];
  } else if (m00 > m11 && m00 > m22) {
    const s = Math.sqrt(1 + m00 - m11 - m22) * 2;
    q = [s / 4, (m01 + m10) / s, (m02 + m20) / s, (m21 - m12) / s];
  } else if (m11 > m22) {
    const s = Math.sqrt(1 + m11 - m00 - m22) * 2;
    q = [(m01 + m10) / s, s / 4, (m12 + m21) / s, (m02 - m20) / s];
  } else {
    const s = Math.sqrt(1 + m22 - m00 - m11) * 2;
    q = [(m02 + m20) / s, (m12 + m21) / s, s / 4, (m10 - m01) / s];
  }
  return normalize(q);
}

/** The camera node's rotation: −Z towards the target, +Y as close to world up as possible. */
function lookAtRotation(eye, target) {
  const z = normalize(sub(eye, target)); // the camera looks down −Z
  const x = normalize(cross([0, 1, 0], z));
  const y = cross(z, x);
  return quatFromBasis(x, y, z);
}

/** Rotation by `deg` degrees about +Y, as a quaternion. */
function yRotation(deg) {
  const h = (deg * Math.PI) / 360;
  return [0, Math.sin(h), 0, Math.cos(h)];
}

// ---- glTF assembly ------------------------------------------------------------------------

const f32 = (xs) => Array.from(new Float32Array(xs));

/** Builds the glTF JSON and the binary buffer. */
export function buildScene() {
  const chunks = []; // Uint8Array pieces of the BIN chunk
  let binLength = 0;
  const json = {
    asset: { version: '2.0', generator: 'verity examples/threejs/make-scene.mjs' },
    extensionsUsed: ['KHR_lights_punctual'],
    extensions: {
      KHR_lights_punctual: {
        lights: [{ name: LIGHT.name, type: 'point', color: f32(LIGHT.color), intensity: LIGHT.intensity }],
      },
    },
    scene: 0,
    scenes: [{ name: 'verity_threejs', nodes: [] }],
    nodes: [],
    meshes: [],
    materials: MATERIALS.map((m) => ({
      name: m.name,
      pbrMetallicRoughness: {
        baseColorFactor: [...f32(m.color), 1],
        metallicFactor: m.metallic,
        roughnessFactor: m.roughness,
      },
    })),
    cameras: [
      {
        name: 'camera',
        type: 'perspective',
        perspective: {
          yfov: f32([CAMERA.yfov])[0],
          aspectRatio: f32([CAMERA.aspectRatio])[0],
          znear: CAMERA.znear,
          zfar: CAMERA.zfar,
        },
      },
    ],
    buffers: [],
    bufferViews: [],
    accessors: [],
  };

  /** Appends a typed array to the BIN chunk as one buffer view (4-byte aligned). */
  function view(typed, target) {
    const bytes = new Uint8Array(typed.buffer, typed.byteOffset, typed.byteLength);
    const offset = binLength;
    chunks.push(bytes);
    binLength += bytes.length;
    const pad = (4 - (binLength % 4)) % 4;
    if (pad) {
      chunks.push(new Uint8Array(pad));
      binLength += pad;
    }
    json.bufferViews.push({ buffer: 0, byteOffset: offset, byteLength: bytes.length, target });
    return json.bufferViews.length - 1;
  }

  function vec3Accessor(values, withBounds) {
    const data = new Float32Array(values);
    const acc = { bufferView: view(data, 34962), componentType: 5126, count: data.length / 3, type: 'VEC3' };
    if (withBounds) {
      const min = [Infinity, Infinity, Infinity];
      const max = [-Infinity, -Infinity, -Infinity];
      for (let i = 0; i < data.length; i++) {
        min[i % 3] = Math.min(min[i % 3], data[i]);
        max[i % 3] = Math.max(max[i % 3], data[i]);
      }
      acc.min = min;
      acc.max = max;
    }
    json.accessors.push(acc);
    return json.accessors.length - 1;
  }

  function indexAccessor(values) {
    const data = new Uint16Array(values);
    if (Math.max(...values) >= 65535) throw new Error('too many vertices for 16-bit indices');
    json.accessors.push({ bufferView: view(data, 34963), componentType: 5123, count: data.length, type: 'SCALAR' });
    return json.accessors.length - 1;
  }

  function addNode(node) {
    json.nodes.push(node);
    json.scenes[0].nodes.push(json.nodes.length - 1);
  }

  function addMesh(name, material, geom, node) {
    const materialIndex = MATERIALS.findIndex((m) => m.name === material);
    json.meshes.push({
      name,
      primitives: [
        {
          attributes: { POSITION: vec3Accessor(geom.positions, true), NORMAL: vec3Accessor(geom.normals, false) },
          indices: indexAccessor(geom.indices),
          material: materialIndex,
          mode: 4,
        },
      ],
    });
    addNode({ name, mesh: json.meshes.length - 1, ...node });
  }

  addMesh('ground', 'ground_grey', groundQuad(4), {});
  addMesh('cube', 'cube_blue', cube(0.6), { translation: [-1.15, 0.3, -0.5], rotation: f32(yRotation(30)) });
  addMesh('sphere_metal', 'metal_copper', uvSphere(0.55, SPHERE_SEGMENTS, SPHERE_RINGS), { translation: [0, 0.55, 0] });
  addMesh('sphere_plastic', 'plastic_red', uvSphere(0.4, SPHERE_SEGMENTS, SPHERE_RINGS), { translation: [1.2, 0.4, -0.6] });
  addNode({ name: 'camera', camera: 0, translation: CAMERA.eye, rotation: f32(lookAtRotation(CAMERA.eye, CAMERA.target)) });
  addNode({ name: LIGHT.name, translation: LIGHT.position, extensions: { KHR_lights_punctual: { light: 0 } } });

  json.buffers.push({ byteLength: binLength });
  const bin = new Uint8Array(binLength);
  let at = 0;
  for (const c of chunks) {
    bin.set(c, at);
    at += c.length;
  }
  return { json, bin };
}

/** The GLB container: 12-byte header, JSON chunk (space-padded), BIN chunk (zero-padded). */
export function glb(json, bin) {
  const text = Buffer.from(JSON.stringify(json), 'utf8');
  const jsonLen = Math.ceil(text.length / 4) * 4;
  const binLen = Math.ceil(bin.length / 4) * 4;
  const total = 12 + 8 + jsonLen + 8 + binLen;
  const out = Buffer.alloc(total, 0);
  out.writeUInt32LE(0x46546c67, 0); // "glTF"
  out.writeUInt32LE(2, 4);
  out.writeUInt32LE(total, 8);
  out.writeUInt32LE(jsonLen, 12);
  out.writeUInt32LE(0x4e4f534a, 16); // "JSON"
  text.copy(out, 20);
  out.fill(0x20, 20 + text.length, 20 + jsonLen);
  const b = 20 + jsonLen;
  out.writeUInt32LE(binLen, b);
  out.writeUInt32LE(0x004e4942, b + 4); // "BIN\0"
  out.set(bin, b + 8);
  return out;
}

if (process.argv[1] && import.meta.url === pathToFileURL(process.argv[1]).href) {
  const outPath = process.argv[2];
  if (!outPath || process.argv.length !== 3) {
    console.error('usage: node make-scene.mjs OUT.glb');
    process.exit(2);
  }
  const { json, bin } = buildScene();
  writeFileSync(outPath, glb(json, bin));
  console.log(`wrote ${outPath}`);
}
