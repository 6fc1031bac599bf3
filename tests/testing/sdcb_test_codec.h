// A test-side `.sdcb` codec written from docs/FORMAT.md, independent of
// io/sdcb/sdcb_file*.cpp: chunk framing, packed payloads (zlib called directly,
// byte planes re-implemented), the version 1 writer this code no longer has,
// and a bit-for-bit model comparison.
#ifndef SDCB_TESTS_TESTING_SDCB_TEST_CODEC_H_
#define SDCB_TESTS_TESTING_SDCB_TEST_CODEC_H_

#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "sdcb/core/spline/spline_model.h"
#include "sdcb/io/sdcb/crc32.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/allocation_tracker.h"

namespace sdcb::testing {

// --- Little-endian values -------------------------------------------------

inline uint64_t GetLe(std::string_view s, size_t pos, int bytes) {
  uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) {
    v |= uint64_t{static_cast<uint8_t>(s[pos + i])} << (8 * i);
  }
  return v;
}

inline double GetLeDouble(std::string_view s, size_t pos) {
  const uint64_t bits = GetLe(s, pos, 8);
  double d;
  std::memcpy(&d, &bits, 8);
  return d;
}

inline std::string Le(uint64_t v, int bytes) {
  std::string s;
  for (int i = 0; i < bytes; ++i) s += static_cast<char>((v >> (8 * i)) & 0xFF);
  return s;
}

inline std::string LeDouble(double d) {
  uint64_t bits;
  std::memcpy(&bits, &d, 8);
  return Le(bits, 8);
}

// --- Chunks ---------------------------------------------------------------

struct RawChunk {
  std::string type;  // 4 bytes
  std::string payload;
};

// Splits a valid file into its chunks (asserting framing and CRCs).
inline std::vector<RawChunk> SplitFile(const std::string& file) {
  std::vector<RawChunk> chunks;
  size_t pos = 12;
  while (pos < file.size()) {
    RawChunk c;
    c.type = file.substr(pos, 4);
    const uint64_t length = GetLe(file, pos + 4, 8);
    c.payload = file.substr(pos + 12, length);
    const uint32_t crc =
        static_cast<uint32_t>(GetLe(file, pos + 12 + length, 4));
    EXPECT_EQ(crc, Crc32(file.substr(pos, 12 + length))) << c.type;
    pos += 16 + length;
    chunks.push_back(std::move(c));
  }
  EXPECT_EQ(pos, file.size());
  return chunks;
}

// Encodes chunks with correct lengths and CRCs after magic + version.
inline std::string JoinFile(const std::vector<RawChunk>& chunks,
                            uint32_t version) {
  std::string file(kSdcbMagic, 8);
  file += Le(version, 4);
  for (const RawChunk& c : chunks) {
    const std::string framed = c.type + Le(c.payload.size(), 8) + c.payload;
    file += framed + Le(Crc32(framed), 4);
  }
  return file;
}

inline RawChunk* Find(std::vector<RawChunk>& chunks, const std::string& type) {
  for (RawChunk& c : chunks) {
    if (c.type == type) return &c;
  }
  return nullptr;
}

// --- Packed payloads: u64 L, then a zlib stream of L bytes -----------------

inline std::string TestInflate(std::string_view payload) {
  const uint64_t length = GetLe(payload, 0, 8);
  std::string out(length, '\0');
  uLongf out_length = static_cast<uLongf>(length);
  const std::string_view stream = payload.substr(8);
  EXPECT_EQ(uncompress(reinterpret_cast<Bytef*>(out.data()), &out_length,
                       reinterpret_cast<const Bytef*>(stream.data()),
                       static_cast<uLong>(stream.size())),
            Z_OK);
  EXPECT_EQ(out_length, length);
  return out;
}

// Packs `inflated` as the writer does (level 6), or with any other level:
// the reader accepts every valid zlib stream.
inline std::string TestPack(std::string_view inflated, int level = 6) {
  uLongf size = compressBound(static_cast<uLong>(inflated.size()));
  std::string stream(size, '\0');
  EXPECT_EQ(compress2(reinterpret_cast<Bytef*>(stream.data()), &size,
                      reinterpret_cast<const Bytef*>(inflated.data()),
                      static_cast<uLong>(inflated.size()), level),
            Z_OK);
  stream.resize(size);
  return Le(inflated.size(), 8) + stream;
}

