#include "local_frames.h"

#include "large_array.h"

#include <algorithm>
#include <cmath>
#include <vector>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define MESHLIFT_FRAMES_AVX 1
#endif

namespace meshlift::frames {
namespace {

using Vec = Vec3;
Vec operator+(Vec a, Vec b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec operator-(Vec a, Vec b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec operator*(double s, Vec a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(Vec a, Vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec cross(Vec a, Vec b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

/// Edges whose frames are computed together: the frame of one edge is a chain of dependent
/// square roots and divisions (~80 cycles of latency); a block of independent edges, laid out
/// component by component, keeps the divider busy instead, four edges per instruction with AVX
/// (two with SSE2, which every x86-64 has).
constexpr std::uint32_t kBlock = FrameBlock::kCapacity;
constexpr std::uint32_t kLanes = 4;

/// A block's inputs besides n = N_a + N_b (in FrameBlock::nx..nz): the edge p_b - p_a; and the
/// lengths that decide the degenerate cases (|edge| as its square: see edge_along_normal).
struct Scratch {
  alignas(32) double ex[kBlock], ey[kBlock], ez[kBlock];
  alignas(32) double length[kBlock], t1_length[kBlock], edge_squared[kBlock];
};

// One block's frames of the regular case, component by component: n normalized, t1, t2, and the
// lengths. Every value is computed by the same IEEE operations, in the same order, as the scalar
// formulas of FORMAT.md §5: packed square roots and divisions round exactly as scalar ones (no
// FMA: each product is rounded before its sum), so the bits are those of an edge-by-edge loop.
// Entries [0, count) rounded up to a multiple of kLanes (the spare ones are not used).
#if defined(MESHLIFT_FRAMES_AVX)
#define MESHLIFT_FRAMES_BLOCK(W, Set, Load, Store, Add, Sub, Mul, Div, Sqrt)                                  \
  for (std::uint32_t i = 0; i < count; i += W) {                                                             \
    /* length = |n|; n = (1 / length) n */                                                                   \
    auto x = Load(b.nx + i), y = Load(b.ny + i), z = Load(b.nz + i);                                         \
    const auto l = Sqrt(Add(Add(Mul(x, x), Mul(y, y)), Mul(z, z)));                                         \
    const auto inverse = Div(Set(1.0), l);                                                                   \
    x = Mul(inverse, x), y = Mul(inverse, y), z = Mul(inverse, z);                                           \
    /* t1 = edge - (edge . n) n */                                                                           \
    const auto a = Load(s.ex + i), c = Load(s.ey + i), e = Load(s.ez + i);                                   \
    const auto along = Add(Add(Mul(a, x), Mul(c, y)), Mul(e, z));                                           \
    auto u = Sub(a, Mul(along, x)), v = Sub(c, Mul(along, y)), w = Sub(e, Mul(along, z));                    \
    const auto tl = Sqrt(Add(Add(Mul(u, u), Mul(v, v)), Mul(w, w)));                                        \
    const auto ee = Add(Add(Mul(a, a), Mul(c, c)), Mul(e, e));                                               \
    /* t1 = (1 / |t1|) t1; t2 = n x t1 */                                                                    \
    const auto inverse_t = Div(Set(1.0), tl);                                                                \
    u = Mul(inverse_t, u), v = Mul(inverse_t, v), w = Mul(inverse_t, w);                                     \
    Store(b.nx + i, x), Store(b.ny + i, y), Store(b.nz + i, z);                                              \
    Store(b.t1x + i, u), Store(b.t1y + i, v), Store(b.t1z + i, w);                                           \
    Store(b.t2x + i, Sub(Mul(y, w), Mul(z, v)));                                                             \
    Store(b.t2y + i, Sub(Mul(z, u), Mul(x, w)));                                                             \
    Store(b.t2z + i, Sub(Mul(x, v), Mul(y, u)));                                                             \
    Store(s.length + i, l), Store(s.t1_length + i, tl), Store(s.edge_squared + i, ee);                       \
  }

__attribute__((target("avx"))) void compute_avx(FrameBlock& b, Scratch& s, std::uint32_t count) {
  MESHLIFT_FRAMES_BLOCK(4, _mm256_set1_pd, _mm256_load_pd, _mm256_store_pd, _mm256_add_pd, _mm256_sub_pd, _mm256_mul_pd,
                        _mm256_div_pd, _mm256_sqrt_pd)
}
void compute_sse2(FrameBlock& b, Scratch& s, std::uint32_t count) {
  MESHLIFT_FRAMES_BLOCK(2, _mm_set1_pd, _mm_load_pd, _mm_store_pd, _mm_add_pd, _mm_sub_pd, _mm_mul_pd, _mm_div_pd,
                        _mm_sqrt_pd)
}
#undef MESHLIFT_FRAMES_BLOCK
#endif

void compute(FrameBlock& b, Scratch& s, std::uint32_t count) {
#if defined(MESHLIFT_FRAMES_AVX)
  static const bool avx = __builtin_cpu_supports("avx");
  if (avx) return compute_avx(b, s, count);
  return compute_sse2(b, s, count);
#else
  for (std::uint32_t i = 0; i < count; ++i) {
    const double l = std::sqrt(b.nx[i] * b.nx[i] + b.ny[i] * b.ny[i] + b.nz[i] * b.nz[i]);
    const Vec n = (1 / l) * Vec{b.nx[i], b.ny[i], b.nz[i]}, edge{s.ex[i], s.ey[i], s.ez[i]};
    Vec t1 = edge - dot(edge, n) * n;
    const double tl = std::sqrt(dot(t1, t1));
    s.edge_squared[i] = dot(edge, edge);
    t1 = (1 / tl) * t1;
    const Vec t2 = cross(n, t1);
    b.nx[i] = n.x, b.ny[i] = n.y, b.nz[i] = n.z;
    b.t1x[i] = t1.x, b.t1y[i] = t1.y, b.t1z[i] = t1.z;
    b.t2x[i] = t2.x, b.t2y[i] = t2.y, b.t2z[i] = t2.z;
    s.length[i] = l, s.t1_length[i] = tl;
  }
#endif
}

}  // namespace

namespace {

/// A level's faces and edges as stored in its topology.
struct StoredLevel {
  const TriangleTopology& t;
  std::uint32_t vertex_count() const { return t.vertex_count; }
  std::uint32_t edge_count() const { return static_cast<std::uint32_t>(t.edge_count()); }
  /// f(a, b, c) for every face, in face order.
  template <class F>
  void for_each_face(F&& f) const {
    for (std::size_t k = 0; k < t.face_count(); ++k) f(t.triangles[3 * k], t.triangles[3 * k + 1], t.triangles[3 * k + 2]);
  }
  void edge(std::uint32_t e, std::uint32_t& a, std::uint32_t& b) const {
    a = t.edge_vertices[2 * e];
    b = t.edge_vertices[2 * e + 1];
  }
};

/// The faces and edges of coarse.refined() (a level the hierarchy does not hold), read off the
/// coarse level by TriangleTopology::refined()'s rule, in the same order and orientation: face f
/// becomes corner faces (c_i, m_i, m_{i+2}) and the centre (m_0, m_1, m_2), m_i = V + e_i; edge
/// e = (a, b) becomes halves 2e = (a, m), 2e + 1 = (m, b); inner edge 2E + 3f + i runs m_{i+2} -> m_{i+1}.
struct RefinedLevel {
  const TriangleTopology& coarse;
  std::uint32_t vertex_count() const { return coarse.vertex_count + static_cast<std::uint32_t>(coarse.edge_count()); }
  std::uint32_t edge_count() const {
    return static_cast<std::uint32_t>(2 * coarse.edge_count() + 3 * coarse.face_count());
  }
  template <class F>
  void for_each_face(F&& f) const {
    const std::uint32_t V = coarse.vertex_count;
    for (std::size_t k = 0; k < coarse.face_count(); ++k) {
      const std::uint32_t* c = &coarse.triangles[3 * k];
      const std::uint32_t m[3] = {V + coarse.face_edges[3 * k], V + coarse.face_edges[3 * k + 1], V + coarse.face_edges[3 * k + 2]};
      f(c[0], m[0], m[2]);
      f(c[1], m[1], m[0]);
      f(c[2], m[2], m[1]);
      f(m[0], m[1], m[2]);
    }
  }
  void edge(std::uint32_t e, std::uint32_t& a, std::uint32_t& b) const { coarse.refined_edge(e, a, b); }
};

/// Area-weighted vertex normals of a level's mesh (the cross product's length is twice the face's
/// area, its direction the face normal), summed face by face in face order.
template <class Level>
void vertex_normals(const Level& level, std::span<const double> coarse, std::size_t s, std::vector<Vec>& normal) {
  auto position = [&](std::uint32_t v) { return Vec{coarse[s * v], coarse[s * v + 1], coarse[s * v + 2]}; };
  assign_large(normal, level.vertex_count(), Vec{0, 0, 0});
  level.for_each_face([&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const Vec p = position(a);
    const Vec n = cross(position(b) - p, position(c) - p);
    normal[a] = normal[a] + n;
    normal[b] = normal[b] + n;
    normal[c] = normal[c] + n;
  });
}

/// The frames of edges [begin, end) in blocks of up to kBlock from `begin`. An edge's frame
/// depends on its own inputs only (the lanes are independent), so any blocking gives its bits.
template <class Level, class Visit>
void frame_blocks(const Level& level, std::span<const double> coarse, std::size_t s, const std::vector<Vec>& normal,
                  std::uint32_t begin, std::uint32_t end, Visit&& visit) {
  auto position = [&](std::uint32_t v) { return Vec{coarse[s * v], coarse[s * v + 1], coarse[s * v + 2]}; };
  // Per edge: n = normalize(N_a + N_b), t1 = normalize(edge - (edge . n) n), t2 = n x t1
  // (local_frames.h), block by block.
  FrameBlock block;
  Scratch scratch;
  for (std::uint32_t first = begin; first < end; first += kBlock) {
    const std::uint32_t count = std::min(kBlock, end - first);
    block.first_edge = first;
    block.count = count;
    for (std::uint32_t i = 0; i < count; ++i) {
      std::uint32_t a, b;
      level.edge(first + i, a, b);
      const Vec n = normal[a] + normal[b], edge = position(b) - position(a);
      block.nx[i] = n.x, block.ny[i] = n.y, block.nz[i] = n.z;
      scratch.ex[i] = edge.x, scratch.ey[i] = edge.y, scratch.ez[i] = edge.z;
    }
    for (std::uint32_t i = count; i % kLanes != 0; ++i) {  // harmless spare entries for the last lanes
      block.nx[i] = block.ny[i] = block.nz[i] = 1;
      scratch.ex[i] = scratch.ey[i] = scratch.ez[i] = 0;
    }
    compute(block, scratch, count);
    for (std::uint32_t i = 0; i < count; ++i) {
      const double length = scratch.length[i];
      // Identity frame, (x, y, z) stay: a normal sum at rounding-noise level against the edge's
      // squared length (FORMAT.md §5: where the faces' normals cancel, as on a symmetric mesh
      // partly decoded, its direction would be set by the last bits of the positions).
      block.identity[i] = !(length > kNormalFloor * scratch.edge_squared[i]) || !std::isfinite(length);
      if (!block.identity[i] && edge_along_normal(scratch.t1_length[i], scratch.edge_squared[i])) [[unlikely]] {
        // The edge is (nearly) along the normal, or has no length: use the axis least aligned with n.
        const Vec n{block.nx[i], block.ny[i], block.nz[i]};
        const double ax = std::abs(n.x), ay = std::abs(n.y), az = std::abs(n.z);
        const Vec axis = ax <= ay && ax <= az ? Vec{1, 0, 0} : (ay <= az ? Vec{0, 1, 0} : Vec{0, 0, 1});
        Vec t1 = axis - dot(axis, n) * n;
        t1 = (1 / std::sqrt(dot(t1, t1))) * t1;
        const Vec t2 = cross(n, t1);
        block.t1x[i] = t1.x, block.t1y[i] = t1.y, block.t1z[i] = t1.z;
        block.t2x[i] = t2.x, block.t2y[i] = t2.y, block.t2z[i] = t2.z;
      }
    }
    visit(block);
  }
}

}  // namespace

LevelFrames::LevelFrames(const SemiRegularHierarchy& h, int level, std::span<const double> coarse, int stride,
                         std::vector<Vec3> storage)
    : hierarchy_(h), level_(level), coarse_(coarse), stride_(static_cast<std::size_t>(stride)), normal_(std::move(storage)) {
  if (h.has_topology(level))
    vertex_normals(StoredLevel{h.topology(level)}, coarse, stride_, normal_);
  else
    vertex_normals(RefinedLevel{h.topology(level - 1)}, coarse, stride_, normal_);
}

std::uint32_t LevelFrames::edge_count() const { return hierarchy_.vertex_count(level_ + 1) - hierarchy_.vertex_count(level_); }

void LevelFrames::for_each_block(std::uint32_t begin, std::uint32_t end, const std::function<void(const FrameBlock&)>& visit) const {
  if (hierarchy_.has_topology(level_))
    frame_blocks(StoredLevel{hierarchy_.topology(level_)}, coarse_, stride_, normal_, begin, end, visit);
  else
    frame_blocks(RefinedLevel{hierarchy_.topology(level_ - 1)}, coarse_, stride_, normal_, begin, end, visit);
}

namespace {

/// Rotates the details of the odd vertices of one block (FrameBlock::rotate, the direction known
/// at compile time): the decoder's inner loop.
template <Direction D>
void rotate_block(const FrameBlock& block, double* first, std::size_t stride) {
  for (std::uint32_t i = 0; i < block.count; ++i) block.rotate(i, first + stride * i, D);
}

}  // namespace

void LevelFrames::rotate(std::uint32_t begin, std::uint32_t end, std::span<double> details, Direction direction) const {
  if (begin >= end) return;
  double* first = details.data() + stride_ * (std::size_t{hierarchy_.vertex_count(level_)} + begin);
  auto visit = [&](const FrameBlock& block) {
    double* d = first + stride_ * (block.first_edge - begin);
    if (direction == Direction::to_global)
      rotate_block<Direction::to_global>(block, d, stride_);
    else
      rotate_block<Direction::to_local>(block, d, stride_);
  };
  if (hierarchy_.has_topology(level_))
    frame_blocks(StoredLevel{hierarchy_.topology(level_)}, coarse_, stride_, normal_, begin, end, visit);
  else
    frame_blocks(RefinedLevel{hierarchy_.topology(level_ - 1)}, coarse_, stride_, normal_, begin, end, visit);
}

void for_each_frame_block(const SemiRegularHierarchy& h, int level, std::span<const double> coarse, int stride,
                          const std::function<void(const FrameBlock&)>& visit) {
  const LevelFrames frames(h, level, coarse, stride);
  frames.for_each_block(0, frames.edge_count(), visit);
}

void rotate_details(const SemiRegularHierarchy& h, int level, std::span<const double> coarse, std::span<double> details,
                    int stride, Direction direction) {
  const LevelFrames frames(h, level, coarse, stride);
  frames.rotate(0, frames.edge_count(), details, direction);
}

}  // namespace meshlift::frames
