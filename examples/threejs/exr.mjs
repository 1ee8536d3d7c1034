// A minimal OpenEXR writer: single-part scanline file, NO_COMPRESSION, FLOAT channels B, G, R
// (alphabetical, as the format requires), one scanline per block.
//
// Layout (OpenEXR "File Layout" / "The OpenEXR File Layout" document):
//   magic 20000630 (76 2f 31 01), version field 2 (single-part scanline, short names),
//   header: attributes `name\0 type\0 size:int32 value`, ended by a 0 byte; the required
//   ones are written: channels (chlist), compression, dataWindow, displayWindow, lineOrder,
//   pixelAspectRatio, screenWindowCenter, screenWindowWidth;
//   offset table: one uint64 per scanline block, the block's byte position in the file;
//   blocks: y (int32), data size (int32), then each channel's row of samples in channel order.
// Everything is little-endian.

const MAGIC = 20000630;
const VERSION = 2;
const FLOAT = 2; // pixel type: UINT 0, HALF 1, FLOAT 2
const NO_COMPRESSION = 0;
const INCREASING_Y = 0;
const CHANNELS = ['B', 'G', 'R']; // offsets into an RGBA pixel: R 0, G 1, B 2
const OFFSET = { R: 0, G: 1, B: 2 };

function attribute(name, type, value) {
  const head = Buffer.from(`${name}\0${type}\0`, 'latin1');
  const size = Buffer.alloc(4);
  size.writeInt32LE(value.length);
  return Buffer.concat([head, size, value]);
}

function int32s(...xs) {
  const b = Buffer.alloc(4 * xs.length);
  xs.forEach((x, i) => b.writeInt32LE(x, 4 * i));
  return b;
}

function float32s(...xs) {
  const b = Buffer.alloc(4 * xs.length);
  xs.forEach((x, i) => b.writeFloatLE(x, 4 * i));
  return b;
}

/**
 * EXR bytes of a width × height image given as RGBA float32, row 0 first. With flipY the
 * rows are written in reverse order (WebGL's bottom-up rows become top-down). Alpha is
 * dropped.
 */
export function encodeExr(rgba, width, height, { flipY = false } = {}) {
  if (rgba.length !== width * height * 4) throw new Error('encodeExr: pixel count does not match width × height');
  const chlist = Buffer.concat([
    ...CHANNELS.map((c) =>
      Buffer.concat([Buffer.from(`${c}\0`, 'latin1'), int32s(FLOAT), Buffer.from([0, 0, 0, 0]), int32s(1, 1)]),
    ),
    Buffer.from([0]),
  ]);
  const box = int32s(0, 0, width - 1, height - 1);
  const header = Buffer.concat([
    int32s(MAGIC, VERSION),
    attribute('channels', 'chlist', chlist),
    attribute('compression', 'compression', Buffer.from([NO_COMPRESSION])),
    attribute('dataWindow', 'box2i', box),
    attribute('displayWindow', 'box2i', box),
    attribute('lineOrder', 'lineOrder', Buffer.from([INCREASING_Y])),
    attribute('pixelAspectRatio', 'float', float32s(1)),
    attribute('screenWindowCenter', 'v2f', float32s(0, 0)),
    attribute('screenWindowWidth', 'float', float32s(1)),
    Buffer.from([0]),
  ]);
  const rowBytes = width * CHANNELS.length * 4;
  const blockBytes = 8 + rowBytes;
  const tableBytes = 8 * height;
  const out = Buffer.alloc(header.length + tableBytes + height * blockBytes);
  header.copy(out, 0);
  const first = header.length + tableBytes;
  for (let y = 0; y < height; y++) {
    out.writeBigUInt64LE(BigInt(first + y * blockBytes), header.length + 8 * y);
    const at = first + y * blockBytes;
    out.writeInt32LE(y, at);
    out.writeInt32LE(rowBytes, at + 4);
    const src = flipY ? height - 1 - y : y;
    let p = at + 8;
    for (const c of CHANNELS)
      for (let x = 0; x < width; x++, p += 4) out.writeFloatLE(rgba[4 * (src * width + x) + OFFSET[c]], p);
  }
  return out;
}
