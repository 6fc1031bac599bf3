// Format version 4 (docs/FORMAT.md): a Model of parts, each a spline stored
// with the chunks of versions 2 and 3, a name and trim loops.
#include <cmath>
#include <cstring>
#include <utility>

#include "sdcb/io/common/atomic_file.h"
#include "sdcb/io/sdcb/byte_packing.h"
#include "sdcb/io/sdcb/kept_mesh_coding.h"
#include "sdcb/io/sdcb/sdcb_chunks.h"
#include "sdcb/io/sdcb/sdcb_file.h"

namespace sdcb {
namespace {

using namespace sdcb_internal;  // NOLINT: the chunk codec of this file

constexpr uint32_t kModelVersion = 4;
constexpr size_t kModelHeadBytes = 8;  // u64 number of parts
// A kept part's reason (WHY) is one sentence.
constexpr size_t kMaxReasonBytes = 4096;

std::string PartPrefix(size_t index) { return "part " + Str(index + 1); }

// "" if `s` is well-formed UTF-8 (no overlong forms, surrogates or code
// points above U+10FFFF), else where it is not.
std::string Utf8Problem(std::string_view s) {
  size_t i = 0;
  while (i < s.size()) {
    const auto b = static_cast<unsigned char>(s[i]);
    int extra = 0;
    uint32_t cp = 0, min = 0;
    if (b < 0x80) {
      ++i;
      continue;
    } else if ((b & 0xE0) == 0xC0) {
      extra = 1, cp = b & 0x1F, min = 0x80;
    } else if ((b & 0xF0) == 0xE0) {
      extra = 2, cp = b & 0x0F, min = 0x800;
    } else if ((b & 0xF8) == 0xF0) {
      extra = 3, cp = b & 0x07, min = 0x10000;
    } else {
      return "byte " + Str(i) + " starts no UTF-8 sequence";
    }
    if (s.size() - i <= static_cast<size_t>(extra)) {
      return "the UTF-8 sequence at byte " + Str(i) + " is cut off";
    }
    for (int k = 1; k <= extra; ++k) {
      const auto c = static_cast<unsigned char>(s[i + k]);
      if ((c & 0xC0) != 0x80) {
        return "the UTF-8 sequence at byte " + Str(i) + " is invalid";
      }
      cp = (cp << 6) | (c & 0x3F);
    }
    if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) {
      return "the UTF-8 sequence at byte " + Str(i) + " is invalid";
    }
    i += extra + 1;
  }
  return "";
}

std::string NameProblem(std::string_view name) {
  if (name.size() > kMaxPartNameBytes) {
    return "its name has " + Str(name.size()) + " bytes, more than " +
           Str(kMaxPartNameBytes);
  }
  const std::string utf8 = Utf8Problem(name);
  return utf8.empty() ? "" : "its name is not UTF-8: " + utf8;
}

// ValidateTrimLoop's sentence, "" if `points` is a valid loop.
std::string TrimLoopProblem(const Eigen::MatrixX3d& points) {
  const Status valid = ValidateTrimLoop(TrimLoop{points});
  return valid.ok() ? "" : valid.message();
}

bool SameSource(const SourceMeshInfo& a, const SourceMeshInfo& b) {
  return a.num_vertices == b.num_vertices && a.num_faces == b.num_faces &&
         a.hash == b.hash && a.file_name == b.file_name;
}

// Version 4 holds what versions 2 and 3 cannot: several parts, a name, trims
// or a model source other than the one part's.
bool NeedsVersion4(const Model& model) {
  if (model.parts.size() != 1) return true;
  const ModelPart& part = model.parts[0];
  return part.kept || !part.name.empty() || part.trimmed() ||
         !model.asset.empty() || !SameSource(model.source, part.spline.source);
}

// TRIM: u64 number of loops L >= 1, L x u64 point counts, then the points of
// all loops in order, packed.
std::string TrimPayload(const std::vector<TrimLoop>& loops) {
  ByteWriter w;
  w.U64(loops.size());
  Eigen::Index total = 0;
  for (const TrimLoop& loop : loops) {
    w.U64(static_cast<uint64_t>(loop.points.rows()));
    total += loop.points.rows();
  }
  Eigen::MatrixX3d all(total, 3);
  Eigen::Index row = 0;
  for (const TrimLoop& loop : loops) {
    all.middleRows(row, loop.points.rows()) = loop.points;
    row += loop.points.rows();
  }
  w.Bytes(PackPoints(all));
  return std::move(w.str());
}

StatusOr<std::vector<TrimLoop>> ParseTrims(std::string_view payload,
                                           size_t file_size) {
  ByteReader r(payload);
  uint64_t num_loops = 0;
  if (!r.U64(&num_loops) || num_loops == 0) {
    return Corrupt("the TRIM chunk declares no loops");
  }
  if (num_loops > r.remaining() / 8) {
    return Corrupt("the TRIM chunk declares " + Str(num_loops) +
                   " loops, more than its " + Str(payload.size()) +
                   " bytes can hold");
  }
  std::vector<uint64_t> counts(num_loops);
  uint64_t total = 0;
  for (uint64_t& count : counts) {
    (void)r.U64(&count);
    if (count < 3) {
      return Corrupt("the TRIM chunk declares a loop of " + Str(count) +
                     " points; a loop needs at least 3");
    }
    total += count;
    // Packed points inflate at most kMaxDeflateRatio-fold.
    if (count > kMaxCount || total > kMaxCount ||
        total >
            kMaxDeflateRatio * static_cast<uint64_t>(file_size) / kPointBytes) {
      return Corrupt("the TRIM chunk declares more points than the file's " +
                     Str(file_size) + " bytes can hold");
    }
  }
  SDCB_ASSIGN_OR_RETURN(const Eigen::MatrixX3d all,
                        UnpackPoints(r.Rest(), total, "TRIM"));
  std::vector<TrimLoop> loops(num_loops);
  Eigen::Index row = 0;
  for (size_t i = 0; i < loops.size(); ++i) {
    const auto n = static_cast<Eigen::Index>(counts[i]);
    loops[i].points = all.middleRows(row, n);
    row += n;
    const std::string problem = TrimLoopProblem(loops[i].points);
    if (!problem.empty()) {
      return Corrupt("trim loop " + Str(i + 1) + ": " + problem);
    }
  }
  return loops;
}

// A kept part: HEAD and KEPT (its triangles), WHY (the reason, UTF-8), and
// none of a spline's chunks or TRIM.
StatusOr<KeptMesh> DecodeKept(const Chunks& chunks, size_t file_size) {
  for (const ChunkType& type : SplineChunkTypes(kModelVersion)) {
    if (type != kHead && type != kEnd && chunks.Has(type)) {
      return Corrupt("a kept part has a " + TypeName(type) + " chunk");
    }
  }
  if (chunks.Has(kTrim)) return Corrupt("a kept part has a TRIM chunk");
  if (!chunks.Has(kWhy)) return Corrupt("a kept part has no WHY chunk");
  KeptMesh kept;
  kept.reason = std::string(chunks.Get(kWhy));
  const std::string problem = Utf8Problem(kept.reason);
  if (kept.reason.empty() || kept.reason.size() > kMaxReasonBytes ||
      !problem.empty()) {
    return Corrupt("the WHY chunk is not a reason of 1 to " +
                   Str(kMaxReasonBytes) + " bytes of UTF-8" +
                   (problem.empty() ? "" : ": " + problem));
  }
  SDCB_ASSIGN_OR_RETURN(
      kept.mesh,
      DecodeKeptMesh(chunks.Get(kHead), chunks.Get(kKept), file_size));
  return kept;
}

StatusOr<ModelPart> DecodePart(std::string_view bytes, std::string_view part,
                               SdcbPartStorage* storage) {
  std::vector<ChunkType> known = SplineChunkTypes(kModelVersion);
  known.push_back(kName);
  known.push_back(kTrim);
  known.push_back(kKept);
  known.push_back(kWhy);
  Chunks chunks(known);
  const auto begin = static_cast<size_t>(part.data() - bytes.data());
  SDCB_RETURN_IF_ERROR(SplitChunks(bytes, &chunks, begin, begin + part.size()));
  ModelPart out;
  if (chunks.Has(kKept)) {
    SDCB_ASSIGN_OR_RETURN(out.kept, DecodeKept(chunks, bytes.size()));
  } else {
    if (chunks.Has(kWhy)) return Corrupt("a fitted part has a WHY chunk");
    SdcbFileInfo spline_info;
    SDCB_ASSIGN_OR_RETURN(
        out.spline,
        DecodeSplineChunks(chunks, kModelVersion, bytes.size(), &spline_info));
    storage->quantization = spline_info.quantization;
    storage->knot_grid_bits = spline_info.knot_grid_bits;
  }
  if (chunks.Has(kName)) {
    const std::string_view name = chunks.Get(kName);
    const std::string problem =
        name.empty() ? "the NAME chunk is empty (an unnamed part has none)"
                     : NameProblem(name);
    if (!problem.empty()) return Corrupt(problem);
    out.name = std::string(name);
  }
  if (chunks.Has(kTrim)) {
    SDCB_ASSIGN_OR_RETURN(out.trims,
                          ParseTrims(chunks.Get(kTrim), bytes.size()));
  }
  return out;
}

}  // namespace

