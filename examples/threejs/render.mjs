#!/usr/bin/env node
// Renders a glb with three.js in headless Chromium and writes the linear RGB result as an
// OpenEXR file, for `verity diff` against the oracle.
//
//   node render.mjs SCENE.glb OUT.exr --width W --height H
//        [--specular-aa on|off] [--energy-compensation on|off] [--fresnel-sg on|off]
//        [--flip-y] [--chromium PATH]
//
// The page (page.mjs) renders once with the glb's camera (aspect W/H) into a WebGL2 RGBA32F
// render target: one sample per pixel at the pixel centre, no MSAA, no tone mapping, no
// shadow maps, no ambient or environment light. The pixels come back through
// readRenderTargetPixels and are written as a single-part scanline EXR (exr.mjs).
//
// Row order: WebGL reads rows bottom-up, and that is what the EXR holds by default (its first
// scanline is the image's bottom row): compare it with `verity diff --flip-y`. --flip-y here
// writes the rows top-down instead (the usual orientation).
//
// Files are served to the page over a local HTTP server on 127.0.0.1 (an ephemeral port):
// Chromium refuses ES-module imports from file:// URLs. Only three/'s build and examples
// folders, page.mjs and the scene are served.

import { createServer } from 'node:http';
import { readFile, writeFile, stat } from 'node:fs/promises';
import { dirname, join, normalize, resolve, sep } from 'node:path';
import { fileURLToPath } from 'node:url';
import puppeteer from 'puppeteer-core';
import { encodeExr } from './exr.mjs';

const HERE = dirname(fileURLToPath(import.meta.url));
const THREE_ROOT = join(HERE, 'node_modules', 'three');

/**
 * Chromium flags. --no-sandbox: Chromium refuses to start as root without it (and container
 * sandboxes often lack the namespaces it needs). --use-angle=swiftshader with
 * --enable-unsafe-swiftshader: WebGL2 on ANGLE's Vulkan backend over SwiftShader, a CPU
 * implementation, whatever GPU the machine has, so every machine renders the same pixels;
 * it offers EXT_color_buffer_float (float render targets).
 */
export const CHROMIUM_FLAGS = [
  '--no-sandbox',
  '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader',
];

const USAGE =
  'usage: node render.mjs SCENE.glb OUT.exr --width W --height H ' +
  '[--specular-aa on|off] [--energy-compensation on|off] [--fresnel-sg on|off] [--flip-y] [--chromium PATH]';

function usage(message) {
  console.error(`render.mjs: ${message}\n${USAGE}`);
  process.exit(2);
}

function parseArgs(argv) {
  const opts = { specularAA: true, energyCompensation: true, fresnelSG: true, flipY: false, chromium: process.env.CHROMIUM || '/usr/bin/chromium' };
  const positional = [];
  const onOff = (flag, v) => (v === 'on' ? true : v === 'off' ? false : usage(`${flag} takes on or off, got ${v}`));
  const size = (flag, v) => {
    const n = Number(v);
    if (!Number.isInteger(n) || n < 1 || n > 8192) usage(`${flag} takes an integer in 1..=8192, got ${v}`);
    return n;
  };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    const value = () => (i + 1 < argv.length ? argv[++i] : usage(`${a} needs a value`));
    if (a === '--width') opts.width = size(a, value());
    else if (a === '--height') opts.height = size(a, value());
    else if (a === '--specular-aa') opts.specularAA = onOff(a, value());
    else if (a === '--energy-compensation') opts.energyCompensation = onOff(a, value());
    else if (a === '--fresnel-sg') opts.fresnelSG = onOff(a, value());
    else if (a === '--flip-y') opts.flipY = true;
    else if (a === '--chromium') opts.chromium = value();
    else if (a === '-h' || a === '--help') {
      console.log(USAGE);
      process.exit(0);
    } else if (a.startsWith('-')) usage(`unknown option ${a}`);
    else positional.push(a);
  }
  if (positional.length !== 2) usage('expected SCENE.glb and OUT.exr');
  if (opts.width === undefined || opts.height === undefined) usage('--width and --height are required');
  [opts.scene, opts.out] = positional;
  return opts;
}

const TYPES = { '.js': 'text/javascript', '.mjs': 'text/javascript', '.html': 'text/html', '.glb': 'model/gltf-binary' };

const PAGE = `<!doctype html>
<html><head><meta charset="utf-8"><link rel="icon" href="data:,">
<script type="importmap">
{ "imports": { "three": "/three/build/three.module.js", "three/addons/": "/three/examples/jsm/" } }
</script>
<script type="module">
import { render } from '/page.mjs';
window.verityRender = render;
window.verityReady = true;
</script>
</head><body></body></html>`;

