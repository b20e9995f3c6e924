// Local frames for the geometry details (issue 3; PGC, Khodakovsky, Schroeder, Sweldens 2000 §4;
// normal meshes, Guskov et al. 2000; V-DMC codes normal-only displacements by default,
// CODEC-NOTES §8). A detail of a remeshed surface points mostly along the surface normal: in
// x, y, z all three components carry it, in a (normal, tangent, tangent) frame one does, and the
// two tangential ones may be quantized more coarsely (FORMAT.md §3, tangent_shift; the frames: §5).
//
// The frame of the odd vertex on edge e = (a, b) of level j is computed from the mesh of level
// j alone, which both sides hold before level j + 1 is synthesized (the decoder exactly so at
// full rate, since the encoder quantizes in closed loop, encoder.cpp):
//   n  = normalize(N_a + N_b), N_v = sum over the faces around v of (p1 - p0) x (p2 - p0)
//        (area-weighted vertex normals of level j);
//   t1 = normalize((p_b - p_a) - n ((p_b - p_a) . n)): the edge direction in the tangent plane;
//   t2 = n x t1.
// Degenerate cases fall back deterministically: n = 0 -> the identity frame (x, y, z); an edge
// along n -> t1 from the coordinate axis least aligned with n.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "meshlift/semi_regular.h"

namespace meshlift::frames {

enum class Direction {
  to_local,   ///< (x, y, z) -> (n, t1, t2): d_local = R^T d, R = [n t1 t2]
  to_global,  ///< (n, t1, t2) -> (x, y, z): d = R d_local
};

/// FORMAT.md §5: a frame is the identity unless |N_a + N_b| > kNormalFloor · (edge · edge).
inline constexpr double kNormalFloor = 1e-12;

/// FORMAT.md §5's test for an edge (nearly) along the normal, !(|t1| > 1e-12 |edge|), given |t1|
/// and edge . edge, with |edge| = sqrt(edge . edge) computed only where the answer is in doubt.
/// When |t1|^2 > 4e-24 |edge|^2 (both sides rounded, |edge|^2 a normal double), |t1| > 2e-12
/// |edge| (1 - 2^-52), which the spec's 1e-12 * sqrt(edge . edge), rounded up twice at most,
/// cannot reach: the answer is "no" without the square root (one fewer per edge in the packed
/// loop). Infinities and NaNs fail that test and take the spec's path.
inline bool edge_along_normal(double t1_length, double edge_squared) {
  if (t1_length * t1_length > 4e-24 * edge_squared && edge_squared > 1e-200) [[likely]] return false;
  return !(t1_length > 1e-12 * std::sqrt(edge_squared));
}

/// The frames of up to kCapacity consecutive edges of one level, component by component: entry
/// i is edge first_edge + i, whose odd vertex is vertex_count(level) + first_edge + i.
struct FrameBlock {
  static constexpr std::uint32_t kCapacity = 64;
  std::uint32_t first_edge = 0, count = 0;
  alignas(32) double nx[kCapacity], ny[kCapacity], nz[kCapacity];
  alignas(32) double t1x[kCapacity], t1y[kCapacity], t1z[kCapacity];
  alignas(32) double t2x[kCapacity], t2y[kCapacity], t2z[kCapacity];
  bool identity[kCapacity];  ///< |N_a + N_b| <= kNormalFloor |edge|^2 or not finite: the detail stays (x, y, z)

  /// Rotates the three values at d by frame i, with the operations of FORMAT.md §5 in their order.
  void rotate(std::uint32_t i, double* d, Direction direction) const {
    if (identity[i]) return;
    const double x = d[0], y = d[1], z = d[2];
    if (direction == Direction::to_local) {  // (n . d, t1 . d, t2 . d)
      d[0] = nx[i] * x + ny[i] * y + nz[i] * z;
      d[1] = t1x[i] * x + t1y[i] * y + t1z[i] * z;
      d[2] = t2x[i] * x + t2y[i] * y + t2z[i] * z;
    } else {  // x n + y t1 + z t2, d holding (n, t1, t2) components
      d[0] = x * nx[i] + y * t1x[i] + z * t2x[i];
      d[1] = x * ny[i] + y * t1y[i] + z * t2y[i];
      d[2] = x * nz[i] + y * t1z[i] + z * t2z[i];
    }
  }
};

/// The frames of the edges of level `level` (of the odd vertices of level `level` + 1) from the
/// level-`level` mesh whose positions are the first vertex_count(level) vertices of `coarse`
/// (`stride` values per vertex, geometry first), range by range: the vertex normals are computed
/// once, at construction, and each range's frames when asked for. For a caller that rotates each
/// block of details just before its synthesis reads them (the decoder), while `coarse` still holds
/// the level-`level` mesh. Any ranges give the same frames (each edge's depends on its own inputs).
/// A 3-vector of the frames' arithmetic (local_frames.cpp).
struct Vec3 {
  double x, y, z;
};

class LevelFrames {
 public:
  /// `storage` (optional): an array whose capacity the vertex normals reuse, so that a caller
  /// running level after level (the decoder) faults in the normals' pages once, not per level.
  LevelFrames(const SemiRegularHierarchy& hierarchy, int level, std::span<const double> coarse, int stride,
              std::vector<Vec3> storage = {});
  /// The normals' storage, capacity kept, for the next level's LevelFrames.
  std::vector<Vec3> release_storage() && { return std::move(normal_); }
  std::uint32_t edge_count() const;
  /// The frames of edges [begin, end), a block of up to FrameBlock::kCapacity at a time from `begin`.
  void for_each_block(std::uint32_t begin, std::uint32_t end, const std::function<void(const FrameBlock&)>& visit) const;
  /// Rotates the details of the odd vertices of edges [begin, end) (`stride` values per vertex
  /// in `details`, which may be `coarse`: the ranges read and written are disjoint).
  void rotate(std::uint32_t begin, std::uint32_t end, std::span<double> details, Direction direction) const;

 private:
  const SemiRegularHierarchy& hierarchy_;
  int level_;
  std::span<const double> coarse_;
  std::size_t stride_;
  std::vector<Vec3> normal_;
};

/// Computes the frames of the odd vertices of level `level` + 1 from the level-`level` mesh whose
/// positions are the first vertex_count(level) vertices of `coarse` (`stride` values per vertex,
/// geometry first), and hands them to `visit` a block at a time, in edge order: for a caller that
/// rotates more than one array by the same frames (the encoder's closed loop) or does more per
/// vertex than rotate it.
void for_each_frame_block(const SemiRegularHierarchy& hierarchy, int level, std::span<const double> coarse, int stride,
                          const std::function<void(const FrameBlock&)>& visit);

/// Rotates the details of the odd vertices of level `level` + 1 (vertices vertex_count(level) ..
/// vertex_count(level + 1) - 1 of `details`) by the frames of the level-`level` mesh whose
/// positions are the first vertex_count(level) vertices of `coarse`. Both arrays hold `stride`
/// values per vertex, geometry first; only the three geometry values of the odd vertices change.
/// `coarse` and `details` may be the same array (the ranges read and written are disjoint).
void rotate_details(const SemiRegularHierarchy& hierarchy, int level, std::span<const double> coarse,
                    std::span<double> details, int stride, Direction direction);

}  // namespace meshlift::frames
