#include "sdcb/io/sdcb/sdcb_file.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/spline/delaunay_configurations.h"
#include "sdcb/io/common/atomic_file.h"
#include "sdcb/io/report/fit_statistics_json.h"
#include "sdcb/io/sdcb/byte_packing.h"
#include "sdcb/io/sdcb/sdcb_chunks.h"

namespace sdcb {
namespace {

using namespace sdcb_internal;  // NOLINT: the chunk codec of this file

// Version 2 (docs/FORMAT.md).
constexpr size_t kHeadPayloadBytes = 40;

std::string Hex64(uint64_t v) {
  char buffer[19];
  std::snprintf(buffer, sizeof buffer, "0x%016llx",
                static_cast<unsigned long long>(v));
  return buffer;
}

StatusOr<QuantizedControlPoints> QuantizeForOptions(
    const SplineModel& model, const SdcbWriteOptions& options) {
  if (options.quantize_bits != kQuantizeBitsAuto) {
    return QuantizeControlPoints(model, options.quantize_bits);
  }
  const double rms = model.statistics.final_result.rmse_percent / 100;
  const double fraction = options.quantize_fraction_of_rms;
  if (!(rms > 0) || !std::isfinite(rms) || !(fraction > 0) ||
      !std::isfinite(fraction)) {
    return InvalidArgumentError(
        "cannot choose the quantization bits: it needs the fit's rms (> 0) "
        "and a fraction of it > 0");
  }
  return QuantizeControlPointsWithin(model, fraction * rms);
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

StatusOr<Head> ParseHead(std::string_view payload, uint32_t version,
                         size_t file_size) {
  if (payload.size() != kHeadPayloadBytes) {
    return Corrupt("the HEAD chunk has " + Str(payload.size()) +
                   " bytes; version " + Str(version) + " needs " +
                   Str(kHeadPayloadBytes));
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

}  // namespace

namespace sdcb_internal {

std::vector<ChunkType> SplineChunkTypes(uint32_t version) {
  std::vector<ChunkType> known = {kHead, kKnot, kCtrl, kQctl, kXfrm,
                                  kStat, kSrcm, kParm, kEnd};
  if (version >= 3) {
    known.push_back(kQknt);
    known.push_back(kPctl);
  }
  return known;
}

StatusOr<SplineModel> DecodeSplineChunks(const Chunks& chunks, uint32_t version,
                                         size_t file_size,
                                         SdcbFileInfo* file_info) {
  ControlPointQuantization* quantization = &file_info->quantization;
  for (const ChunkType& required : {kXfrm, kSrcm, kEnd}) {
    if (!chunks.Has(required)) {
      return Corrupt("the required chunk " + TypeName(required) +
                     " is missing");
    }
  }
  const bool knot_grid = version >= 3 && chunks.Has(kQknt);
  if (chunks.Has(kKnot) == knot_grid) {
    return Corrupt(knot_grid ? "the file has both a 'KNOT' and a 'QKNT' chunk"
                   : version >= 3
                       ? "the required chunk 'KNOT' (or 'QKNT') is missing"
                       : "the required chunk 'KNOT' is missing");
  }
  const bool predicted = version >= 3 && chunks.Has(kPctl);
  std::vector<std::string> control;
  for (const ChunkType& t : {kCtrl, kQctl, kPctl}) {
    if (chunks.IndexOf(t) >= 0 && chunks.Has(t)) control.push_back(TypeName(t));
  }
  if (control.empty()) {
    return Corrupt(std::string("the required chunk 'CTRL' (or 'QCTL'") +
                   (version >= 3 ? ", 'PCTL'" : "") + ") is missing");
  }
  if (control.size() == 2) {
    return Corrupt("the file has both a " + control[0] + " and a " +
                   control[1] + " chunk");
  }
  if (control.size() == 3) {
    return Corrupt("the file has a 'CTRL', a 'QCTL' and a 'PCTL' chunk");
  }
  // A writer uses version 3 only for its chunks (SerializeSdcb writes the
  // lowest version that holds the file); a version 4 part may use any.
  if (version == 3 && !knot_grid && !predicted) {
    return Corrupt(
        "a version 3 file needs a 'QKNT' or a 'PCTL' chunk (without them it "
        "would be version 2)");
  }
  SDCB_ASSIGN_OR_RETURN(const Head head,
                        ParseHead(chunks.Get(kHead), version, file_size));
  SplineModel m;
  m.degree = head.degree;
  m.basis_form = head.basis_form;
  if (knot_grid) {
    SDCB_ASSIGN_OR_RETURN(m.knots,
                          ParseKnotGrid(chunks.Get(kQknt), head.num_knots,
                                        &file_info->knot_grid_bits));
  } else {
    SDCB_ASSIGN_OR_RETURN(
        m.knots, UnpackPoints(chunks.Get(kKnot), head.num_knots, "KNOT"));
  }
  if (chunks.Has(kCtrl)) {
    SDCB_ASSIGN_OR_RETURN(
        m.control_points,
        UnpackPoints(chunks.Get(kCtrl), head.num_basis, "CTRL"));
  } else if (chunks.Has(kQctl)) {
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
  // PCTL's prediction follows the configurations: decoded once they are
  // known to be the writer's.
  if (predicted) {
    SDCB_ASSIGN_OR_RETURN(m.control_points,
                          ParsePredicted(chunks.Get(kPctl), m.configurations,
                                         head.basis_form, quantization));
  }
  const Status valid = ValidateSplineModel(m);
  if (!valid.ok()) return Corrupt("invalid model: " + valid.message());
  return m;
}

}  // namespace sdcb_internal

namespace {

// Versions 2 and 3 (version 3 adds QKNT and PCTL).
StatusOr<SplineModel> DecodeVersion2Or3(std::string_view bytes,
                                        uint32_t version,
                                        SdcbFileInfo* file_info) {
  Chunks chunks(SplineChunkTypes(version));
  SDCB_RETURN_IF_ERROR(SplitChunks(bytes, &chunks));
  return DecodeSplineChunks(chunks, version, bytes.size(), file_info);
}

}  // namespace

uint64_t HashConfigurations(const DelaunayConfigurations& configurations) {
  const std::string bytes = BasisPayload(configurations);
  return Fnv1a64(bytes.data(), bytes.size());
}

namespace sdcb_internal {

StatusOr<uint32_t> AppendSplineChunks(const SplineModel& model,
                                      const SdcbWriteOptions& options,
                                      ByteWriter* file, SdcbFileInfo* info) {
  const Status valid = ValidateSplineModel(model);
  if (!valid.ok()) {
    return InvalidArgumentError("cannot write an invalid model: " +
                                valid.message());
  }
  if (options.quantize_bits != 0 &&
      options.quantize_bits != kQuantizeBitsAuto &&
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
  if (options.format_version != 2 && options.format_version != 3) {
    return InvalidArgumentError("cannot write .sdcb format version " +
                                Str(options.format_version) +
                                "; versions 2 and 3 are written");
  }
  const bool version3 = options.format_version == 3;
  ControlPointQuantization quantization;
  ChunkType control_type = kCtrl;
  std::string control_points;
  if (options.quantize_bits == 0) {
    control_points = PackPoints(model.control_points);
  } else {
    SDCB_ASSIGN_OR_RETURN(const QuantizedControlPoints q,
                          QuantizeForOptions(model, options));
    control_type = version3 ? kPctl : kQctl;
    control_points = version3 ? PredictedPayload(q, model.configurations)
                              : QuantizedPayload(q);
    quantization = q.quantization;
  }
  // Knots a fit snapped to its grid are stored as their grid codes.
  const int grid_bits = model.statistics.options.knot_grid_bits;
  std::vector<UnitVectorCode> knot_codes;
  if (version3 && grid_bits >= kMinUnitVectorGridBits &&
      grid_bits <= kMaxUnitVectorGridBits) {
    for (Eigen::Index i = 0; i < model.knots.rows(); ++i) {
      UnitVectorCode code;
      if (!IsOnUnitVectorGrid(model.knots.row(i).transpose(), grid_bits,
                              &code)) {
        knot_codes.clear();
        break;
      }
      knot_codes.push_back(code);
    }
  }
  const bool knot_grid = !knot_codes.empty();
  const uint32_t version = knot_grid || control_type == kPctl ? 3 : 2;
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

  AppendChunk(kHead, HeadPayload(head), file);
  if (knot_grid) {
    AppendChunk(kQknt, KnotGridPayload(knot_codes, grid_bits), file);
  } else {
    AppendChunk(kKnot, PackPoints(model.knots), file);
  }
  AppendChunk(control_type, control_points, file);
  AppendChunk(kXfrm, TransformPayload(model.transform), file);
  AppendChunk(kStat, Packed(FitStatisticsToJson(model.statistics).dump()),
              file);
  AppendChunk(kSrcm, SourcePayload(model.source), file);
  if (parameters) AppendChunk(kParm, PackPoints(model.parameters), file);
  info->quantization = quantization;
  info->knot_grid_bits = knot_grid ? grid_bits : 0;
  return version;
}

}  // namespace sdcb_internal

StatusOr<std::string> SerializeSdcb(const SplineModel& model,
                                    const SdcbWriteOptions& options,
                                    SdcbFileInfo* info) {
  ByteWriter chunks;
  SdcbFileInfo written;
  SDCB_ASSIGN_OR_RETURN(const uint32_t version,
                        AppendSplineChunks(model, options, &chunks, &written));
  ByteWriter file;
  file.Bytes(std::string_view(kSdcbMagic, sizeof kSdcbMagic));
  file.U32(version);
  file.Bytes(chunks.str());
  AppendChunk(kEnd, std::string_view(), &file);
  if (info != nullptr) {
    *info = written;
    info->format_version = version;
    info->file_bytes = file.str().size();
    info->parts = {{written.quantization, written.knot_grid_bits}};
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
  SdcbFileInfo decoded;
  if (version >= 4) {
    // A one-part model of one untrimmed part reads as its spline.
    SDCB_ASSIGN_OR_RETURN(Model model, DecodeVersion4(bytes, &decoded));
    const size_t parts = model.parts.size();
    if (parts > 1 || model.parts[0].trimmed() || model.parts[0].kept) {
      return UnsupportedError(
          "the file holds " +
          (parts > 1                  ? Str(parts) + " parts"
           : model.parts[0].trimmed() ? std::string("a trimmed part")
                                      : std::string("a kept (unfitted) part")) +
          "; this reads only models of one closed part (`sdcb info` lists "
          "the parts)");
    }
    if (info != nullptr) *info = decoded;
    return std::move(model.parts[0].spline);
  }
  StatusOr<SplineModel> model =
      version == 1 ? DecodeVersion1(bytes)
                   : DecodeVersion2Or3(bytes, version, &decoded);
  if (model.ok() && info != nullptr) {
    *info = decoded;
    info->format_version = version;
    info->file_bytes = bytes.size();
    info->parts = {{decoded.quantization, decoded.knot_grid_bits}};
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
  SDCB_ASSIGN_OR_RETURN(const std::string bytes, ReadFileBytes(path));
  StatusOr<SplineModel> model = ParseSdcb(bytes, info);
  if (!model.ok()) return model.status().WithPrefix(path);
  return model;
}

namespace sdcb_internal {

StatusOr<std::string> ReadFileBytes(const std::string& path) {
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
  return bytes;
}

}  // namespace sdcb_internal

}  // namespace sdcb
