#include "sdcb/converters/cad_patch_cache.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace sdcb {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The pole indices (into BicubicPatch::poles) of local edge k, from corner
// k to corner k + 1.
std::array<int, 4> EdgePoleIndices(int k) {
  switch (k) {
    case 0:
      return {0, 1, 2, 3};
    case 1:
      return {3, 7, 11, 15};
    case 2:
      return {15, 14, 13, 12};
    default:
      return {12, 8, 4, 0};
  }
}

}  // namespace

PointKey KeyOf(const Eigen::Vector3d& p) {
  PointKey key;
  std::memcpy(key.data(), p.data(), sizeof key);
  return key;
}
EdgeKeyPoints EdgeKeyOf(const FaceKey& face, int c) {
  const PointKey& a = face[c];
  const PointKey& b = face[(c + 1) % 4];
  return a < b ? EdgeKeyPoints{a, b} : EdgeKeyPoints{b, a};
}

PatchCache::PatchCache(const PiecewiseSurface& surface,
                       const CadPatchOptions& options)
    : surface_(surface), k_(options.fit_samples_per_side) {
  // The edge curves' inner poles: least squares over the k inner points.
  Eigen::Matrix2d normal_matrix = Eigen::Matrix2d::Zero();
  edge_basis_.resize(k_);
  for (int m = 0; m < k_; ++m) {
    CubicBernstein((m + 1.0) / (k_ + 1.0), edge_basis_[m].data(), nullptr);
    normal_matrix(0, 0) += edge_basis_[m][1] * edge_basis_[m][1];
    normal_matrix(0, 1) += edge_basis_[m][1] * edge_basis_[m][2];
    normal_matrix(1, 1) += edge_basis_[m][2] * edge_basis_[m][2];
  }
  normal_matrix(1, 0) = normal_matrix(0, 1);
  edge_inverse_ = normal_matrix.inverse();
  // The faces' inner poles: the same design matrix for every face.
  full_.resize(k_ * k_, 16);
  for (int j = 0; j < k_; ++j) {
    for (int i = 0; i < k_; ++i) {
      double bu[4], bv[4];
      CubicBernstein((i + 0.5) / k_, bu, nullptr);
      CubicBernstein((j + 0.5) / k_, bv, nullptr);
      for (int q = 0; q < 16; ++q) {
        full_(j * k_ + i, q) = bu[q % 4] * bv[q / 4];
      }
    }
  }
  design_.resize(k_ * k_, 4);
  for (int c = 0; c < 4; ++c) design_.col(c) = full_.col(kInner[c]);
  solver_.compute((design_.transpose() * design_).eval());
}

