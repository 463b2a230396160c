// The viewer's in-memory map, filled vertex by vertex by either reader:
//   positions   Float32Array 3V
//   counts      Uint32Array V     viewpoints of each vertex (0 = none)
//   uniform     Uint8Array V      1: one colour for all viewpoints, stored once
//   shared      bool              every vertex with viewpoints uses the same direction set
//   dirs        Float32Array 3D   direction records; dirOffset[i] is vertex i's first
//   colors      Float32Array 3C   colour records; colorOffset[i] is vertex i's first
//   materials   Float32Array 9M   diffuse, reflective, emissive
//   faces       Int32Array 5F     v0 v1 v2 v3 (-1: triangle), material
// Identical direction sets and uniform colours are stored once, as in the .bsb format.
import { Growable } from './growable.js';

export class MapBuilder {
  constructor() {
    this.vertexCount = 0;
    this.positions = new Growable(Float32Array, 3 * 1024);
    this.counts = new Growable(Uint32Array);
    this.uniform = new Growable(Uint8Array);
    this.dirOffset = new Growable(Uint32Array);
    this.colorOffset = new Growable(Uint32Array);
    this.colors = new Growable(Float32Array, 3 * 1024);
    this.mode = 'none'; // 'none' -> 'shared' -> 'separate'
    this.shared = null; // Float32Array of the shared direction set
    this.dirs = null; // Growable, once separate
    this.curDirs = new Growable(Float32Array, 3 * 64);
    this.curColors = new Growable(Float32Array, 3 * 64);
    this.open = false;
  }

  addVertex(x, y, z) {
    this.endVertex();
    this.positions.push3(x, y, z);
    this.vertexCount++;
    this.open = true;
  }

  addViewpoint(dx, dy, dz, r, g, b) {
    this.curDirs.push3(dx, dy, dz);
    this.curColors.push3(r, g, b);
  }

  endVertices() {
    this.endVertex();
  }

  endVertex() {
    if (!this.open) return;
    this.open = false;
    const n = this.curDirs.length / 3;
    this.counts.push(n);
    this.colorOffset.push(this.colors.length / 3);
    const cd = this.curDirs.data.subarray(0, 3 * n);
    const cc = this.curColors.data.subarray(0, 3 * n);
    this.curDirs.length = 0;
    this.curColors.length = 0;
    if (n === 0) {
      this.uniform.push(0);
      this.dirOffset.push(0);
      return;
    }
    let same = true;
    for (let k = 3; k < 3 * n && same; ++k) same = cc[k] === cc[k % 3];
    this.uniform.push(same ? 1 : 0);
    this.colors.append(same ? cc.subarray(0, 3) : cc);
    this.addDirections(cd);
  }

  addDirections(cd) {
    if (this.mode === 'none') {
      this.mode = 'shared';
      this.shared = cd.slice();
    } else if (this.mode === 'shared' && !sameArray(cd, this.shared)) {
      // First vertex with another set: give every earlier vertex its own copy.
      this.mode = 'separate';
      this.dirs = new Growable(Float32Array, 2 * this.vertexCount * this.shared.length);
      const counts = this.counts.data;
      for (let i = 0; i + 1 < this.vertexCount; ++i) {
        this.dirOffset.data[i] = this.dirs.length / 3;
        if (counts[i] > 0) this.dirs.append(this.shared);
      }
    }
    if (this.mode === 'shared') {
      this.dirOffset.push(0);
    } else {
      this.dirOffset.push(this.dirs.length / 3);
      this.dirs.append(cd);
    }
  }

  finish(materials, faces) {
    this.endVertex();
    return {
      vertexCount: this.vertexCount,
      positions: this.positions.take(),
      counts: this.counts.take(),
      uniform: this.uniform.take(),
      shared: this.mode !== 'separate',
      dirs: this.mode === 'separate' ? this.dirs.take() : (this.shared ?? new Float32Array(0)),
      dirOffset: this.dirOffset.take(),
      colorOffset: this.colorOffset.take(),
      colors: this.colors.take(),
      materials,
      faces,
    };
  }
}

function sameArray(a, b) {
  if (a.length !== b.length) return false;
  for (let i = 0; i < a.length; ++i) if (a[i] !== b[i]) return false;
  return true;
}

// Transferable buffers of a map, for postMessage from the worker.
export function mapTransferables(map) {
  return [map.positions, map.counts, map.uniform, map.dirs, map.dirOffset, map.colorOffset,
    map.colors, map.materials, map.faces].map((a) => a.buffer);
}
