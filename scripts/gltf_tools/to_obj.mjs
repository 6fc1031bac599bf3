// Decodes a glTF / GLB (Draco and meshopt included) with glTF Transform and
// writes its triangles as one OBJ (positions with the node transforms
// applied, so KHR_mesh_quantization's dequantization; faces 1-based), so
// that a compressed file can be measured against another mesh.
//   node scripts/gltf_tools/to_obj.mjs IN.glb OUT.obj
import { writeFileSync } from 'node:fs';
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
const lines = [];
let base = 1;
for (const node of document.getRoot().listNodes()) {
  const mesh = node.getMesh();
  if (!mesh) continue;
  const m = node.getWorldMatrix();
  for (const prim of mesh.listPrimitives()) {
    const p = prim.getAttribute('POSITION');
    const v = [0, 0, 0];
    for (let i = 0; i < p.getCount(); i++) {
      p.getElement(i, v);
      const x = m[0] * v[0] + m[4] * v[1] + m[8] * v[2] + m[12];
      const y = m[1] * v[0] + m[5] * v[1] + m[9] * v[2] + m[13];
      const z = m[2] * v[0] + m[6] * v[1] + m[10] * v[2] + m[14];
      lines.push(`v ${x} ${y} ${z}`);
    }
    const indices = prim.getIndices();
    const count = indices ? indices.getCount() : p.getCount();
    for (let t = 0; t < count; t += 3) {
      const f = [0, 1, 2].map((k) => base + (indices ? indices.getScalar(t + k) : t + k));
      lines.push(`f ${f[0]} ${f[1]} ${f[2]}`);
    }
    base += p.getCount();
  }
}
writeFileSync(process.argv[3], lines.join('\n') + '\n');
