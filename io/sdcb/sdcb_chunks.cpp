#include "sdcb/io/sdcb/sdcb_chunks.h"

#include <limits>
#include <nlohmann/json.hpp>

#include "sdcb/io/report/fit_statistics_json.h"
#include "sdcb/io/sdcb/crc32.h"

namespace sdcb::sdcb_internal {
namespace {

bool ValidTypeChar(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') ||
         (c >= '0' && c <= '9') || c == ' ' || c == '_';
}

}  // namespace

std::string TypeName(const ChunkType& t) {
  std::string s = "'";
  for (char c : t) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7F) {
      s += c;
    } else {
      static const char* kHex = "0123456789abcdef";
      s += "\\x";
      s += kHex[u >> 4];
      s += kHex[u & 15];
    }
  }
  return s + "'";
}

void AppendChunk(const ChunkType& type, std::string_view payload,
                 ByteWriter* file) {
  ByteWriter frame;
  frame.Bytes(std::string_view(type.data(), type.size()));
  frame.U64(payload.size());
  uint32_t crc = Crc32(frame.str());
  crc = Crc32Update(crc, payload.data(), payload.size());
  file->Bytes(frame.str());
  file->Bytes(payload);
  file->U32(crc);
}

int Chunks::IndexOf(const ChunkType& t) const {
  for (size_t i = 0; i < known_.size(); ++i) {
    if (known_[i] == t) return static_cast<int>(i);
  }
  return -1;
}

bool Chunks::Set(int index, std::string_view payload) {
  if (present_[index]) return false;
  present_[index] = true;
  payload_[index] = payload;
  return true;
}

Status SplitChunks(std::string_view bytes, Chunks* chunks, size_t begin,
                   size_t end) {
  const bool whole_file = end == std::string_view::npos;
  if (whole_file) end = bytes.size();
  size_t pos = begin;
  bool first = true;
  while (true) {
    const size_t left = end - pos;
    if (left < kChunkFrameBytes) {
      return Corrupt(whole_file
                         ? "truncated: the file ends at byte " + Str(end) +
                               " inside a chunk header, before the END "
                               "chunk"
                         : "the PART payload ends at byte " + Str(end) +
                               " inside a chunk header, before its END "
                               "chunk");
    }
    ChunkType type;
    std::memcpy(type.data(), bytes.data() + pos, 4);
    ByteReader length_reader(bytes.substr(pos + 4, 8));
    uint64_t length = 0;
    (void)length_reader.U64(&length);
    if (length > left - kChunkFrameBytes) {
      return Corrupt("chunk " + TypeName(type) + " at byte " + Str(pos) +
                     " declares " + Str(length) + " payload bytes but only " +
                     Str(left - kChunkFrameBytes) +
                     " remain (truncated or corrupt)");
    }
    const std::string_view framed = bytes.substr(pos, 12 + length);
    ByteReader crc_reader(bytes.substr(pos + 12 + length, 4));
    uint32_t stored_crc = 0;
    (void)crc_reader.U32(&stored_crc);
    if (Crc32(framed) != stored_crc) {
      return Corrupt("chunk " + TypeName(type) + " at byte " + Str(pos) +
                     " fails its CRC-32 check (the data is corrupt)");
    }
    for (char c : type) {
      if (!ValidTypeChar(c)) {
        return Corrupt("chunk at byte " + Str(pos) + " has an invalid type " +
                       TypeName(type));
      }
    }
    if (first && type != kHead) {
      return Corrupt("the first chunk is " + TypeName(type) +
                     ", not the required 'HEAD'");
    }
    first = false;
    const int known = chunks->IndexOf(type);
    if (chunks->IsRepeated(type)) {
      chunks->AddRepeated(framed.substr(12));
    } else if (known >= 0 && !chunks->Set(known, framed.substr(12))) {
      return Corrupt("chunk " + TypeName(type) + " occurs twice");
    }
    pos += kChunkFrameBytes + length;
    if (type == kEnd) {
      if (length != 0) return Corrupt("the END chunk is not empty");
      if (pos != end) {
        return Corrupt(Str(end - pos) +
                       " unexpected bytes follow the END chunk");
      }
      return Status::Ok();
    }
  }
}

