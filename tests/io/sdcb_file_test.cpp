// Tests io/sdcb_file.* and io/crc32.*: bit-exact round trips, deterministic
// bytes, the documented layout (docs/FORMAT.md, re-encoded here by an
// independent test-side chunk codec), and hostile files: every single-byte
// corruption and every truncation of a valid file is rejected, crafted files
// with valid CRCs but bad contents are rejected with a message naming the
// problem, and no count read from a file leads to an allocation larger than
// the file justifies.
#include "sdcb/io/sdcb_file.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "sdcb/io/crc32.h"
#include "testing/spline_model_fixture.h"
#include "testing/temp_dir.h"

// --- Allocation tracking -----------------------------------------------------
// The executable's malloc interposes glibc's (operator new and Eigen both end
// here) and records the largest single request while tracking is on.
namespace {
std::atomic<bool> g_track_allocations{false};
std::atomic<size_t> g_largest_allocation{0};
}  // namespace

extern "C" void* __libc_malloc(size_t size);  // glibc's own allocator
extern "C" void* malloc(size_t size) {
  if (g_track_allocations.load(std::memory_order_relaxed)) {
    size_t seen = g_largest_allocation.load(std::memory_order_relaxed);
    while (size > seen && !g_largest_allocation.compare_exchange_weak(
                              seen, size, std::memory_order_relaxed)) {
    }
  }
  return __libc_malloc(size);
}

