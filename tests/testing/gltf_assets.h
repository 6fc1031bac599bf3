// glTF assets for the reader's tests: the Khronos Duck as a GLB (converted
// by `assimp` from assimp-testmodels' COLLADA duck.dae: Debian ships no
// glTF 2 Duck), the glTF 2 files of assimp-testmodels, base64 for
// hand-written data URIs.
#ifndef SDCB_TESTS_TESTING_GLTF_ASSETS_H_
#define SDCB_TESTS_TESTING_GLTF_ASSETS_H_

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "testing/run_sdcb.h"

namespace sdcb::testing {

// assimp-testmodels' glTF 2 folder.
inline const char* kAssimpGltf2 = "/usr/share/assimp/models/glTF2";

// Writes DIR/Duck.glb with `assimp export` (assimp-utils); "" when assimp or
// the COLLADA duck is missing.
inline std::string MakeDuckGlb(const std::string& dir) {
  const std::string dae = "/usr/share/assimp/models/Collada/duck.dae";
  const std::string glb = dir + "/Duck.glb";
  if (!std::filesystem::exists(dae)) return "";
  const std::string command = "assimp export " + ShellQuote(dae) + " " +
                              ShellQuote(glb) + " -f glb2 >/dev/null 2>&1";
  if (std::system(command.c_str()) != 0 || !std::filesystem::exists(glb)) {
    return "";
  }
  return glb;
}

// Standard base64 (RFC 4648, padded), for hand-written data URIs.
inline std::string Base64(const std::string& data) {
  static const char* kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < data.size(); i += 3) {
    uint32_t v = static_cast<unsigned char>(data[i]) << 16;
    if (i + 1 < data.size()) v |= static_cast<unsigned char>(data[i + 1]) << 8;
    if (i + 2 < data.size()) v |= static_cast<unsigned char>(data[i + 2]);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < data.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += i + 2 < data.size() ? kAlphabet[v & 63] : '=';
  }
  return out;
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_GLTF_ASSETS_H_