// Byte b of value i is planes[b * n + i].
inline std::string TestFromPlanes(std::string_view planes, int width) {
  const size_t n = planes.size() / width;
  std::string out(planes.size(), '\0');
  for (size_t i = 0; i < n; ++i) {
    for (int b = 0; b < width; ++b) out[i * width + b] = planes[b * n + i];
  }
  return out;
}
inline std::string TestToPlanes(std::string_view values, int width) {
  const size_t n = values.size() / width;
  std::string out(values.size(), '\0');
  for (size_t i = 0; i < n; ++i) {
    for (int b = 0; b < width; ++b) out[b * n + i] = values[i * width + b];
  }
  return out;
}

// Packed points: doubles by coordinate (all x, all y, all z), byte planes.
inline Eigen::MatrixX3d TestUnpackPoints(std::string_view payload) {
  const std::string values = TestFromPlanes(TestInflate(payload), 8);
  const Eigen::Index rows = static_cast<Eigen::Index>(values.size() / 24);
  Eigen::MatrixX3d m(rows, 3);
  for (int c = 0; c < 3; ++c) {
    for (Eigen::Index i = 0; i < rows; ++i) {
      m(i, c) = GetLeDouble(values, 8 * (c * rows + i));
    }
  }
  return m;
}
inline std::string TestPackPoints(const Eigen::MatrixX3d& m) {
  std::string values;
  for (int c = 0; c < 3; ++c) {
    for (Eigen::Index i = 0; i < m.rows(); ++i) values += LeDouble(m(i, c));
  }
  return TestPack(TestToPlanes(values, 8));
}

// --- Configurations ----------------------------------------------------------

// Version 1's BSIS records.
inline std::string TestBasisBytes(const DelaunayConfigurations& c) {
  std::string bsis;
  for (const ConfigurationSet& s : c.sets) {
    bsis += Le(s.boundaries.size(), 4);
    for (int k : s.knots) bsis += Le(k, 4);
    for (const auto& t : s.boundaries) {
      for (int k : t) bsis += Le(k, 4);
    }
  }
  return bsis;
}

// FNV-1a 64 as docs/FORMAT.md defines it.
inline uint64_t TestFnv1a64(std::string_view bytes) {
  uint64_t h = 0xcbf29ce484222325ULL;
  for (char c : bytes) {
    h ^= static_cast<uint8_t>(c);
    h *= 0x100000001b3ULL;
  }
  return h;
}

// --- Version 1 writer (appendix A of docs/FORMAT.md) ---------------------

inline std::string RowPoints(const Eigen::MatrixX3d& m) {
  std::string s;
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    for (int c = 0; c < 3; ++c) s += LeDouble(m(i, c));
  }
  return s;
}

// Version 1's STAT: the keys that version wrote, times 0.
inline std::string Version1Statistics(const FitStatistics& s) {
  using nlohmann::json;
  const auto round = [](const RoundStatistics& r) {
    return json{{"round", r.round},
                {"knots", r.knots},
                {"control_points", r.control_points},
                {"rmse_percent", r.rmse_percent},
                {"max_error_percent", r.max_error_percent},
                {"seconds", 0.0}};
  };
  json rounds = json::array();
  for (const RoundStatistics& r : s.rounds) rounds.push_back(round(r));
  return json{{"rounds", rounds},
              {"final", round(s.final_result)},
              {"options",
               {{"degree", s.options.degree},
                {"rmse_percent", s.options.rmse_percent},
                {"knots_per_round", s.options.knots_per_round},
                {"max_rounds", s.options.max_rounds},
                {"lambda", s.options.lambda}}},
              {"timings",
               {{"parameterization", 0.0},
                {"knot_placement", 0.0},
                {"configurations", 0.0},
                {"basis", 0.0},
                {"solve", 0.0},
                {"total", 0.0}}}}
      .dump();
}