Status CheckCount(uint64_t count, uint64_t bytes_each, uint64_t expansion,
                  size_t file_size, const char* what) {
  // count * bytes_each <= expansion * file_size, without overflow.
  if (count > kMaxCount ||
      count > expansion * static_cast<uint64_t>(file_size) / bytes_each) {
    return Corrupt("HEAD declares " + Str(count) + " " + what +
                   ", more than the file's " + Str(file_size) +
                   " bytes can hold");
  }
  return Status::Ok();
}

StatusOr<int> CheckDegree(uint32_t degree) {
  if (degree > static_cast<uint32_t>(kMaxSplineDegree)) {
    return Corrupt("HEAD declares degree " + Str(degree) + ", outside 0.." +
                   Str(kMaxSplineDegree));
  }
  return static_cast<int>(degree);
}

std::string BasisPayload(const DelaunayConfigurations& configurations) {
  ByteWriter w;
  for (const ConfigurationSet& set : configurations.sets) {
    w.U32(static_cast<uint32_t>(set.boundaries.size()));
    for (int knot : set.knots) w.U32(static_cast<uint32_t>(knot));
    for (const std::array<int, 3>& triple : set.boundaries) {
      for (int knot : triple) w.U32(static_cast<uint32_t>(knot));
    }
  }
  return std::move(w.str());
}

StatusOr<Eigen::MatrixX3d> ParsePoints(std::string_view payload, uint64_t rows,
                                       const char* chunk, const char* what) {
  if (payload.size() != rows * kPointBytes) {
    return Corrupt(std::string("the ") + chunk + " chunk has " +
                   Str(payload.size()) + " bytes; HEAD's " + Str(rows) + " " +
                   what + " need " + Str(rows * kPointBytes));
  }
  Eigen::MatrixX3d m(static_cast<Eigen::Index>(rows), 3);
  ByteReader r(payload);
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    for (int c = 0; c < 3; ++c) (void)r.F64(&m(i, c));
  }
  return m;
}

std::string TransformPayload(const NormalizingTransform& t) {
  ByteWriter w;
  w.F64(t.scale);
  for (int c = 0; c < 3; ++c) w.F64(t.translation[c]);
  return std::move(w.str());
}

StatusOr<NormalizingTransform> ParseTransform(std::string_view payload) {
  if (payload.size() != kXfrmPayloadBytes) {
    return Corrupt("the XFRM chunk has " + Str(payload.size()) +
                   " bytes; it needs " + Str(kXfrmPayloadBytes));
  }
  NormalizingTransform t;
  ByteReader r(payload);
  (void)r.F64(&t.scale);
  for (int c = 0; c < 3; ++c) (void)r.F64(&t.translation[c]);
  return t;
}

std::string SourcePayload(const SourceMeshInfo& s) {
  ByteWriter w;
  w.U64(static_cast<uint64_t>(s.num_vertices));
  w.U64(static_cast<uint64_t>(s.num_faces));
  w.U64(s.hash);
  w.Bytes(s.file_name);
  return std::move(w.str());
}

StatusOr<SourceMeshInfo> ParseSource(std::string_view payload) {
  if (payload.size() < kSrcmFixedBytes) {
    return Corrupt("the SRCM chunk has " + Str(payload.size()) +
                   " bytes; it needs at least " + Str(kSrcmFixedBytes));
  }
  ByteReader r(payload);
  uint64_t vertices = 0, faces = 0;
  SourceMeshInfo s;
  (void)r.U64(&vertices);
  (void)r.U64(&faces);
  (void)r.U64(&s.hash);
  constexpr auto kMax =
      static_cast<uint64_t>(std::numeric_limits<int64_t>::max());
  if (vertices > kMax || faces > kMax) {
    return Corrupt("the SRCM chunk has an impossible vertex or face count");
  }
  s.num_vertices = static_cast<int64_t>(vertices);
  s.num_faces = static_cast<int64_t>(faces);
  s.file_name = std::string(r.Rest());
  return s;
}

StatusOr<FitStatistics> ParseStatistics(std::string_view json_text) {
  const nlohmann::json j =
      nlohmann::json::parse(json_text.begin(), json_text.end(),
                            /*cb=*/nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) {
    return Corrupt("the STAT chunk is not valid JSON");
  }
  StatusOr<FitStatistics> s = FitStatisticsFromJson(j);
  if (!s.ok()) return Corrupt("the STAT chunk: " + s.status().message());
  return s;
}

}  // namespace sdcb::sdcb_internal
