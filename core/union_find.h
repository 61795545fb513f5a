// Disjoint sets with path halving and union by size: near-constant time per
// operation, which keeps weld merging and cycle detection linear.
#pragma once
#include <cstddef>
#include <numeric>
#include <vector>

namespace mbx {
using std::size_t;

class UnionFind {
public:
    explicit UnionFind(size_t n = 0) { reset(n); }
    void reset(size_t n) {
        parent_.resize(n);
        size_.assign(n, 1);
        std::iota(parent_.begin(), parent_.end(), 0);
    }
    size_t add() {
        parent_.push_back(parent_.size());
        size_.push_back(1);
        return parent_.size() - 1;
    }
    size_t find(size_t x) {
        while (parent_[x] != x) {
            parent_[x] = parent_[parent_[x]];
            x = parent_[x];
        }
        return x;
    }
    // Returns false when a and b were already joined (the edge closes a cycle).
    bool unite(size_t a, size_t b) {
        a = find(a);
        b = find(b);
        if (a == b) return false;
        if (size_[a] < size_[b]) std::swap(a, b);
        parent_[b] = a;
        size_[a] += size_[b];
        return true;
    }

private:
    std::vector<size_t> parent_;
    std::vector<size_t> size_;
};

}  // namespace mbx
