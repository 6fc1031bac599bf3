#include "sdcb/io/sdcb/control_point_coding.h"

#include <algorithm>
#include <utility>

#include "sdcb/io/sdcb/range_coder.h"

namespace sdcb {
namespace {

// Contexts per coordinate: the bit length of the mean zigzag residual of
// the neighbours used for the prediction, capped.
constexpr int kMagnitudeClasses = 20;

// The rounded mean of the neighbours' codes of coordinate `c`, or of the
// previous point in the order; also the context (c, magnitude class).
struct Prediction {
  uint32_t value = 0;
  int context = 0;
};

Prediction Predict(const std::vector<uint32_t>& codes,
                   const std::vector<uint32_t>& zigzags, size_t rows,
                   const PredictionPlan& plan, size_t position, int c) {
  const size_t self = static_cast<size_t>(plan.order[position]);
  const size_t base = static_cast<size_t>(c) * rows;
  const int begin = plan.offsets[position], end = plan.offsets[position + 1];
  Prediction p;
  uint64_t sum = 0, magnitude = 0, count = 0;
  if (begin < end) {
    for (int k = begin; k < end; ++k) {
      const size_t j = static_cast<size_t>(plan.neighbours[k]);
      sum += codes[base + j];
      magnitude += zigzags[base + j];
    }
    count = static_cast<uint64_t>(end - begin);
  } else if (position > 0) {
    const size_t j = static_cast<size_t>(plan.order[position - 1]);
    sum = codes[base + j];
    magnitude = zigzags[base + j];
    count = 1;
  }
  if (count > 0) {
    p.value = static_cast<uint32_t>((sum + count / 2) / count);
    magnitude /= count;
  }
  // The point's residuals of the coordinates coded before this one.
  if (c > 0) {
    uint64_t own = 0;
    for (int d = 0; d < c; ++d)
      own += zigzags[static_cast<size_t>(d) * rows + self];
    magnitude = (2 * magnitude + own / c) / 3;
  }
  const int length = BitLength(static_cast<uint32_t>(magnitude));
  p.context = c * kMagnitudeClasses + std::min(length, kMagnitudeClasses - 1);
  return p;
}

}  // namespace

PredictionPlan PlanControlPointPrediction(
    const DelaunayConfigurations& configurations) {
  const int m = static_cast<int>(configurations.sets.size());
  // (set minus one knot, set) pairs; equal keys are adjacent sets.
  std::vector<std::pair<std::vector<int>, int>> keys;
  for (int i = 0; i < m; ++i) {
    const std::vector<int>& knots = configurations.sets[i].knots;
    for (size_t drop = 0; drop < knots.size(); ++drop) {
      std::vector<int> key;
      key.reserve(knots.size() - 1);
      for (size_t t = 0; t < knots.size(); ++t) {
        if (t != drop) key.push_back(knots[t]);
      }
      keys.emplace_back(std::move(key), i);
    }
  }
  std::sort(keys.begin(), keys.end());
  std::vector<std::vector<int>> adjacent(m);
  for (size_t a = 0; a < keys.size();) {
    size_t b = a;
    while (b < keys.size() && keys[b].first == keys[a].first) ++b;
    for (size_t x = a; x < b; ++x) {
      for (size_t y = a; y < b; ++y) {
        if (x != y) adjacent[keys[x].second].push_back(keys[y].second);
      }
    }
    a = b;
  }
  for (std::vector<int>& list : adjacent) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  PredictionPlan plan;
  plan.order.reserve(m);
  std::vector<int> position(m, -1);
  for (int root = 0; root < m; ++root) {
    if (position[root] >= 0) continue;
    size_t head = plan.order.size();
    position[root] = static_cast<int>(plan.order.size());
    plan.order.push_back(root);
    for (; head < plan.order.size(); ++head) {
      for (int j : adjacent[plan.order[head]]) {
        if (position[j] < 0) {
          position[j] = static_cast<int>(plan.order.size());
          plan.order.push_back(j);
        }
      }
    }
  }
  plan.offsets.reserve(m + 1);
  plan.offsets.push_back(0);
  for (int p = 0; p < m; ++p) {
    for (int j : adjacent[plan.order[p]]) {
      if (position[j] < p) plan.neighbours.push_back(j);
    }
    plan.offsets.push_back(static_cast<int>(plan.neighbours.size()));
  }
  return plan;
}

std::string EncodePredictedCodes(const std::vector<uint32_t>& codes,
                                 const PredictionPlan& plan) {
  const size_t rows = plan.order.size();
  std::vector<uint32_t> zigzags(codes.size(), 0);
  IntegerModel model(3 * kMagnitudeClasses);
  RangeEncoder encoder;
  for (size_t p = 0; p < rows; ++p) {
    const size_t i = static_cast<size_t>(plan.order[p]);
    for (int c = 0; c < 3; ++c) {
      const Prediction prediction = Predict(codes, zigzags, rows, plan, p, c);
      const size_t at = static_cast<size_t>(c) * rows + i;
      zigzags[at] = Zigzag(codes[at] - prediction.value);
      model.Encode(zigzags[at], prediction.context, &encoder);
    }
  }
  return encoder.Finish();
}

StatusOr<std::vector<uint32_t>> DecodePredictedCodes(std::string_view stream,
                                                     const PredictionPlan& plan,
                                                     int bits) {
  const size_t rows = plan.order.size();
  std::vector<uint32_t> codes(3 * rows, 0), zigzags(3 * rows, 0);
  const uint64_t top = (uint64_t{1} << bits) - 1;
  IntegerModel model(3 * kMagnitudeClasses);
  RangeDecoder decoder(stream);
  for (size_t p = 0; p < rows; ++p) {
    const size_t i = static_cast<size_t>(plan.order[p]);
    for (int c = 0; c < 3; ++c) {
      const Prediction prediction = Predict(codes, zigzags, rows, plan, p, c);
      const size_t at = static_cast<size_t>(c) * rows + i;
      uint32_t z = 0;
      if (!model.Decode(prediction.context, &decoder, &z)) {
        return CorruptFileError("control point " + std::to_string(i) +
                                " has a residual longer than 32 bits");
      }
      const uint32_t code = prediction.value + Unzigzag(z);
      if (code > top || decoder.overran()) {
        return CorruptFileError(
            decoder.overran()
                ? "the range-coded stream ends before control point " +
                      std::to_string(i)
                : "control point " + std::to_string(i) + "'s code " +
                      std::to_string(code) + " exceeds " +
                      std::to_string(bits) + " bits");
      }
      codes[at] = code;
      zigzags[at] = z;
    }
  }
  if (decoder.unread() != 0) {
    return CorruptFileError("the range-coded stream has " +
                            std::to_string(decoder.unread()) +
                            " bytes after its last control point");
  }
  return codes;
}

}  // namespace sdcb
