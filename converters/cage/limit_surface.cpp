#include "sdcb/converters/cage/limit_surface.h"

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <tbb/parallel_for.h>

#include <string>
#include <utility>

namespace sdcb {

namespace osd = OpenSubdiv;

struct LimitSurface::Impl {
  std::unique_ptr<osd::Far::TopologyRefiner> refiner;
  std::vector<std::unique_ptr<osd::Bfr::Surface<double>>> surfaces;
  std::vector<std::vector<int>> control_points;  // per face
};

LimitSurface::LimitSurface(std::unique_ptr<Impl> impl, SubdivisionScheme scheme,
                           int num_vertices)
    : impl_(std::move(impl)), scheme_(scheme), num_vertices_(num_vertices) {}
LimitSurface::LimitSurface(LimitSurface&&) noexcept = default;
LimitSurface& LimitSurface::operator=(LimitSurface&&) noexcept = default;
LimitSurface::~LimitSurface() = default;

StatusOr<LimitSurface> LimitSurface::Create(
    SubdivisionScheme scheme, int num_vertices,
    const std::vector<std::array<int, 4>>& faces, int approximation_level,
    const std::vector<std::array<int, 2>>& creases) {
  const int corners = scheme == SubdivisionScheme::kLoop ? 3 : 4;
  const int nf = static_cast<int>(faces.size());
  if (nf == 0 || num_vertices < 3) {
    return InvalidArgumentError("subdivision cage: the cage has no faces");
  }
  std::vector<int> sizes(nf, corners);
  std::vector<int> indices;
  indices.reserve(static_cast<size_t>(nf) * corners);
  for (const auto& f : faces) {
    for (int k = 0; k < corners; ++k) {
      if (f[k] < 0 || f[k] >= num_vertices) {
        return InvalidArgumentError(
            "subdivision cage: a face refers to a missing vertex");
      }
      indices.push_back(f[k]);
    }
  }
  using Factory =
      osd::Far::TopologyRefinerFactory<osd::Far::TopologyDescriptor>;
  osd::Far::TopologyDescriptor descriptor;
  descriptor.numVertices = num_vertices;
  descriptor.numFaces = nf;
  descriptor.numVertsPerFace = sizes.data();
  descriptor.vertIndicesPerFace = indices.data();
  std::vector<int> crease_pairs;
  for (const auto& [a, b] : creases) {
    if (a < 0 || a >= num_vertices || b < 0 || b >= num_vertices) {
      return InvalidArgumentError(
          "subdivision cage: a crease refers to a missing vertex");
    }
    crease_pairs.push_back(a);
    crease_pairs.push_back(b);
  }
  const std::vector<float> crease_weights(creases.size(),
                                          osd::Sdc::Crease::SHARPNESS_INFINITE);
  descriptor.numCreases = static_cast<int>(creases.size());
  descriptor.creaseVertexIndexPairs = crease_pairs.data();
  descriptor.creaseWeights = crease_weights.data();
  osd::Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(osd::Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  const osd::Sdc::SchemeType type = scheme == SubdivisionScheme::kLoop
                                        ? osd::Sdc::SCHEME_LOOP
                                        : osd::Sdc::SCHEME_CATMARK;
  auto impl = std::make_unique<Impl>();
  impl->refiner.reset(Factory::Create(descriptor, Factory::Options(type, sdc)));
  if (!impl->refiner) {
    return InvalidArgumentError(
        "subdivision cage: OpenSubdiv rejected the cage's topology");
  }
  osd::Bfr::RefinerSurfaceFactory<>::Options options;
  options.SetApproxLevelSmooth(approximation_level);
  const osd::Bfr::RefinerSurfaceFactory<> factory(*impl->refiner, options);
  impl->surfaces.resize(nf);
  impl->control_points.resize(nf);
  for (int f = 0; f < nf; ++f) {
    auto surface = std::make_unique<osd::Bfr::Surface<double>>();
    if (!factory.InitVertexSurface(f, surface.get()) || !surface->IsValid()) {
      return InvalidArgumentError("subdivision cage: face " +
                                  std::to_string(f) +
                                  " has no limit surface (a boundary or a "
                                  "non-manifold vertex)");
    }
    std::vector<int>& cps = impl->control_points[f];
    cps.resize(surface->GetNumControlPoints());
    surface->GetControlPointIndices(cps.data());
    impl->surfaces[f] = std::move(surface);
  }
  return LimitSurface(std::move(impl), scheme, num_vertices);
}

int LimitSurface::num_faces() const {
  return static_cast<int>(impl_->surfaces.size());
}

bool LimitSurface::IsRegular(int f) const {
  return impl_->surfaces[f]->IsRegular();
}

void LimitSurface::Stencil(int f, double u, double v, LimitStencil* out) const {
  const std::vector<int>& cps = impl_->control_points[f];
  const size_t n = cps.size();
  out->position.assign(n, 0.0);
  out->du.assign(n, 0.0);
  out->dv.assign(n, 0.0);
  const double uv[2] = {u, v};
  impl_->surfaces[f]->EvaluateStencil(uv, out->position.data(), out->du.data(),
                                      out->dv.data());
  out->indices = cps;
}

Eigen::Vector3d LimitSurface::Evaluate(int f, double u, double v,
                                       const Eigen::MatrixX3d& cage,
                                       Eigen::Vector3d* du,
                                       Eigen::Vector3d* dv) const {
  LimitStencil s;
  Stencil(f, u, v, &s);
  Eigen::Vector3d p = Eigen::Vector3d::Zero(), pu = p, pv = p;
  for (size_t k = 0; k < s.indices.size(); ++k) {
    const Eigen::Vector3d c = cage.row(s.indices[k]).transpose();
    p += s.position[k] * c;
    pu += s.du[k] * c;
    pv += s.dv[k] * c;
  }
  if (du) *du = pu;
  if (dv) *dv = pv;
  return p;
}

PreparedLimit::PreparedLimit(const LimitSurface& limit,
                             const Eigen::MatrixX3d& cage)
    : limit_(limit) {
  const auto& surfaces = limit.impl_->surfaces;
  const int nf = static_cast<int>(surfaces.size());
  first_.resize(nf + 1);
  first_[0] = 0;
  for (int f = 0; f < nf; ++f) {
    first_[f + 1] = first_[f] + 3 * surfaces[f]->GetNumPatchPoints();
  }
  points_.resize(first_[nf]);
  // Bfr reads the mesh's points as one contiguous x, y, z array.
  std::vector<double> mesh(3 * cage.rows());
  for (Eigen::Index i = 0; i < cage.rows(); ++i) {
    for (int k = 0; k < 3; ++k) mesh[3 * i + k] = cage(i, k);
  }
  const osd::Bfr::Surface<double>::PointDescriptor xyz(3);
  tbb::parallel_for(0, nf, [&](int f) {
    surfaces[f]->PreparePatchPoints(mesh.data(), xyz,
                                    points_.data() + first_[f], xyz);
  });
}

Eigen::Vector3d PreparedLimit::Evaluate(int f, double u, double v,
                                        Eigen::Vector3d* du,
                                        Eigen::Vector3d* dv) const {
  const double uv[2] = {u, v};
  const osd::Bfr::Surface<double>::PointDescriptor xyz(3);
  Eigen::Vector3d p, pu, pv;
  limit_.impl_->surfaces[f]->Evaluate(uv, points_.data() + first_[f], xyz,
                                      p.data(), pu.data(), pv.data());
  if (du) *du = pu;
  if (dv) *dv = pv;
  return p;
}

}  // namespace sdcb