/** Serves the page, page.mjs, three/build, three/examples/jsm and the scene at /scene.glb. */
function serve(scenePath) {
  const roots = [
    ['/three/build/', join(THREE_ROOT, 'build')],
    ['/three/examples/jsm/', join(THREE_ROOT, 'examples', 'jsm')],
  ];
  const server = createServer(async (req, res) => {
    const url = new URL(req.url, 'http://localhost').pathname;
    let file = null;
    if (url === '/') {
      res.writeHead(200, { 'content-type': TYPES['.html'] }).end(PAGE);
      return;
    }
    if (url === '/page.mjs') file = join(HERE, 'page.mjs');
    else if (url === '/scene.glb') file = scenePath;
    else
      for (const [prefix, dir] of roots)
        if (url.startsWith(prefix)) {
          const f = normalize(join(dir, decodeURIComponent(url.slice(prefix.length))));
          if (f.startsWith(dir + sep)) file = f;
        }
    try {
      if (!file) throw new Error('not served');
      const body = await readFile(file);
      const ext = file.slice(file.lastIndexOf('.'));
      res.writeHead(200, { 'content-type': TYPES[ext] || 'application/octet-stream' }).end(body);
    } catch {
      res.writeHead(404).end();
    }
  });
  return new Promise((ok, err) => {
    server.once('error', err);
    server.listen(0, '127.0.0.1', () => ok(server));
  });
}

async function main() {
  const opts = parseArgs(process.argv.slice(2));
  const scenePath = resolve(opts.scene);
  await stat(scenePath).catch(() => usage(`scene not found: ${opts.scene}`));
  await stat(THREE_ROOT).catch(() => {
    throw new Error(`three.js is not installed in ${THREE_ROOT}: run npm ci in ${HERE} (or scripts/setup.sh)`);
  });
  await stat(opts.chromium).catch(() => {
    throw new Error(`Chromium not found at ${opts.chromium}: apt-get install chromium (or scripts/setup.sh), or pass --chromium PATH`);
  });

  const t0 = Date.now();
  const server = await serve(scenePath);
  const origin = `http://127.0.0.1:${server.address().port}`;
  let browser;
  try {
    browser = await puppeteer.launch({ executablePath: opts.chromium, headless: true, args: CHROMIUM_FLAGS, timeout: 60_000 });
    const page = await browser.newPage();
    const problems = [];
    page.on('console', (m) => {
      if (m.type() === 'error' || m.type() === 'warn' || m.type() === 'warning') problems.push(`console.${m.type()}: ${m.text()}`);
    });
    page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
    page.on('requestfailed', (r) => problems.push(`request failed: ${r.url()}`));
    page.on('response', (r) => {
      if (r.status() >= 400) problems.push(`HTTP ${r.status()}: ${r.url()}`);
    });
    await page.goto(`${origin}/`, { waitUntil: 'load' });
    await page.waitForFunction('window.verityReady === true', { timeout: 30_000 }).catch(() => {
      throw new Error(`the page did not load three.js: ${problems.join('; ') || 'no message'}`);
    });
    const result = await page.evaluate(
      (args) => window.verityRender(args),
      { url: `${origin}/scene.glb`, width: opts.width, height: opts.height, specularAA: opts.specularAA, energyCompensation: opts.energyCompensation, fresnelSG: opts.fresnelSG },
    );
    // Any warning or error from three.js or WebGL (e.g. an unreadable render target) fails the
    // render: its pixels would not be what the flags say.
    if (problems.length) throw new Error(`the page reported problems:\n  ${problems.join('\n  ')}`);

    const rgba = new Float32Array(new Uint8Array(Buffer.from(result.pixels, 'base64')).buffer);
    if (rgba.length !== opts.width * opts.height * 4) throw new Error(`read back ${rgba.length} floats, expected ${opts.width * opts.height * 4}`);
    await writeFile(opts.out, encodeExr(rgba, opts.width, opts.height, { flipY: opts.flipY }));
    const i = result.info;
    console.log(
      `render.mjs: three.js r${i.three} on ${i.gl}: ${opts.width}x${opts.height}, specular AA ${opts.specularAA ? 'on' : 'off'}, ` +
        `energy compensation ${opts.energyCompensation ? 'on' : 'off'}, SG Fresnel ${opts.fresnelSG ? 'on' : 'off'}, rows ${opts.flipY ? 'top-down' : 'bottom-up (WebGL order)'} -> ${opts.out} ` +
        `(draw+readback ${i.renderMs.toFixed(0)} ms, total ${((Date.now() - t0) / 1000).toFixed(1)} s)`,
    );
  } finally {
    if (browser) await browser.close();
    server.close();
  }
}

main().catch((e) => {
  console.error(`render.mjs: ${e.message}`);
  process.exit(1);
});
