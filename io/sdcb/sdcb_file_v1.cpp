// Reading `.sdcb` format version 1 (docs/FORMAT.md, appendix A): stored
// configurations (BSIS), uncompressed doubles, always the normalized basis.
// This code no longer writes version 1.
#include "sdcb/io/sdcb/sdcb_chunks.h"

namespace sdcb::sdcb_internal {
namespace {

constexpr size_t kHeadPayloadBytes = 28;

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
  SDCB_ASSIGN_OR_RETURN(h.degree, CheckDegree(degree));
  SDCB_RETURN_IF_ERROR(
      CheckCount(h.num_knots, kPointBytes, 1, file_size, "knots"));
  SDCB_RETURN_IF_ERROR(CheckCount(h.num_basis,
                                  BasisRecordBytes(h.degree, 1) + kPointBytes,
                                  1, file_size, "basis functions"));
  SDCB_RETURN_IF_ERROR(CheckCount(h.num_parameters, kPointBytes, 1, file_size,
                                  "sphere parameters"));
  return h;
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

}  // namespace

StatusOr<SplineModel> DecodeVersion1(std::string_view bytes) {
  Chunks chunks({kHead, kKnot, kBsis, kCtrl, kXfrm, kStat, kSrcm, kParm, kEnd});
  SDCB_RETURN_IF_ERROR(SplitChunks(bytes, &chunks));
  for (const ChunkType& required : {kKnot, kBsis, kCtrl, kXfrm, kSrcm, kEnd}) {
    if (!chunks.Has(required)) {
      return Corrupt("the required chunk " + TypeName(required) +
                     " is missing");
    }
  }
  SDCB_ASSIGN_OR_RETURN(const Head head,
                        ParseHead(chunks.Get(kHead), bytes.size()));
  SplineModel m;
  m.degree = head.degree;
  m.basis_form = BasisForm::kNormalized;
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

}  // namespace sdcb::sdcb_internal