inline std::vector<RawChunk> Version1Chunks(const SplineModel& m) {
  std::vector<RawChunk> chunks;
  chunks.push_back({"HEAD", Le(m.degree, 4) + Le(m.knots.rows(), 8) +
                                Le(m.configurations.sets.size(), 8) +
                                Le(m.parameters.rows(), 8)});
  chunks.push_back({"KNOT", RowPoints(m.knots)});
  chunks.push_back({"BSIS", TestBasisBytes(m.configurations)});
  chunks.push_back({"CTRL", RowPoints(m.control_points)});
  chunks.push_back({"XFRM", LeDouble(m.transform.scale) +
                                LeDouble(m.transform.translation[0]) +
                                LeDouble(m.transform.translation[1]) +
                                LeDouble(m.transform.translation[2])});
  chunks.push_back({"STAT", Version1Statistics(m.statistics)});
  chunks.push_back({"SRCM", Le(m.source.num_vertices, 8) +
                                Le(m.source.num_faces, 8) +
                                Le(m.source.hash, 8) + m.source.file_name});
  if (m.parameters.rows() > 0) {
    chunks.push_back({"PARM", RowPoints(m.parameters)});
  }
  chunks.push_back({"END ", ""});
  return chunks;
}

// --- Model comparison by bits ---------------------------------------------

inline bool SameBits(double a, double b) { return std::memcmp(&a, &b, 8) == 0; }

inline bool SameBits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
  for (Eigen::Index i = 0; i < a.rows(); ++i) {
    for (Eigen::Index j = 0; j < a.cols(); ++j) {
      if (!SameBits(a(i, j), b(i, j))) return false;
    }
  }
  return true;
}

inline bool SameRound(const RoundStatistics& a, const RoundStatistics& b) {
  return a.round == b.round && a.knots == b.knots &&
         a.control_points == b.control_points &&
         SameBits(a.rmse_percent, b.rmse_percent) &&
         SameBits(a.max_error_percent, b.max_error_percent) &&
         SameBits(a.vertex_rmse_percent, b.vertex_rmse_percent) &&
         SameBits(a.vertex_max_error_percent, b.vertex_max_error_percent) &&
         SameBits(a.folded_area_percent, b.folded_area_percent) &&
         SameBits(a.boundary_error_percent, b.boundary_error_percent);
}

// Every field, doubles compared bit for bit (so -0.0 != 0.0).
inline ::testing::AssertionResult BitIdentical(const SplineModel& a,
                                               const SplineModel& b) {
  auto fail = [](const char* what) {
    return ::testing::AssertionFailure() << "models differ in " << what;
  };
  if (a.degree != b.degree) return fail("degree");
  if (!SameBits(a.knots, b.knots)) return fail("knots");
  if (a.configurations.degree != b.configurations.degree) {
    return fail("configurations.degree");
  }
  const auto& sa = a.configurations.sets;
  const auto& sb = b.configurations.sets;
  if (sa.size() != sb.size()) return fail("number of sets");
  for (size_t i = 0; i < sa.size(); ++i) {
    if (sa[i].knots != sb[i].knots) return fail("set knots");
    if (sa[i].boundaries != sb[i].boundaries) return fail("set boundaries");
  }
  if (!SameBits(a.control_points, b.control_points)) {
    return fail("control points");
  }
  if (!SameBits(a.transform.scale, b.transform.scale) ||
      !SameBits(a.transform.translation, b.transform.translation)) {
    return fail("transform");
  }
  const FitStatistics& fa = a.statistics;
  const FitStatistics& fb = b.statistics;
  if (fa.rounds.size() != fb.rounds.size()) return fail("number of rounds");
  for (size_t i = 0; i < fa.rounds.size(); ++i) {
    if (!SameRound(fa.rounds[i], fb.rounds[i])) return fail("a round");
  }
  if (!SameRound(fa.final_result, fb.final_result)) return fail("final");
  if (fa.error_measure != fb.error_measure) return fail("error measure");
  if (fa.reached_target != fb.reached_target) return fail("reached target");
  const RecordedFitOptions& oa = fa.options;
  const RecordedFitOptions& ob = fb.options;
  if (oa.degree != ob.degree || !SameBits(oa.rmse_percent, ob.rmse_percent) ||
      !SameBits(oa.max_error_percent, ob.max_error_percent) ||
      oa.knots_per_round != ob.knots_per_round ||
      !SameBits(oa.knots_growth, ob.knots_growth) ||
      oa.initial_knots != ob.initial_knots || oa.max_rounds != ob.max_rounds ||
      oa.max_control_points != ob.max_control_points ||
      !SameBits(oa.lambda, ob.lambda) || !SameBits(oa.alpha, ob.alpha) ||
      !SameBits(oa.regularization, ob.regularization) ||
      !SameBits(oa.fairness, ob.fairness) ||
      !SameBits(oa.samples_per_spacing, ob.samples_per_spacing) ||
      oa.max_fold_rounds != ob.max_fold_rounds ||
      oa.fallback_accepts_folds != ob.fallback_accepts_folds ||
      oa.round_samples_per_knot != ob.round_samples_per_knot ||
      oa.final_surface_samples != ob.final_surface_samples ||
      oa.final_mesh_samples != ob.final_mesh_samples ||
      !SameBits(oa.thinned_cells_per_spacing, ob.thinned_cells_per_spacing)) {
    return fail("options");
  }
  if (a.basis_form != b.basis_form) return fail("basis form");
  if (a.source.num_vertices != b.source.num_vertices ||
      a.source.num_faces != b.source.num_faces ||
      a.source.hash != b.source.hash ||
      a.source.file_name != b.source.file_name) {
    return fail("source");
  }
  if (!SameBits(a.parameters, b.parameters)) return fail("parameters");
  return ::testing::AssertionSuccess();
}

