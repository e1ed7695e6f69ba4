// Internal: a World's slots (particle systems, deformables, articulations) put back as a State
// holds them, without letting an id handed out since the save become valid again.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

namespace inertia::detail {

/// The generation of a restored slot. One live in the State takes its saved generation (the
/// ids of the save are valid again); a free one takes one above every id handed out for it
/// since the save (its generation now, or the next one while it is live).
inline std::uint32_t restoredGeneration(bool savedLive, std::uint32_t saved, std::uint32_t current,
                                        bool currentLive) {
  if (savedLive) return saved;
  return std::max(saved, currentLive ? current + 1 : current);
}

/// Makes room for the State's `count` slots. Slots made since the save (beyond `count`) are
/// kept, freed under their next generation, rather than dropped: a later slot there must not
/// hand out their ids again.
template <class Slot, class T>
void prepareRestoredSlots(std::vector<Slot>& slots, std::unique_ptr<T> Slot::*member,
                          std::size_t count) {
  for (std::size_t i = count; i < slots.size(); ++i) {
    if (!(slots[i].*member)) continue;
    const std::uint32_t generation = slots[i].generation + 1;
    slots[i] = Slot{};
    slots[i].generation = generation;
  }
  if (slots.size() < count) slots.resize(count);
}

}  // namespace inertia::detail