namespace sdcb_internal {

StatusOr<Model> DecodeVersion4(std::string_view bytes, SdcbFileInfo* info) {
  Chunks top({kHead, kSrcm, kAsst, kEnd}, kPart);
  SDCB_RETURN_IF_ERROR(SplitChunks(bytes, &top));
  if (!top.Has(kSrcm)) return Corrupt("the required chunk 'SRCM' is missing");
  const std::string_view head = top.Get(kHead);
  if (head.size() != kModelHeadBytes) {
    return Corrupt("the HEAD chunk has " + Str(head.size()) +
                   " bytes; version 4 needs " + Str(kModelHeadBytes));
  }
  ByteReader r(head);
  uint64_t num_parts = 0;
  (void)r.U64(&num_parts);
  // The count is compared, never allocated from.
  if (num_parts == 0) return Corrupt("HEAD declares 0 parts");
  if (num_parts != top.repeated().size()) {
    return Corrupt("HEAD declares " + Str(num_parts) +
                   " parts but the file has " + Str(top.repeated().size()) +
                   " PART chunks");
  }
  Model model;
  SDCB_ASSIGN_OR_RETURN(model.source, ParseSource(top.Get(kSrcm)));
  if (top.Has(kAsst)) {
    if (top.Get(kAsst).empty()) return Corrupt("the ASST chunk is empty");
    model.asset = std::string(top.Get(kAsst));
  }
  SdcbFileInfo decoded;
  decoded.format_version = kModelVersion;
  decoded.file_bytes = bytes.size();
  for (size_t i = 0; i < top.repeated().size(); ++i) {
    SdcbPartStorage storage;
    StatusOr<ModelPart> part = DecodePart(bytes, top.repeated()[i], &storage);
    if (!part.ok()) return part.status().WithPrefix(PartPrefix(i));
    model.parts.push_back(std::move(*part));
    decoded.parts.push_back(storage);
  }
  decoded.quantization = decoded.parts[0].quantization;
  decoded.knot_grid_bits = decoded.parts[0].knot_grid_bits;
  *info = std::move(decoded);
  return model;
}

}  // namespace sdcb_internal

