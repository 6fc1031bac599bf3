// Tests that io/sdcb/sdcb_file.* still reads format version 1 (docs/FORMAT.md,
// appendix A), which it no longer writes: a real version 1 file
// (tests/data/cow_round0_v1.sdcb) and files made by the test-side version 1
// writer (testing/sdcb_test_codec.h), which the real file proves faithful;
// every single-byte corruption and truncation is rejected, crafted files with
// valid CRCs but bad contents are rejected naming the problem.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/allocation_tracker.h"
#include "testing/sdcb_test_codec.h"
#include "testing/spline_model_fixture.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

using testing::BitIdentical;
using testing::ExpectCorrupt;
using testing::Find;
using testing::JoinFile;
using testing::Le;
using testing::LeDouble;
using testing::MakeTestModel;
using testing::RawChunk;
using testing::ReadBytes;
using testing::SplitFile;
using testing::Version1Chunks;

std::string Version1File(const SplineModel& m) {
  return JoinFile(Version1Chunks(m), 1);
}

// What a version 1 file can hold: no basis form (normalized), the statistics
// version 1 recorded.
SplineModel AsVersion1Reads(SplineModel m) {
  m.basis_form = BasisForm::kNormalized;
  FitStatistics& s = m.statistics;
  const auto v1_round = [](RoundStatistics& r) {
    r.vertex_rmse_percent = r.rmse_percent;
    r.vertex_max_error_percent = r.max_error_percent;
    r.folded_area_percent = 0.0;
  };
  for (RoundStatistics& r : s.rounds) v1_round(r);
  v1_round(s.final_result);
  const RecordedFitOptions o = s.options;
  s.options = RecordedFitOptions();
  s.options.degree = o.degree;
  s.options.rmse_percent = o.rmse_percent;
  s.options.knots_per_round = o.knots_per_round;
  s.options.max_rounds = o.max_rounds;
  s.options.lambda = o.lambda;
  s.error_measure = ErrorMeasure::kVertices;
  s.reached_target = s.final_result.rmse_percent <= o.rmse_percent;
  return m;
}

TEST(SdcbFileV1Test, TheTestWriterReproducesARealVersionOneFile) {
  const std::string file =
      ReadBytes(testing::TestDataPath("cow_round0_v1.sdcb"));
  ASSERT_GT(file.size(), 100000u);
  SdcbFileInfo info;
  const StatusOr<SplineModel> m = ParseSdcb(file, &info);
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_EQ(info.format_version, 1u);
  EXPECT_EQ(info.file_bytes, file.size());
  EXPECT_TRUE(info.quantization.lossless());
  EXPECT_EQ(m->basis_form, BasisForm::kNormalized);
  EXPECT_EQ(m->knots.rows(), 100);
  EXPECT_EQ(m->parameters.rows(), m->source.num_vertices);
  // Every byte of the file is what the documented layout says.
  EXPECT_EQ(Version1File(*m), file);
}

TEST(SdcbFileV1Test, RoundTripsThroughVersionTwoForEveryDegree) {
  for (int k = 0; k <= kMaxSplineDegree; ++k) {
    const SplineModel model = AsVersion1Reads(MakeTestModel(k, k + 9, 6));
    const StatusOr<SplineModel> v1 = ParseSdcb(Version1File(model));
    ASSERT_TRUE(v1.ok()) << v1.status().message();
    EXPECT_TRUE(BitIdentical(model, *v1)) << "degree " << k;
    // A version 1 model writes as version 2 and reads back unchanged.
    const StatusOr<std::string> v2 = SerializeSdcb(*v1);
    ASSERT_TRUE(v2.ok()) << v2.status().message();
    EXPECT_EQ(testing::GetLe(*v2, 8, 4), 2u);
    const StatusOr<SplineModel> back = ParseSdcb(*v2);
    ASSERT_TRUE(back.ok()) << back.status().message();
    EXPECT_TRUE(BitIdentical(model, *back));
  }
}

TEST(SdcbFileV1Test, EverySingleByteCorruptionIsRejected) {
  const SplineModel model = AsVersion1Reads(MakeTestModel(1, 7, 3));
  const std::string file = Version1File(model);
  ASSERT_LT(file.size(), 4000u);  // keep the loop quick
  const size_t largest =
      testing::ExpectEverySingleByteCorruptionRejected(file, model);
  EXPECT_LT(largest, 16 * file.size() + 4096);
}

