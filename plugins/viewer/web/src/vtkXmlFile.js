// Reads the VTK XML files trephine writes (and any VTK XML file whose arrays
// are appended raw, zlib-compressed or not, with UInt32 or UInt64 headers):
// the .vtu of a brain, the .vtp of a tool or of a skull block. Arrays are
// decoded when asked for, so a frame whose topology is known reads its points
// only.
import { unzlibSync } from 'fflate';

const kTypes = {
  Float32: Float32Array,
  Float64: Float64Array,
  Int8: Int8Array,
  UInt8: Uint8Array,
  Int16: Int16Array,
  UInt16: Uint16Array,
  Int32: Int32Array,
  UInt32: Uint32Array,
  Int64: BigInt64Array,
  UInt64: BigUint64Array,
};

function indexOfBytes(bytes, text, from = 0) {
  const codes = Array.from(text, (c) => c.charCodeAt(0));
  outer: for (let i = from; i + codes.length <= bytes.length; ++i) {
    for (let j = 0; j < codes.length; ++j) if (bytes[i + j] !== codes[j]) continue outer;
    return i;
  }
  return -1;
}

export class VtkXmlFile {
  // `bytes`: the whole file; `name`: for the messages.
  constructor(bytes, name) {
    this.name = name;
    this.bytes = bytes;
    const appended = indexOfBytes(bytes, '<AppendedData');
    const headerEnd = appended >= 0 ? appended : bytes.length;
    let text = new TextDecoder().decode(bytes.subarray(0, headerEnd));
    if (appended >= 0) text += '</VTKFile>';
    const document = new DOMParser().parseFromString(text, 'application/xml');
    const failure = document.querySelector('parsererror');
    if (failure) throw new Error(`${name}: not VTK XML (${failure.textContent.slice(0, 120)})`);
    this.root = document.documentElement;
    this.type = this.root.getAttribute('type');
    this.compressed = this.root.getAttribute('compressor') === 'vtkZLibDataCompressor';
    this.header64 = this.root.getAttribute('header_type') === 'UInt64';
    if (this.root.getAttribute('byte_order') === 'BigEndian') throw new Error(`${name}: big-endian files are not read`);
    this.binaryStart = -1;
    if (appended >= 0) {
      const underscore = bytes.indexOf('_'.charCodeAt(0), appended);
      if (underscore < 0) throw new Error(`${name}: AppendedData without its '_' marker`);
      this.binaryStart = underscore + 1;
    }
    this.piece = this.root.querySelector('Piece');
  }

  count(attribute) {
    return this.piece ? Number(this.piece.getAttribute(attribute) || 0) : 0;
  }

  // The DataArray element under `section` (e.g. 'Points', 'PointData',
  // 'Cells') named `arrayName` (or the first when null).
  element(section, arrayName = null) {
    const parent = this.piece && this.piece.querySelector(`:scope > ${section}`);
    if (!parent) return null;
    for (const array of parent.querySelectorAll(':scope > DataArray')) {
      if (arrayName === null || array.getAttribute('Name') === arrayName) return array;
    }
    return null;
  }

  // The typed array of that DataArray, or null when the file has none.
  array(section, arrayName = null) {
    const element = this.element(section, arrayName);
    if (!element) return null;
    const Type = kTypes[element.getAttribute('type')];
    if (!Type) throw new Error(`${this.name}: ${section}/${arrayName}: unknown type ${element.getAttribute('type')}`);
    if (element.getAttribute('format') !== 'appended' || this.binaryStart < 0) {
      throw new Error(`${this.name}: ${section}/${arrayName}: only appended raw arrays are read`);
    }
    const bytes = this.decode(this.binaryStart + Number(element.getAttribute('offset')));
    return new Type(bytes.buffer, bytes.byteOffset, bytes.byteLength / Type.BYTES_PER_ELEMENT);
  }

  readHeader(view, at) {
    return this.header64 ? Number(view.getBigUint64(at, true)) : view.getUint32(at, true);
  }

  // The bytes of the array that starts at `start`: its header, then the data
  // (uncompressed) or the zlib blocks.
  decode(start) {
    const bytes = this.bytes;
    const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    const word = this.header64 ? 8 : 4;
    const fail = (what) => {
      throw new Error(`${this.name}: array at byte ${start}: ${what}`);
    };
    if (start + word > bytes.length) fail('past the end of the file');
    if (!this.compressed) {
      const size = this.readHeader(view, start);
      if (start + word + size > bytes.length) fail('its data run past the end of the file');
      return bytes.slice(start + word, start + word + size);  // aligned copy
    }
    const blocks = this.readHeader(view, start);
    const blockSize = this.readHeader(view, start + word);
    const lastSize = this.readHeader(view, start + 2 * word);
    if (start + (3 + blocks) * word > bytes.length) fail('its block sizes run past the end of the file');
    const total = blocks === 0 ? 0 : (blocks - 1) * blockSize + (lastSize || blockSize);
    const out = new Uint8Array(total);
    let at = start + (3 + blocks) * word;
    for (let b = 0; b < blocks; ++b) {
      const compressedSize = this.readHeader(view, start + (3 + b) * word);
      if (at + compressedSize > bytes.length) fail(`block ${b} runs past the end of the file`);
      const block = unzlibSync(bytes.subarray(at, at + compressedSize));
      out.set(block, b * blockSize);
      at += compressedSize;
    }
    return out;
  }
}

// Base64 to bytes (Uint8Array.fromBase64 where the browser has it).
export function bytesFromBase64(text) {
  if (typeof Uint8Array.fromBase64 === 'function') return Uint8Array.fromBase64(text);
  const binary = atob(text);
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; ++i) bytes[i] = binary.charCodeAt(i);
  return bytes;
}
