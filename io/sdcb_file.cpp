#include "sdcb/io/sdcb_file.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "sdcb/io/atomic_file.h"
#include "sdcb/io/crc32.h"
#include "sdcb/io/fit_statistics_json.h"

namespace sdcb {
namespace {

using ChunkType = std::array<char, 4>;

// Chunk types of format version 1, in the order they are written.
constexpr ChunkType kHead = {'H', 'E', 'A', 'D'};
constexpr ChunkType kKnot = {'K', 'N', 'O', 'T'};
constexpr ChunkType kBsis = {'B', 'S', 'I', 'S'};
constexpr ChunkType kCtrl = {'C', 'T', 'R', 'L'};
constexpr ChunkType kXfrm = {'X', 'F', 'R', 'M'};
constexpr ChunkType kStat = {'S', 'T', 'A', 'T'};
constexpr ChunkType kSrcm = {'S', 'R', 'C', 'M'};
constexpr ChunkType kParm = {'P', 'A', 'R', 'M'};
constexpr ChunkType kEnd = {'E', 'N', 'D', ' '};

constexpr size_t kHeaderBytes = 12;      // magic + version
constexpr size_t kChunkFrameBytes = 16;  // type + length + CRC
constexpr size_t kHeadPayloadBytes = 28;
constexpr size_t kXfrmPayloadBytes = 32;
constexpr size_t kSrcmFixedBytes = 24;
constexpr size_t kPointBytes = 24;  // three f64
// Counts must also be valid `int` indices.
constexpr uint64_t kMaxCount = std::numeric_limits<int32_t>::max();

std::string Str(uint64_t x) { return std::to_string(x); }

// Printable form of a chunk type for messages.
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

// ---------------------------------------------------------------------------
// Writing.

class ByteWriter {
 public:
  void U32(uint32_t v) {
    for (int i = 0; i < 4; ++i) out_ += static_cast<char>(v >> (8 * i));
  }
  void U64(uint64_t v) {
    for (int i = 0; i < 8; ++i) out_ += static_cast<char>(v >> (8 * i));
  }
  void F64(double d) {
    uint64_t bits;
    std::memcpy(&bits, &d, sizeof bits);
    U64(bits);
  }
  void Points(const Eigen::MatrixX3d& m) {
    for (Eigen::Index i = 0; i < m.rows(); ++i) {
      for (int c = 0; c < 3; ++c) F64(m(i, c));
    }
  }
  void Bytes(std::string_view s) { out_.append(s.data(), s.size()); }
  std::string& str() { return out_; }

