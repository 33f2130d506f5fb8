#include "world_registry.h"

#include <mutex>

namespace incise::capi {

namespace {

struct Slot {
  std::unique_ptr<WorldState> state;
  std::uint32_t generation = 1;  // 0 is never used: a zero-initialised id names nothing
};

std::mutex table_mutex;
std::vector<Slot> table;
std::vector<std::uint32_t> free_slots;

}  // namespace

incise_world_id addWorld(std::unique_ptr<WorldState> state) {
  std::lock_guard lock(table_mutex);
  if (free_slots.empty()) {
    table.emplace_back();
    free_slots.push_back(static_cast<std::uint32_t>(table.size() - 1));
  }
  const std::uint32_t index = free_slots.back();
  free_slots.pop_back();
  table[index].state = std::move(state);
  return {index, table[index].generation};
}

WorldState* findWorld(incise_world_id id) noexcept {
  std::lock_guard lock(table_mutex);
  if (id.index >= table.size() || table[id.index].generation != id.generation) return nullptr;
  return table[id.index].state.get();
}

bool removeWorld(incise_world_id id) noexcept {
  std::unique_ptr<WorldState> doomed;  // destroyed outside the lock
  {
    std::lock_guard lock(table_mutex);
    if (id.index >= table.size() || table[id.index].generation != id.generation || !table[id.index].state) return false;
    doomed = std::move(table[id.index].state);
    Slot& slot = table[id.index];
    slot.generation = slot.generation == UINT32_MAX ? 1 : slot.generation + 1;
    try {
      free_slots.push_back(id.index);
    } catch (...) {  // no room to reuse the slot: it stays empty, its generation moved on
    }
  }
  return true;
}

}  // namespace incise::capi
