#include "base_values.h"

#include <algorithm>
#include <cmath>

#include "base_mesh_coder.h"
#include "meshlift/mesh.h"

namespace meshlift::base_values {

namespace {

// How vertex v is predicted (FORMAT.md §5.1), from the base faces in stream order alone: the
// first face that has v, seen from v, has corners (v, x, y).
enum class Kind : std::uint8_t {
  zero,           // no earlier vertex: 0
  copy,           // a = the one corner labelled before v, or else v - 1
  midpoint,       // floor((a + b) / 2): x and y are older, but no earlier face has the edge xy
  parallelogram,  // a + b - d: the earlier face (x, y, d) across the edge xy (Touma, Gotsman 1998)
};
struct Recipe {
  Kind kind = Kind::zero;
  std::uint32_t a = 0, b = 0, d = 0;
};

std::vector<Recipe> recipes(const TriangleTopology& base) {
  const std::uint32_t V = base.vertex_count;
  std::vector<std::uint32_t> first_face(V, kNone), first_corner(V, 0);
  for (std::uint32_t f = 0; f < base.face_count(); ++f)
    for (std::uint32_t i = 0; i < 3; ++i)
      if (const std::uint32_t u = base.triangles[3 * f + i]; first_face[u] == kNone) first_face[u] = f, first_corner[u] = i;
  std::vector<Recipe> out(V);
  for (std::uint32_t v = 0; v < V; ++v) {
    Recipe& r = out[v];
    if (first_face[v] != kNone) {
      const std::uint32_t f = first_face[v], i = first_corner[v];
      const std::uint32_t x = base.triangles[3 * f + (i + 1) % 3], y = base.triangles[3 * f + (i + 2) % 3];
      if (x < v && y < v) {
        // The face across x -> y: the first face with both is f or it, whichever comes first.
        const std::uint32_t e = base.face_edges[3 * f + (i + 1) % 3];
        const std::uint32_t across = base.edge_faces[2 * e] == f ? base.edge_faces[2 * e + 1] : base.edge_faces[2 * e];
        r = across != kNone && across < f ? Recipe{Kind::parallelogram, x, y, base.opposite_vertex(across, e)}
                                          : Recipe{Kind::midpoint, x, y, 0};
        continue;
      }
      if (x < v || y < v) {
        r = {Kind::copy, x < v ? x : y, 0, 0};
        continue;
      }
    }
    if (v > 0) r = {Kind::copy, v - 1, 0, 0};
  }
  return out;
}

std::int64_t predict(const Recipe& r, const std::int64_t* high, std::size_t k, std::size_t c) {
  switch (r.kind) {
    case Kind::zero:
      return 0;
    case Kind::copy:
      return high[k * r.a + c];
    case Kind::midpoint:
      return (high[k * r.a + c] + high[k * r.b + c]) >> 1;  // floor (an arithmetic shift, C++20)
    case Kind::parallelogram:
      return high[k * r.a + c] + high[k * r.b + c] - high[k * r.d + c];
  }
  return 0;
}

/// sign * (magnitude >> shift) of the first `vertices` vertices' coefficients.
std::vector<std::int64_t> high_parts(const zerotree::Quantized& q, std::uint32_t vertices, int shift) {
  const std::size_t n = std::size_t{vertices} * static_cast<std::size_t>(q.components);
  std::vector<std::int64_t> high(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto m = static_cast<std::int64_t>(q.coefficients[i].magnitude >> shift);
    high[i] = q.coefficients[i].negative ? -m : m;
  }
  return high;
}

/// The lowest base plane the integer coder can hold.
int lowest_plane(int top_plane) { return std::max(0, top_plane + 1 - kMaxPlanes); }

// One residual: |r| by the adaptive Elias-gamma code, then its sign if not 0 (1 = negative).
struct Models {
  std::vector<base_mesh::UintCoder> magnitude;
  std::vector<BitModel> negative;
  explicit Models(std::size_t components) : magnitude(components), negative(components) {}
};

}  // namespace

int choose_base_plane(const TriangleTopology& base, const zerotree::Quantized& q, int top_plane) {
  const std::uint32_t base_vertices = base.vertex_count;
  if (top_plane < 0 || base_vertices == 0) return top_plane + 1;
  const std::vector<Recipe> recipe = recipes(base);
  const std::vector<std::int64_t> value = high_parts(q, base_vertices, 0);
  const auto k = static_cast<std::size_t>(q.components);
  double sum = 0;
  for (std::uint32_t v = 0; v < base_vertices; ++v)
    for (std::size_t c = 0; c < k; ++c) {
      const auto r = static_cast<double>(value[k * v + c] - predict(recipe[v], value.data(), k, c));
      sum += r * r;
    }
  const double rms = std::sqrt(sum / static_cast<double>(value.size()));
  const int plane = rms >= 2 ? static_cast<int>(std::floor(std::log2(rms / 2))) : 0;
  return std::clamp(plane, lowest_plane(top_plane), top_plane + 1);
}

void encode(const TriangleTopology& base, const zerotree::Quantized& q, int base_plane, int top_plane,
            RangeEncoder& encoder) {
  if (base_plane > top_plane) return;
  const std::uint32_t base_vertices = base.vertex_count;
  const std::vector<Recipe> recipe = recipes(base);
  const std::vector<std::int64_t> high = high_parts(q, base_vertices, base_plane);
  const auto k = static_cast<std::size_t>(q.components);
  Models m(k);
  for (std::uint32_t v = 0; v < base_vertices; ++v)
    for (std::size_t c = 0; c < k; ++c) {
      const std::int64_t r = high[k * v + c] - predict(recipe[v], high.data(), k, c);
      m.magnitude[c].encode(encoder, static_cast<std::uint32_t>(r < 0 ? -r : r));
      if (r != 0) encoder.encode(m.negative[c], r < 0);
    }
}

std::uint32_t decode(const TriangleTopology& base, int components, int base_plane, int top_plane, RangeDecoder& decoder,
                     std::vector<std::int64_t>& high, bool& corrupt) {
  const std::uint32_t base_vertices = base.vertex_count;
  const auto k = static_cast<std::size_t>(components);
  corrupt = false;
  high.assign(std::size_t{base_vertices} * k, 0);
  if (base_plane > top_plane) return base_vertices;
  const std::vector<Recipe> recipe = recipes(base);
  const std::int64_t bound = std::int64_t{1} << (top_plane + 1 - base_plane);  // |high| < bound
  Models m(k);
  for (std::uint32_t v = 0; v < base_vertices; ++v)
    for (std::size_t c = 0; c < k; ++c) {
      std::uint32_t magnitude = 0;
      int negative = 0;
      if (!m.magnitude[c].decode(decoder, magnitude) ||
          (magnitude != 0 && (negative = decoder.decode(m.negative[c]), decoder.exhausted()))) {
        // Cut (or an invalid integer code): the vertices before v are whole.
        corrupt = !decoder.exhausted();
        std::fill(high.begin() + static_cast<std::ptrdiff_t>(k * v), high.end(), 0);
        return v;
      }
      const std::int64_t value = predict(recipe[v], high.data(), k, c) + (negative ? -std::int64_t{magnitude} : magnitude);
      if (value <= -bound || value >= bound) {
        corrupt = true;
        std::fill(high.begin() + static_cast<std::ptrdiff_t>(k * v), high.end(), 0);
        return v;
      }
      high[k * v + c] = value;
    }
  return base_vertices;
}

}  // namespace meshlift::base_values
