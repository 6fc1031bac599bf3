// Decodes a glTF / GLB (Draco and meshopt included) with glTF Transform and
// prints {"triangles": N, "positions": [[x, y, z], ...]} with the node
// transforms applied (KHR_mesh_quantization's dequantization), so tests can
// compare a compressed file with the uncompressed export.
//   node scripts/gltf_tools/decode.mjs FILE
import { NodeIO } from '@gltf-transform/core';
import { ALL_EXTENSIONS } from '@gltf-transform/extensions';
import draco3d from 'draco3dgltf';
import { MeshoptDecoder } from 'meshoptimizer';

const io = new NodeIO().registerExtensions(ALL_EXTENSIONS).registerDependencies({
  'draco3d.decoder': await draco3d.createDecoderModule(),
  'meshopt.decoder': MeshoptDecoder,
});
await MeshoptDecoder.ready;
const document = await io.read(process.argv[2]);
let triangles = 0;
const positions = [];
for (const node of document.getRoot().listNodes()) {
  const mesh = node.getMesh();
  if (!mesh) continue;
  const m = node.getWorldMatrix();
  for (const prim of mesh.listPrimitives()) {
    const indices = prim.getIndices();
    triangles += (indices ? indices.getCount() : prim.getAttribute('POSITION').getCount()) / 3;
    const p = prim.getAttribute('POSITION');
    const v = [0, 0, 0];
    for (let i = 0; i < p.getCount(); i++) {
      p.getElement(i, v);
      positions.push([
        m[0] * v[0] + m[4] * v[1] + m[8] * v[2] + m[12],
        m[1] * v[0] + m[5] * v[1] + m[9] * v[2] + m[13],
        m[2] * v[0] + m[6] * v[1] + m[10] * v[2] + m[14],
      ]);
    }
  }
}
console.log(JSON.stringify({ triangles, positions }));