namespace sdcb {
namespace {

using testing::FreshTestDir;
using testing::MakeTestModel;
using testing::ReadBytes;
using testing::WriteBytes;

// ParseSdcb, also reporting the largest single allocation it made.
StatusOr<SplineModel> TrackedParse(std::string_view bytes, size_t* largest) {
  g_largest_allocation = 0;
  g_track_allocations = true;
  StatusOr<SplineModel> result = ParseSdcb(bytes);
  g_track_allocations = false;
  *largest = g_largest_allocation;
  return result;
}

// --- Model comparison by bits ---------------------------------------------

bool SameBits(double a, double b) { return std::memcmp(&a, &b, 8) == 0; }

bool SameBits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
  for (Eigen::Index i = 0; i < a.rows(); ++i) {
    for (Eigen::Index j = 0; j < a.cols(); ++j) {
      if (!SameBits(a(i, j), b(i, j))) return false;
    }
  }
  return true;
}

bool SameRound(const RoundStatistics& a, const RoundStatistics& b) {
  return a.round == b.round && a.knots == b.knots &&
         a.control_points == b.control_points &&
         SameBits(a.rmse_percent, b.rmse_percent) &&
         SameBits(a.max_error_percent, b.max_error_percent) &&
         SameBits(a.vertex_rmse_percent, b.vertex_rmse_percent) &&
         SameBits(a.vertex_max_error_percent, b.vertex_max_error_percent) &&
         SameBits(a.folded_area_percent, b.folded_area_percent);
}

// Every field, doubles compared bit for bit (so -0.0 != 0.0).
::testing::AssertionResult BitIdentical(const SplineModel& a,
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
      oa.knots_per_round != ob.knots_per_round ||
      oa.initial_knots != ob.initial_knots || oa.max_rounds != ob.max_rounds ||
      oa.max_control_points != ob.max_control_points ||
      !SameBits(oa.lambda, ob.lambda) || !SameBits(oa.alpha, ob.alpha) ||
      !SameBits(oa.regularization, ob.regularization) ||
      !SameBits(oa.fairness, ob.fairness) ||
      !SameBits(oa.samples_per_spacing, ob.samples_per_spacing) ||
      oa.fold_retries != ob.fold_retries ||
      oa.round_samples_per_knot != ob.round_samples_per_knot ||
      oa.final_surface_samples != ob.final_surface_samples) {
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

// --- Independent chunk codec, written from docs/FORMAT.md -------------------

struct RawChunk {
  std::string type;  // 4 bytes
  std::string payload;
};

uint64_t GetLe(std::string_view s, size_t pos, int bytes) {
  uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) {
    v |= uint64_t{static_cast<uint8_t>(s[pos + i])} << (8 * i);
  }
  return v;
}

std::string Le(uint64_t v, int bytes) {
  std::string s;
  for (int i = 0; i < bytes; ++i) s += static_cast<char>((v >> (8 * i)) & 0xFF);
  return s;
}

std::string LeDouble(double d) {
  uint64_t bits;
  std::memcpy(&bits, &d, 8);
  return Le(bits, 8);
}

// Splits a valid file into its chunks (asserting framing and CRCs).
std::vector<RawChunk> SplitFile(const std::string& file) {
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
std::string JoinFile(const std::vector<RawChunk>& chunks,
                     uint32_t version = 1) {
  std::string file(kSdcbMagic, 8);
  file += Le(version, 4);
  for (const RawChunk& c : chunks) {
    const std::string framed = c.type + Le(c.payload.size(), 8) + c.payload;
    file += framed + Le(Crc32(framed), 4);
  }
  return file;
}

RawChunk* Find(std::vector<RawChunk>& chunks, const std::string& type) {
  for (RawChunk& c : chunks) {
    if (c.type == type) return &c;
  }
  return nullptr;
}

std::string Serialize(const SplineModel& m) {
  StatusOr<std::string> bytes = SerializeSdcb(m);
  EXPECT_TRUE(bytes.ok()) << bytes.status().message();
  return bytes.ok() ? *bytes : std::string();
}

// Expects `file` to be rejected as corrupt with `fragment` in the message.
void ExpectCorrupt(const std::string& file, const std::string& fragment) {
  const StatusOr<SplineModel> m = ParseSdcb(file);
  ASSERT_FALSE(m.ok()) << "accepted a file that should fail with: " << fragment;
  EXPECT_EQ(m.status().code(), StatusCode::kCorruptFile) << fragment;
  EXPECT_NE(m.status().message().find(fragment), std::string::npos)
      << "message: " << m.status().message()
      << "\nexpected to contain: " << fragment;
}

// --- CRC-32 -----------------------------------------------------------------

TEST(Crc32Test, KnownValues) {
  EXPECT_EQ(Crc32("123456789"), 0xCBF43926u);  // the standard check value
  EXPECT_EQ(Crc32(""), 0u);
  EXPECT_EQ(Crc32("The quick brown fox jumps over the lazy dog"), 0x414FA339u);
  EXPECT_EQ(Crc32(std::string(1, '\0')), 0xD202EF8Du);
}

TEST(Crc32Test, IncrementalEqualsWhole) {
  const std::string s = "spherical DCB-spline surfaces";
  for (size_t cut = 0; cut <= s.size(); ++cut) {
    EXPECT_EQ(
        Crc32Update(Crc32(s.substr(0, cut)), s.data() + cut, s.size() - cut),
        Crc32(s));
  }
}

// --- Round trips and determinism -------------------------------------------

TEST(SdcbFileTest, RoundTripIsBitIdenticalForEveryDegree) {
  for (int k = 0; k <= kMaxSplineDegree; ++k) {
    for (int parameters : {0, 6}) {
      const SplineModel model = MakeTestModel(k, k + 9, parameters, 20 + k);
      ASSERT_TRUE(ValidateSplineModel(model).ok());
      const std::string bytes = Serialize(model);
      const StatusOr<SplineModel> back = ParseSdcb(bytes);
      ASSERT_TRUE(back.ok()) << back.status().message();
      EXPECT_TRUE(BitIdentical(model, *back)) << "degree " << k;
      // Re-serializing the parsed model reproduces the bytes.
      EXPECT_EQ(Serialize(*back), bytes);
    }
  }
}

TEST(SdcbFileTest, SpecialDoublesSurviveBitForBit) {
  const SplineModel model = MakeTestModel();
  const StatusOr<SplineModel> back = ParseSdcb(Serialize(model));
  ASSERT_TRUE(back.ok());
  // The fixture put these into the first control points; check them
  // explicitly, not only through BitIdentical.
  EXPECT_TRUE(std::signbit(back->control_points(0, 0)));
  EXPECT_EQ(back->control_points(0, 0), 0.0);
  EXPECT_EQ(back->control_points(0, 1),
            std::numeric_limits<double>::denorm_min());
  EXPECT_EQ(back->control_points(0, 2), -2.5e-310);
  EXPECT_EQ(back->control_points(1, 0), std::numeric_limits<double>::max());
  EXPECT_EQ(back->control_points(1, 1), std::numeric_limits<double>::lowest());
  EXPECT_EQ(back->transform.translation[1], 1e-320);
  EXPECT_EQ(back->statistics.rounds[0].folded_area_percent,
            std::numeric_limits<double>::denorm_min());
  EXPECT_TRUE(std::signbit(back->statistics.options.fairness));  // -0.0
  EXPECT_EQ(back->source.file_name, "meshes/bunny \xc3\xa9.off");
}

TEST(SdcbFileTest, StatisticsJsonIsBitExactForRandomDoubles) {
  // STAT is JSON text; every finite double, drawn as random bit patterns
  // (all exponents, denormals, both signs), must come back unchanged.
  SplineModel model = MakeTestModel();
  std::mt19937_64 rng(5);
  const auto random_double = [&] {
    while (true) {
      const uint64_t bits = rng();
      double d;
      std::memcpy(&d, &bits, 8);
      if (std::isfinite(d)) return d;
    }
  };
  model.statistics.rounds.resize(300);
  for (RoundStatistics& r : model.statistics.rounds) {
    r.rmse_percent = random_double();
    r.max_error_percent = random_double();
    r.vertex_rmse_percent = random_double();
    r.vertex_max_error_percent = random_double();
    r.folded_area_percent = random_double();
  }
  model.statistics.options.lambda = 0.1 + 0.2;
  model.statistics.options.alpha = 5e-324;
  model.statistics.options.regularization = 1.7976931348623157e308;
  const StatusOr<SplineModel> back = ParseSdcb(Serialize(model));
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_TRUE(BitIdentical(model, *back));
}

TEST(SdcbFileTest, WritingTwiceGivesIdenticalFiles) {
  const std::string dir = FreshTestDir();
  const SplineModel model = MakeTestModel(3, 14, 8);
  ASSERT_TRUE(WriteSdcbFile(model, dir + "/a.sdcb").ok());
  ASSERT_TRUE(WriteSdcbFile(MakeTestModel(3, 14, 8), dir + "/b.sdcb").ok());
  const std::string a = ReadBytes(dir + "/a.sdcb");
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, ReadBytes(dir + "/b.sdcb"));
  EXPECT_EQ(a, Serialize(model));
  const StatusOr<SplineModel> back = ReadSdcbFile(dir + "/a.sdcb");
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_TRUE(BitIdentical(model, *back));
  // Only the two outputs exist: no temporary files left behind.
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    (void)e;
    ++files;
  }
  EXPECT_EQ(files, 2);
}