std::vector<FaceRecord*> PatchCache::Update(const SphereCage& layout) {
  const int nf = layout.num_faces();
  std::vector<FaceKey> keys(nf);
  std::unordered_map<FaceKey, FaceRecord, KeyHash<4>> faces;
  faces.reserve(nf);
  std::vector<int> fresh;
  for (int f = 0; f < nf; ++f) {
    for (int c = 0; c < 4; ++c) {
      keys[f][c] = KeyOf(layout.sphere_points.row(layout.faces[f][c]));
    }
    auto old = faces_.find(keys[f]);
    if (old != faces_.end()) {
      faces.emplace(keys[f], std::move(old->second));
    } else if (faces.emplace(keys[f], FaceRecord()).second) {
      fresh.push_back(f);
    }
  }
  faces_ = std::move(faces);

  // The new faces' edges that have no curve yet, from the smaller end.
  std::unordered_map<EdgeKeyPoints, std::array<Eigen::Vector3d, 4>, KeyHash<2>>
      edges;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> ends;
  std::vector<EdgeKeyPoints> new_edges;
  for (int f : fresh) {
    for (int c = 0; c < 4; ++c) {
      const int a = layout.faces[f][c], b = layout.faces[f][(c + 1) % 4];
      const bool forward = keys[f][c] < keys[f][(c + 1) % 4];
      const EdgeKeyPoints key = EdgeKeyOf(keys[f], c);
      if (edges_.count(key) || edges.count(key)) continue;
      edges.emplace(key, std::array<Eigen::Vector3d, 4>());
      new_edges.push_back(key);
      ends.emplace_back(layout.sphere_points.row(forward ? a : b),
                        layout.sphere_points.row(forward ? b : a));
    }
  }
  const Eigen::Index ne = static_cast<Eigen::Index>(new_edges.size());
  Eigen::MatrixX3d directions(ne * (k_ + 2), 3);
  for (Eigen::Index e = 0; e < ne; ++e) {
    const auto& [a, b] = ends[e];
    directions.row(e * (k_ + 2)) = a;
    directions.row(e * (k_ + 2) + k_ + 1) = b;
    for (int m = 0; m < k_; ++m) {
      const double t = (m + 1.0) / (k_ + 1.0);
      directions.row(e * (k_ + 2) + m + 1) =
          ((1.0 - t) * a + t * b).normalized();
    }
  }
  Eigen::MatrixX3d targets;
  surface_.EvaluateMany(directions, &targets, nullptr);
  for (Eigen::Index e = 0; e < ne; ++e) {
    const Eigen::Index base = e * (k_ + 2);
    const Eigen::Vector3d q0 = targets.row(base);
    const Eigen::Vector3d q3 = targets.row(base + k_ + 1);
    Eigen::Matrix<double, 2, 3> rhs = Eigen::Matrix<double, 2, 3>::Zero();
    for (int m = 0; m < k_; ++m) {
      const Eigen::RowVector3d r = targets.row(base + m + 1) -
                                   edge_basis_[m][0] * q0.transpose() -
                                   edge_basis_[m][3] * q3.transpose();
      rhs.row(0) += edge_basis_[m][1] * r;
      rhs.row(1) += edge_basis_[m][2] * r;
    }
    const Eigen::Matrix<double, 2, 3> inner = edge_inverse_ * rhs;
    edges[new_edges[e]] = {q0, inner.row(0).transpose(),
                           inner.row(1).transpose(), q3};
  }
  // The curves of the layout's edges only.
  for (int f = 0; f < nf; ++f) {
    for (int c = 0; c < 4; ++c) {
      const EdgeKeyPoints key = EdgeKeyOf(keys[f], c);
      if (edges.count(key)) continue;
      auto old = edges_.find(key);
      if (old != edges_.end()) edges.emplace(key, old->second);
    }
  }
  edges_ = std::move(edges);

  // The new faces' inner poles, boundary held fixed.
  const Eigen::Index nfresh = static_cast<Eigen::Index>(fresh.size());
  Eigen::MatrixX3d face_directions(nfresh * k_ * k_, 3);
  for (Eigen::Index i = 0; i < nfresh; ++i) {
    for (int j = 0; j < k_; ++j) {
      for (int m = 0; m < k_; ++m) {
        face_directions.row((i * k_ + j) * k_ + m) =
            layout.SpherePoint(fresh[i], (m + 0.5) / k_, (j + 0.5) / k_);
      }
    }
  }
  surface_.EvaluateMany(face_directions, &targets, nullptr);
  for (Eigen::Index i = 0; i < nfresh; ++i) {
    const int f = fresh[i];
    BicubicPatch& patch = faces_.at(keys[f]).patch;
    for (int side = 0; side < 4; ++side) {
      const bool forward = keys[f][side] < keys[f][(side + 1) % 4];
      const auto& curve = edges_.at(EdgeKeyOf(keys[f], side));
      const std::array<int, 4> slots = EdgePoleIndices(side);
      for (int q = 0; q < 4; ++q) {
        patch.poles[slots[q]] = forward ? curve[q] : curve[3 - q];
      }
    }
    Eigen::MatrixX3d rhs = targets.middleRows(i * k_ * k_, k_ * k_);
    for (int q = 0; q < 16; ++q) {
      if (q == 5 || q == 6 || q == 9 || q == 10) continue;
      rhs -= full_.col(q) * patch.poles[q].transpose();
    }
    const Eigen::Matrix<double, 4, 3> inner =
        solver_.solve(design_.transpose() * rhs);
    for (int c = 0; c < 4; ++c)
      patch.poles[kInner[c]] = inner.row(c).transpose();
  }

  std::vector<FaceRecord*> records(nf);
  for (int f = 0; f < nf; ++f) records[f] = &faces_.at(keys[f]);
  return records;
}

void PatchCache::Measure(const SphereCage& layout,
                         const std::vector<int>& faces,
                         const std::vector<FaceRecord*>& records, int n,
                         bool fine) const {
  const int order = fine ? 3 * n : n;
  const int per_face = (order + 1) * (order + 1);
  const Eigen::Index count = static_cast<Eigen::Index>(faces.size());
  Eigen::MatrixX3d directions(count * per_face, 3);
  tbb::parallel_for(Eigen::Index{0}, count, [&](Eigen::Index i) {
    for (int j = 0; j <= order; ++j) {
      for (int m = 0; m <= order; ++m) {
        directions.row(i * per_face + j * (order + 1) + m) =
            layout.SpherePoint(faces[i], double(m) / order, double(j) / order);
      }
    }
  });
  Eigen::MatrixX3d points, normals;
  surface_.EvaluateMany(directions, &points, &normals);
  tbb::parallel_for(Eigen::Index{0}, count, [&](Eigen::Index i) {
    FaceRecord& r = *records[faces[i]];
    double max_distance = 0.0, max_angle = 0.0, squares = 0.0, area = 0.0;
    for (int j = 0; j <= order; ++j) {
      for (int m = 0; m <= order; ++m) {
        Eigen::Vector3d du, dv;
        const Eigen::Vector3d b =
            r.patch.Evaluate(double(m) / order, double(j) / order, &du, &dv);
        const Eigen::Index row = i * per_face + j * (order + 1) + m;
        const double d = (b - points.row(row).transpose()).norm();
        const Eigen::Vector3d patch_normal = du.cross(dv);
        const Eigen::Vector3d spline_normal = normals.row(row);
        if (patch_normal.norm() > 0.0 && spline_normal.norm() > 0.0) {
          const double c = std::clamp(
              patch_normal.normalized().dot(spline_normal), -1.0, 1.0);
          max_angle = std::max(max_angle, std::acos(c) * 180.0 / kPi);
        }
        // Trapezoid weights of the lattice.
        const double w = ((m == 0 || m == order) ? 0.5 : 1.0) *
                         ((j == 0 || j == order) ? 0.5 : 1.0) *
                         patch_normal.norm();
        squares += w * d * d;
        area += w;
        max_distance = std::max(max_distance, d);
      }
    }
    if (fine) {
      r.fine = true;
      r.fine_max_distance = max_distance;
      r.fine_max_angle = max_angle;
    } else {
      r = FaceRecord{r.patch, n, max_distance, max_angle, squares, area};
    }
  });
}

}  // namespace sdcb
