// A run's data as `trephine view` wrote it next to the viewer (runs side by
// side: run K's in data/run_K/, all manifests in data/manifest.js):
//   data/manifest.js   window.trephineRuns[K] = {name, source, folder,
//     parts:  [{name, kind: 'mesh' | 'tool' | 'polydata' | 'blocks', states}]
//             a state is a file; for 'blocks' (a .vtm of blocks) it is
//             {file, changes: [[block, file or ''], ...], still: [...]} against
//             the state before (still: the finer level, drawn when still);
//     frames: [{t (s), states: [per part: its state, -1 before its first]}],
//     files:  {file: chunk}, plots: {t, force, penetration} or null}
//   a mesh part has ranges {displacement (mm), force (N), von_mises (kPa)}:
//   the largest of each over the run; a blocks part may have a volume
//   {density: file, removed: file} (skullVolume.js reads them);
//   summary: the run's summary.json, as a string (its events).
//   data/FOLDER/chunk_N.js  trephineChunk(K, N, {"vtk/brain_00012.vtu": "<base64>", ...})
// Chunks are scripts, not fetched files, so that the viewer opens from the
// disk (file://) with nothing installed and no server.
import { VtkXmlFile, bytesFromBase64 } from './vtkXmlFile.js';
import { TriangleFile } from './triangleFile.js';

export class RunData {
  constructor(manifest, index = 0) {
    this.manifest = manifest;
    this.encoded = new Map();  // file -> base64, until decoded
    this.files = new Map();    // file -> VtkXmlFile
    this.chunkLoads = new Map();  // chunk -> Promise
    this.chunkArrived = new Map();  // chunk -> resolve
    // Every block state's files, accumulated from the changes.
    for (const part of manifest.parts) {
      if (part.kind !== 'blocks') continue;
      let blocks = [];
      let still = [];
      for (const state of part.states) {
        blocks = blocks.slice();
        for (const [block, file] of state.changes) blocks[block] = file;
        state.blocks = blocks.filter((file) => file);
        still = still.slice();
        for (const [block, file] of state.still || []) still[block] = file;
        state.stillBlocks = still.filter((file) => file);
      }
    }
    // Chunks call trephineChunk(run, chunk, files): to that run's data.
    window.trephineChunkTargets = window.trephineChunkTargets || [];
    window.trephineChunkTargets[index] = this;
    window.trephineChunk = (run, chunk, files) => {
      const target = window.trephineChunkTargets[run];
      if (target) target.arrive(chunk, files);
    };
  }

  arrive(chunk, files) {
    for (const [name, text] of Object.entries(files)) this.encoded.set(name, text);
    const resolve = this.chunkArrived.get(chunk);
    if (resolve) resolve();
  }

  get frames() {
    return this.manifest.frames;
  }

  loadChunk(chunk) {
    let load = this.chunkLoads.get(chunk);
    if (!load) {
      load = new Promise((resolve, reject) => {
        this.chunkArrived.set(chunk, resolve);
        const script = document.createElement('script');
        script.src = `data/${this.manifest.folder || ''}chunk_${String(chunk).padStart(5, '0')}.js`;
        script.onerror = () => reject(new Error(`${script.src}: could not be loaded`));
        document.head.appendChild(script);
      });
      this.chunkLoads.set(chunk, load);
    }
    return load;
  }

  // Resolves once every named file is at hand.
  async require(names) {
    const chunks = new Set();
    for (const name of names) {
      if (this.files.has(name) || this.encoded.has(name)) continue;
      const chunk = this.manifest.files[name];
      if (chunk === undefined) throw new Error(`${name}: not in the viewer's data (run trephine view again)`);
      chunks.add(chunk);
    }
    await Promise.all([...chunks].map((chunk) => this.loadChunk(chunk)));
  }

  isAtHand(names) {
    return names.every((name) => this.files.has(name) || this.encoded.has(name));
  }

  file(name) {
    let file = this.files.get(name);
    if (!file) {
      const text = this.encoded.get(name);
      if (text === undefined) throw new Error(`${name}: not loaded`);
      const bytes = bytesFromBase64(text);
      file = name.endsWith('.tri') ? new TriangleFile(bytes, name) : new VtkXmlFile(bytes, name);
      this.encoded.delete(name);
      this.files.set(name, file);
    }
    return file;
  }

  // The raw bytes of a file (the skull's volume), once.
  bytes(name) {
    const text = this.encoded.get(name);
    if (text === undefined) throw new Error(`${name}: not loaded`);
    this.encoded.delete(name);
    return bytesFromBase64(text);
  }

  // Every file frame `index` shows; `still`: the still level of its blocks.
  namesOf(index, still = false) {
    const names = [];
    this.manifest.frames[index].states.forEach((state, part) => {
      if (state < 0) return;
      const value = this.manifest.parts[part].states[state];
      if (typeof value === 'string') names.push(value);
      else names.push(...(still ? value.stillBlocks : value.blocks));
    });
    return names;
  }

  // The last frame at or before time t (s).
  frameAt(t) {
    const frames = this.manifest.frames;
    let low = 0;
    let high = frames.length - 1;
    while (low < high) {
      const middle = (low + high + 1) >> 1;
      if (frames[middle].t <= t + 1e-9) low = middle;
      else high = middle - 1;
    }
    return low;
  }
}