TEST(SdcbFileTest, LayoutMatchesFormatDocument) {
  const SplineModel model = MakeTestModel(2, 10, 4);
  const std::string file = Serialize(model);
  ASSERT_GE(file.size(), 12u);
  EXPECT_EQ(file.substr(0, 8), std::string("\x89SDCB\r\n\x1a", 8));
  EXPECT_EQ(GetLe(file, 8, 4), 1u);
  std::vector<RawChunk> chunks = SplitFile(file);
  std::vector<std::string> types;
  for (const RawChunk& c : chunks) types.push_back(c.type);
  EXPECT_EQ(types,
            (std::vector<std::string>{"HEAD", "KNOT", "BSIS", "CTRL", "XFRM",
                                      "STAT", "SRCM", "PARM", "END "}));
  EXPECT_EQ(JoinFile(chunks), file);

  const std::string& head = Find(chunks, "HEAD")->payload;
  ASSERT_EQ(head.size(), 28u);
  EXPECT_EQ(GetLe(head, 0, 4), 2u);
  EXPECT_EQ(GetLe(head, 4, 8), 10u);
  EXPECT_EQ(GetLe(head, 12, 8), model.configurations.sets.size());
  EXPECT_EQ(GetLe(head, 20, 8), 4u);

  const std::string& knots = Find(chunks, "KNOT")->payload;
  ASSERT_EQ(knots.size(), 10u * 24);
  EXPECT_EQ(knots.substr(24 * 3 + 8, 8), LeDouble(model.knots(3, 1)));

  std::string bsis;
  for (const ConfigurationSet& s : model.configurations.sets) {
    bsis += Le(s.boundaries.size(), 4);
    for (int k : s.knots) bsis += Le(k, 4);
    for (const auto& t : s.boundaries) {
      for (int k : t) bsis += Le(k, 4);
    }
  }
  EXPECT_EQ(Find(chunks, "BSIS")->payload, bsis);

  const std::string& ctrl = Find(chunks, "CTRL")->payload;
  EXPECT_EQ(ctrl.substr(0, 8), LeDouble(-0.0));

  EXPECT_EQ(Find(chunks, "XFRM")->payload,
            LeDouble(model.transform.scale) +
                LeDouble(model.transform.translation[0]) +
                LeDouble(model.transform.translation[1]) +
                LeDouble(model.transform.translation[2]));

  const nlohmann::json stat =
      nlohmann::json::parse(Find(chunks, "STAT")->payload);
  EXPECT_EQ(stat["rounds"].size(), 3u);
  EXPECT_EQ(stat["final"]["knots"], 300);
  EXPECT_EQ(stat["options"]["regularization"], 12.5);
  EXPECT_EQ(stat["options"]["lambda"], 0.2);

  EXPECT_EQ(Find(chunks, "SRCM")->payload, Le(4, 8) + Le(4, 8) +
                                               Le(0xfedcba9876543210ULL, 8) +
                                               "meshes/bunny \xc3\xa9.off");
  EXPECT_EQ(Find(chunks, "PARM")->payload.size(), 4u * 24);
  EXPECT_TRUE(Find(chunks, "END ")->payload.empty());
}

