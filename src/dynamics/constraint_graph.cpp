#include "constraint_graph.h"

#include <array>

namespace inertia::detail {

namespace {

// Per colour, then per kind (joints 0, contacts 1): how many constraints.
using Counts = std::array<std::array<std::uint32_t, 2>, kMaxColors + 1>;

// Groups: the colours in use, in order, then the overflow; per kind the offsets of each group
// and, for the stable placement below, where each colour's next constraint goes.
void groupOffsets(const Counts& counts, std::vector<std::uint32_t>& offsets,
                  std::array<std::uint32_t, kMaxColors + 1>& next, int kind) {
  offsets.assign(1, 0);
  for (int c = 0; c <= kMaxColors; ++c) {
    const auto& n = counts[std::size_t(c)];
    if (n[0] + n[1] == 0) continue;
    next[std::size_t(c)] = offsets.back();
    offsets.push_back(offsets.back() + n[std::size_t(kind)]);
  }
}

}  // namespace

void colorGraph(std::span<const GraphEdge> joints, std::span<const GraphEdge> contacts,
                const std::vector<SolverBody>& bodies, ConstraintColoring& out) {
  const std::size_t words = (bodies.size() + 63) / 64;
  const std::size_t total = joints.size() + contacts.size();
  std::vector<std::uint64_t>& used = out.used;
  std::vector<std::uint8_t>& color = out.color;
  used.assign(kMaxColors * words, 0);
  color.assign(total, kMaxColors);
  static_assert(kMaxColors < 256);
  Counts counts{};
  auto moving = [&](int i) { return i >= 0 && bodies[static_cast<std::size_t>(i)].invMass > 0; };
  for (std::size_t k = 0; k < total; ++k) {
    const bool joint = k < joints.size();
    const GraphEdge& e = joint ? joints[k] : contacts[k - joints.size()];
    const int a = e.bodyA, b = e.bodyB;
    for (int c = 0; c < kMaxColors; ++c) {
      std::uint64_t* set = used.data() + std::size_t(c) * words;
      auto taken = [&](int i) { return moving(i) && (set[std::size_t(i) / 64] >> (i % 64)) & 1u; };
      if (taken(a) || taken(b)) continue;
      if (moving(a)) set[std::size_t(a) / 64] |= std::uint64_t(1) << (a % 64);
      if (moving(b)) set[std::size_t(b) / 64] |= std::uint64_t(1) << (b % 64);
      color[k] = std::uint8_t(c);
      break;
    }
    ++counts[std::size_t(color[k])][joint ? 0 : 1];
  }
  out.overflow = counts[kMaxColors][0] + counts[kMaxColors][1] > 0;
  // Stable: within a group, the constraints of a kind keep their order.
  std::array<std::uint32_t, kMaxColors + 1> nextJoint{}, nextContact{};
  groupOffsets(counts, out.jointOffsets, nextJoint, 0);
  groupOffsets(counts, out.offsets, nextContact, 1);
  out.jointOrder.resize(joints.size());
  out.order.resize(contacts.size());
  for (std::size_t k = 0; k < total; ++k) {
    if (k < joints.size())
      out.jointOrder[nextJoint[color[k]]++] = static_cast<std::uint32_t>(k);
    else
      out.order[nextContact[color[k]]++] = static_cast<std::uint32_t>(k - joints.size());
  }
}

}  // namespace inertia::detail
