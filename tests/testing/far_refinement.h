// Uniform subdivision by OpenSubdiv's Far (TopologyRefiner + PrimvarRefiner),
// the oracle for the cage converters: it shares no code path with Bfr's limit
// stencils, which the converters use.
#ifndef SDCB_TESTS_TESTING_FAR_REFINEMENT_H_
#define SDCB_TESTS_TESTING_FAR_REFINEMENT_H_

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

namespace sdcb::testing {

// A point for PrimvarRefinerReal<double>.
struct FarPoint {
  double p[3] = {0, 0, 0};
  void Clear(void* = nullptr) { p[0] = p[1] = p[2] = 0; }
  void AddWithWeight(const FarPoint& s, double w) {
    for (int k = 0; k < 3; ++k) p[k] += w * s.p[k];
  }
};

// The Far refiner of a closed polygon cage (`faces`: corner lists).
// `creases`: infinitely sharp edges (vertex pairs).
inline std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> MakeFarRefiner(
    bool loop, int num_vertices, const std::vector<std::vector<int>>& faces,
    const std::vector<std::array<int, 2>>& creases = {}) {
  namespace osd = OpenSubdiv;
  std::vector<int> sizes, indices;
  for (const auto& f : faces) {
    sizes.push_back(static_cast<int>(f.size()));
    indices.insert(indices.end(), f.begin(), f.end());
  }
  osd::Far::TopologyDescriptor d;
  d.numVertices = num_vertices;
  d.numFaces = static_cast<int>(faces.size());
  d.numVertsPerFace = sizes.data();
  d.vertIndicesPerFace = indices.data();
  std::vector<int> pairs;
  for (const auto& [a, b] : creases) {
    pairs.push_back(a);
    pairs.push_back(b);
  }
  const std::vector<float> sharpness(creases.size(),
                                     osd::Sdc::Crease::SHARPNESS_INFINITE);
  d.numCreases = static_cast<int>(creases.size());
  d.creaseVertexIndexPairs = pairs.data();
  d.creaseWeights = sharpness.data();
  osd::Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(osd::Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  using Factory =
      osd::Far::TopologyRefinerFactory<osd::Far::TopologyDescriptor>;
  return std::unique_ptr<osd::Far::TopologyRefiner>(Factory::Create(
      d, Factory::Options(
             loop ? osd::Sdc::SCHEME_LOOP : osd::Sdc::SCHEME_CATMARK, sdc)));
}

struct FarRefined {
  // The finest level's vertices, and their limit positions.
  Eigen::MatrixX3d points, limit;
  // The finest level's faces (quads or triangles), for meshes of the limit.
  std::vector<std::vector<int>> faces;
};

// Refines the cage `levels` times uniformly (Far) and evaluates the finest
// level's vertices at the limit (PrimvarRefiner::Limit).
inline FarRefined RefineWithFar(
    bool loop, const Eigen::MatrixX3d& cage,
    const std::vector<std::vector<int>>& faces, int levels,
    const std::vector<std::array<int, 2>>& creases = {}) {
  namespace osd = OpenSubdiv;
  auto refiner =
      MakeFarRefiner(loop, static_cast<int>(cage.rows()), faces, creases);
  FarRefined out;
  if (!refiner) return out;
  osd::Far::TopologyRefiner::UniformOptions uniform(levels);
  uniform.fullTopologyInLastLevel = true;  // PrimvarRefiner::Limit needs it
  refiner->RefineUniform(uniform);
  std::vector<FarPoint> all(refiner->GetNumVerticesTotal());
  for (Eigen::Index i = 0; i < cage.rows(); ++i) {
    for (int k = 0; k < 3; ++k) all[i].p[k] = cage(i, k);
  }
  osd::Far::PrimvarRefinerReal<double> primvar(*refiner);
  FarPoint* src = all.data();
  for (int level = 1; level <= levels; ++level) {
    FarPoint* dst = src + refiner->GetLevel(level - 1).GetNumVertices();
    primvar.Interpolate(level, src, dst);
    src = dst;
  }
  const osd::Far::TopologyLevel& last = refiner->GetLevel(levels);
  const int n = last.GetNumVertices();
  std::vector<FarPoint> limit(n);
  primvar.Limit(src, limit);
  out.points.resize(n, 3);
  out.limit.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      out.points(i, k) = src[i].p[k];
      out.limit(i, k) = limit[i].p[k];
    }
  }
  for (int f = 0; f < last.GetNumFaces(); ++f) {
    const auto v = last.GetFaceVertices(f);
    out.faces.emplace_back(v.begin(), v.end());
  }
  return out;
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_FAR_REFINEMENT_H_