StatusOr<std::string> SerializeSdcbModel(const Model& model,
                                         const SdcbWriteOptions& options,
                                         SdcbFileInfo* info) {
  if (model.parts.empty()) {
    return InvalidArgumentError("cannot write a model of no parts");
  }
  for (size_t i = 0; i < model.parts.size(); ++i) {
    const ModelPart& part = model.parts[i];
    std::string problem = NameProblem(part.name);
    if (part.kept) {
      const Status valid = ValidateModelPart(part);
      if (!valid.ok()) problem = valid.message();
      const std::string& why = part.kept->reason;
      if (problem.empty() &&
          (why.size() > kMaxReasonBytes || !Utf8Problem(why).empty())) {
        problem = "its reason is not 1 to " + Str(kMaxReasonBytes) +
                  " bytes of UTF-8";
      }
    }
    for (size_t t = 0; problem.empty() && t < part.trims.size(); ++t) {
      problem = TrimLoopProblem(part.trims[t].points);
      if (!problem.empty())
        problem = "trim loop " + Str(t + 1) + ": " + problem;
    }
    if (!problem.empty()) {
      return InvalidArgumentError("cannot write the model: " + PartPrefix(i) +
                                  ": " + problem);
    }
  }
  if (!NeedsVersion4(model)) {
    return SerializeSdcb(model.parts[0].spline, options, info);
  }
  ByteWriter head;
  head.U64(model.parts.size());
  ByteWriter file;
  file.Bytes(std::string_view(kSdcbMagic, sizeof kSdcbMagic));
  file.U32(kModelVersion);
  AppendChunk(kHead, head.str(), &file);
  AppendChunk(kSrcm, SourcePayload(model.source), &file);
  if (!model.asset.empty()) AppendChunk(kAsst, model.asset, &file);
  SdcbFileInfo written;
  for (size_t i = 0; i < model.parts.size(); ++i) {
    const ModelPart& part = model.parts[i];
    ByteWriter chunks;
    SdcbFileInfo part_info;
    if (part.kept) {
      const KeptMeshPayloads kept = EncodeKeptMesh(part.kept->mesh);
      AppendChunk(kHead, kept.head, &chunks);
      AppendChunk(kKept, kept.kept, &chunks);
      AppendChunk(kWhy, part.kept->reason, &chunks);
    } else {
      StatusOr<uint32_t> version =
          AppendSplineChunks(part.spline, options, &chunks, &part_info);
      if (!version.ok()) return version.status().WithPrefix(PartPrefix(i));
    }
    if (!part.name.empty()) AppendChunk(kName, part.name, &chunks);
    if (part.trimmed()) AppendChunk(kTrim, TrimPayload(part.trims), &chunks);
    AppendChunk(kEnd, std::string_view(), &chunks);
    AppendChunk(kPart, chunks.str(), &file);
    written.parts.push_back({part_info.quantization, part_info.knot_grid_bits});
  }
  AppendChunk(kEnd, std::string_view(), &file);
  if (info != nullptr) {
    written.format_version = kModelVersion;
    written.file_bytes = file.str().size();
    written.quantization = written.parts[0].quantization;
    written.knot_grid_bits = written.parts[0].knot_grid_bits;
    *info = std::move(written);
  }
  return std::move(file.str());
}

