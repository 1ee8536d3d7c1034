// Runs in the browser page (served by render.mjs): loads the glb with three.js's GLTFLoader,
// renders it once with the glb's camera into an RGBA32F render target (no tone mapping, no
// MSAA, no shadows, no ambient or environment light) and returns the pixels.
//
// The switches (specular anti-aliasing, energy compensation, spherical-Gaussian Fresnel) patch
// three.js r187's shader chunks through material.onBeforeCompile; every patch asserts that the
// text it replaces is there, so a three.js that changed the chunk fails here instead of
// rendering something else (README.md, "What the switches patch").

import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

/** The text each switch removes, exactly as three.js r187 writes it. */
export const PATCHES = {
  // src/renderers/shaders/ShaderChunk/lights_physical_fragment.glsl.js:13 — geometric
  // specular anti-aliasing: roughness widened by the screen-space derivatives of the normal
  // (lines 7–8 compute geometryRoughness from dFdx/dFdy of nonPerturbedNormal).
  specularAA: {
    chunk: 'lights_physical_fragment',
    find: 'material.roughness += geometryRoughness;',
    replace: '/* verity: --specular-aa off */',
  },
  // src/renderers/shaders/ShaderChunk/lights_fragment_begin.glsl.js:73 — multiple-scattering
  // energy compensation of the direct (punctual) specular lobe, applied in
  // lights_physical_pars_fragment.glsl.js:595 (RE_Direct_Physical).
  energyCompensation: {
    chunk: 'lights_fragment_begin',
    find: 'material.multiScatteringCompensation = 1.0 + material.specularColorBlended * ( 1.0 / EssMs - 1.0 );',
    replace: 'material.multiScatteringCompensation = vec3( 1.0 ); /* verity: --energy-compensation off */',
  },
  // src/renderers/shaders/ShaderChunk/common.glsl.js:116 and :129 — F_Schlick (vec3 and float)
  // evaluates (1 − cos θ)⁵ with Epic's spherical-Gaussian fit exp2((−5.55473c − 6.98316)c);
  // off: Schlick's polynomial, which the glTF specification (Appendix B) and the oracle use.
  fresnelSG: {
    chunk: 'common',
    find: 'float fresnel = exp2( ( - 5.55473 * dotVH - 6.98316 ) * dotVH );',
    count: 2,
    replace: 'float fresnel = pow4( 1.0 - dotVH ) * ( 1.0 - dotVH ); /* verity: --fresnel-sg off */',
  },
};

function fail(message) {
  throw new Error(message);
}

/** Inlines `#include <chunk>` with the patched chunk; asserts that the include is found once
 * and `find` exactly `count` times. */
function patchShader(source, { chunk, find, replace, count = 1 }) {
  const include = `#include <${chunk}>`;
  const text = THREE.ShaderChunk[chunk];
  if (typeof text !== 'string') fail(`three.js ${THREE.REVISION} has no shader chunk ${chunk}`);
  if (source.split(include).length !== 2) fail(`fragment shader does not include <${chunk}> exactly once`);
  if (text.split(find).length !== count + 1)
    fail(`three.js ${THREE.REVISION}: ShaderChunk.${chunk} no longer contains, exactly ${count} time(s): ${find}`);
  return source.replace(include, () => text.split(find).join(replace));
}

/**
 * Renders `url` at width × height; returns { pixels: base64 of RGBA float32, rows bottom-up
 * as WebGL reads them, info }.
 */
