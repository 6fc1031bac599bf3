#include "sdcb/core/mesh/triangle_mesh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace sdcb {

Status CheckFaceIndices(const TriangleMesh& mesh) {
  const int nv = mesh.num_vertices();
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.faces(f, k);
      if (v < 0 || v >= nv) {
        return InvalidInputError("face " + std::to_string(f) +
                                 " refers to vertex " + std::to_string(v) +
                                 ", but there are only " + std::to_string(nv) +
                                 " vertices");
      }
    }
  }
  return Status::Ok();
}

Eigen::VectorXd VertexAreas(const TriangleMesh& mesh) {
  Eigen::VectorXd area = Eigen::VectorXd::Zero(mesh.vertices.rows());
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
    const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1));
    const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2));
    const double t = 0.5 * (b - a).cross(c - a).norm();
    for (int k = 0; k < 3; ++k) area[mesh.faces(f, k)] += t / 3;
  }
  return area;
}

double SignedVolume(const Eigen::MatrixX3d& vertices,
                    const Eigen::MatrixX3i& faces) {
  double six_volume = 0.0;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3d a = vertices.row(faces(f, 0));
    const Eigen::Vector3d b = vertices.row(faces(f, 1));
    const Eigen::Vector3d c = vertices.row(faces(f, 2));
    six_volume += a.dot(b.cross(c));
  }
  return six_volume / 6.0;
}

Eigen::MatrixX3d VertexNormals(const TriangleMesh& mesh) {
  Eigen::MatrixX3d normal = Eigen::MatrixX3d::Zero(mesh.vertices.rows(), 3);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
    const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1));
    const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2));
    const Eigen::RowVector3d n = 0.5 * (b - a).cross(c - a).transpose();
    for (int k = 0; k < 3; ++k) normal.row(mesh.faces(f, k)) += n;
  }
  for (Eigen::Index v = 0; v < normal.rows(); ++v) {
    const double length = normal.row(v).norm();
    if (length > 0) normal.row(v) /= length;
  }
  return normal;
}

double CoveringRadius(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                      const Eigen::Vector3d& c) {
  double l[3] = {(b - c).squaredNorm(), (c - a).squaredNorm(),
                 (a - b).squaredNorm()};
  std::sort(l, l + 3);
  const double twice_area = (b - a).cross(c - a).norm();
  // Obtuse, right or degenerate: the circumcentre is not inside.
  if (!(l[0] + l[1] > l[2]) || !(twice_area > 0)) return 0.5 * std::sqrt(l[2]);
  // R = |a - b| |b - c| |c - a| / (4 area).
  return std::sqrt(l[0] * l[1] * l[2]) / (2.0 * twice_area);
}

namespace {

// SplitToEdgeLength's state: the points made so far and the midpoint of
// every edge split, made once (a + b is b + a, so the two triangles of an
// edge agree on it).
class EdgeSplitter {
 public:
  EdgeSplitter(const TriangleMesh& mesh, double max_edge_length)
      : mesh_(mesh),
        nv_(mesh.vertices.rows()),
        max_squared_(max_edge_length * max_edge_length) {}

  int64_t num_vertices() const {
    return nv_ + static_cast<int64_t>(added_.size());
  }

  Eigen::RowVector3d Position(int v) const {
    return v < nv_ ? Eigen::RowVector3d(mesh_.vertices.row(v))
                   : added_[static_cast<size_t>(v - nv_)];
  }

  bool Longer(int a, int b) const {
    return (Position(b) - Position(a)).squaredNorm() > max_squared_;
  }

  int Middle(int a, int b) {
    const uint64_t key = (static_cast<uint64_t>(std::min(a, b)) << 32) |
                         static_cast<uint32_t>(std::max(a, b));
    const auto [it, inserted] =
        midpoint_.emplace(key, static_cast<int>(num_vertices()));
    if (inserted) added_.push_back(0.5 * (Position(a) + Position(b)));
    return it->second;
  }

  // The points of edge (a, b) from a to b once it is split as every edge
  // is: at its midpoint while longer than the limit, the halves alike.
  void AppendEdgePoints(int a, int b, std::vector<int>* out) {
    if (!Longer(a, b)) {
      if (out->empty()) out->push_back(a);
      out->push_back(b);
      return;
    }
    const int m = Middle(a, b);
    AppendEdgePoints(a, m, out);
    AppendEdgePoints(m, b, out);
  }

