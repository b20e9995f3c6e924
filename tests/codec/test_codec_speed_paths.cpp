// The decoder's fast paths against the plain computations they replace, bit for bit: the local
// frames computed block by block with packed arithmetic (codec/local_frames.cpp) against the
// formulas of FORMAT.md §3 edge by edge; the coding forest read off the topologies against the
// hierarchy's stored coefficient tree; stencil tables built one level at a time against all at once.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "../../codec/local_frames.h"
#include "../../codec/stencils.h"
#include "../../codec/zerotree_coder.h"
#include "meshlift/codec.h"
#include "lifting_rows.h"
#include "meshlift/lifting.h"
#include "test_meshes.h"

using namespace meshlift;

namespace {

struct Vec {
  double x, y, z;
};
Vec operator+(Vec a, Vec b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec operator-(Vec a, Vec b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec operator*(double s, Vec a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(Vec a, Vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec cross(Vec a, Vec b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

/// FORMAT.md §3's local frames, written out edge by edge as the spec's pseudo-code reads.
void reference_rotate(const SemiRegularHierarchy& h, int level, const std::vector<double>& coarse,
                      std::vector<double>& details, int stride, frames::Direction direction) {
  const TriangleTopology& t = h.topology(level);
  const auto s = static_cast<std::size_t>(stride);
  auto p = [&](std::uint32_t v) { return Vec{coarse[s * v], coarse[s * v + 1], coarse[s * v + 2]}; };
  std::vector<Vec> normal(t.vertex_count, Vec{0, 0, 0});
  for (std::size_t f = 0; f < t.face_count(); ++f) {
    const std::uint32_t* c = &t.triangles[3 * f];
    const Vec n = cross(p(c[1]) - p(c[0]), p(c[2]) - p(c[0]));
    for (int i = 0; i < 3; ++i) normal[c[i]] = normal[c[i]] + n;
  }
  for (std::uint32_t e = 0; e < t.edge_count(); ++e) {
    const std::uint32_t a = t.edge_vertices[2 * e], b = t.edge_vertices[2 * e + 1];
    Vec n = normal[a] + normal[b];
    const double len = std::sqrt(dot(n, n));
    const Vec d = p(b) - p(a);
    if (!(len > 1e-12 * dot(d, d)) || !std::isfinite(len)) continue;
    n = (1 / len) * n;
    Vec t1 = d - dot(d, n) * n;
    double l1 = std::sqrt(dot(t1, t1));
    if (!(l1 > 1e-12 * std::sqrt(dot(d, d)))) {
      const double ax = std::abs(n.x), ay = std::abs(n.y), az = std::abs(n.z);
      const Vec axis = ax <= ay && ax <= az ? Vec{1, 0, 0} : (ay <= az ? Vec{0, 1, 0} : Vec{0, 0, 1});
      t1 = axis - dot(axis, n) * n;
      l1 = std::sqrt(dot(t1, t1));
    }
    t1 = (1 / l1) * t1;
    const Vec t2 = cross(n, t1);
    double* x = &details[s * h.odd_vertex(level, e)];
    const Vec v{x[0], x[1], x[2]};
    const Vec out = direction == frames::Direction::to_local ? Vec{dot(n, v), dot(t1, v), dot(t2, v)}
                                                             : v.x * n + v.y * t1 + v.z * t2;
    x[0] = out.x, x[1] = out.y, x[2] = out.z;
  }
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

}  // namespace

TEST_CASE("local frames block by block give the bits of FORMAT.md's edge-by-edge formulas, degenerate edges too",
          "[frames]") {
  // Edge counts below, at and across the block of 64 and the lanes of 4: a disk (10 edges), the
  // icosahedron (30), a grid with boundary (3n^2+2n edges), a torus, refined.
  for (const TriangleMesh& base : {test::disk(5), test::icosahedron(), test::grid(4), test::torus()}) {
    const SemiRegularHierarchy h(TriangleTopology::build(static_cast<std::uint32_t>(base.vertex_count()), base.triangles), 3);
    for (int stride : {3, 5}) {
      const std::size_t V = h.vertex_count(3);
      for (int variant = 0; variant < 4; ++variant) {
        std::vector<double> coarse = test::random_values(V * stride, 7 + variant);
        if (variant == 1) {
          // Coincident vertices (edges of no length: the axis fallback) and a flat patch.
          for (std::uint32_t v = 0; v < h.vertex_count(2); v += 3)
            for (int k = 0; k < 3; ++k) coarse[stride * v + k] = coarse[k];
        } else if (variant == 2) {
          // Everything at one point: every normal is 0, every frame the identity.
          for (std::uint32_t v = 0; v < V; ++v)
            for (int k = 0; k < 3; ++k) coarse[stride * v + k] = 0.25;
        } else if (variant == 3) {
          // Pieces of a line: normals of length 0 next to edges along the normal of their neighbours.
          for (std::uint32_t v = 0; v < V; ++v)
            if (v % 2 == 0) coarse[stride * v] = coarse[stride * v + 1] = 0;
        }
        for (int level = 0; level < 3; ++level)
          for (frames::Direction direction : {frames::Direction::to_local, frames::Direction::to_global}) {
            std::vector<double> expected = test::random_values(V * stride, 99);
            std::vector<double> got = expected;
            reference_rotate(h, level, coarse, expected, stride, direction);
            frames::rotate_details(h, level, coarse, got, stride, direction);
            INFO("variant " << variant << ", level " << level << ", stride " << stride);
            REQUIRE(same_bits(got, expected));
            // In place (coarse and details one array): the coarse range is read, the odd range written.
            std::vector<double> together = coarse, reference = coarse;
            reference_rotate(h, level, coarse, reference, stride, direction);
            frames::rotate_details(h, level, together, together, stride, direction);
            REQUIRE(same_bits(together, reference));
          }
      }
    }
  }
}

TEST_CASE("coding forest read off the topologies is the hierarchy's coefficient tree", "[zerotree]") {
  for (const TriangleMesh& base : {test::icosahedron(), test::grid(3), test::disk(7), test::torus()}) {
    const TriangleTopology topology = TriangleTopology::build(static_cast<std::uint32_t>(base.vertex_count()), base.triangles);
    for (int levels : {1, 2, 4}) {
      const SemiRegularHierarchy full(topology, levels), lean(topology, levels, false, false);
      const zerotree::Forest forest(lean);
      for (std::uint32_t v = full.vertex_count(0); v < full.vertex_count(levels); ++v) {
        const auto tree = full.children(v), coded = forest.children(v);
        REQUIRE(std::vector<std::uint32_t>(coded.begin(), coded.end()) == std::vector<std::uint32_t>(tree.begin(), tree.end()));
      }
      CHECK_THROWS_AS(lean.children(full.vertex_count(0)), std::logic_error);
      CHECK((lean.memory_bytes() < full.memory_bytes() || levels < 2));
    }
  }
}

TEST_CASE("stencil tables one level at a time synthesize the same bits as all at once", "[lifting]") {
  const TriangleMesh base = test::grid(3);
  const SemiRegularHierarchy h(TriangleTopology::build(static_cast<std::uint32_t>(base.vertex_count()), base.triangles), 3);
  const std::vector<double> input = test::random_values(std::size_t{h.vertex_count(3)} * 4, 3);
  for (Scheme scheme : {Scheme::linear, Scheme::butterfly, Scheme::loop})
    for (bool update : {false, true}) {
      const WaveletOptions options{scheme, update};
      std::vector<double> all = input, by_level = input;
      WaveletTransform(h, options).synthesize(all, 4);
      for (int j = 0; j < 3; ++j) WaveletTransform(h, options, j, j + 1).synthesize(by_level, 4, j + 1, j);
      CHECK(same_bits(all, by_level));
      const WaveletTransform middle(h, options, 1, 2);
      CHECK(middle.steps(0).empty());
      CHECK_FALSE(middle.steps(1).empty());
      CHECK_THROWS_AS(middle.synthesize(by_level, 4, 3, 1), std::logic_error);
      CHECK_THROWS_AS(middle.synthesize(by_level, 4, 1, 0), std::logic_error);
      CHECK_THROWS_AS(middle.analyze(by_level, 4), std::logic_error);
      CHECK_NOTHROW(middle.synthesize(by_level, 4, 1, 1));  // no level asked for
    }
  CHECK_THROWS_AS(WaveletTransform(h, {}, 2, 1), std::invalid_argument);
  CHECK_THROWS_AS(WaveletTransform(h, {}, 0, 4), std::invalid_argument);
}

TEST_CASE("encode refuses a precision whose magnitudes pass 2^31 - with and without local frames", "[codec]") {
  const SemiRegularMesh mesh = refine_linear(test::icosahedron(), 2);
  for (bool frames : {false, true}) {
    EncodeOptions options;
    options.local_frames = frames;
    options.precision_bits = 40;  // base values ~ the diagonal / 2: ~2^39 steps
    CHECK_THROWS_WITH(encode(mesh, options), Catch::Contains("too fine"));
    options.precision_bits = 24;
    CHECK(decode(encode(mesh, options)).status == Status::ok);
  }
}

using test::expand_rows;

TEST_CASE("Loop rows in blocks are the rows of the whole tables - and synthesize_level gives their bits", "[lifting]") {
  // A pillow (two faces on three vertices) makes merged rows; the grid and disk boundaries and
  // extraordinary vertices their own patterns.
  const TriangleMesh pillow{{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2, 0, 2, 1}};
  for (const TriangleMesh& base : {test::icosahedron(), test::grid(3), test::disk(5), test::torus(), pillow}) {
    const SemiRegularHierarchy h(TriangleTopology::build(static_cast<std::uint32_t>(base.vertex_count()), base.triangles), 4);
    for (int j = 1; j < 4; ++j) {
      const TriangleTopology &coarse = h.topology(j - 1), &fine = h.topology(j);
      std::vector<std::vector<double>> whole = expand_rows(stencils::loop_predict_refined(coarse, fine));
      for (const auto& row : expand_rows(stencils::loop_update_refined(coarse, fine))) whole.push_back(row);
      for (std::uint32_t block_rows : {1u, 5u, 64u, 1u << 20}) {
        std::vector<std::vector<double>> blocks;
        std::size_t count = 0;
        stencils::loop_refined_blocks(coarse, fine, block_rows, [&](const LiftingStep& s) {
          ++count;
          CHECK(s.indices.size() >= LiftingStep::kPadding);
          for (std::size_t k = s.indices.size() - LiftingStep::kPadding; k < s.indices.size(); ++k) REQUIRE(s.indices[k] == 0);
          for (const auto& row : expand_rows(s)) blocks.push_back(row);
        });
        INFO("level " << j << ", block rows " << block_rows);
        REQUIRE(blocks == whole);
        if (block_rows == 1) CHECK(count == 2 * coarse.edge_count() + coarse.face_count() + 1);  // one item per block
      }
    }
    const std::vector<double> input = test::random_values(std::size_t{h.vertex_count(4)} * 3, 11);
    for (Scheme scheme : {Scheme::linear, Scheme::butterfly, Scheme::loop})
      for (bool update : {false, true}) {
        std::vector<double> tables = input, levels = input;
        WaveletTransform(h, {scheme, update}).synthesize(tables, 3);
        for (int j = 0; j < 4; ++j) synthesize_level(h, {scheme, update}, j, levels, 3);
        CHECK(same_bits(tables, levels));
      }
  }
}