// Expects `file` to be rejected as corrupt with `fragment` in the message.
inline void ExpectCorrupt(const std::string& file,
                          const std::string& fragment) {
  const StatusOr<SplineModel> m = ParseSdcb(file);
  ASSERT_FALSE(m.ok()) << "accepted a file that should fail with: " << fragment;
  EXPECT_EQ(m.status().code(), StatusCode::kCorruptFile) << fragment;
  EXPECT_NE(m.status().message().find(fragment), std::string::npos)
      << "message: " << m.status().message()
      << "\nexpected to contain: " << fragment;
}

// --- Hostile input -------------------------------------------------------

// Flips each bit and each whole byte of `file` (a valid file of `model`) in
// turn: every result must be refused (corrupt or unsupported, with a
// message); CRC-32 detects every single-byte error, so none may be accepted.
// Returns the largest single allocation any of the parses made.
inline size_t ExpectEverySingleByteCorruptionRejected(
    const std::string& file, const SplineModel& model) {
  int accepted = 0;
  size_t largest = 0;
  for (size_t i = 0; i < file.size(); ++i) {
    for (int mask : {1, 2, 4, 8, 16, 32, 64, 128, 255}) {
      std::string bad = file;
      bad[i] = static_cast<char>(bad[i] ^ mask);
      StatusOr<SplineModel> m = InternalError("not parsed");
      largest = std::max(largest,
                         LargestAllocationDuring([&] { m = ParseSdcb(bad); }));
      if (m.ok()) {
        ++accepted;
        EXPECT_TRUE(BitIdentical(model, *m)) << "byte " << i;
      } else {
        EXPECT_TRUE(m.status().code() == StatusCode::kCorruptFile ||
                    m.status().code() == StatusCode::kUnsupported)
            << m.status().message();
        EXPECT_FALSE(m.status().message().empty());
      }
    }
  }
  EXPECT_EQ(accepted, 0);
  return largest;
}

// A model a reader accepted from damaged bytes must be valid and write
// back to a file that reads to the same model.
inline void ExpectWritesBackFaithfully(const SplineModel& m) {
  ASSERT_TRUE(ValidateSplineModel(m).ok());
  const StatusOr<std::string> again = SerializeSdcb(m);
  ASSERT_TRUE(again.ok()) << again.status().message();
  const StatusOr<SplineModel> reread = ParseSdcb(*again);
  ASSERT_TRUE(reread.ok());
  EXPECT_TRUE(BitIdentical(m, *reread));
}

// Changes, inserts or drops 1 to 4 random bytes of `bytes`.
inline void MutateBytes(std::mt19937* rng, std::string* bytes) {
  std::string& p = *bytes;
  const int edits = 1 + static_cast<int>((*rng)() % 4);
  for (int e = 0; e < edits; ++e) {
    const size_t at = p.empty() ? 0 : (*rng)() % p.size();
    switch ((*rng)() % 4) {
      case 0:  // overwrite a byte
      case 1:
        if (!p.empty()) p[at] = static_cast<char>((*rng)());
        break;
      case 2:  // insert a byte
        p.insert(p.begin() + at, static_cast<char>((*rng)()));
        break;
      default:  // drop a byte
        if (!p.empty()) p.erase(at, 1);
    }
  }
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_SDCB_TEST_CODEC_H_
