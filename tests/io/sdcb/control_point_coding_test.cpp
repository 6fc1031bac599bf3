// Tests io/sdcb/control_point_coding.*: the prediction plan against its
// definition checked by brute force over all pairs of basis functions (a
// permutation; each point's neighbours are the sets sharing all but one knot
// and coded before it), round trips of random, smooth and extreme codes at
// every bit count, and streams that are cut, extended or damaged.
#include "sdcb/io/sdcb/control_point_coding.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "sdcb/core/spline/delaunay_configurations.h"
#include "testing/random_knots.h"

namespace sdcb {
namespace {

DelaunayConfigurations Configurations(int knots, int degree, unsigned seed) {
  StatusOr<DelaunayConfigurations> c =
      ComputeDelaunayConfigurations(testing::UniformKnots(knots, seed), degree);
  EXPECT_TRUE(c.ok()) << c.status().message();
  return *c;
}

int SharedKnots(const std::vector<int>& a, const std::vector<int>& b) {
  std::vector<int> common;
  std::set_intersection(a.begin(), a.end(), b.begin(), b.end(),
                        std::back_inserter(common));
  return static_cast<int>(common.size());
}

TEST(ControlPointCodingTest, PlanFollowsItsDefinition) {
  for (int degree : {0, 2, 4}) {
    const DelaunayConfigurations c = Configurations(30, degree, 2 + degree);
    const int m = static_cast<int>(c.sets.size());
    const PredictionPlan plan = PlanControlPointPrediction(c);
    std::vector<int> sorted = plan.order;
    std::sort(sorted.begin(), sorted.end());
    for (int i = 0; i < m; ++i) ASSERT_EQ(sorted[i], i);
    EXPECT_EQ(plan.order[0], 0);
    ASSERT_EQ(plan.offsets.size(), static_cast<size_t>(m + 1));
    std::vector<int> position(m);
    for (int p = 0; p < m; ++p) position[plan.order[p]] = p;
    const int k3 = degree + 3;
    for (int p = 0; p < m; ++p) {
      const int i = plan.order[p];
      std::vector<int> expected;
      for (int j = 0; j < m; ++j) {
        if (j != i && position[j] < p &&
            SharedKnots(c.sets[i].knots, c.sets[j].knots) == k3 - 1) {
          expected.push_back(j);
        }
      }
      const std::vector<int> got(plan.neighbours.begin() + plan.offsets[p],
                                 plan.neighbours.begin() + plan.offsets[p + 1]);
      ASSERT_EQ(got, expected) << "position " << p;
      // Breadth-first over a connected graph: only the first has none.
      if (p > 0) EXPECT_FALSE(got.empty()) << p;
    }
  }
}

std::vector<uint32_t> RandomCodes(size_t count, int bits, unsigned seed) {
  std::mt19937_64 rng(seed);
  const uint64_t top = (uint64_t{1} << bits) - 1;
  std::vector<uint32_t> codes(count);
  for (uint32_t& c : codes) c = static_cast<uint32_t>(rng() & top);
  return codes;
}

TEST(ControlPointCodingTest, CodesRoundTripAtEveryBitCount) {
  const DelaunayConfigurations c = Configurations(40, 3, 9);
  const PredictionPlan plan = PlanControlPointPrediction(c);
  const size_t m = c.sets.size();
  for (int bits = 1; bits <= 32; ++bits) {
    std::vector<std::vector<uint32_t>> cases = {RandomCodes(3 * m, bits, bits)};
    const uint32_t top = static_cast<uint32_t>((uint64_t{1} << bits) - 1);
    cases.push_back(std::vector<uint32_t>(3 * m, top));  // all at the top
    std::vector<uint32_t> alternating(3 * m);            // 0 and top in turn
    for (size_t i = 0; i < alternating.size(); ++i) {
      alternating[i] = i % 2 ? top : 0;
    }
    cases.push_back(alternating);
    for (const std::vector<uint32_t>& codes : cases) {
      const std::string stream = EncodePredictedCodes(codes, plan);
      const StatusOr<std::vector<uint32_t>> back =
          DecodePredictedCodes(stream, plan, bits);
      ASSERT_TRUE(back.ok()) << bits << ": " << back.status().message();
      ASSERT_EQ(*back, codes) << bits;
    }
  }
}

// Smooth codes (a function of each set's knots) cost fewer bits than
// random ones: the prediction works.
TEST(ControlPointCodingTest, SmoothCodesCostLittle) {
  const Eigen::MatrixX3d knots = testing::UniformKnots(200, 4);
  const DelaunayConfigurations c = *ComputeDelaunayConfigurations(knots, 2);
  const PredictionPlan plan = PlanControlPointPrediction(c);
  const size_t m = c.sets.size();
  std::vector<uint32_t> smooth(3 * m);
  for (size_t i = 0; i < m; ++i) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int k : c.sets[i].knots) mean += knots.row(k).transpose();
    mean /= static_cast<double>(c.sets[i].knots.size());
    for (int d = 0; d < 3; ++d) {
      smooth[d * m + i] = static_cast<uint32_t>((mean[d] + 1) * 511.5);
    }
  }
  const size_t smooth_bytes = EncodePredictedCodes(smooth, plan).size();
  const size_t random_bytes =
      EncodePredictedCodes(RandomCodes(3 * m, 10, 1), plan).size();
  EXPECT_GT(random_bytes, 3 * m);  // about 10 bits a code and more
  EXPECT_LT(4 * smooth_bytes, 3 * random_bytes);  // measured: 0.64
  ASSERT_EQ(*DecodePredictedCodes(EncodePredictedCodes(smooth, plan), plan, 10),
            smooth);
}

TEST(ControlPointCodingTest, DamagedStreamsAreRejectedOrInRange) {
  const DelaunayConfigurations c = Configurations(20, 2, 5);
  const PredictionPlan plan = PlanControlPointPrediction(c);
  const std::vector<uint32_t> codes = RandomCodes(3 * c.sets.size(), 12, 3);
  const std::string stream = EncodePredictedCodes(codes, plan);
  for (size_t cut = 0; cut < stream.size(); ++cut) {
    const auto r = DecodePredictedCodes(stream.substr(0, cut), plan, 12);
    ASSERT_FALSE(r.ok()) << cut;
    EXPECT_EQ(r.status().code(), StatusCode::kCorruptFile);
  }
  EXPECT_FALSE(DecodePredictedCodes(stream + '\0', plan, 12).ok());
  // Fewer bits than the codes need.
  EXPECT_FALSE(DecodePredictedCodes(stream, plan, 4).ok());
  std::mt19937 rng(8);
  for (int trial = 0; trial < 3000; ++trial) {
    std::string bad = stream;
    bad[rng() % bad.size()] ^= static_cast<char>(1 + rng() % 255);
    const auto r = DecodePredictedCodes(bad, plan, 12);
    if (!r.ok()) continue;
    for (uint32_t code : *r) ASSERT_LT(code, 4096u);
  }
}

}  // namespace
}  // namespace sdcb
