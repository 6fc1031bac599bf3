// PiecewiseSurface's cells and buffers, shared by its source files
// (piecewise_surface.cpp: the cells and their regions;
// piecewise_surface_eval.cpp: evaluation). Not part of the API.
#ifndef SDCB_CORE_SPLINE_PIECEWISE_SURFACE_CELLS_H_
#define SDCB_CORE_SPLINE_PIECEWISE_SURFACE_CELLS_H_

#include <Eigen/Core>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "sdcb/core/spline/block_arena.h"
#include "sdcb/core/spline/piecewise_region_builder.h"
#include "sdcb/core/spline/piecewise_surface.h"

namespace sdcb {

// Quadtree node in (u, v) of a cube face: centre (uc, vc), half side h. An
// inner node's children are child .. child + 3, quadrant (u >= uc) + 2 (v
// >= vc); a leaf has child = -1 and its index in leaves_.
struct PiecewiseSurface::Node {
  double uc = 0.0, vc = 0.0, h = 1.0;
  int child = -1;
  int leaf = -1;
};

// Open-addressing map from region key to coefficients, in the arena.
// Written only under the leaf's mutex; read without it: a slot's value is
// stored (release) after its key, so a reader that sees the value sees the
// key. A full table is replaced by a larger copy (the old one stays in the
// arena, for readers still probing it).
struct PiecewiseSurface::Table {
  struct Slot {
    std::atomic<uint64_t> key{0};
    std::atomic<const double*> value{nullptr};
  };
  static uint64_t Hash(uint64_t key) { return key * 0x9E3779B97F4A7C15ULL; }
  static Table* Make(int log2, BlockArena* arena) {
    Table* table = arena->New<Table>();
    table->shift = 64 - log2;
    table->mask = (uint64_t{1} << log2) - 1;
    table->slots = arena->New<Slot>(uint64_t{1} << log2);
    return table;
  }
  const double* Find(uint64_t key) const {
    for (uint64_t i = Hash(key) >> shift;; i = (i + 1) & mask) {
      const double* v = slots[i].value.load(std::memory_order_acquire);
      if (v == nullptr) return nullptr;
      if (slots[i].key.load(std::memory_order_relaxed) == key) return v;
    }
  }
  void Insert(uint64_t key, const double* value) {
    uint64_t i = Hash(key) >> shift;
    while (slots[i].value.load(std::memory_order_relaxed) != nullptr) {
      i = (i + 1) & mask;
    }
    slots[i].key.store(key, std::memory_order_relaxed);
    slots[i].value.store(value, std::memory_order_release);
    ++count;
  }
  int shift = 64;
  uint64_t mask = 0;
  Slot* slots = nullptr;
  int64_t count = 0;
};

// The batch evaluations' buffers.
struct PiecewiseSurface::Scratch {
  std::vector<uint32_t> leaf_of;        // per row
  std::vector<uint32_t> start;          // counting sort by leaf
  std::vector<uint32_t> order;          // rows by leaf (stable)
  std::vector<double> sorted, results;  // a chunk's directions and results
};

struct PiecewiseSurface::Leaf {
  Eigen::Vector3d origin, e1, e2;  // local chart o + s e1 + t e2
  Eigen::Vector3d axis;            // the cube face's: origin . axis = 1
  std::vector<int> lines;          // indices into segments_, ascending
  // Per line: t_a x t_b, then twice PerturbedDetSign's filter (beyond it the
  // float sign is the exact one; within it PerturbedDetSign decides).
  std::vector<double> planes;
  std::vector<int> sets;  // basis functions meeting the cell
  bool slow = false;      // too many lines: use the spline
  // Its sums are ill-conditioned (PiecewiseRegionBuilder::Build): use the
  // spline. Found when the first region is built.
  mutable std::atomic<bool> ill_conditioned{false};
  // The regions built so far (readers load it without the mutex) and what
  // builds more (made on the first region, under the mutex).
  mutable std::atomic<Table*> table{nullptr};
  mutable std::mutex mutex;
  mutable std::unique_ptr<PiecewiseRegionBuilder> builder;
};

}  // namespace sdcb

#endif  // SDCB_CORE_SPLINE_PIECEWISE_SURFACE_CELLS_H_
