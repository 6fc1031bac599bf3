#include "sdcb/io/sdcb_file.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/spline/delaunay_configurations.h"
#include "sdcb/io/atomic_file.h"
#include "sdcb/io/byte_packing.h"
#include "sdcb/io/fit_statistics_json.h"
#include "sdcb/io/sdcb_chunks.h"

namespace sdcb {
namespace {

using namespace sdcb_internal;  // NOLINT: the chunk codec of this file

// Version 2 (docs/FORMAT.md).
constexpr size_t kHeadPayloadBytes = 40;
constexpr size_t kPackedLengthBytes = 8;  // u64 inflated length
// QCTL before its packed codes: u32 bits, 3 f64 origin, 3 f64 step, f64 D,
// f64 max basis sum.
constexpr size_t kQctlFixedBytes = 4 + 24 + 24 + 8 + 8;
constexpr uint64_t kCodeRowBytes = 12;  // three u32 codes

std::string Hex64(uint64_t v) {
  char buffer[19];
  std::snprintf(buffer, sizeof buffer, "0x%016llx",
                static_cast<unsigned long long>(v));
  return buffer;
}

// ---------------------------------------------------------------------------
// Packed payloads: u64 inflated length L, then a zlib stream of L bytes.

std::string Packed(const std::string& inflated) {
  ByteWriter w;
  w.U64(inflated.size());
  w.Bytes(ZlibCompress(inflated));
  return std::move(w.str());
}

// Inflates a packed payload; `expected` (if >= 0) is the length the counts
// imply.
StatusOr<std::string> Unpacked(std::string_view payload, int64_t expected,
                               const char* chunk) {
  ByteReader r(payload);
  uint64_t length = 0;
  if (!r.U64(&length)) {
    return Corrupt(std::string("the ") + chunk + " chunk has " +
                   Str(payload.size()) +
                   " bytes, too few for its inflated length");
  }
  if (expected >= 0 && length != static_cast<uint64_t>(expected)) {
    return Corrupt(std::string("the ") + chunk + " chunk declares " +
                   Str(length) + " inflated bytes; HEAD's counts need " +
                   Str(expected));
  }
  StatusOr<std::string> inflated = ZlibDecompress(r.Rest(), length);
  if (!inflated.ok()) {
    return Corrupt(std::string("the ") + chunk +
                   " chunk: " + inflated.status().message());
  }
  return inflated;
}

// Points as doubles by coordinate (all x, then all y, then all z), in byte
// planes.
std::string PackPoints(const Eigen::MatrixX3d& points) {
  ByteWriter w;
  for (int c = 0; c < 3; ++c) {
    for (Eigen::Index i = 0; i < points.rows(); ++i) w.F64(points(i, c));
  }
  return Packed(ToBytePlanes(w.str(), 8));
}

StatusOr<Eigen::MatrixX3d> UnpackPoints(std::string_view payload, uint64_t rows,
                                        const char* chunk) {
  SDCB_ASSIGN_OR_RETURN(
      const std::string planes,
      Unpacked(payload, static_cast<int64_t>(rows * kPointBytes), chunk));
  const std::string values = FromBytePlanes(planes, 8);
  ByteReader r(values);
  Eigen::MatrixX3d m(static_cast<Eigen::Index>(rows), 3);
  for (int c = 0; c < 3; ++c) {
    for (Eigen::Index i = 0; i < m.rows(); ++i) (void)r.F64(&m(i, c));
  }
  return m;
}

// Zigzag code of a difference taken modulo 2^32 (read as int32): small
// differences of either sign give small codes.
uint32_t Zigzag(uint32_t difference) {
  return (difference << 1) ^ (0u - (difference >> 31));
}
uint32_t Unzigzag(uint32_t z) { return (z >> 1) ^ (0u - (z & 1u)); }

// QCTL: the grid, then the codes of each coordinate as zigzag differences
// from the previous control point's (control points of neighbouring sets
// share knots and lie close), u32 in byte planes.
std::string QuantizedPayload(const QuantizedControlPoints& q) {
  ByteWriter w;
  const ControlPointQuantization& g = q.quantization;
  w.U32(static_cast<uint32_t>(g.bits));
  for (int c = 0; c < 3; ++c) w.F64(g.origin[c]);
  for (int c = 0; c < 3; ++c) w.F64(g.step[c]);
  w.F64(g.max_displacement);
  w.F64(g.max_basis_sum);
  ByteWriter codes;
  const size_t rows = q.codes.size() / 3;
  for (int c = 0; c < 3; ++c) {
    uint32_t previous = 0;
    for (size_t i = 0; i < rows; ++i) {
      const uint32_t code = q.codes[c * rows + i];
      codes.U32(Zigzag(code - previous));
      previous = code;
    }
  }
  w.Bytes(Packed(ToBytePlanes(codes.str(), 4)));
  return std::move(w.str());
}

StatusOr<Eigen::MatrixX3d> ParseQuantized(std::string_view payload,
                                          uint64_t rows, BasisForm form,
                                          ControlPointQuantization* g) {
  if (payload.size() < kQctlFixedBytes) {
    return Corrupt("the QCTL chunk has " + Str(payload.size()) +
                   " bytes; it needs at least " + Str(kQctlFixedBytes));
  }
  ByteReader r(payload);
  uint32_t bits = 0;
  (void)r.U32(&bits);
  for (int c = 0; c < 3; ++c) (void)r.F64(&g->origin[c]);
  for (int c = 0; c < 3; ++c) (void)r.F64(&g->step[c]);
  (void)r.F64(&g->max_displacement);
  (void)r.F64(&g->max_basis_sum);
  if (bits < kMinQuantizationBits || bits > kMaxQuantizationBits) {
    return Corrupt("the QCTL chunk declares " + Str(bits) + " bits; " +
                   Str(kMinQuantizationBits) + ".." +
                   Str(kMaxQuantizationBits) + " are valid");
  }
  g->bits = static_cast<int>(bits);
  if (!g->origin.allFinite() || !g->step.allFinite() ||
      (g->step.array() < 0).any()) {
    return Corrupt(
        "the QCTL chunk's grid needs a finite origin and finite steps >= 0");
  }
  g->basis_sum_measured = form == BasisForm::kRaw;
  if (!std::isfinite(g->max_displacement) || !(g->max_displacement >= 0) ||
      !std::isfinite(g->max_basis_sum) ||
      (form == BasisForm::kNormalized ? g->max_basis_sum != 1.0
                                      : !(g->max_basis_sum > 0))) {
    return Corrupt(
        "the QCTL chunk's error bound is invalid (the displacement must be "
        "finite and >= 0, the basis sum 1 for the normalized basis, finite "
        "and > 0 for the raw one)");
  }
  SDCB_ASSIGN_OR_RETURN(
      const std::string planes,
      Unpacked(r.Rest(), static_cast<int64_t>(rows * kCodeRowBytes), "QCTL"));
  const std::string zigzags = FromBytePlanes(planes, 4);
  ByteReader codes_reader(zigzags);
  std::vector<uint32_t> codes(3 * rows);
  const uint64_t top = (uint64_t{1} << bits) - 1;
  for (int c = 0; c < 3; ++c) {
    uint32_t previous = 0;
    for (uint64_t i = 0; i < rows; ++i) {
      uint32_t z = 0;
      (void)codes_reader.U32(&z);
      const uint32_t code = previous + Unzigzag(z);
      if (code > top) {
        return Corrupt("the QCTL chunk's code " + Str(code) +
                       " of control point " + Str(i) + " exceeds " + Str(bits) +
                       " bits");
      }
      codes[c * rows + i] = code;
      previous = code;
    }
  }
  return DequantizeControlPoints(g->origin, g->step, codes);
}

// ---------------------------------------------------------------------------
// Version 2.

struct Head {
  int degree = 0;
  BasisForm basis_form = BasisForm::kNormalized;
  uint64_t num_knots = 0;
  uint64_t num_basis = 0;
  uint64_t num_parameters = 0;
  uint64_t configuration_hash = 0;
};

std::string HeadPayload(const Head& h) {
  ByteWriter w;
  w.U32(static_cast<uint32_t>(h.degree));
  w.U32(static_cast<uint32_t>(h.basis_form));
  w.U64(h.num_knots);
  w.U64(h.num_basis);
  w.U64(h.num_parameters);
  w.U64(h.configuration_hash);
  return std::move(w.str());
}

StatusOr<Head> ParseHead(std::string_view payload, size_t file_size) {
  if (payload.size() != kHeadPayloadBytes) {
    return Corrupt("the HEAD chunk has " + Str(payload.size()) +
                   " bytes; version 2 needs " + Str(kHeadPayloadBytes));
  }
  ByteReader r(payload);
  uint32_t degree = 0, form = 0;
  Head h;
  (void)r.U32(&degree);
  (void)r.U32(&form);
  (void)r.U64(&h.num_knots);
  (void)r.U64(&h.num_basis);
  (void)r.U64(&h.num_parameters);
  (void)r.U64(&h.configuration_hash);
  SDCB_ASSIGN_OR_RETURN(h.degree, CheckDegree(degree));
  if (form != static_cast<uint32_t>(BasisForm::kNormalized) &&
      form != static_cast<uint32_t>(BasisForm::kRaw)) {
    return Corrupt("HEAD declares the unknown basis form " + Str(form));
  }
  h.basis_form = static_cast<BasisForm>(form);
  // Packed data inflates at most kMaxDeflateRatio-fold.
  SDCB_RETURN_IF_ERROR(CheckCount(h.num_knots, kPointBytes, kMaxDeflateRatio,
                                  file_size, "knots"));
  SDCB_RETURN_IF_ERROR(CheckCount(h.num_basis, kCodeRowBytes, kMaxDeflateRatio,
                                  file_size, "basis functions"));
  SDCB_RETURN_IF_ERROR(CheckCount(h.num_parameters, kPointBytes,
                                  kMaxDeflateRatio, file_size,
                                  "sphere parameters"));
  return h;
}

// Describes the first difference between two configuration lists, or "".
std::string ConfigurationDifference(const DelaunayConfigurations& a,
                                    const DelaunayConfigurations& b) {
  if (a.degree != b.degree) return "their degrees differ";
  if (a.sets.size() != b.sets.size()) {
    return Str(a.sets.size()) + " basis functions instead of " +
           Str(b.sets.size());
  }
  for (size_t i = 0; i < a.sets.size(); ++i) {
    if (a.sets[i].knots != b.sets[i].knots ||
        a.sets[i].boundaries != b.sets[i].boundaries) {
      return "basis function " + Str(i) + " differs";
    }
  }
  return "";
}

StatusOr<SplineModel> DecodeVersion2(std::string_view bytes,
                                     ControlPointQuantization* quantization) {
  Chunks chunks({kHead, kKnot, kCtrl, kQctl, kXfrm, kStat, kSrcm, kParm, kEnd});
  SDCB_RETURN_IF_ERROR(SplitChunks(bytes, &chunks));
  for (const ChunkType& required : {kKnot, kXfrm, kSrcm, kEnd}) {
    if (!chunks.Has(required)) {
      return Corrupt("the required chunk " + TypeName(required) +
                     " is missing");
    }
  }
  if (chunks.Has(kCtrl) == chunks.Has(kQctl)) {
    return Corrupt(chunks.Has(kCtrl)
                       ? "the file has both a 'CTRL' and a 'QCTL' chunk"
                       : "the required chunk 'CTRL' (or 'QCTL') is missing");
  }
  SDCB_ASSIGN_OR_RETURN(const Head head,
                        ParseHead(chunks.Get(kHead), bytes.size()));
  SplineModel m;
  m.degree = head.degree;
  m.basis_form = head.basis_form;
  SDCB_ASSIGN_OR_RETURN(
      m.knots, UnpackPoints(chunks.Get(kKnot), head.num_knots, "KNOT"));
  if (chunks.Has(kCtrl)) {
    SDCB_ASSIGN_OR_RETURN(
        m.control_points,
        UnpackPoints(chunks.Get(kCtrl), head.num_basis, "CTRL"));
  } else {
    SDCB_ASSIGN_OR_RETURN(m.control_points,
                          ParseQuantized(chunks.Get(kQctl), head.num_basis,
                                         head.basis_form, quantization));
  }
  SDCB_ASSIGN_OR_RETURN(m.transform, ParseTransform(chunks.Get(kXfrm)));
  if (chunks.Has(kStat)) {
    SDCB_ASSIGN_OR_RETURN(const std::string json,
                          Unpacked(chunks.Get(kStat), -1, "STAT"));
    SDCB_ASSIGN_OR_RETURN(m.statistics, ParseStatistics(json));
  }
  SDCB_ASSIGN_OR_RETURN(m.source, ParseSource(chunks.Get(kSrcm)));
  if (chunks.Has(kParm) != (head.num_parameters > 0)) {
    return Corrupt("HEAD declares " + Str(head.num_parameters) +
                   " sphere parameters but the PARM chunk is " +
                   (chunks.Has(kParm) ? "present" : "missing"));
  }
  if (chunks.Has(kParm)) {
    SDCB_ASSIGN_OR_RETURN(
        m.parameters,
        UnpackPoints(chunks.Get(kParm), head.num_parameters, "PARM"));
  }

  // The configurations: recomputed from the knots (the costly step, last).
  if (m.knots.rows() < m.degree + 4) {
    return Corrupt("invalid model: the model has " + Str(m.knots.rows()) +
                   " knots; degree " + Str(m.degree) + " needs at least " +
                   Str(m.degree + 4));
  }
  if (const Eigen::Index bad = FirstNonUnitRow(m.knots); bad >= 0) {
    return Corrupt("invalid model: knot " + Str(bad) + " is not a unit vector");
  }
  StatusOr<DelaunayConfigurations> configurations =
      ComputeDelaunayConfigurations(m.knots, m.degree);
  if (!configurations.ok()) {
    return Corrupt("the configurations cannot be recomputed from the knots: " +
                   configurations.status().message());
  }
  m.configurations = std::move(*configurations);
  if (m.configurations.sets.size() != head.num_basis) {
    return Corrupt("the knots define " + Str(m.configurations.sets.size()) +
                   " basis functions but HEAD declares " + Str(head.num_basis));
  }
  const uint64_t hash = HashConfigurations(m.configurations);
  if (hash != head.configuration_hash) {
    return Corrupt("the configurations recomputed from the knots have hash " +
                   Hex64(hash) + ", not the file's " +
                   Hex64(head.configuration_hash) +
                   " (corrupt file, or written with other configurations)");
  }
  const Status valid = ValidateSplineModel(m);
  if (!valid.ok()) return Corrupt("invalid model: " + valid.message());
  return m;
}

}  // namespace

uint64_t HashConfigurations(const DelaunayConfigurations& configurations) {
  const std::string bytes = BasisPayload(configurations);
  return Fnv1a64(bytes.data(), bytes.size());
}

StatusOr<std::string> SerializeSdcb(const SplineModel& model,
                                    const SdcbWriteOptions& options,
                                    SdcbFileInfo* info) {
  const Status valid = ValidateSplineModel(model);
  if (!valid.ok()) {
    return InvalidArgumentError("cannot write an invalid model: " +
                                valid.message());
  }
  if (options.quantize_bits != 0 &&
      (options.quantize_bits < kMinQuantizationBits ||
       options.quantize_bits > kMaxQuantizationBits)) {
    return InvalidArgumentError("cannot quantize control points to " +
                                std::to_string(options.quantize_bits) +
                                " bits; 0 (exact) or " +
                                Str(kMinQuantizationBits) + ".." +
                                Str(kMaxQuantizationBits) + " are supported");
  }
  // Version 2 stores only what the reader cannot recompute: refuse a model
  // whose configurations the reader would not reproduce.
  StatusOr<DelaunayConfigurations> recomputed =
      ComputeDelaunayConfigurations(model.knots, model.degree);
  if (!recomputed.ok()) {
    return InvalidArgumentError(
        "cannot write the model: its knots do not define configurations: " +
        recomputed.status().message());
  }
  const std::string difference =
      ConfigurationDifference(model.configurations, *recomputed);
  if (!difference.empty()) {
    return InvalidArgumentError(
        "cannot write the model: its configurations are not those of its "
        "knots (the model has " +
        difference + ")");
  }
  ControlPointQuantization quantization;
  std::string control_points;
  if (options.quantize_bits == 0) {
    control_points = PackPoints(model.control_points);
  } else {
    SDCB_ASSIGN_OR_RETURN(const QuantizedControlPoints q,
                          QuantizeControlPoints(model, options.quantize_bits));
    control_points = QuantizedPayload(q);
    quantization = q.quantization;
  }
  const bool parameters =
      options.store_parameters && model.parameters.rows() > 0;
  Head head;
  head.degree = model.degree;
  head.basis_form = model.basis_form;
  head.num_knots = static_cast<uint64_t>(model.knots.rows());
  head.num_basis = model.configurations.sets.size();
  head.num_parameters =
      parameters ? static_cast<uint64_t>(model.parameters.rows()) : 0;
  head.configuration_hash = HashConfigurations(model.configurations);

  ByteWriter file;
  file.Bytes(std::string_view(kSdcbMagic, sizeof kSdcbMagic));
  file.U32(kSdcbFormatVersion);
  AppendChunk(kHead, HeadPayload(head), &file);
  AppendChunk(kKnot, PackPoints(model.knots), &file);
  AppendChunk(quantization.lossless() ? kCtrl : kQctl, control_points, &file);
  AppendChunk(kXfrm, TransformPayload(model.transform), &file);
  AppendChunk(kStat, Packed(FitStatisticsToJson(model.statistics).dump()),
              &file);
  AppendChunk(kSrcm, SourcePayload(model.source), &file);
  if (parameters) AppendChunk(kParm, PackPoints(model.parameters), &file);
  AppendChunk(kEnd, std::string_view(), &file);
  if (info != nullptr) {
    info->format_version = kSdcbFormatVersion;
    info->file_bytes = file.str().size();
    info->quantization = quantization;
  }
  return std::move(file.str());
}

StatusOr<SplineModel> ParseSdcb(std::string_view bytes, SdcbFileInfo* info) {
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
  ControlPointQuantization quantization;
  StatusOr<SplineModel> model = version == 1
                                    ? DecodeVersion1(bytes)
                                    : DecodeVersion2(bytes, &quantization);
  if (model.ok() && info != nullptr) {
    info->format_version = version;
    info->file_bytes = bytes.size();
    info->quantization = quantization;
  }
  return model;
}

Status WriteSdcbFile(const SplineModel& model, const std::string& path,
                     const SdcbWriteOptions& options, SdcbFileInfo* info) {
  StatusOr<std::string> bytes = SerializeSdcb(model, options, info);
  if (!bytes.ok()) return bytes.status().WithPrefix(path);
  return WriteFileAtomically(*bytes, path);
}

StatusOr<SplineModel> ReadSdcbFile(const std::string& path,
                                   SdcbFileInfo* info) {
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
  StatusOr<SplineModel> model = ParseSdcb(bytes, info);
  if (!model.ok()) return model.status().WithPrefix(path);
  return model;
}

}  // namespace sdcb