TEST(SdcbFileTest, ModelWithoutParametersHasNoParmChunk) {
  const std::string file = Serialize(MakeTestModel(1, 7, 0));
  std::vector<RawChunk> chunks = SplitFile(file);
  EXPECT_EQ(Find(chunks, "PARM"), nullptr);
  EXPECT_EQ(GetLe(Find(chunks, "HEAD")->payload, 20, 8), 0u);
  const StatusOr<SplineModel> back = ParseSdcb(file);
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->parameters.rows(), 0);
}

// --- Hostile input
// ------------------------------------------------------------

TEST(SdcbFileTest, EverySingleByteCorruptionIsRejected) {
  const SplineModel model = MakeTestModel(1, 7, 3);
  const std::string file = Serialize(model);
  ASSERT_LT(file.size(), 4000u);  // keep the loop quick
  int accepted = 0;
  size_t largest_overall = 0;
  for (size_t i = 0; i < file.size(); ++i) {
    for (int mask : {1, 2, 4, 8, 16, 32, 64, 128, 255}) {
      std::string bad = file;
      bad[i] = static_cast<char>(bad[i] ^ mask);
      size_t largest = 0;
      const StatusOr<SplineModel> m = TrackedParse(bad, &largest);
      largest_overall = std::max(largest_overall, largest);
      if (m.ok()) {
        // Allowed only if the model is unchanged; CRC-32 detects every
        // single-byte error, so this should not happen at all.
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
  // Nothing read from a corrupt file made an allocation beyond a small
  // multiple of its size.
  EXPECT_LT(largest_overall, 16 * file.size() + 4096);
}

TEST(SdcbFileTest, EveryTruncationIsRejected) {
  const std::string file = Serialize(MakeTestModel(2, 9, 2));
  for (size_t length = 0; length < file.size(); ++length) {
    const StatusOr<SplineModel> m = ParseSdcb(file.substr(0, length));
    ASSERT_FALSE(m.ok()) << "accepted a file cut to " << length << " bytes";
    EXPECT_EQ(m.status().code(), StatusCode::kCorruptFile);
  }
  ExpectCorrupt(file.substr(0, file.size() - 1), "truncated");
  ExpectCorrupt(file.substr(0, file.size() - 16), "before the END chunk");
}

TEST(SdcbFileTest, UnknownChunksAreSkipped) {
  const SplineModel model = MakeTestModel(2, 9, 2);
  std::vector<RawChunk> chunks = SplitFile(Serialize(model));
  chunks.insert(chunks.begin() + 1,
                RawChunk{"note", "added by a newer writer"});
  chunks.insert(chunks.end() - 1,
                RawChunk{"ZZ_9", std::string("\0\xff\x01 binary", 10)});
  chunks.insert(chunks.end() - 1, RawChunk{"EMPT", ""});
  const std::string file = JoinFile(chunks);
  const StatusOr<SplineModel> back = ParseSdcb(file);
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_TRUE(BitIdentical(model, *back));
  // An unknown chunk is still CRC-checked.
  std::string bad = file;
  bad[bad.find("added by")] ^= 0x20;
  ExpectCorrupt(bad, "'note'");
  ExpectCorrupt(bad, "CRC");
}

TEST(SdcbFileTest, ChunksBetweenHeadAndEndMayComeInAnyOrder) {
  const SplineModel model = MakeTestModel(2, 9, 2);
  std::vector<RawChunk> chunks = SplitFile(Serialize(model));
  std::reverse(chunks.begin() + 1, chunks.end() - 1);
  ASSERT_EQ(chunks[1].type, "PARM");
  const StatusOr<SplineModel> back = ParseSdcb(JoinFile(chunks));
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_TRUE(BitIdentical(model, *back));
}

TEST(SdcbFileTest, AbsurdCountsAreRejectedWithoutAllocating) {
  const std::string file = Serialize(MakeTestModel(1, 7, 3));
  // The tracker sees the reader's allocations: a valid parse allocates the
  // 7 x 3 knot matrix at least.
  size_t valid_largest = 0;
  ASSERT_TRUE(TrackedParse(file, &valid_largest).ok());
  EXPECT_GE(valid_largest, 7u * 24);
  struct Case {
    size_t offset;  // within the HEAD payload
    uint64_t value;
    const char* what;
  };
  const Case cases[] = {
      {4, uint64_t{1} << 60, "knots"},
      {4, 1'000'000, "knots"},
      {12, uint64_t{1} << 60, "basis functions"},
      {12, 100'000, "basis functions"},
      {20, uint64_t{1} << 62, "sphere parameters"},
      {20, 5'000'000, "sphere parameters"},
  };
  for (const Case& c : cases) {
    std::vector<RawChunk> chunks = SplitFile(file);
    std::string& head = Find(chunks, "HEAD")->payload;
    head.replace(c.offset, 8, Le(c.value, 8));
    size_t largest = 0;
    const StatusOr<SplineModel> m = TrackedParse(JoinFile(chunks), &largest);
    ASSERT_FALSE(m.ok()) << c.what << " " << c.value;
    EXPECT_EQ(m.status().code(), StatusCode::kCorruptFile);
    EXPECT_NE(m.status().message().find(std::to_string(c.value) + " " + c.what +
                                        ", more than the file's"),
              std::string::npos)
        << m.status().message();
    EXPECT_LT(largest, 16 * file.size() + 4096) << c.what << " " << c.value;
  }
}

TEST(SdcbFileTest, CraftedFilesWithValidCrcsAreRejected) {
  const SplineModel model = MakeTestModel(1, 7, 3);
  const std::string file = Serialize(model);
  const auto edit = [&](const std::string& type, auto change) {
    std::vector<RawChunk> chunks = SplitFile(file);
    change(Find(chunks, type)->payload);
    return JoinFile(chunks);
  };
  // Knot index out of range (first knot index of the first basis function).
  ExpectCorrupt(edit("BSIS", [](std::string& p) { p.replace(4, 4, Le(7, 4)); }),
                "refers to knot 7, but the file has 7 knots");
  // A boundary knot (in range) that is not in its set.
  {
    const ConfigurationSet& s0 = model.configurations.sets[0];
    int outside = 0;
    while (std::count(s0.knots.begin(), s0.knots.end(), outside)) ++outside;
    ExpectCorrupt(edit("BSIS",
                       [&](std::string& p) {
                         p.replace(4 + 4 * 4 + 8, 4, Le(outside, 4));
                       }),
                  "not in the set");
  }
  ExpectCorrupt(edit("BSIS", [](std::string& p) { p.replace(0, 4, Le(0, 4)); }),
                "declares 0 boundary triples");
  ExpectCorrupt(
      edit("BSIS", [](std::string& p) { p.replace(0, 4, Le(1u << 31, 4)); }),
      "allows 1..4");
  ExpectCorrupt(edit("BSIS", [](std::string& p) { p += Le(0, 4); }),
                "bytes after its last basis function");
  ExpectCorrupt(
      edit("CTRL",
           [](std::string& p) { p.replace(24, 8, LeDouble(std::nan(""))); }),
      "control point coordinate is not finite");
  ExpectCorrupt(edit("CTRL", [](std::string& p) { p.resize(p.size() - 24); }),
                "the CTRL chunk has");
  ExpectCorrupt(
      edit("KNOT", [](std::string& p) { p.replace(0, 8, LeDouble(2.0)); }),
      "knot 0 is not a unit vector");
  ExpectCorrupt(
      edit("XFRM", [](std::string& p) { p.replace(0, 8, LeDouble(-1.0)); }),
      "finite scale > 0");
  ExpectCorrupt(edit("XFRM", [](std::string& p) { p += "x"; }),
                "the XFRM chunk has 33 bytes");
  ExpectCorrupt(edit("HEAD", [](std::string& p) { p.replace(0, 4, Le(6, 4)); }),
                "degree 6");
  ExpectCorrupt(edit("HEAD", [](std::string& p) { p.replace(0, 4, Le(2, 4)); }),
                "");  // degree 2 does not match the 4-knot sets
  ExpectCorrupt(edit("STAT", [](std::string& p) { p.pop_back(); }),
                "STAT chunk is not valid JSON");
  ExpectCorrupt(edit("STAT",
                     [](std::string& p) {
                       auto j = nlohmann::json::parse(p);
                       j["options"].erase("lambda");
                       p = j.dump();
                     }),
                "statistics.options lacks the key \"lambda\"");
  ExpectCorrupt(edit("STAT",
                     [](std::string& p) {
                       auto j = nlohmann::json::parse(p);
                       j["rounds"][1]["knots"] = "many";
                       p = j.dump();
                     }),
                "statistics.rounds[1].knots is not an integer");
  ExpectCorrupt(edit("STAT",
                     [](std::string& p) {
                       auto j = nlohmann::json::parse(p);
                       j["final"]["round"] = uint64_t{1} << 40;
                       p = j.dump();
                     }),
                "statistics.final.round is out of range");
  // Deeply nested JSON must not exhaust the stack.
  ExpectCorrupt(edit("STAT",
                     [](std::string& p) {
                       p = std::string(200000, '[') + std::string(200000, ']');
                     }),
                "statistics is not a JSON object");
  ExpectCorrupt(edit("STAT", [](std::string& p) { p = "{\"rounds\": 1e999}"; }),
                "STAT chunk");
  ExpectCorrupt(edit("SRCM", [](std::string& p) { p.resize(20); }),
                "the SRCM chunk has 20 bytes");
  ExpectCorrupt(edit("PARM", [](std::string& p) { p.resize(48); }),
                "the PARM chunk has 48 bytes");
}

TEST(SdcbFileTest, RandomMutationsWithValidCrcsNeverCrash) {
  // Structure-aware fuzzing: change, insert or drop bytes inside one chunk's
  // payload and recompute its CRC, so only the content checks stand between
  // the bytes and the model. Whatever is accepted must be a valid model that
  // writes back to the same bytes it was read from.
  const std::vector<RawChunk> good =
      SplitFile(Serialize(MakeTestModel(1, 7, 3)));
  std::mt19937 rng(11);
  int accepted = 0;
  size_t largest_overall = 0;
  for (int iteration = 0; iteration < 20000; ++iteration) {
    std::vector<RawChunk> chunks = good;
    std::string& p = chunks[rng() % chunks.size()].payload;
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int e = 0; e < edits; ++e) {
      const size_t at = p.empty() ? 0 : rng() % p.size();
      switch (rng() % 4) {
        case 0:  // overwrite a byte
        case 1:
          if (!p.empty()) p[at] = static_cast<char>(rng());
          break;
        case 2:  // insert a byte
          p.insert(p.begin() + at, static_cast<char>(rng()));
          break;
        default:  // drop a byte
          if (!p.empty()) p.erase(at, 1);
      }
    }
    const std::string file = JoinFile(chunks);
    size_t largest = 0;
    const StatusOr<SplineModel> m = TrackedParse(file, &largest);
    largest_overall = std::max(largest_overall, largest);
    if (!m.ok()) {
      EXPECT_FALSE(m.status().message().empty());
      continue;
    }
    ++accepted;
    ASSERT_TRUE(ValidateSplineModel(*m).ok());
    const StatusOr<std::string> again = SerializeSdcb(*m);
    ASSERT_TRUE(again.ok());
    // An accepted model survives a write/read cycle unchanged.
    const StatusOr<SplineModel> reread = ParseSdcb(*again);
    ASSERT_TRUE(reread.ok());
    EXPECT_TRUE(BitIdentical(*m, *reread));
  }
  EXPECT_LT(largest_overall, 16 * JoinFile(good).size() + 4096);
  // Some mutations are harmless (a control point's low bits, the file
  // name); most are not. Both kinds must have been exercised.
  EXPECT_GT(accepted, 100);
  EXPECT_LT(accepted, 20000 - 100);
}

TEST(SdcbFileTest, ChunkStructureViolationsAreRejected) {
  const SplineModel model = MakeTestModel(1, 7, 3);
  const std::vector<RawChunk> good = SplitFile(Serialize(model));
  {
    std::vector<RawChunk> c = good;
    c.insert(c.end() - 1, *Find(c, "XFRM"));
    ExpectCorrupt(JoinFile(c), "chunk 'XFRM' occurs twice");
  }
  for (const char* required : {"KNOT", "BSIS", "CTRL", "XFRM", "SRCM"}) {
    std::vector<RawChunk> c = good;
    c.erase(c.begin() + (Find(c, required) - c.data()));
    ExpectCorrupt(JoinFile(c), std::string("the required chunk '") + required +
                                   "' is missing");
  }
  {
    std::vector<RawChunk> c = good;
    c.pop_back();  // END
    ExpectCorrupt(JoinFile(c), "before the END chunk");
  }
  {
    std::vector<RawChunk> c = good;
    std::swap(c[0], c[1]);
    ExpectCorrupt(JoinFile(c), "the first chunk is 'KNOT'");
  }
  {
    std::vector<RawChunk> c = good;
    c.erase(c.begin() + (Find(c, "PARM") - c.data()));
    ExpectCorrupt(JoinFile(c), "PARM chunk is missing");
  }
  {
    std::vector<RawChunk> c = SplitFile(Serialize(MakeTestModel(1, 7, 0)));
    c.insert(c.end() - 1, RawChunk{"PARM", ""});
    ExpectCorrupt(JoinFile(c), "PARM chunk is present");
  }
  {
    std::vector<RawChunk> c = good;
    Find(c, "END ")->payload = "x";
    ExpectCorrupt(JoinFile(c), "END chunk is not empty");
  }
  ExpectCorrupt(JoinFile(good) + "extra", "5 unexpected bytes follow");
  {
    std::vector<RawChunk> c = good;
    c.insert(c.end() - 1, RawChunk{std::string("B\0D!", 4), ""});
    ExpectCorrupt(JoinFile(c), "invalid type 'B\\x00D!'");
  }
  // STAT is optional: without it the statistics are the defaults.
  {
    std::vector<RawChunk> c = good;
    c.erase(c.begin() + (Find(c, "STAT") - c.data()));
    const StatusOr<SplineModel> m = ParseSdcb(JoinFile(c));
    ASSERT_TRUE(m.ok()) << m.status().message();
    EXPECT_TRUE(m->statistics.rounds.empty());
    EXPECT_EQ(m->statistics.options.degree, 0);
    EXPECT_TRUE(SameBits(m->control_points, model.control_points));
  }
}

TEST(SdcbFileTest, HeaderProblemsAreNamed) {
  const std::vector<RawChunk> chunks = SplitFile(Serialize(MakeTestModel()));
  const StatusOr<SplineModel> newer = ParseSdcb(JoinFile(chunks, 2));
  ASSERT_FALSE(newer.ok());
  EXPECT_EQ(newer.status().code(), StatusCode::kUnsupported);
  EXPECT_NE(newer.status().message().find("format version 2"),
            std::string::npos);
  ExpectCorrupt(JoinFile(chunks, 0), "format version is 0");
  ExpectCorrupt("", "the file is empty");
  ExpectCorrupt(std::string(kSdcbMagic, 5), "only 5 bytes");
  ExpectCorrupt(std::string(kSdcbMagic, 8) + "\x01", "only 9 bytes");
  ExpectCorrupt("\x89SDCX", "magic number");
  ExpectCorrupt("OFF\n4 4 0\n", "magic number");
  // A text-mode transfer turning CR LF into LF.
  std::string mangled = JoinFile(chunks);
  mangled.erase(5, 1);
  ExpectCorrupt(mangled, "text-mode transfer");
}

// --- Files ------------------------------------------------------------------

TEST(SdcbFileTest, FileErrorsNameThePathAndLeaveNoPartialFile) {
  const std::string dir = FreshTestDir();
  const std::string path = dir + "/model.sdcb";
  const SplineModel model = MakeTestModel();

  const StatusOr<SplineModel> missing = ReadSdcbFile(dir + "/none.sdcb");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.status().code(), StatusCode::kIoError);
  EXPECT_EQ(missing.status().message().rfind(dir + "/none.sdcb: ", 0), 0u);

  const StatusOr<SplineModel> directory = ReadSdcbFile(dir);
  ASSERT_FALSE(directory.ok());
  EXPECT_EQ(directory.status().code(), StatusCode::kIoError);

  // An invalid model is refused and nothing is written.
  SplineModel invalid = model;
  invalid.control_points(0, 0) = std::nan("");
  const Status refused = WriteSdcbFile(invalid, path);
  EXPECT_EQ(refused.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(
      refused.message().rfind(path + ": cannot write an invalid model", 0), 0u);
  EXPECT_FALSE(std::filesystem::exists(path));

  // A failed write leaves an existing file untouched.
  ASSERT_TRUE(WriteSdcbFile(model, path).ok());
  const std::string before = ReadBytes(path);
  EXPECT_FALSE(WriteSdcbFile(invalid, path).ok());
  EXPECT_EQ(ReadBytes(path), before);
  EXPECT_FALSE(WriteSdcbFile(model, dir + "/no/such/dir/m.sdcb").ok());

  // A truncated file on disk: corrupt, message starts with the path.
  const std::string cut = dir + "/cut.sdcb";
  WriteBytes(cut, before.substr(0, before.size() / 2));
  const StatusOr<SplineModel> truncated = ReadSdcbFile(cut);
  ASSERT_FALSE(truncated.ok());
  EXPECT_EQ(truncated.status().code(), StatusCode::kCorruptFile);
  EXPECT_EQ(truncated.status().message().rfind(cut + ": ", 0), 0u);
}

}  // namespace
}  // namespace sdcb
