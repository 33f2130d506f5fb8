// Private: lists of ints in one pool (node -> elements, base tet -> elements), each list with room to grow;
// a list that outgrows its room moves to the pool's end with twice the room (its old place is left unused).
// Order within a list is the order of add() (remove() keeps the others' order): deterministic.
// Cost: add O(list) when moving, else O(1); remove O(list). Allocation: none while the pool's reserve
// lasts; beyond it amortised growth, counted in overflows(). Threads: one owner.
#pragma once

#include <algorithm>
#include <cstddef>
#include <span>
#include <vector>

namespace incise::physics::detail {

class Buckets {
 public:
  // No lists; room reserved for `lists` lists and `entries` entries (with their slack).
  void reserve(std::size_t lists, std::size_t entries) {
    first_.reserve(lists), count_.reserve(lists), room_.reserve(lists), pool_.reserve(entries);
  }
  void clear() noexcept { first_.clear(), count_.clear(), room_.clear(), pool_.clear(); }
  // Appends an empty list with room for `room` entries; returns its index.
  int addList(int room) {
    grow(first_, 1), grow(count_, 1), grow(room_, 1), grow(pool_, static_cast<std::size_t>(room));
    first_.push_back(static_cast<int>(pool_.size()));
    count_.push_back(0);
    room_.push_back(room);
    pool_.resize(pool_.size() + static_cast<std::size_t>(room), -1);
    return static_cast<int>(first_.size()) - 1;
  }
  int lists() const noexcept { return static_cast<int>(first_.size()); }
  std::span<const int> operator[](int list) const noexcept {
    const auto l = static_cast<std::size_t>(list);
    return {pool_.data() + first_[l], static_cast<std::size_t>(count_[l])};
  }
  void add(int list, int value) {
    const auto l = static_cast<std::size_t>(list);
    if (count_[l] == room_[l]) move(l, std::max(4, 2 * room_[l]));
    pool_[static_cast<std::size_t>(first_[l] + count_[l]++)] = value;
  }
  // Removes the first `value` in the list (nothing if absent).
  void remove(int list, int value) noexcept {
    const auto l = static_cast<std::size_t>(list);
    int* begin = pool_.data() + first_[l];
    int* end = begin + count_[l];
    int* at = std::find(begin, end, value);
    if (at == end) return;
    std::copy(at + 1, end, at);
    --count_[l];
  }
  void clearList(int list) noexcept { count_[static_cast<std::size_t>(list)] = 0; }
  int overflows() const noexcept { return overflows_; }

 private:
  template <class V>
  void grow(V& v, std::size_t extra) {
    if (v.size() + extra > v.capacity()) ++overflows_;
  }
  void move(std::size_t l, int room) {
    grow(pool_, static_cast<std::size_t>(room));
    const int from = first_[l];
    first_[l] = static_cast<int>(pool_.size());
    pool_.resize(pool_.size() + static_cast<std::size_t>(room), -1);
    std::copy(pool_.begin() + from, pool_.begin() + from + count_[l], pool_.begin() + first_[l]);
    room_[l] = room;
  }

  std::vector<int> first_, count_, room_, pool_;
  int overflows_ = 0;
};

}  // namespace incise::physics::detail
