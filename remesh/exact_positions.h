// Vertices by their exact position, for joining coincident ones (weld.h's first_at_same_position)
// and the corners of an STL file (stl_reader.h). Internal to remesh/.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace meshlift {

/// A hash table of the vertices of an xyz array by position, "the same" as weld.h defines it:
/// coordinates equal as numbers (-0 and +0 alike), a non-finite position the same as no other.
/// Open addressing, at most half full, grown as vertices are added: expected constant time per
/// vertex. A slot holds a vertex + 1 (0: empty) and 32 bits of its position's hash, so that a
/// probe reads another vertex's coordinates only when those bits match.
class ExactPositions {
 public:
  explicit ExactPositions(std::size_t expected_vertices);
  /// The first vertex added at vertex v's position in `positions` (the xyz array, which may have
  /// grown since the last call but holds the vertices added so far unchanged); if there is none,
  /// v itself, added (unless its position is not finite).
  std::uint32_t first_at(std::span<const double> positions, std::uint32_t v);

  /// Asks the cache for the slot where first_at(positions, v) starts probing: a table of millions
  /// of vertices is read at random, and called a few vertices ahead this hides the miss.
  void prefetch(std::span<const double> positions, std::uint32_t v) const;

 private:
  static std::uint64_t hash(const double* p);
  void insert(std::uint64_t h, std::uint32_t v);
  std::vector<std::uint64_t> slots_;
  std::size_t stored_ = 0;
};

}  // namespace meshlift
