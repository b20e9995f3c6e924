#include "base_values.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "base_mesh_coder.h"
#include "meshlift/mesh.h"

namespace meshlift::base_values {

namespace {

// How vertex v is predicted (FORMAT.md §5.1). The decoder knows the whole base connectivity
// before the base part (§4) and has decoded every vertex labelled below v, so v's prediction may
// read any of them.
enum class Kind : std::uint8_t {
  zero,            // no earlier vertex: 0
  copy,            // a = the corner labelled before v of the first face with v, or else v - 1
  midpoint,        // floor((a + b) / 2): both other corners of that face are older, no parallelogram
  parallelograms,  // floor(mean of x + y - d) over v's parallelograms (a = first, b = count)
};
struct Recipe {
  Kind kind = Kind::zero;
  std::uint32_t a = 0, b = 0;
};

// v's parallelograms (Touma, Gotsman 1998): for every face (v, x, y) of v whose corners x, y are
// labelled before v, the face across the edge x -> y if its third corner d is also labelled
// before v; predicting v by the mean of all of them (Cohen-Or, Cohen, Ironi 2002, "Multi-way
// geometry encoding"; Draco's MeshPredictionSchemeMultiParallelogram) instead of the one across
// the face that first reached v (format version 3) codes nine corpus bases in 5.6 % fewer bytes
// (docs/RESULTS.md).
struct Predictor {
  std::vector<Recipe> recipe;          // per vertex
  std::vector<std::uint32_t> corners;  // x, y, d per parallelogram, grouped by vertex
};

Predictor predictor(const TriangleTopology& base) {
  const std::uint32_t V = base.vertex_count, F = base.face_count();
  Predictor out;
  out.recipe.resize(V);
  // The parallelogram of corner i of face f, as (x, y, d); d = kNone if there is none.
  auto parallelogram = [&](std::uint32_t f, std::uint32_t i) {
    const std::uint32_t v = base.triangles[3 * f + i];
    const std::uint32_t x = base.triangles[3 * f + (i + 1) % 3], y = base.triangles[3 * f + (i + 2) % 3];
    if (x >= v || y >= v) return std::array<std::uint32_t, 3>{x, y, kNone};
    const std::uint32_t e = base.face_edges[3 * f + (i + 1) % 3];
    const std::uint32_t across = base.edge_faces[2 * e] == f ? base.edge_faces[2 * e + 1] : base.edge_faces[2 * e];
    const std::uint32_t d = across == kNone ? kNone : base.opposite_vertex(across, e);
    return std::array<std::uint32_t, 3>{x, y, d < v ? d : kNone};
  };
  // Count, then place each vertex's parallelograms (face order; the sum does not depend on it).
  std::vector<std::uint32_t> first(std::size_t{V} + 1, 0);
  for (std::uint32_t f = 0; f < F; ++f)
    for (std::uint32_t i = 0; i < 3; ++i)
      if (parallelogram(f, i)[2] != kNone) ++first[base.triangles[3 * f + i] + 1];
  for (std::uint32_t v = 0; v < V; ++v) first[v + 1] += first[v];
  out.corners.resize(3 * std::size_t{first[V]});
  std::vector<std::uint32_t> next(first.begin(), first.end() - 1), first_face(V, kNone), first_corner(V, 0);
  for (std::uint32_t f = 0; f < F; ++f)
    for (std::uint32_t i = 0; i < 3; ++i) {
      const std::uint32_t v = base.triangles[3 * f + i];
      if (first_face[v] == kNone) first_face[v] = f, first_corner[v] = i;
      if (const auto p = parallelogram(f, i); p[2] != kNone) std::copy(p.begin(), p.end(), &out.corners[3 * std::size_t{next[v]++}]);
    }
  for (std::uint32_t v = 0; v < V; ++v) {
    Recipe& r = out.recipe[v];
    if (first[v + 1] > first[v]) {
      r = {Kind::parallelograms, first[v], first[v + 1] - first[v]};
    } else if (first_face[v] != kNone) {
      const auto corners = parallelogram(first_face[v], first_corner[v]);
      const std::uint32_t x = corners[0], y = corners[1];
      r = x < v && y < v ? Recipe{Kind::midpoint, x, y}
          : x < v        ? Recipe{Kind::copy, x, 0}
          : y < v        ? Recipe{Kind::copy, y, 0}
          : v > 0        ? Recipe{Kind::copy, v - 1, 0}
                         : Recipe{};
    } else if (v > 0) {
      r = {Kind::copy, v - 1, 0};
    }
  }
  return out;
}

/// floor(s / n) for n > 0 (C++ division truncates towards zero; this rounds down, as Python's //).
std::int64_t floor_divide(std::int64_t s, std::int64_t n) { return s / n - (s % n < 0 ? 1 : 0); }

std::int64_t predict(const Predictor& p, std::uint32_t v, const std::int64_t* high, std::size_t k, std::size_t c) {
  const Recipe& r = p.recipe[v];
  switch (r.kind) {
    case Kind::zero:
      return 0;
    case Kind::copy:
      return high[k * r.a + c];
    case Kind::midpoint:
      return (high[k * r.a + c] + high[k * r.b + c]) >> 1;  // floor (an arithmetic shift, C++20)
    case Kind::parallelograms: {
      // |high| < 2^29 (kMaxPlanes), so each term is below 3 * 2^29 and fewer than 2^32 of them
      // sum to less than 2^63.
      std::int64_t sum = 0;
      const std::uint32_t* t = p.corners.data() + 3 * std::size_t{r.a};
      for (const std::uint32_t* end = t + 3 * std::size_t{r.b}; t != end; t += 3)
        sum += high[k * t[0] + c] + high[k * t[1] + c] - high[k * t[2] + c];
      return floor_divide(sum, r.b);
    }
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

std::vector<std::int64_t> residuals(const TriangleTopology& base, std::span<const std::int64_t> high, int components) {
  const Predictor p = predictor(base);
  const auto k = static_cast<std::size_t>(components);
  std::vector<std::int64_t> out(high.size());
  for (std::uint32_t v = 0; v < base.vertex_count; ++v)
    for (std::size_t c = 0; c < k; ++c) out[k * v + c] = high[k * v + c] - predict(p, v, high.data(), k, c);
  return out;
}

int choose_base_plane(const TriangleTopology& base, const zerotree::Quantized& q, int top_plane) {
  const std::uint32_t base_vertices = base.vertex_count;
  if (top_plane < 0 || base_vertices == 0) return top_plane + 1;
  const std::vector<std::int64_t> residual = residuals(base, high_parts(q, base_vertices, 0), q.components);
  double sum = 0;
  for (const std::int64_t r : residual) sum += static_cast<double>(r) * static_cast<double>(r);
  const double rms = std::sqrt(sum / static_cast<double>(residual.size()));
  const int plane = rms >= 2 ? static_cast<int>(std::floor(std::log2(rms / 2))) : 0;
  return std::clamp(plane, lowest_plane(top_plane), top_plane + 1);
}

void encode(const TriangleTopology& base, const zerotree::Quantized& q, int base_plane, int top_plane,
            RangeEncoder& encoder) {
  if (base_plane > top_plane) return;
  const std::vector<std::int64_t> residual = residuals(base, high_parts(q, base.vertex_count, base_plane), q.components);
  const auto k = static_cast<std::size_t>(q.components);
  Models m(k);
  for (std::size_t i = 0; i < residual.size(); ++i) {
    const std::int64_t r = residual[i];
    m.magnitude[i % k].encode(encoder, static_cast<std::uint32_t>(r < 0 ? -r : r));
    if (r != 0) encoder.encode(m.negative[i % k], r < 0);
  }
}

std::uint32_t decode(const TriangleTopology& base, int components, int base_plane, int top_plane, RangeDecoder& decoder,
                     std::vector<std::int64_t>& high, bool& corrupt) {
  const std::uint32_t base_vertices = base.vertex_count;
  const auto k = static_cast<std::size_t>(components);
  corrupt = false;
  high.assign(std::size_t{base_vertices} * k, 0);
  if (base_plane > top_plane) return base_vertices;
  const Predictor p = predictor(base);
  const std::int64_t bound = std::int64_t{1} << (top_plane + 1 - base_plane);  // |high| < bound
  Models m(k);
  for (std::uint32_t v = 0; v < base_vertices; ++v)
    for (std::size_t c = 0; c < k; ++c) {
      std::uint32_t magnitude = 0;
      int negative = 0;
      if (!m.magnitude[c].decode(decoder, magnitude) ||
          (magnitude != 0 && (negative = decoder.decode(m.negative[c]), decoder.exhausted()))) {
        // Cut (or an invalid integer code): the vertices before v are whole. The others take
        // their prediction with a zero residual, in label order (FORMAT.md §5.1): a prefix shows
        // the base's shape extrapolated from the vertices that came, not those at the centre.
        // Clamped to the values' range, as a decoded value must be: predictions of predictions
        // could otherwise grow without bound along the labels.
        corrupt = !decoder.exhausted();
        for (std::uint32_t u = v; u < base_vertices; ++u)
          for (std::size_t d = 0; d < k; ++d)
            high[k * u + d] = corrupt ? 0 : std::clamp(predict(p, u, high.data(), k, d), 1 - bound, bound - 1);
        return v;
      }
      const std::int64_t value = predict(p, v, high.data(), k, c) + (negative ? -std::int64_t{magnitude} : magnitude);
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
