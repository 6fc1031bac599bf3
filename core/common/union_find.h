// Disjoint sets over 0..n-1 (union-find with path halving), each set named
// by its smallest member: the mesh's components, fans and boundary loops.
#ifndef SDCB_CORE_COMMON_UNION_FIND_H_
#define SDCB_CORE_COMMON_UNION_FIND_H_

#include <algorithm>
#include <numeric>
#include <vector>

namespace sdcb {

class UnionFind {
 public:
  explicit UnionFind(int n) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  // The smallest member of x's set.
  int Find(int x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void Union(int a, int b) {
    a = Find(a);
    b = Find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<int> parent_;
};

}  // namespace sdcb

#endif  // SDCB_CORE_COMMON_UNION_FIND_H_