StatusOr<Model> ParseSdcbModel(std::string_view bytes, SdcbFileInfo* info) {
  // Versions 1 to 3 and every framing problem: ParseSdcb's checks.
  if (bytes.size() >= kHeaderBytes &&
      std::memcmp(bytes.data(), kSdcbMagic, sizeof kSdcbMagic) == 0) {
    ByteReader r(bytes.substr(sizeof kSdcbMagic, 4));
    uint32_t version = 0;
    (void)r.U32(&version);
    if (version == kModelVersion) {
      SdcbFileInfo decoded;
      SDCB_ASSIGN_OR_RETURN(Model model, DecodeVersion4(bytes, &decoded));
      if (info != nullptr) *info = std::move(decoded);
      return model;
    }
  }
  SDCB_ASSIGN_OR_RETURN(SplineModel spline, ParseSdcb(bytes, info));
  return SinglePartModel(std::move(spline));
}

Status WriteSdcbModelFile(const Model& model, const std::string& path,
                          const SdcbWriteOptions& options, SdcbFileInfo* info) {
  StatusOr<std::string> bytes = SerializeSdcbModel(model, options, info);
  if (!bytes.ok()) return bytes.status().WithPrefix(path);
  return WriteFileAtomically(*bytes, path);
}

StatusOr<Model> ReadSdcbModelFile(const std::string& path, SdcbFileInfo* info) {
  SDCB_ASSIGN_OR_RETURN(const std::string bytes, ReadFileBytes(path));
  StatusOr<Model> model = ParseSdcbModel(bytes, info);
  if (!model.ok()) return model.status().WithPrefix(path);
  return model;
}

}  // namespace sdcb
