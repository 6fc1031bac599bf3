// INTERNAL to io/sdcb/sdcb_file*.cpp (installed with the other headers, not an
// API): the chunk framing every `.sdcb` format version shares, the
// little-endian byte codecs, and the chunk decoders versions 1 and 2 share.
// docs/FORMAT.md specifies the bytes.
#ifndef SDCB_IO_SDCB_SDCB_CHUNKS_H_
#define SDCB_IO_SDCB_SDCB_CHUNKS_H_

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/sphere/unit_vector_grid.h"
#include "sdcb/core/spline/model.h"
#include "sdcb/core/spline/spline_model.h"
#include "sdcb/io/sdcb/control_point_quantization.h"
#include "sdcb/io/sdcb/sdcb_file.h"

namespace sdcb::sdcb_internal {

using ChunkType = std::array<char, 4>;

// Chunk types; HEAD first, END last in every version.
constexpr ChunkType kHead = {'H', 'E', 'A', 'D'};
constexpr ChunkType kKnot = {'K', 'N', 'O', 'T'};
constexpr ChunkType kBsis = {'B', 'S', 'I', 'S'};  // version 1 only
constexpr ChunkType kCtrl = {'C', 'T', 'R', 'L'};
constexpr ChunkType kQctl = {'Q', 'C', 'T', 'L'};  // versions 2 and 3
constexpr ChunkType kPctl = {'P', 'C', 'T', 'L'};  // version 3
constexpr ChunkType kQknt = {'Q', 'K', 'N', 'T'};  // version 3
constexpr ChunkType kXfrm = {'X', 'F', 'R', 'M'};
constexpr ChunkType kStat = {'S', 'T', 'A', 'T'};
constexpr ChunkType kSrcm = {'S', 'R', 'C', 'M'};
constexpr ChunkType kParm = {'P', 'A', 'R', 'M'};
constexpr ChunkType kEnd = {'E', 'N', 'D', ' '};
// Version 4: the file's PART chunks (each a chunk sequence of one part) and,
// inside a part, its name and trim loops.
constexpr ChunkType kPart = {'P', 'A', 'R', 'T'};
constexpr ChunkType kName = {'N', 'A', 'M', 'E'};
constexpr ChunkType kTrim = {'T', 'R', 'I', 'M'};
constexpr ChunkType kAsst = {'A', 'S', 'S', 'T'};  // version 4: glTF asset

constexpr size_t kHeaderBytes = 12;      // magic + version
constexpr size_t kChunkFrameBytes = 16;  // type + length + CRC
constexpr size_t kXfrmPayloadBytes = 32;
constexpr size_t kSrcmFixedBytes = 24;
constexpr size_t kPointBytes = 24;      // three f64
constexpr uint64_t kCodeRowBytes = 12;  // three u32 codes
// Counts must also be valid `int` indices.
constexpr uint64_t kMaxCount = 0x7fffffff;

inline std::string Str(uint64_t x) { return std::to_string(x); }

// Printable form of a chunk type for messages: 'HEAD', 'B\x00D!'.
std::string TypeName(const ChunkType& t);

inline Status Corrupt(const std::string& message) {
  return CorruptFileError(message);
}

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
  // Row by row: x, y, z of each point.
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

// Appends type, u64 length, payload and CRC-32 of (type, length, payload).
void AppendChunk(const ChunkType& type, std::string_view payload,
                 ByteWriter* file);

// The payloads of the chunk types a version knows, after framing and CRC
// checks; other types are skipped. A known type occurs at most once, except
// the one `repeated` type (version 4's PART), whose payloads are kept in
// file order.
class Chunks {
 public:
  explicit Chunks(std::vector<ChunkType> known,
                  ChunkType repeated = {'\0', '\0', '\0', '\0'})
      : known_(std::move(known)),
        present_(known_.size(), false),
        payload_(known_.size()),
        repeated_type_(repeated) {}

  // -1 if `t` is not known.
  int IndexOf(const ChunkType& t) const;
  bool Has(const ChunkType& t) const { return present_[IndexOf(t)]; }
  std::string_view Get(const ChunkType& t) const {
    return payload_[IndexOf(t)];
  }
  // False if the type was already set.
  bool Set(int index, std::string_view payload);
  bool IsRepeated(const ChunkType& t) const { return t == repeated_type_; }
  void AddRepeated(std::string_view payload) { repeated_.push_back(payload); }
  const std::vector<std::string_view>& repeated() const { return repeated_; }