 private:
  std::string out_;
};

// Appends type, u64 length, payload and CRC-32 of (type, length, payload).
void AppendChunk(const ChunkType& type, const std::string& payload,
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

std::string HeadPayload(const SplineModel& m) {
  ByteWriter w;
  w.U32(static_cast<uint32_t>(m.degree));
  w.U64(static_cast<uint64_t>(m.knots.rows()));
  w.U64(m.configurations.sets.size());
  w.U64(static_cast<uint64_t>(m.parameters.rows()));
  return std::move(w.str());
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

std::string PointsPayload(const Eigen::MatrixX3d& points) {
  ByteWriter w;
  w.Points(points);
  return std::move(w.str());
}

std::string TransformPayload(const NormalizingTransform& t) {
  ByteWriter w;
  w.F64(t.scale);
  for (int c = 0; c < 3; ++c) w.F64(t.translation[c]);
  return std::move(w.str());
}

std::string SourcePayload(const SourceMeshInfo& s) {
  ByteWriter w;
  w.U64(static_cast<uint64_t>(s.num_vertices));
  w.U64(static_cast<uint64_t>(s.num_faces));
  w.U64(s.hash);
  w.Bytes(s.file_name);
  return std::move(w.str());
}

// ---------------------------------------------------------------------------
// Reading.

// Bounds-checked little-endian reads from a byte range. Every read checks the
// bytes left; callers check lengths up front too, so a failed read here means
// a length rule was broken.
class ByteReader {
 public:
  explicit ByteReader(std::string_view data) : data_(data) {}
  size_t remaining() const { return data_.size() - pos_; }
  bool U32(uint32_t* v) {
    if (remaining() < 4) return false;
    *v = 0;
    for (int i = 0; i < 4; ++i) *v |= uint32_t{Byte(i)} << (8 * i);
    pos_ += 4;
    return true;
  }
  bool U64(uint64_t* v) {
    if (remaining() < 8) return false;
    *v = 0;
    for (int i = 0; i < 8; ++i) *v |= uint64_t{Byte(i)} << (8 * i);
    pos_ += 8;
    return true;
  }
  bool F64(double* d) {
    uint64_t bits;
    if (!U64(&bits)) return false;
    std::memcpy(d, &bits, sizeof bits);
    return true;
  }
  std::string_view Rest() {
    std::string_view rest = data_.substr(pos_);
    pos_ = data_.size();
    return rest;
  }

 private:
  uint8_t Byte(int i) const { return static_cast<uint8_t>(data_[pos_ + i]); }
  std::string_view data_;
  size_t pos_ = 0;
};

Status Corrupt(const std::string& message) { return CorruptFileError(message); }

// The payloads of the chunk types version 1 knows, after framing and CRC
// checks; unknown types are dropped.
struct Chunks {
  static constexpr int kNumKnown = 9;
  static constexpr std::array<ChunkType, kNumKnown> kKnown = {
      kHead, kKnot, kBsis, kCtrl, kXfrm, kStat, kSrcm, kParm, kEnd};
  std::array<bool, kNumKnown> present{};
  std::array<std::string_view, kNumKnown> payload{};

  static int IndexOf(const ChunkType& t) {
    for (int i = 0; i < kNumKnown; ++i) {
      if (kKnown[i] == t) return i;
    }
    return -1;
  }
  bool Has(const ChunkType& t) const { return present[IndexOf(t)]; }
  std::string_view Get(const ChunkType& t) const { return payload[IndexOf(t)]; }
};

bool ValidTypeChar(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') ||
         (c >= '0' && c <= '9') || c == ' ' || c == '_';
}

// Splits the chunk sequence after the 12-byte header, checking framing and
// CRCs: every chunk lies inside the file, has a valid type and CRC, a known
// type occurs at most once, HEAD comes first, END comes last with nothing
// after it.
StatusOr<Chunks> SplitChunks(std::string_view bytes) {
  Chunks chunks;
  size_t pos = kHeaderBytes;
  bool first = true;
  while (true) {
    const size_t left = bytes.size() - pos;
    if (left < kChunkFrameBytes) {
      return Corrupt("truncated: the file ends at byte " + Str(bytes.size()) +
                     " inside a chunk header, before the END chunk");
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
    const uint32_t crc = Crc32(framed);
    if (crc != stored_crc) {
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
    const int known = Chunks::IndexOf(type);
    if (known >= 0) {
      if (chunks.present[known]) {
        return Corrupt("chunk " + TypeName(type) + " occurs twice");
      }
      chunks.present[known] = true;
      chunks.payload[known] = framed.substr(12);
    }
    pos += kChunkFrameBytes + length;
    if (type == kEnd) {
      if (length != 0) return Corrupt("the END chunk is not empty");
      if (pos != bytes.size()) {
        return Corrupt(Str(bytes.size() - pos) +
                       " unexpected bytes follow the END chunk");
      }
      return chunks;
    }
  }
}

struct Head {
  int degree = 0;
  uint64_t num_knots = 0;
  uint64_t num_basis = 0;
  uint64_t num_parameters = 0;
};

// Bytes of one BSIS record with `boundaries` triples.
uint64_t BasisRecordBytes(int degree, uint64_t boundaries) {
  return 4 + 4 * static_cast<uint64_t>(degree + 3) + 12 * boundaries;
}

StatusOr<Head> ParseHead(std::string_view payload, size_t file_size) {
  if (payload.size() != kHeadPayloadBytes) {
    return Corrupt("the HEAD chunk has " + Str(payload.size()) +
                   " bytes; version 1 needs " + Str(kHeadPayloadBytes));
  }
  ByteReader r(payload);
  uint32_t degree = 0;
  Head h;
  (void)r.U32(&degree);
  (void)r.U64(&h.num_knots);
  (void)r.U64(&h.num_basis);
  (void)r.U64(&h.num_parameters);
  if (degree > static_cast<uint32_t>(kMaxSplineDegree)) {
    return Corrupt("HEAD declares degree " + Str(degree) + ", outside 0.." +
                   Str(kMaxSplineDegree));
  }
  h.degree = static_cast<int>(degree);
  // Each count must be payable by the bytes of the file before anything is
  // allocated for it.
  const struct {
    const char* what;
    uint64_t count;
    uint64_t bytes_each;
  } counts[] = {
      {"knots", h.num_knots, kPointBytes},
      {"basis functions", h.num_basis,
       BasisRecordBytes(h.degree, 1) + kPointBytes},
      {"sphere parameters", h.num_parameters, kPointBytes},
  };
  for (const auto& c : counts) {
    if (c.count > kMaxCount || c.count > file_size / c.bytes_each) {
      return Corrupt("HEAD declares " + Str(c.count) + " " + c.what +
                     ", more than the file's " + Str(file_size) +
                     " bytes can hold");
    }
  }
  return h;
}

// Reads exactly `rows` points from a chunk whose size must match.
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

StatusOr<DelaunayConfigurations> ParseBasis(std::string_view payload,
                                            const Head& head) {
  const uint64_t max_boundaries = static_cast<uint64_t>(head.degree + 3) *
                                  (head.degree + 2) * (head.degree + 1) / 6;
  if (head.num_basis > payload.size() / BasisRecordBytes(head.degree, 1)) {
    return Corrupt("the BSIS chunk's " + Str(payload.size()) +
                   " bytes cannot hold HEAD's " + Str(head.num_basis) +
                   " basis functions");
  }
  DelaunayConfigurations out;
  out.degree = head.degree;
  out.sets.resize(head.num_basis);
  ByteReader r(payload);
  const auto knot_index = [&](uint64_t i, uint32_t v, int* out_index) {
    if (v >= head.num_knots) {
      return Corrupt("basis function " + Str(i) + " refers to knot " + Str(v) +
                     ", but the file has " + Str(head.num_knots) + " knots");
    }
    *out_index = static_cast<int>(v);
    return Status::Ok();
  };
  for (uint64_t i = 0; i < head.num_basis; ++i) {
    uint32_t boundaries = 0;
    if (!r.U32(&boundaries)) {
      return Corrupt("the BSIS chunk ends inside basis function " + Str(i));
    }
    if (boundaries == 0 || boundaries > max_boundaries) {
      return Corrupt("basis function " + Str(i) + " declares " +
                     Str(boundaries) + " boundary triples; degree " +
                     Str(head.degree) + " allows 1.." + Str(max_boundaries));
    }
    if (BasisRecordBytes(head.degree, boundaries) - 4 > r.remaining()) {
      return Corrupt("the BSIS chunk ends inside basis function " + Str(i));
    }
    ConfigurationSet& set = out.sets[i];
    set.knots.resize(head.degree + 3);
    for (int& knot : set.knots) {
      uint32_t v = 0;
      (void)r.U32(&v);
      SDCB_RETURN_IF_ERROR(knot_index(i, v, &knot));
    }
    set.boundaries.resize(boundaries);
    for (std::array<int, 3>& triple : set.boundaries) {
      for (int& knot : triple) {
        uint32_t v = 0;
        (void)r.U32(&v);
        SDCB_RETURN_IF_ERROR(knot_index(i, v, &knot));
      }
    }
  }
  if (r.remaining() != 0) {
    return Corrupt("the BSIS chunk has " + Str(r.remaining()) +
                   " bytes after its last basis function");
  }
  return out;
}

StatusOr<NormalizingTransform> ParseTransform(std::string_view payload) {
  if (payload.size() != kXfrmPayloadBytes) {
    return Corrupt("the XFRM chunk has " + Str(payload.size()) +
                   " bytes; version 1 needs " + Str(kXfrmPayloadBytes));
  }
  NormalizingTransform t;
  ByteReader r(payload);
  (void)r.F64(&t.scale);
  for (int c = 0; c < 3; ++c) (void)r.F64(&t.translation[c]);
  return t;
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

StatusOr<FitStatistics> ParseStatistics(std::string_view payload) {
  const nlohmann::json j =
      nlohmann::json::parse(payload.begin(), payload.end(), /*cb=*/nullptr,
                            /*allow_exceptions=*/false);
  if (j.is_discarded()) {
    return Corrupt("the STAT chunk is not valid JSON");
  }
  StatusOr<FitStatistics> s = FitStatisticsFromJson(j);
  if (!s.ok()) return Corrupt("the STAT chunk: " + s.status().message());
  return s;
}

StatusOr<SplineModel> DecodeChunks(const Chunks& chunks, size_t file_size) {
  for (const ChunkType& required : {kKnot, kBsis, kCtrl, kXfrm, kSrcm, kEnd}) {
    if (!chunks.Has(required)) {
      return Corrupt("the required chunk " + TypeName(required) +
                     " is missing");
    }
  }
  SDCB_ASSIGN_OR_RETURN(const Head head,
                        ParseHead(chunks.Get(kHead), file_size));
  SplineModel m;
  m.degree = head.degree;
  SDCB_ASSIGN_OR_RETURN(
      m.knots, ParsePoints(chunks.Get(kKnot), head.num_knots, "KNOT", "knots"));
  SDCB_ASSIGN_OR_RETURN(m.configurations, ParseBasis(chunks.Get(kBsis), head));
  SDCB_ASSIGN_OR_RETURN(m.control_points,
                        ParsePoints(chunks.Get(kCtrl), head.num_basis, "CTRL",
                                    "basis functions"));
  SDCB_ASSIGN_OR_RETURN(m.transform, ParseTransform(chunks.Get(kXfrm)));
  if (chunks.Has(kStat)) {
    SDCB_ASSIGN_OR_RETURN(m.statistics, ParseStatistics(chunks.Get(kStat)));
  }
  SDCB_ASSIGN_OR_RETURN(m.source, ParseSource(chunks.Get(kSrcm)));
  if (chunks.Has(kParm) != (head.num_parameters > 0)) {
    return Corrupt("HEAD declares " + Str(head.num_parameters) +
                   " sphere parameters but the PARM chunk is " +
                   (chunks.Has(kParm) ? "present" : "missing"));
  }
  if (chunks.Has(kParm)) {
    SDCB_ASSIGN_OR_RETURN(m.parameters,
                          ParsePoints(chunks.Get(kParm), head.num_parameters,
                                      "PARM", "sphere parameters"));
  }
  const Status valid = ValidateSplineModel(m);
  if (!valid.ok()) return Corrupt("invalid model: " + valid.message());
  return m;
}

}  // namespace

StatusOr<std::string> SerializeSdcb(const SplineModel& model) {
  const Status valid = ValidateSplineModel(model);
  if (!valid.ok()) {
    return InvalidArgumentError("cannot write an invalid model: " +
                                valid.message());
  }
  ByteWriter file;
  file.Bytes(std::string_view(kSdcbMagic, sizeof kSdcbMagic));
  file.U32(kSdcbFormatVersion);
  AppendChunk(kHead, HeadPayload(model), &file);
  AppendChunk(kKnot, PointsPayload(model.knots), &file);
  AppendChunk(kBsis, BasisPayload(model.configurations), &file);
  AppendChunk(kCtrl, PointsPayload(model.control_points), &file);
  AppendChunk(kXfrm, TransformPayload(model.transform), &file);
  AppendChunk(kStat, FitStatisticsToJson(model.statistics).dump(), &file);
  AppendChunk(kSrcm, SourcePayload(model.source), &file);
  if (model.parameters.rows() > 0) {
    AppendChunk(kParm, PointsPayload(model.parameters), &file);
  }
  AppendChunk(kEnd, std::string(), &file);
  return std::move(file.str());
}

StatusOr<SplineModel> ParseSdcb(std::string_view bytes) {
  const size_t magic_bytes = std::min(bytes.size(), sizeof kSdcbMagic);
  if (bytes.empty()) return Corrupt("the file is empty");
  if (std::memcmp(bytes.data(), kSdcbMagic, magic_bytes) == 0 &&
      bytes.size() < kHeaderBytes) {
    return Corrupt("truncated: the file has only " + Str(bytes.size()) +
                   " bytes, less than the 12-byte header");
  }
  if (std::memcmp(bytes.data(), kSdcbMagic, magic_bytes) != 0 ||
      bytes.size() < kHeaderBytes) {
    return Corrupt(
        "not an .sdcb model: the file does not start with the .sdcb magic "
        "number (or it was damaged by a text-mode transfer)");
  }
  ByteReader r(bytes.substr(sizeof kSdcbMagic, 4));
  uint32_t version = 0;
  (void)r.U32(&version);
  if (version == 0) return Corrupt("the format version is 0, which is invalid");
  if (version > kSdcbFormatVersion) {
    return UnsupportedError("the file has .sdcb format version " +
                            Str(version) + "; this sdcb reads versions up to " +
                            Str(kSdcbFormatVersion));
  }
  SDCB_ASSIGN_OR_RETURN(const Chunks chunks, SplitChunks(bytes));
  return DecodeChunks(chunks, bytes.size());
}

Status WriteSdcbFile(const SplineModel& model, const std::string& path) {
  StatusOr<std::string> bytes = SerializeSdcb(model);
  if (!bytes.ok()) return bytes.status().WithPrefix(path);
  return WriteFileAtomically(*bytes, path);
}

StatusOr<SplineModel> ReadSdcbFile(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    return IoError(path + ": is a directory, not an .sdcb model");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return IoError(path + ": cannot open the file (" + std::strerror(errno) +
                   ")");
  }
  std::string bytes((std::istreambuf_iterator<char>(in)),
                    std::istreambuf_iterator<char>());
  if (in.bad()) return IoError(path + ": reading the file failed");
  StatusOr<SplineModel> model = ParseSdcb(bytes);
  if (!model.ok()) return model.status().WithPrefix(path);
  return model;
}

}  // namespace sdcb
