// libFuzzer harness: the `sdcb batch` manifest parser
// (io/batch/batch_manifest.h). Invariants: rows come in increasing line order,
// within the text's lines.
#include <cstdint>
#include <string_view>

#include "sdcb/io/batch/batch_manifest.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto rows = sdcb::ParseBatchManifest(text);
  if (!rows.ok()) return 0;
  int lines = 1;
  for (char c : text) lines += c == '\n';
  int previous = 0;
  for (const sdcb::ManifestRow& row : *rows) {
    if (row.line <= previous || row.line > lines) __builtin_trap();
    previous = row.line;
  }
  return 0;
}