export async function render({ url, width, height, specularAA, energyCompensation, fresnelSG }) {
  const canvas = document.createElement('canvas');
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: false, alpha: false, depth: true, stencil: false });
  const shaderErrors = [];
  renderer.debug.checkShaderErrors = true;
  renderer.debug.onShaderError = (gl, program, vs, fs) => {
    shaderErrors.push(`${gl.getProgramInfoLog(program)} ${gl.getShaderInfoLog(vs)} ${gl.getShaderInfoLog(fs)}`);
  };
  renderer.setPixelRatio(1);
  renderer.setSize(width, height, false);
  renderer.toneMapping = THREE.NoToneMapping;
  renderer.shadowMap.enabled = false;
  renderer.setClearColor(0x000000, 1);
  const gl = renderer.getContext();
  if (!(gl instanceof WebGL2RenderingContext)) fail('no WebGL2 context');
  if (!renderer.extensions.has('EXT_color_buffer_float'))
    fail('EXT_color_buffer_float is missing: no float render targets (see README.md for Chromium flags)');

  const gltf = await new GLTFLoader().loadAsync(url);
  const scene = gltf.scene;
  scene.background = null;
  scene.environment = null;
  const camera = gltf.cameras[0] ?? fail('the glb has no camera');
  if (!camera.isPerspectiveCamera) fail('the glb camera is not perspective');
  camera.aspect = width / height;
  camera.updateProjectionMatrix();

  // Only the glb's punctual lights, unshadowed; only MeshStandardMaterial, patched.
  const patches = [];
  if (!specularAA) patches.push(PATCHES.specularAA);
  if (!energyCompensation) patches.push(PATCHES.energyCompensation);
  if (!fresnelSG) patches.push(PATCHES.fresnelSG);
  const cacheKey = `verity-aa-${specularAA}-ec-${energyCompensation}-sg-${fresnelSG}`;
  const materials = new Set();
  const compiled = new Set();
  const lights = [];
  scene.traverse((o) => {
    if (o.isLight) {
      if (!(o.isPointLight || o.isSpotLight || o.isDirectionalLight)) fail(`unexpected light ${o.type} ${o.name}`);
      o.castShadow = false;
      lights.push({ name: o.name, type: o.type, intensity: o.intensity, decay: o.decay, distance: o.distance });
    }
    if (o.isMesh) {
      o.castShadow = false;
      o.receiveShadow = false;
      const m = o.material;
      if (!m.isMeshStandardMaterial || m.isMeshPhysicalMaterial)
        fail(`${o.name}: material ${m.name} is ${m.type}, expected MeshStandardMaterial`);
      if (m.envMap || m.lightMap || m.aoMap || m.emissiveMap || m.map || m.normalMap || m.emissive.getHex() !== 0)
        fail(`${o.name}: material ${m.name} has maps or emission this example does not expect`);
      m.onBeforeCompile = (shader) => {
        for (const p of patches) shader.fragmentShader = patchShader(shader.fragmentShader, p);
        compiled.add(m.uuid);
      };
      m.customProgramCacheKey = () => cacheKey;
      m.needsUpdate = true;
      materials.add(m);
    }
  });
  if (lights.length === 0) fail('the glb has no KHR_lights_punctual light');

  const target = new THREE.WebGLRenderTarget(width, height, {
    type: THREE.FloatType,
    format: THREE.RGBAFormat,
    samples: 0,
    depthBuffer: true,
    stencilBuffer: false,
    minFilter: THREE.NearestFilter,
    magFilter: THREE.NearestFilter,
    generateMipmaps: false,
  });
  renderer.setRenderTarget(target);
  renderer.clear();
  const t0 = performance.now();
  renderer.render(scene, camera);
  const pixels = new Float32Array(width * height * 4);
  renderer.readRenderTargetPixels(target, 0, 0, width, height, pixels);
  const renderMs = performance.now() - t0;
  renderer.setRenderTarget(null);

  if (shaderErrors.length) fail(`shader errors: ${shaderErrors.join('\n')}`);
  for (const m of materials) if (!compiled.has(m.uuid)) fail(`material ${m.name} was not compiled through the patch`);
  const lost = gl.getError();
  if (lost !== gl.NO_ERROR) fail(`WebGL error 0x${lost.toString(16)}`);

  // Float32Array → base64, in slices (String.fromCharCode takes a bounded argument list).
  const bytes = new Uint8Array(pixels.buffer);
  let bin = '';
  for (let i = 0; i < bytes.length; i += 0x8000) bin += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
  const dbg = gl.getExtension('WEBGL_debug_renderer_info');
  return {
    pixels: btoa(bin),
    info: {
      three: THREE.REVISION,
      gl: dbg ? gl.getParameter(dbg.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER),
      materials: [...materials].map((m) => ({ name: m.name, metalness: m.metalness, roughness: m.roughness })),
      lights,
      camera: { fov: camera.fov, aspect: camera.aspect, near: camera.near, far: camera.far },
      patches: patches.map((p) => `${p.chunk}: ${p.find}`),
      renderMs,
    },
  };
}
