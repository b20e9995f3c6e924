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

struct Vec {
  double x, y, z;
};
Vec operator+(Vec a, Vec b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec operator-(Vec a, Vec b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec operator*(double s, Vec a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(Vec a, Vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec cross(Vec a, Vec b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

/// Edges whose frames are computed together: the frame of one edge is a chain of dependent
/// square roots and divisions (~80 cycles of latency); a block of independent edges, laid out
/// component by component, keeps the divider busy instead, four edges per instruction with AVX
/// (two with SSE2, which every x86-64 has).
constexpr std::uint32_t kBlock = 64;
constexpr std::uint32_t kLanes = 4;

/// One block's frames, component by component. Inputs: n = N_a + N_b, the edge p_b - p_a.
/// Outputs: the normalized n, t1 and t2 of the regular case, and the lengths that decide whether
/// an edge takes it (see frame_of). Every value is computed by the same IEEE operations, in the
/// same order, as the scalar formulas of local_frames.h (FORMAT.md §3): packed square roots and
/// divisions round exactly as scalar ones, so the bits are those of an edge-by-edge loop.
struct Block {
  alignas(32) double nx[kBlock], ny[kBlock], nz[kBlock];
  alignas(32) double ex[kBlock], ey[kBlock], ez[kBlock];
  alignas(32) double t1x[kBlock], t1y[kBlock], t1z[kBlock];
  alignas(32) double t2x[kBlock], t2y[kBlock], t2z[kBlock];
  alignas(32) double length[kBlock], t1_length[kBlock], edge_length[kBlock];

  /// Frames of entries [0, count); count is rounded up to a multiple of kLanes (the spare
  /// entries hold whatever the arrays hold: their results are not used).
  void compute(std::uint32_t count) {
#if defined(MESHLIFT_FRAMES_AVX)
    static const bool avx = __builtin_cpu_supports("avx");
    if (avx) return compute_avx(count);
    return compute_sse2(count);
#else
    for (std::uint32_t i = 0; i < count; ++i) {
      const double l = std::sqrt(nx[i] * nx[i] + ny[i] * ny[i] + nz[i] * nz[i]);
      const Vec n = (1 / l) * Vec{nx[i], ny[i], nz[i]}, edge{ex[i], ey[i], ez[i]};
      Vec t1 = edge - dot(edge, n) * n;
      const double tl = std::sqrt(dot(t1, t1));
      edge_length[i] = 1e-12 * std::sqrt(dot(edge, edge));
      t1 = (1 / tl) * t1;
      const Vec t2 = cross(n, t1);
      nx[i] = n.x, ny[i] = n.y, nz[i] = n.z;
      t1x[i] = t1.x, t1y[i] = t1.y, t1z[i] = t1.z;
      t2x[i] = t2.x, t2y[i] = t2.y, t2z[i] = t2.z;
      length[i] = l, t1_length[i] = tl;
    }
#endif
  }

#if defined(MESHLIFT_FRAMES_AVX)
// The same steps for both widths: Set, Load, ... name the intrinsics of one width. (No FMA: each
// product is rounded before its sum, as in the scalar formulas.)
#define MESHLIFT_FRAMES_BLOCK(W, Set, Load, Store, Add, Sub, Mul, Div, Sqrt)                                  \
  for (std::uint32_t i = 0; i < count; i += W) {                                                             \
    /* length = |n|; n = (1 / length) n */                                                                   \
    auto x = Load(nx + i), y = Load(ny + i), z = Load(nz + i);                                               \
    const auto l = Sqrt(Add(Add(Mul(x, x), Mul(y, y)), Mul(z, z)));                                         \
    const auto inverse = Div(Set(1.0), l);                                                                   \
    x = Mul(inverse, x), y = Mul(inverse, y), z = Mul(inverse, z);                                           \
    /* t1 = edge - (edge . n) n */                                                                           \
    const auto a = Load(ex + i), b = Load(ey + i), c = Load(ez + i);                                         \
    const auto along = Add(Add(Mul(a, x), Mul(b, y)), Mul(c, z));                                            \
    auto u = Sub(a, Mul(along, x)), v = Sub(b, Mul(along, y)), w = Sub(c, Mul(along, z));                    \
    const auto tl = Sqrt(Add(Add(Mul(u, u), Mul(v, v)), Mul(w, w)));                                        \
    const auto el = Sqrt(Add(Add(Mul(a, a), Mul(b, b)), Mul(c, c)));                                        \
    /* t1 = (1 / |t1|) t1; t2 = n x t1 */                                                                    \
    const auto inverse_t = Div(Set(1.0), tl);                                                                \
    u = Mul(inverse_t, u), v = Mul(inverse_t, v), w = Mul(inverse_t, w);                                     \
    Store(nx + i, x), Store(ny + i, y), Store(nz + i, z);                                                    \
    Store(t1x + i, u), Store(t1y + i, v), Store(t1z + i, w);                                                 \
    Store(t2x + i, Sub(Mul(y, w), Mul(z, v)));                                                               \
    Store(t2y + i, Sub(Mul(z, u), Mul(x, w)));                                                               \
    Store(t2z + i, Sub(Mul(x, v), Mul(y, u)));                                                               \
    Store(length + i, l), Store(t1_length + i, tl), Store(edge_length + i, Mul(Set(1e-12), el));             \
  }

  __attribute__((target("avx"))) void compute_avx(std::uint32_t count) {
    MESHLIFT_FRAMES_BLOCK(4, _mm256_set1_pd, _mm256_load_pd, _mm256_store_pd, _mm256_add_pd, _mm256_sub_pd,
                          _mm256_mul_pd, _mm256_div_pd, _mm256_sqrt_pd)
  }
  void compute_sse2(std::uint32_t count) {
    MESHLIFT_FRAMES_BLOCK(2, _mm_set1_pd, _mm_load_pd, _mm_store_pd, _mm_add_pd, _mm_sub_pd, _mm_mul_pd, _mm_div_pd,
                          _mm_sqrt_pd)
  }
#undef MESHLIFT_FRAMES_BLOCK
#endif
};

}  // namespace

void rotate_details(const SemiRegularHierarchy& h, int level, std::span<const double> coarse, std::span<double> details,
                    int stride, Direction direction) {
  const TriangleTopology& t = h.topology(level);
  const std::size_t s = static_cast<std::size_t>(stride);
  auto position = [&](std::uint32_t v) { return Vec{coarse[s * v], coarse[s * v + 1], coarse[s * v + 2]}; };

  // Area-weighted vertex normals of the level-j mesh (the cross product's length is twice the
  // face's area, its direction the face normal).
  std::vector<Vec> normal;
  assign_large(normal, t.vertex_count, Vec{0, 0, 0});
  for (std::size_t f = 0; f < t.face_count(); ++f) {
    const std::uint32_t a = t.triangles[3 * f], b = t.triangles[3 * f + 1], c = t.triangles[3 * f + 2];
    const Vec p = position(a);
    const Vec n = cross(position(b) - p, position(c) - p);
    normal[a] = normal[a] + n;
    normal[b] = normal[b] + n;
    normal[c] = normal[c] + n;
  }

  // Per edge: n = normalize(N_a + N_b), t1 = normalize(edge - (edge . n) n), t2 = n x t1
  // (local_frames.h), block by block (Block).
  const auto E = static_cast<std::uint32_t>(t.edge_count());
  Block block;
  for (std::uint32_t first = 0; first < E; first += kBlock) {
    const std::uint32_t count = std::min(kBlock, E - first);
    for (std::uint32_t i = 0; i < count; ++i) {
      const std::uint32_t a = t.edge_vertices[2 * (first + i)], b = t.edge_vertices[2 * (first + i) + 1];
      const Vec n = normal[a] + normal[b], edge = position(b) - position(a);
      block.nx[i] = n.x, block.ny[i] = n.y, block.nz[i] = n.z;
      block.ex[i] = edge.x, block.ey[i] = edge.y, block.ez[i] = edge.z;
    }
    for (std::uint32_t i = count; i % kLanes != 0; ++i) {  // harmless spare entries for the last lanes
      block.nx[i] = block.ny[i] = block.nz[i] = 1;
      block.ex[i] = block.ey[i] = block.ez[i] = 0;
    }
    block.compute(count);
    for (std::uint32_t i = 0; i < count; ++i) {
      const double length = block.length[i];
      if (!(length > 0) || !std::isfinite(length)) continue;  // identity frame: leave (x, y, z) as is
      const Vec n{block.nx[i], block.ny[i], block.nz[i]};
      Vec t1{block.t1x[i], block.t1y[i], block.t1z[i]}, t2{block.t2x[i], block.t2y[i], block.t2z[i]};
      if (!(block.t1_length[i] > block.edge_length[i])) [[unlikely]] {
        // The edge is (nearly) along the normal, or has no length: use the axis least aligned with n.
        const double ax = std::abs(n.x), ay = std::abs(n.y), az = std::abs(n.z);
        const Vec axis = ax <= ay && ax <= az ? Vec{1, 0, 0} : (ay <= az ? Vec{0, 1, 0} : Vec{0, 0, 1});
        t1 = axis - dot(axis, n) * n;
        t1 = (1 / std::sqrt(dot(t1, t1))) * t1;
        t2 = cross(n, t1);
      }
      double* d = &details[s * h.odd_vertex(level, first + i)];
      const Vec v{d[0], d[1], d[2]};
      if (direction == Direction::to_local) {
        d[0] = dot(n, v);
        d[1] = dot(t1, v);
        d[2] = dot(t2, v);
      } else {
        const Vec g = v.x * n + v.y * t1 + v.z * t2;  // v holds (n, t1, t2) components here
        d[0] = g.x;
        d[1] = g.y;
        d[2] = g.z;
      }
    }
  }
}

}  // namespace meshlift::frames
