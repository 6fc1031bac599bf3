#include "sdcb/converters/gltf/glb_container.h"

#include <cstdint>

namespace sdcb {
namespace {

constexpr uint32_t kMagic = 0x46546C67u;      // "glTF"
constexpr uint32_t kJsonChunk = 0x4E4F534Au;  // "JSON"
constexpr uint32_t kBinChunk = 0x004E4942u;   // "BIN\0"

void AppendU32(std::string* s, uint32_t v) {
  for (int i = 0; i < 4; ++i) s->push_back(static_cast<char>(v >> (8 * i)));
}

uint32_t ReadU32(std::string_view s, size_t at) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) {
    v |= static_cast<uint32_t>(static_cast<unsigned char>(s[at + i]))
         << (8 * i);
  }
  return v;
}

}  // namespace

void Pad4(std::string* s, char fill) {
  while (s->size() % 4 != 0) s->push_back(fill);
}

std::string PackGlb(std::string json_text, std::string bin) {
  Pad4(&json_text, ' ');
  Pad4(&bin, '\0');
  std::string out;
  AppendU32(&out, kMagic);
  AppendU32(&out, 2);
  AppendU32(&out, static_cast<uint32_t>(12 + 8 + json_text.size() +
                                        (bin.empty() ? 0 : 8 + bin.size())));
  AppendU32(&out, static_cast<uint32_t>(json_text.size()));
  AppendU32(&out, kJsonChunk);
  out += json_text;
  if (!bin.empty()) {
    AppendU32(&out, static_cast<uint32_t>(bin.size()));
    AppendU32(&out, kBinChunk);
    out += bin;
  }
  return out;
}

StatusOr<GlbChunks> SplitGlb(std::string_view glb) {
  if (glb.size() < 20 || ReadU32(glb, 0) != kMagic) {
    return CorruptFileError("the GLB header is missing or truncated");
  }
  if (ReadU32(glb, 4) != 2) {
    return CorruptFileError("the GLB is of version " +
                            std::to_string(ReadU32(glb, 4)) +
                            ", not 2 (glTF 2.0; `assimp export FILE "
                            "OUT.glb -f glb2` converts glTF 1)");
  }
  const uint64_t json_length = ReadU32(glb, 12);
  if (ReadU32(glb, 16) != kJsonChunk) {
    return CorruptFileError("the GLB's first chunk is not JSON");
  }
  if (20 + json_length > glb.size()) {
    return CorruptFileError("the GLB's JSON chunk of " +
                            std::to_string(json_length) +
                            " bytes reaches past the end of the file (" +
                            std::to_string(glb.size()) + " bytes)");
  }
  GlbChunks chunks;
  chunks.json = glb.substr(20, json_length);
  const uint64_t at = 20 + json_length;
  if (at + 8 <= glb.size() && ReadU32(glb, at + 4) == kBinChunk) {
    const uint64_t bin_length = ReadU32(glb, at);
    if (at + 8 + bin_length > glb.size()) {
      return CorruptFileError("the GLB's BIN chunk of " +
                              std::to_string(bin_length) +
                              " bytes reaches past the end of the file (" +
                              std::to_string(glb.size()) + " bytes)");
    }
    chunks.bin = glb.substr(at + 8, bin_length);
  }
  return chunks;
}

}  // namespace sdcb
