// The simplified surfaces `trephine view` writes for a skull's blocks (.tri):
// "TRI1", uint32 point and triangle counts, float32 points (mm), uint32
// corners; little-endian.
export class TriangleFile {
  constructor(bytes, name) {
    this.name = name;
    const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    const magic = String.fromCharCode(bytes[0], bytes[1], bytes[2], bytes[3]);
    if (bytes.length < 12 || magic !== 'TRI1') throw new Error(`${name}: not a TRI1 surface`);
    const points = view.getUint32(4, true);
    const triangles = view.getUint32(8, true);
    if (bytes.length !== 12 + 12 * points + 12 * triangles)
      throw new Error(`${name}: ${bytes.length} bytes for ${points} points and ${triangles} triangles`);
    // Aligned copies (the file's arrays start at byte 12).
    const copy = bytes.slice(12);
    this.points = new Float32Array(copy.buffer, 0, 3 * points);
    this.triangles = new Uint32Array(copy.buffer, 12 * points, 3 * triangles);
  }

  surface() {
    return { points: this.points, triangles: this.triangles };
  }
}
