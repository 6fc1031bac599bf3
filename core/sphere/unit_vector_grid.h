// A grid of unit vectors that a file can name with two integers: the
// octahedral map (the unit sphere projected onto the octahedron
// |x| + |y| + |z| = 1, its lower half folded out over the square
// [-1, 1]^2), sampled at (2^bits)^2 points. Used to store knots in a few
// bytes each (the `.sdcb` QKNT chunk, docs/FORMAT.md): a fit that snaps its
// knots to the grid (FitOptions::knot_grid_bits) stores them exactly.
//
// Codes on the folded square's edges that name the same point decode to the
// same bits (zeros are +0), so the grid's vectors are a fixed set.
// Decoding is exact and reproducible: u = (2 a - top) / top with top =
// 2^bits - 1 (integers exact in a double, one correctly rounded division),
// z = 1 - |u| - |v| (and the fold for z < 0), then the vector divided by
// its norm, computed with std::fma and std::sqrt (both correctly rounded in
// IEEE-754): the same bits on every conforming platform, whatever the
// compiler contracts elsewhere.
#ifndef SDCB_CORE_SPHERE_UNIT_VECTOR_GRID_H_
#define SDCB_CORE_SPHERE_UNIT_VECTOR_GRID_H_

#include <Eigen/Core>
#include <cstdint>

namespace sdcb {

// Bits per grid coordinate the functions below accept.
constexpr int kMinUnitVectorGridBits = 2;
constexpr int kMaxUnitVectorGridBits = 26;

struct UnitVectorCode {
  uint32_t a = 0, b = 0;  // each in [0, 2^bits - 1]
};

// The unit vector of grid point (a, b). `bits` in kMinUnitVectorGridBits..
// kMaxUnitVectorGridBits, a and b below 2^bits (not checked).
Eigen::Vector3d DecodeUnitVector(const UnitVectorCode& code, int bits);

// The grid point whose cell holds the octahedral image of `direction` (any
// finite nonzero vector; the nearest grid coordinates, so the decoded vector
// is within 2.5 * 2^(1 - bits) radians: 7.6e-5 for 16 bits).
UnitVectorCode EncodeUnitVector(const Eigen::Vector3d& direction, int bits);

// True, with its code, if `v` is exactly (bit for bit) a decoded grid
// vector.
bool IsOnUnitVectorGrid(const Eigen::Vector3d& v, int bits,
                        UnitVectorCode* code);

}  // namespace sdcb

#endif  // SDCB_CORE_SPHERE_UNIT_VECTOR_GRID_H_
