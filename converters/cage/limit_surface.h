// The limit surface of a subdivision cage (Catmull-Clark or Loop), through
// OpenSubdiv's Bfr: per face, the limit stencils (weights of cage vertices)
// of the position and its first derivatives at a parameter (u, v), and
// evaluation for given cage positions. The stencils are the rows of the
// cage's least-squares fit (converters/cage/subdivision_cage.h).
//
// Faces at extraordinary vertices are not polynomial; Bfr represents them by
// patches refined `approximation_level` times around the extraordinary
// vertex (OpenSubdiv's default is 2; the Gregory patches at that level differ
// from the exact limit by far less than a cage's fit error, see
// docs/CAGE.md).
#ifndef SDCB_CONVERTERS_CAGE_LIMIT_SURFACE_H_
#define SDCB_CONVERTERS_CAGE_LIMIT_SURFACE_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "sdcb/core/common/status.h"

namespace sdcb {

enum class SubdivisionScheme { kCatmullClark, kLoop };

// The weights of the cage vertices `indices` (distinct) in the limit
// position and its parameter derivatives at one (face, u, v).
struct LimitStencil {
  std::vector<int> indices;
  std::vector<double> position, du, dv;
};

class LimitSurface {
 public:
  // `faces`: corner indices counter-clockwise seen from outside, quads
  // (Catmull-Clark) or triangles (Loop: the fourth entry is ignored) of a
  // closed manifold cage with `num_vertices` vertices. kInvalidArgument if
  // OpenSubdiv rejects the topology or a face has no limit surface.
  // `creases`: edges (vertex pairs, each an edge of the faces) that are
  // infinitely sharp (OpenSubdiv's Sdc::Crease::SHARPNESS_INFINITE).
  static StatusOr<LimitSurface> Create(
      SubdivisionScheme scheme, int num_vertices,
      const std::vector<std::array<int, 4>>& faces, int approximation_level = 4,
      const std::vector<std::array<int, 2>>& creases = {});

  LimitSurface(LimitSurface&&) noexcept;
  LimitSurface& operator=(LimitSurface&&) noexcept;
  ~LimitSurface();

  SubdivisionScheme scheme() const { return scheme_; }
  int num_faces() const;
  int num_vertices() const { return num_vertices_; }
  // Whether face `f` is one regular polynomial patch.
  bool IsRegular(int f) const;

  // The stencil at (u, v) of face `f` (quads: [0, 1]^2; triangles: u, v >= 0,
  // u + v <= 1). Safe to call from many threads at once.
  void Stencil(int f, double u, double v, LimitStencil* out) const;
  // The limit point at (u, v) of face `f` for cage positions `cage` (#V by
  // 3), with its derivatives when `du`, `dv` are not null (through the
  // stencil; PreparedLimit evaluates many points of one cage faster).
  Eigen::Vector3d Evaluate(int f, double u, double v,
                           const Eigen::MatrixX3d& cage,
                           Eigen::Vector3d* du = nullptr,
                           Eigen::Vector3d* dv = nullptr) const;

 private:
  friend class PreparedLimit;
  struct Impl;
  explicit LimitSurface(std::unique_ptr<Impl> impl, SubdivisionScheme scheme,
                        int num_vertices);
  std::unique_ptr<Impl> impl_;
  SubdivisionScheme scheme_ = SubdivisionScheme::kCatmullClark;
  int num_vertices_ = 0;
};

// The limit surface of one set of cage positions, prepared for many
// evaluations: OpenSubdiv Bfr's patch points of every face, computed once,
// so that an evaluation is one patch evaluation (no stencil over the cage).
// Equal to LimitSurface::Evaluate to rounding. `limit` must outlive it.
class PreparedLimit {
 public:
  // `cage`: #V by 3 positions of `limit`'s vertices.
  PreparedLimit(const LimitSurface& limit, const Eigen::MatrixX3d& cage);

  const LimitSurface& limit() const { return limit_; }
  // As LimitSurface::Evaluate. Safe to call from many threads at once.
  Eigen::Vector3d Evaluate(int f, double u, double v,
                           Eigen::Vector3d* du = nullptr,
                           Eigen::Vector3d* dv = nullptr) const;

 private:
  const LimitSurface& limit_;
  std::vector<double> points_;  // x, y, z of every face's patch points
  std::vector<int64_t> first_;  // per face, its first point's offset
};

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_CAGE_LIMIT_SURFACE_H_