 private:
  std::vector<ChunkType> known_;
  std::vector<bool> present_;
  std::vector<std::string_view> payload_;
  ChunkType repeated_type_;
  std::vector<std::string_view> repeated_;
};

// Splits the chunk sequence after the 12-byte header of `bytes`, checking
// framing and CRCs: every chunk lies inside the file, has a valid type and
// CRC, a known type occurs at most once, HEAD comes first, END comes last
// (empty) with nothing after it. `chunks` lists the known types. The
// sequence is bytes[begin, end) (end npos: the end of `bytes`); a version 4
// part's sequence is its PART payload. Byte offsets in messages count from
// the start of `bytes`.
Status SplitChunks(std::string_view bytes, Chunks* chunks,
                   size_t begin = kHeaderBytes,
                   size_t end = std::string_view::npos);

// Each count read from HEAD must be payable by the file before anything is
// allocated for it: count <= kMaxCount and count * bytes_each <=
// expansion * file_size (expansion 1 for stored bytes, the deflate limit for
// packed ones). Fails naming `what`.
Status CheckCount(uint64_t count, uint64_t bytes_each, uint64_t expansion,
                  size_t file_size, const char* what);

// The degree read from HEAD: 0..kMaxSplineDegree, else corrupt.
StatusOr<int> CheckDegree(uint32_t degree);

// Version 1's BSIS payload for `configurations` (the records of
// docs/FORMAT.md, appendix); version 2 hashes these bytes.
std::string BasisPayload(const DelaunayConfigurations& configurations);

// Reads exactly `rows` points (row by row) from `payload`, whose size must be
// 24 * rows; `chunk` and `what` name them in messages.
StatusOr<Eigen::MatrixX3d> ParsePoints(std::string_view payload, uint64_t rows,
                                       const char* chunk, const char* what);

std::string TransformPayload(const NormalizingTransform& t);
StatusOr<NormalizingTransform> ParseTransform(std::string_view payload);
std::string SourcePayload(const SourceMeshInfo& s);
StatusOr<SourceMeshInfo> ParseSource(std::string_view payload);
// The STAT JSON text (io/report/fit_statistics_json.h).
StatusOr<FitStatistics> ParseStatistics(std::string_view json_text);

// Packed payloads (docs/FORMAT.md): u64 inflated length L, then a zlib
// stream of L bytes. Unpacked checks L against `expected` (if >= 0), the
// length the counts imply; `chunk` names it in messages.
std::string Packed(const std::string& inflated);
StatusOr<std::string> Unpacked(std::string_view payload, int64_t expected,
                               const char* chunk);
// Points as doubles by coordinate (all x, then all y, then all z), in byte
// planes, packed; UnpackPoints needs exactly `rows` of them.
std::string PackPoints(const Eigen::MatrixX3d& points);
StatusOr<Eigen::MatrixX3d> UnpackPoints(std::string_view payload, uint64_t rows,
                                        const char* chunk);

// QCTL (zigzag deltas of the previous point's codes, packed) and PCTL
// (codes predicted from the adjacent basis functions', range-coded,
// io/sdcb/control_point_coding.h). The parsers fill `g` and return the stored
// control points; `rows` / the configurations give their number.
std::string QuantizedPayload(const QuantizedControlPoints& q);
StatusOr<Eigen::MatrixX3d> ParseQuantized(std::string_view payload,
                                          uint64_t rows, BasisForm form,
                                          ControlPointQuantization* g);
std::string PredictedPayload(const QuantizedControlPoints& q,
                             const DelaunayConfigurations& configurations);
StatusOr<Eigen::MatrixX3d> ParsePredicted(
    std::string_view payload, const DelaunayConfigurations& configurations,
    BasisForm form, ControlPointQuantization* g);

// QKNT: knots on the octahedral grid of `bits` bits
// (core/sphere/unit_vector_grid.h), 2 x bits bits each; ParseKnotGrid needs
// exactly `rows` knots and sets *grid_bits.
std::string KnotGridPayload(const std::vector<UnitVectorCode>& codes, int bits);
StatusOr<Eigen::MatrixX3d> ParseKnotGrid(std::string_view payload,
                                         uint64_t rows, int* grid_bits);

// Decodes the chunks of a version 1 file (io/sdcb/sdcb_file_v1.cpp).
StatusOr<SplineModel> DecodeVersion1(std::string_view bytes);

// One spline's chunks as versions 2 and 3 store them, shared by those files
// and version 4's parts (io/sdcb/sdcb_file.cpp).
// The chunk types a spline of `version` may hold (QKNT, PCTL from 3 on).
std::vector<ChunkType> SplineChunkTypes(uint32_t version);
// Appends HEAD, KNOT or QKNT, CTRL or QCTL or PCTL, XFRM, STAT, SRCM and
// PARM (not END) for `model` to `file`; returns the lowest version (2 or 3)
// that holds them and sets info->quantization and info->knot_grid_bits.
// kInvalidArgument as SerializeSdcb.
StatusOr<uint32_t> AppendSplineChunks(const SplineModel& model,
                                      const SdcbWriteOptions& options,
                                      ByteWriter* file, SdcbFileInfo* info);
// Decodes a spline from split chunks (SplineChunkTypes(version) known);
// version 3 must use QKNT or PCTL, version 4 (a part) may. `file_size`
// bounds HEAD's counts. Sets file_info->quantization and knot_grid_bits.
StatusOr<SplineModel> DecodeSplineChunks(const Chunks& chunks, uint32_t version,
                                         size_t file_size,
                                         SdcbFileInfo* file_info);

// The bytes of the file at `path`; kIoError naming it if it cannot be read.
StatusOr<std::string> ReadFileBytes(const std::string& path);

// Decodes a version 4 file (io/sdcb/sdcb_model_file.cpp) and fills all of
// *info.
StatusOr<Model> DecodeVersion4(std::string_view bytes, SdcbFileInfo* info);

}  // namespace sdcb::sdcb_internal

#endif  // SDCB_IO_SDCB_SDCB_CHUNKS_H_