TEST(SdcbFileV1Test, EveryTruncationIsRejected) {
  const std::string file = Version1File(MakeTestModel(2, 9, 2));
  for (size_t length = 0; length < file.size(); ++length) {
    const StatusOr<SplineModel> m = ParseSdcb(file.substr(0, length));
    ASSERT_FALSE(m.ok()) << "accepted a file cut to " << length << " bytes";
    EXPECT_EQ(m.status().code(), StatusCode::kCorruptFile);
  }
  ExpectCorrupt(file.substr(0, file.size() - 1), "truncated");
}

TEST(SdcbFileV1Test, AbsurdCountsAreRejectedWithoutAllocating) {
  const std::string file = Version1File(MakeTestModel(1, 7, 3));
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
    Find(chunks, "HEAD")->payload.replace(c.offset, 8, Le(c.value, 8));
    StatusOr<SplineModel> m = InternalError("not parsed");
    const size_t largest = testing::LargestAllocationDuring(
        [&] { m = ParseSdcb(JoinFile(chunks, 1)); });
    ASSERT_FALSE(m.ok()) << c.what << " " << c.value;
    EXPECT_EQ(m.status().code(), StatusCode::kCorruptFile);
    EXPECT_NE(m.status().message().find(std::to_string(c.value) + " " + c.what +
                                        ", more than the file's"),
              std::string::npos)
        << m.status().message();
    EXPECT_LT(largest, 16 * file.size() + 4096) << c.what << " " << c.value;
  }
}

TEST(SdcbFileV1Test, CraftedFilesWithValidCrcsAreRejected) {
  const SplineModel model = MakeTestModel(1, 7, 3);
  const std::string file = Version1File(model);
  const auto edit = [&](const std::string& type, auto change) {
    std::vector<RawChunk> chunks = SplitFile(file);
    change(Find(chunks, type)->payload);
    return JoinFile(chunks, 1);
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
  ExpectCorrupt(edit("HEAD", [](std::string& p) { p += "x"; }),
                "version 1 needs 28");
  ExpectCorrupt(edit("STAT", [](std::string& p) { p.pop_back(); }),
                "STAT chunk is not valid JSON");
  ExpectCorrupt(edit("SRCM", [](std::string& p) { p.resize(20); }),
                "the SRCM chunk has 20 bytes");
  ExpectCorrupt(edit("PARM", [](std::string& p) { p.resize(48); }),
                "the PARM chunk has 48 bytes");
  {
    std::vector<RawChunk> c = SplitFile(file);
    c.erase(c.begin() + (Find(c, "BSIS") - c.data()));
    ExpectCorrupt(JoinFile(c, 1), "the required chunk 'BSIS' is missing");
  }
}

TEST(SdcbFileV1Test, RandomMutationsWithValidCrcsNeverCrash) {
  // Change, insert or drop bytes inside one chunk's payload and recompute
  // its CRC: whatever is accepted must be a valid model that survives a
  // write/read cycle (as version 2) unchanged.
  const std::vector<RawChunk> good =
      SplitFile(Version1File(MakeTestModel(1, 7, 3)));
  std::mt19937 rng(11);
  int accepted = 0;
  size_t largest_overall = 0;
  for (int iteration = 0; iteration < 5000; ++iteration) {
    std::vector<RawChunk> chunks = good;
    testing::MutateBytes(&rng, &chunks[rng() % chunks.size()].payload);
    StatusOr<SplineModel> m = InternalError("not parsed");
    largest_overall =
        std::max(largest_overall, testing::LargestAllocationDuring([&] {
                   m = ParseSdcb(JoinFile(chunks, 1));
                 }));
    if (!m.ok()) {
      EXPECT_FALSE(m.status().message().empty());
      continue;
    }
    ++accepted;
    ASSERT_TRUE(ValidateSplineModel(*m).ok());
    // A version 1 file's configurations are stored, not recomputed: a
    // mutation may give valid but not Delaunay ones, which version 2 then
    // refuses to write. Otherwise the model survives a write/read cycle.
    const StatusOr<std::string> again = SerializeSdcb(*m);
    if (!again.ok()) {
      EXPECT_NE(again.status().message().find("not those of its knots"),
                std::string::npos)
          << again.status().message();
      continue;
    }
    const StatusOr<SplineModel> reread = ParseSdcb(*again);
    ASSERT_TRUE(reread.ok());
    EXPECT_TRUE(BitIdentical(*m, *reread));
  }
  EXPECT_LT(largest_overall, 16 * JoinFile(good, 1).size() + 4096);
  EXPECT_GT(accepted, 25);
  EXPECT_LT(accepted, 5000 - 25);
}

}  // namespace
}  // namespace sdcb