  // The pieces of t whose edges (a, b) and (c, a) are longer than the limit
  // and (b, c) is not: the two edges split as every edge is, and the strip
  // between them cut across, from the corner a to the edge (b, c), each
  // piece's third point the one of the two sides whose next point is
  // nearer in fraction of its side. A needle is thus cut into pieces as
  // wide as it, as many as its length asks.
  void AppendStrip(int a, int b, int c, std::vector<Eigen::RowVector3i>* out) {
    std::vector<int> p, q;
    AppendEdgePoints(a, b, &p);
    AppendEdgePoints(a, c, &q);
    const size_t n = p.size() - 1, m = q.size() - 1;
    out->emplace_back(a, p[1], q[1]);
    size_t i = 1, j = 1;
    while (i < n || j < m) {
      if (j == m || (i < n && static_cast<double>(i + 1) * m <=
                                  static_cast<double>(j + 1) * n)) {
        out->emplace_back(p[i], p[i + 1], q[j]);
        ++i;
      } else {
        out->emplace_back(p[i], q[j + 1], q[j]);
        ++j;
      }
    }
  }

  TriangleMesh Result(const std::vector<Eigen::RowVector3i>& faces) const {
    TriangleMesh out;
    out.vertices.resize(num_vertices(), 3);
    out.vertices.topRows(nv_) = mesh_.vertices;
    for (size_t i = 0; i < added_.size(); ++i) {
      out.vertices.row(nv_ + static_cast<Eigen::Index>(i)) = added_[i];
    }
    out.faces.resize(static_cast<Eigen::Index>(faces.size()), 3);
    for (size_t i = 0; i < faces.size(); ++i) {
      out.faces.row(static_cast<Eigen::Index>(i)) = faces[i];
    }
    return out;
  }

 private:
  const TriangleMesh& mesh_;
  const Eigen::Index nv_;
  const double max_squared_;
  std::vector<Eigen::RowVector3d> added_;
  std::unordered_map<uint64_t, int> midpoint_;
};

}  // namespace

std::optional<TriangleMesh> SplitToEdgeLength(const TriangleMesh& mesh,
                                              double max_edge_length,
                                              int64_t max_vertices) {
  if (mesh.vertices.rows() > max_vertices) return std::nullopt;
  if (!(max_edge_length > 0)) return mesh;
  EdgeSplitter splitter(mesh, max_edge_length);
  std::vector<Eigen::RowVector3i> faces;
  faces.reserve(static_cast<size_t>(mesh.faces.rows()));
  // Depth first, the faces in order: a triangle's pieces are split before
  // the next triangle.
  std::vector<Eigen::RowVector3i> stack, pieces;
  for (Eigen::Index f = mesh.faces.rows() - 1; f >= 0; --f) {
    stack.push_back(mesh.faces.row(f));
  }
  while (!stack.empty()) {
    const Eigen::RowVector3i t = stack.back();
    stack.pop_back();
    bool split[3];
    int count = 0;
    for (int k = 0; k < 3; ++k) {
      split[k] = splitter.Longer(t[k], t[(k + 1) % 3]);
      count += split[k];
    }
    if (count == 0) {
      faces.push_back(t);
      continue;
    }
    // Rotated so that (a, b) is split and, with two, (c, a) too: the
    // pieces keep the triangle's orientation.
    int r = 0;
    while (!split[r] || (count == 2 && !split[(r + 2) % 3])) ++r;
    const int a = t[r], b = t[(r + 1) % 3], c = t[(r + 2) % 3];
    pieces.clear();
    if (count == 1) {
      const int ab = splitter.Middle(a, b);
      pieces.emplace_back(a, ab, c);
      pieces.emplace_back(ab, b, c);
    } else if (count == 2) {
      splitter.AppendStrip(a, b, c, &pieces);
    } else {
      const int ab = splitter.Middle(a, b), bc = splitter.Middle(b, c),
                ca = splitter.Middle(c, a);
      pieces.emplace_back(a, ab, ca);
      pieces.emplace_back(ab, b, bc);
      pieces.emplace_back(ca, bc, c);
      pieces.emplace_back(ab, bc, ca);
    }
    if (splitter.num_vertices() > max_vertices) return std::nullopt;
    // A strip's pieces across it can still be longer (a wide strip).
    stack.insert(stack.end(), pieces.rbegin(), pieces.rend());
  }
  return splitter.Result(faces);
}

double SplitEdgeLengthFor(double area, int64_t vertices) {
  return std::sqrt(3.0 * area / static_cast<double>(vertices));
}

}  // namespace sdcb
