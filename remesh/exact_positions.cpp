// See exact_positions.h.
#include "exact_positions.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace meshlift {

ExactPositions::ExactPositions(std::size_t expected_vertices)
    : slots_(std::bit_ceil(std::max<std::size_t>(2 * expected_vertices, 16)), 0) {}

std::uint64_t ExactPositions::hash(const double* p) {
  auto bits = [](double x) { return std::bit_cast<std::uint64_t>(x + 0.0); };  // -0 + 0 = +0: alike
  // splitmix64's finalizer over the three coordinates' bits.
  std::uint64_t h = bits(p[0]);
  for (int k = 1; k < 3; ++k) {
    h ^= bits(p[k]) + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
    h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ULL;
    h = (h ^ (h >> 27)) * 0x94d049bb133111ebULL;
    h ^= h >> 31;
  }
  return h;
}

void ExactPositions::prefetch(std::span<const double> positions, std::uint32_t v) const {
  __builtin_prefetch(&slots_[hash(&positions[3 * std::size_t{v}]) & (slots_.size() - 1)]);
}

void ExactPositions::insert(std::uint64_t h, std::uint32_t v) {
  const std::size_t mask = slots_.size() - 1;
  std::size_t i = h & mask;
  while (slots_[i] != 0) i = (i + 1) & mask;
  slots_[i] = (h >> 32) << 32 | (std::uint64_t{v} + 1);
}

std::uint32_t ExactPositions::first_at(std::span<const double> positions, std::uint32_t v) {
  const double* q = &positions[3 * std::size_t{v}];
  if (!(std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2]))) return v;
  const std::uint64_t h = hash(q), tag = h >> 32;
  const std::size_t mask = slots_.size() - 1;
  for (std::size_t i = h & mask; slots_[i] != 0; i = (i + 1) & mask) {
    const std::uint64_t entry = slots_[i];
    const std::size_t u = (entry & 0xffffffffu) - 1;
    if ((entry >> 32) == tag && positions[3 * u] == q[0] && positions[3 * u + 1] == q[1] && positions[3 * u + 2] == q[2])
      return static_cast<std::uint32_t>(u);
  }
  if (2 * (stored_ + 1) > slots_.size()) {
    // Twice the slots, every stored vertex placed again by its position's hash.
    std::vector<std::uint64_t> old(2 * slots_.size(), 0);
    old.swap(slots_);
    for (const std::uint64_t entry : old)
      if (entry != 0) {
        const std::uint32_t u = static_cast<std::uint32_t>((entry & 0xffffffffu) - 1);
        insert(hash(&positions[3 * std::size_t{u}]), u);
      }
  }
  insert(h, v);
  ++stored_;
  return v;
}

}  // namespace meshlift
