// Private: disjoint sets over the elements 0 .. n-1 (union-find), for grouping connected pieces: the
// components of a surface mesh (surface_mesh_check.cpp) and the groups of child tets around a cut node
// that stay joined through uncut faces (tet_cutter.cpp).
//
// One int per element, in a caller-owned std::vector (so a hot loop can reuse a reserved buffer and not
// allocate): a root holds minus the size of its set, any other element its parent. Union by size and path
// halving (a form of path compression) keep every tree shallow.
// Which element of a set is its root depends on the order of the unions; the sets do not.
// Cost: reset O(n) (no allocation within the buffer's capacity); find and unite amortised O(alpha(n)),
// effectively O(1). Threads: one UnionFind per thread. Failure: none checked; elements must lie in 0..n-1.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

namespace incise::core::detail {

class UnionFind {
 public:
  // n singletons in `storage` (resized to n; its capacity is kept). The UnionFind must not outlive it.
  UnionFind(std::vector<int>& storage, std::size_t n) : parent_(storage) { parent_.assign(n, -1); }

  // The root of x's set (the same for every element of the set until the next unite()).
  int find(int x) {
    while (parent_[at(x)] >= 0) {
      const int up = parent_[at(x)];
      if (parent_[at(up)] < 0) return up;
      x = parent_[at(x)] = parent_[at(up)];  // halving: x now points to its grandparent, and moves there
    }
    return x;
  }

  // Joins the sets of a and b (nothing if they are already one); the larger set's root stays the root.
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (parent_[at(a)] > parent_[at(b)]) std::swap(a, b);  // sizes are negative: a is the larger set
    parent_[at(a)] += parent_[at(b)];
    parent_[at(b)] = a;
  }

  bool isRoot(int x) const { return parent_[at(x)] < 0; }

 private:
  static std::size_t at(int x) { return static_cast<std::size_t>(x); }
  std::vector<int>& parent_;
};

}  // namespace incise::core::detail
