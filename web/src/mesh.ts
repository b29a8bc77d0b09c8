// The mesh as the station sends it (src/hydra_multi/web/viewer_mesh.h): u32 header length, a JSON
// header, f32 positions, u8 colours (padded to 4 bytes), u32 labels, u32 faces.

export interface ViewerMesh {
  seq: number;
  vertices: number;
  faces: number;
  robots: Record<string, [number, number, number, number]>;
  positions: Float32Array;
  colours: Uint8Array;
  labels: Uint32Array;
  indices: Uint32Array;
}

export function parseMesh(buffer: ArrayBuffer): ViewerMesh {
  const headerLength = new DataView(buffer).getUint32(0, true);
  const header = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 4, headerLength)));
  const n: number = header.vertices;
  const m: number = header.faces;
  let at = 4 + headerLength;
  const positions = new Float32Array(buffer, at, 3 * n);
  at += 12 * n;
  const colours = new Uint8Array(buffer, at, 3 * n);
  at += Math.ceil((3 * n) / 4) * 4;
  const labels = new Uint32Array(buffer, at, n);
  at += 4 * n;
  const indices = new Uint32Array(buffer, at, 3 * m);
  if (at + 12 * m !== buffer.byteLength) throw new Error(`mesh: ${buffer.byteLength} bytes, expected ${at + 12 * m}`);
  return { seq: header.seq, vertices: n, faces: m, robots: header.robots, positions, colours, labels, indices };
}
