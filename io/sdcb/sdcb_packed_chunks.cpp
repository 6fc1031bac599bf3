// The packed and quantized payloads of `.sdcb` format versions 2 and 3
// (docs/FORMAT.md, "Packed payloads", QCTL, PCTL, QKNT): declared in
// io/sdcb/sdcb_chunks.h.
#include <cmath>

#include "sdcb/core/sphere/unit_vector_grid.h"
#include "sdcb/io/sdcb/byte_packing.h"
#include "sdcb/io/sdcb/control_point_coding.h"
#include "sdcb/io/sdcb/range_coder.h"
#include "sdcb/io/sdcb/sdcb_chunks.h"

namespace sdcb::sdcb_internal {
namespace {

// QCTL / PCTL before their codes: u32 bits, 3 f64 origin, 3 f64 step, f64
// D, f64 max basis sum.
constexpr size_t kQctlFixedBytes = 4 + 24 + 24 + 8 + 8;

}  // namespace

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
                   Str(length) + " inflated bytes; the declared counts need " +
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

// The grid and bound that QCTL and PCTL start with.
void WriteGrid(const ControlPointQuantization& g, ByteWriter* w) {
  w->U32(static_cast<uint32_t>(g.bits));
  for (int c = 0; c < 3; ++c) w->F64(g.origin[c]);
  for (int c = 0; c < 3; ++c) w->F64(g.step[c]);
  w->F64(g.max_displacement);
  w->F64(g.max_basis_sum);
}

// QCTL (version 2): the grid, then the codes of each coordinate as zigzag
// differences from the previous control point's, u32 in byte planes.
std::string QuantizedPayload(const QuantizedControlPoints& q) {
  ByteWriter w;
  WriteGrid(q.quantization, &w);
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

// The grid and bound of a QCTL or PCTL payload (`chunk`); returns the rest.
StatusOr<std::string_view> ParseGrid(std::string_view payload, BasisForm form,
                                     const char* chunk,
                                     ControlPointQuantization* g) {
  if (payload.size() < kQctlFixedBytes) {
    return Corrupt(std::string("the ") + chunk + " chunk has " +
                   Str(payload.size()) + " bytes; it needs at least " +
                   Str(kQctlFixedBytes));
  }
  ByteReader r(payload);
  uint32_t bits = 0;
  (void)r.U32(&bits);
  for (int c = 0; c < 3; ++c) (void)r.F64(&g->origin[c]);
  for (int c = 0; c < 3; ++c) (void)r.F64(&g->step[c]);
  (void)r.F64(&g->max_displacement);
  (void)r.F64(&g->max_basis_sum);
  if (bits < kMinQuantizationBits || bits > kMaxQuantizationBits) {
    return Corrupt(std::string("the ") + chunk + " chunk declares " +
                   Str(bits) + " bits; " + Str(kMinQuantizationBits) + ".." +
                   Str(kMaxQuantizationBits) + " are valid");
  }
  g->bits = static_cast<int>(bits);
  if (!g->origin.allFinite() || !g->step.allFinite() ||
      (g->step.array() < 0).any()) {
    return Corrupt(std::string("the ") + chunk +
                   " chunk's grid needs a finite origin and finite steps >= 0");
  }
  g->basis_sum_measured = form == BasisForm::kRaw;
  if (!std::isfinite(g->max_displacement) || !(g->max_displacement >= 0) ||
      !std::isfinite(g->max_basis_sum) ||
      (form == BasisForm::kNormalized ? g->max_basis_sum != 1.0
                                      : !(g->max_basis_sum > 0))) {
    return Corrupt(
        std::string("the ") + chunk +
        " chunk's error bound is invalid (the displacement must be "
        "finite and >= 0, the basis sum 1 for the normalized basis, finite "
        "and > 0 for the raw one)");
  }
  return r.Rest();
}

StatusOr<Eigen::MatrixX3d> ParseQuantized(std::string_view payload,
                                          uint64_t rows, BasisForm form,
                                          ControlPointQuantization* g) {
  SDCB_ASSIGN_OR_RETURN(const std::string_view rest,
                        ParseGrid(payload, form, "QCTL", g));
  const uint32_t bits = static_cast<uint32_t>(g->bits);
  SDCB_ASSIGN_OR_RETURN(
      const std::string planes,
      Unpacked(rest, static_cast<int64_t>(rows * kCodeRowBytes), "QCTL"));
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
// QKNT: u32 bits, then per knot its two grid coordinates of `bits` bits
// each, packed most significant bit first, zero bits up to the byte.

std::string KnotGridPayload(const std::vector<UnitVectorCode>& codes,
                            int bits) {
  ByteWriter w;
  w.U32(static_cast<uint32_t>(bits));
  uint64_t buffer = 0;
  int filled = 0;
  std::string packed;
  auto put = [&](uint32_t value) {
    buffer = (buffer << bits) | value;
    filled += bits;
    while (filled >= 8) {
      filled -= 8;
      packed += static_cast<char>((buffer >> filled) & 0xFF);
    }
  };
  for (const UnitVectorCode& c : codes) {
    put(c.a);
    put(c.b);
  }
  if (filled > 0) packed += static_cast<char>((buffer << (8 - filled)) & 0xFF);
  w.Bytes(packed);
  return std::move(w.str());
}

StatusOr<Eigen::MatrixX3d> ParseKnotGrid(std::string_view payload,
                                         uint64_t rows, int* grid_bits) {
  ByteReader r(payload);
  uint32_t bits = 0;
  if (!r.U32(&bits) || bits < kMinUnitVectorGridBits ||
      bits > kMaxUnitVectorGridBits) {
    return Corrupt("the QKNT chunk needs a grid of " +
                   Str(kMinUnitVectorGridBits) + ".." +
                   Str(kMaxUnitVectorGridBits) + " bits");
  }
  const std::string_view packed = r.Rest();
  const uint64_t expected = (2 * bits * rows + 7) / 8;
  if (packed.size() != expected) {
    return Corrupt("the QKNT chunk has " + Str(packed.size()) +
                   " bytes of codes; " + Str(rows) + " knots of " + Str(bits) +
                   " bits need " + Str(expected));
  }
  Eigen::MatrixX3d knots(static_cast<Eigen::Index>(rows), 3);
  uint64_t buffer = 0;
  int filled = 0;
  size_t at = 0;
  auto get = [&] {
    while (filled < static_cast<int>(bits)) {
      buffer = (buffer << 8) | static_cast<uint8_t>(packed[at++]);
      filled += 8;
    }
    filled -= static_cast<int>(bits);
    return static_cast<uint32_t>((buffer >> filled) &
                                 ((uint64_t{1} << bits) - 1));
  };
  for (Eigen::Index i = 0; i < knots.rows(); ++i) {
    UnitVectorCode c;
    c.a = get();
    c.b = get();
    knots.row(i) = DecodeUnitVector(c, static_cast<int>(bits)).transpose();
  }
  if ((buffer & ((uint64_t{1} << filled) - 1)) != 0) {
    return Corrupt("the QKNT chunk's padding bits are not zero");
  }
  *grid_bits = static_cast<int>(bits);
  return knots;
}

// ---------------------------------------------------------------------------
// PCTL: the grid of QCTL, then the range-coded codes.

std::string PredictedPayload(const QuantizedControlPoints& q,
                             const DelaunayConfigurations& configurations) {
  ByteWriter w;
  WriteGrid(q.quantization, &w);
  w.Bytes(EncodePredictedCodes(q.codes,
                               PlanControlPointPrediction(configurations)));
  return std::move(w.str());
}

StatusOr<Eigen::MatrixX3d> ParsePredicted(
    std::string_view payload, const DelaunayConfigurations& configurations,
    BasisForm form, ControlPointQuantization* g) {
  SDCB_ASSIGN_OR_RETURN(const std::string_view stream,
                        ParseGrid(payload, form, "PCTL", g));
  StatusOr<std::vector<uint32_t>> codes = DecodePredictedCodes(
      stream, PlanControlPointPrediction(configurations), g->bits);
  if (!codes.ok()) {
    return Corrupt("the PCTL chunk: " + codes.status().message());
  }
  return DequantizeControlPoints(g->origin, g->step, *codes);
}

}  // namespace sdcb::sdcb_internal
