// libFuzzer harness: the OBJ reader (see mesh_fuzzer.h).
#include "mesh_fuzzer.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return FuzzMeshFormat(data, size, sdcb::MeshFileFormat::kObj);
}
