// More of the codec's fast paths against the plain computations they replace (issue 3's third
// round): butterfly's regular rows written straight and the predict step a block at a time
// against the rule's rows built source by source; a hierarchy without the topology below its
// finest level against the whole one (faces, frames, forest); frames range by range and the
// details turned inside synthesize_level against a separate pass; the encoder's level weights
// (impulses over their support only) against full syntheses.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <mutex>
#include <algorithm>
#include <numbers>
#include <optional>
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

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

using test::expand_rows;
using test::topology_of;

/// The modified butterfly rule (CODEC-NOTES §2) for edge e, source by source as the rule reads,
/// repeated sources merged in first-seen order (weights summed): target, 1, then (source,
/// weight) pairs, as expand_rows writes a row. Written from the rule, with searches, not from
/// the codec's tables.
std::vector<double> butterfly_reference_row(const TriangleTopology& t, std::uint32_t e) {
  std::vector<double> row{static_cast<double>(t.vertex_count + e), 1.0};
  auto add = [&](std::uint32_t v, double w) {
    for (std::size_t k = 2; k < row.size(); k += 2)
      if (row[k] == v) {
        row[k + 1] += w;
        return;
      }
    row.push_back(v);
    row.push_back(w);
  };
  const VertexEdges ve(t);
  auto irregular = [&](std::uint32_t v) { return !ve.boundary[v] && ve.valence(v) != 6; };
  auto face_with = [&](std::uint32_t u, std::uint32_t w, std::uint32_t not_face) {  // the face of edge (u, w) other than not_face
    for (std::uint32_t k = ve.offsets[u]; k < ve.offsets[u + 1]; ++k) {
      const std::uint32_t x = ve.edges[k];
      const std::uint32_t a = t.edge_vertices[2 * x], b = t.edge_vertices[2 * x + 1];
      if ((a == u && b == w) || (a == w && b == u))
        return std::pair{x, t.edge_faces[2 * x] == not_face ? t.edge_faces[2 * x + 1] : t.edge_faces[2 * x]};
    }
    return std::pair{kNone, kNone};
  };
  const std::uint32_t a0 = t.edge_vertices[2 * e], a1 = t.edge_vertices[2 * e + 1];
  if (t.is_boundary_edge(e)) {
    auto other_boundary_neighbour = [&](std::uint32_t v, std::uint32_t not_this) {
      for (std::uint32_t k = ve.offsets[v]; k < ve.offsets[v + 1]; ++k) {
        const std::uint32_t x = ve.edges[k];
        if (!t.is_boundary_edge(x)) continue;
        const std::uint32_t w = t.edge_vertices[2 * x] == v ? t.edge_vertices[2 * x + 1] : t.edge_vertices[2 * x];
        if (w != not_this) return w;
      }
      return kNone;
    };
    add(a0, 9.0 / 16);
    add(a1, 9.0 / 16);
    add(other_boundary_neighbour(a0, a1), -1.0 / 16);
    add(other_boundary_neighbour(a1, a0), -1.0 / 16);
    return row;
  }
  if (!irregular(a0) && !irregular(a1)) {
    add(a0, 0.5);
    add(a1, 0.5);
    for (int side = 0; side < 2; ++side) {
      const std::uint32_t f = t.edge_faces[2 * e + side];
      const std::uint32_t b = t.opposite_vertex(f, e);
      add(b, 1.0 / 8);
      for (const std::uint32_t x : {a0, a1}) {
        const auto [wing, across] = face_with(x, b, f);
        if (across != kNone) {
          add(t.opposite_vertex(across, wing), -1.0 / 16);
        } else {  // reflected tip x + b - y
          add(x, -1.0 / 16);
          add(b, -1.0 / 16);
          add(x == a0 ? a1 : a0, 1.0 / 16);
        }
      }
    }
    return row;
  }
  const double share = irregular(a0) && irregular(a1) ? 0.5 : 1.0;
  for (const std::uint32_t x : {a0, a1}) {
    if (!irregular(x)) continue;
    const unsigned K = ve.valence(x);
    std::vector<double> s(K);
    if (K == 3) s = {5.0 / 12, -1.0 / 12, -1.0 / 12};
    else if (K == 4) s = {3.0 / 8, 0.0, -1.0 / 8, 0.0};
    else
      for (unsigned i = 0; i < K; ++i) {
        const double angle = 2.0 * std::numbers::pi * i / K;
        s[i] = (0.25 + std::cos(angle) + 0.5 * std::cos(2 * angle)) / K;
      }
    add(x, share * 0.75);
    // The ring in face order from the edge's other endpoint, through the edge's first face.
    std::uint32_t w = x == a0 ? a1 : a0, edge = e, f = t.edge_faces[2 * e];
    for (unsigned i = 0; i < K; ++i) {
      add(w, share * s[i]);
      const std::uint32_t next = t.opposite_vertex(f, edge);
      std::tie(edge, f) = face_with(x, next, f);
      w = next;
    }
  }
  return row;
}

}  // namespace

TEST_CASE("butterfly rows written straight, a block at a time and applied as read are the rule's rows - irregular, boundary, pillow",
          "[lifting]") {
  const TriangleMesh pillow{{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2, 0, 2, 1}};
  const TriangleMesh tetrahedron{{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3}};
  const TriangleMesh triangle{{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2}};
  // A fan of five faces around vertex 0 with one gap: an interior-looking extraordinary corner
  // that is on the boundary, next to interior extraordinary vertices after refinement.
  const TriangleMesh open_fan{{0, 0, 0, 1, 0, 0, 0.5, 0.8, 0, -0.5, 0.8, 0, -1, 0, 0, -0.5, -0.8, 0, 0.5, -0.8, 0},
                              {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5, 0, 5, 6}};
  for (const TriangleMesh& base : {test::icosahedron(), test::grid(4), test::disk(5), test::bicone(3), test::bicone(4),
                                   test::torus(), pillow, tetrahedron, triangle, open_fan}) {
    const SemiRegularHierarchy h(topology_of(base), 3);
    for (int j = 0; j < 3; ++j) {
      const TriangleTopology& t = h.topology(j);
      std::vector<std::vector<double>> reference;
      for (std::uint32_t e = 0; e < t.edge_count(); ++e) reference.push_back(butterfly_reference_row(t, e));
      INFO("level " << j << ", " << t.vertex_count << " vertices");
      REQUIRE(expand_rows(stencils::predict(t, Scheme::butterfly)) == reference);
      for (Scheme scheme : {Scheme::linear, Scheme::butterfly}) {
        const std::vector<std::vector<double>> whole = expand_rows(stencils::predict(t, scheme));
        // Above the base, one set of refined rows for every use below.
        std::optional<stencils::RefinedPredictRows> refined;
        if (j > 0) refined.emplace(h.topology(j - 1), scheme);
        for (std::uint32_t block_rows : {1u, 7u, 64u, 1u << 20}) {
          std::vector<std::vector<double>> blocks;
          stencils::predict_blocks(t, scheme, block_rows, [&](const LiftingStep& s) {
            CHECK(s.row_count <= block_rows);
            for (std::size_t k = s.indices.size() - LiftingStep::kPadding; k < s.indices.size(); ++k) REQUIRE(s.indices[k] == 0);
            for (const auto& row : expand_rows(s)) blocks.push_back(row);
          });
          REQUIRE(blocks == whole);
          if (j == 0) continue;
          // The same rows read off the level below, without this level's topology, applied as they
          // are read: the same bits as the rows' synthesis written here from them (the target
          // times the scale, then the sources in row order), in 1, 3 and 4 channels, on one thread
          // and on two. The odd values start as NaN and before_odd writes each chunk's details,
          // so a row computed before its chunk was handed over would show.
          const std::uint32_t first_odd = h.vertex_count(j), fine = h.vertex_count(j + 1);
          for (const int channels : {1, 3, 4})
            for (const bool concurrent : {false, true}) {
              const auto n = static_cast<std::size_t>(channels);
              std::vector<double> values(fine * n), details(fine * n);
              for (std::size_t i = 0; i < values.size(); ++i) {
                values[i] = std::sin(0.37 * static_cast<double>(i) + 1.0);
                details[i] = 1e-3 * std::cos(1.3 * static_cast<double>(i));
              }
              std::vector<double> expected = values;
              std::copy(details.begin() + first_odd * n, details.end(), expected.begin() + first_odd * n);
              for (const auto& row : whole) {
                const auto target = static_cast<std::size_t>(row[0]);
                for (std::size_t c = 0; c < n; ++c) {
                  double acc = row[1] * expected[target * n + c];
                  for (std::size_t k = 2; k < row.size(); k += 2) acc += row[k + 1] * expected[static_cast<std::size_t>(row[k]) * n + c];
                  expected[target * n + c] = acc;
                }
              }
              std::fill(values.begin() + first_odd * n, values.end(), std::nan(""));
              std::mutex handed_lock;
              std::vector<int> handed(fine - first_odd, 0);
              refined->synthesize(
                  block_rows, values.data(), channels,
                  [&](std::uint32_t first, std::uint32_t count) {
                    const std::lock_guard<std::mutex> lock(handed_lock);
                    for (std::uint32_t v = first; v < first + count && v >= first_odd && v < fine; ++v) {
                      ++handed[v - first_odd];
                      std::copy_n(details.begin() + v * n, n, values.begin() + v * n);
                    }
                  },
                  concurrent);
              INFO(to_string(scheme) << ", block rows " << block_rows << ", " << channels << " channels"
                                     << (concurrent ? ", two threads" : ""));
              REQUIRE(same_bits(values, expected));
              REQUIRE(std::count(handed.begin(), handed.end(), 1) == static_cast<std::ptrdiff_t>(handed.size()));
            }
          REQUIRE(expand_rows(stencils::refined_predict(h.topology(j - 1), scheme)) == whole);
        }
        if (j == 0) continue;
        // The rows' column sums read off the level below, through the same refined rows that every
        // synthesis above used: the table's, bit for bit.
        std::vector<double> sums(h.vertex_count(j), 0.0), expected_sums(h.vertex_count(j), 0.0);
        stencils::add_column_sums(stencils::predict(t, scheme), expected_sums);
        refined->add_column_sums(sums);
        REQUIRE(same_bits(sums, expected_sums));
      }
    }
    CHECK_THROWS_AS(stencils::predict_blocks(h.topology(0), Scheme::loop, 64, [](const LiftingStep&) {}),
                    std::invalid_argument);
    CHECK_THROWS_AS(stencils::RefinedPredictRows(h.topology(0), Scheme::loop), std::invalid_argument);
    CHECK_THROWS_AS(stencils::refined_predict(h.topology(0), Scheme::loop), std::invalid_argument);
  }
}

TEST_CASE("a hierarchy without the topology below its finest level gives the same faces, forest and frames",
          "[semi_regular]") {
  for (const TriangleMesh& base : {test::icosahedron(), test::grid(3), test::disk(7), test::torus()}) {
    for (int levels : {1, 2, 3}) {
      const SemiRegularHierarchy full(topology_of(base), levels);
      const SemiRegularHierarchy lean(topology_of(base), levels, false, false, false),
          lean_faces(topology_of(base), levels, true, false, false);
      INFO(levels << " levels");
      for (int j = 0; j <= levels; ++j) REQUIRE(lean.vertex_count(j) == full.vertex_count(j));
      CHECK(lean.has_topology(levels - 1) == (levels == 1));
      CHECK(full.has_topology(levels - 1));
      if (levels >= 2) {
        CHECK_THROWS_AS(lean.topology(levels - 1), std::logic_error);
        CHECK_THROWS_AS(lean.triangles(levels - 1), std::logic_error);
        CHECK(lean.memory_bytes() < SemiRegularHierarchy(topology_of(base), levels, false, false).memory_bytes());
      }
      for (int j = 0; j <= levels; ++j) REQUIRE(lean.copy_triangles(j) == full.triangles(j));
      REQUIRE(lean_faces.triangles(levels) == full.triangles(levels));
      const zerotree::Forest lean_forest(lean), full_forest(full);
      REQUIRE(lean_forest.odd_children == full_forest.odd_children);
      REQUIRE(lean_forest.root_children == full_forest.root_children);
      // The frames of the level below the finest, read off the level below it.
      const std::vector<double> values = test::random_values(std::size_t{full.vertex_count(levels)} * 4, 5);
      std::vector<double> from_full = values, from_lean = values;
      frames::rotate_details(full, levels - 1, values, from_full, 4, frames::Direction::to_local);
      frames::rotate_details(lean, levels - 1, values, from_lean, 4, frames::Direction::to_local);
      REQUIRE(same_bits(from_full, from_lean));
      // The synthesis of that level, which needs only its vertex count (the mean-preserving
      // update too: its edges are read off the level below), bit for bit the tables' synthesis.
      for (Scheme scheme : {Scheme::linear, Scheme::butterfly, Scheme::loop})
        for (const bool update : {false, true})
          for (const int channels : {1, 3, 4}) {
            const std::vector<double> start(values.begin(), values.begin() + std::ptrdiff_t{full.vertex_count(levels)} * channels);
            std::vector<double> synthesized_full = start, synthesized_lean = start, on_two = start, tables = start;
            synthesize_level(full, {scheme, update}, levels - 1, synthesized_full, channels);
            synthesize_level(lean, {scheme, update}, levels - 1, synthesized_lean, channels);
            synthesize_level(lean, {scheme, update}, levels - 1, on_two, channels, nullptr, true);
            WaveletTransform(full, {scheme, update}).synthesize(tables, channels, levels, levels - 1);
            INFO(to_string(scheme) << (update ? " + update, " : ", ") << channels << " channels");
            REQUIRE(same_bits(synthesized_full, synthesized_lean));
            REQUIRE(same_bits(synthesized_full, on_two));
            REQUIRE(same_bits(synthesized_full, tables));
            if (scheme == Scheme::loop) {
              CHECK_THROWS_AS(update_weights(lean, scheme, levels - 1), std::invalid_argument);
              continue;
            }
            // The update's weights made once and handed over (a streaming decoder's), on one
            // thread and on two: the same bits; weights of another level are refused.
            const std::vector<double> weights = update_weights(lean, scheme, levels - 1);
            std::vector<double> handed = start, handed_on_two = start;
            synthesize_level(lean, {scheme, update}, levels - 1, handed, channels, nullptr, false, weights);
            synthesize_level(lean, {scheme, update}, levels - 1, handed_on_two, channels, nullptr, true, weights);
            REQUIRE(same_bits(synthesized_full, handed));  // without the update they are ignored
            REQUIRE(same_bits(synthesized_full, handed_on_two));
            // They are what it uses: zero weights leave the even vertices as they are.
            std::vector<double> unweighted = start;
            synthesize_level(lean, {scheme, update}, levels - 1, unweighted, channels, nullptr, false,
                             std::vector<double>(weights.size(), 0.0));
            CHECK(same_bits(synthesized_full, unweighted) == !update);
            if (update && levels >= 2)
              CHECK_THROWS_AS(synthesize_level(lean, {scheme, update}, levels - 1, handed, channels, nullptr, false,
                                               update_weights(lean, scheme, levels - 2)),
                              std::invalid_argument);
          }
      SemiRegularHierarchy released(topology_of(base), levels, false, false, false);
      REQUIRE(std::move(released).release_finest_triangles() == full.triangles(levels));
    }
  }
}

TEST_CASE("frames range by range and details turned inside synthesize_level give the bits of separate passes",
          "[frames]") {
  for (const TriangleMesh& base : {test::disk(5), test::icosahedron(), test::grid(4)}) {
    const SemiRegularHierarchy h(topology_of(base), 3);
    const std::vector<double> values = test::random_values(std::size_t{h.vertex_count(3)} * 3, 9);
    for (int level = 0; level < 3; ++level) {
      const frames::LevelFrames level_frames(h, level, values, 3);
      const std::uint32_t E = level_frames.edge_count();
      REQUIRE(E == h.topology(level).edge_count());
      std::vector<double> whole = values, pieces = values;
      frames::rotate_details(h, level, values, whole, 3, frames::Direction::to_global);
      for (std::uint32_t begin = 0, step = 1; begin < E; begin += step, step = step * 3 + 1)
        level_frames.rotate(begin, std::min(E, begin + step), pieces, frames::Direction::to_global);
      INFO("level " << level);
      REQUIRE(same_bits(whole, pieces));
    }
    for (Scheme scheme : {Scheme::linear, Scheme::butterfly, Scheme::loop})
      for (bool update : {false, true}) {
        const WaveletOptions options{scheme, update};
        std::vector<double> separate = values, inside = values;
        for (int j = 0; j < 3; ++j) {
          frames::rotate_details(h, j, separate, separate, 3, frames::Direction::to_global);
          synthesize_level(h, options, j, separate, 3);
          const frames::LevelFrames level_frames(h, j, inside, 3);
          const std::uint32_t first_odd = h.vertex_count(j);
          std::vector<int> seen(h.vertex_count(j + 1) - first_odd, 0);
          synthesize_level(h, options, j, inside, 3, [&](std::uint32_t first, std::uint32_t count) {
            REQUIRE(first >= first_odd);
            REQUIRE(first + count <= h.vertex_count(j + 1));
            for (std::uint32_t v = first; v < first + count; ++v) ++seen[v - first_odd];
            level_frames.rotate(first - first_odd, first - first_odd + count, inside, frames::Direction::to_global);
          });
          for (const int s : seen) REQUIRE(s == 1);
        }
        INFO("scheme " << to_string(scheme) << ", update " << update);
        REQUIRE(same_bits(separate, inside));
      }
  }
}

TEST_CASE("the encoder's level weights are the norms of full impulse syntheses, as floats bit for bit", "[codec]") {
  for (const TriangleMesh& base : {test::icosahedron(), test::grid(4), test::disk(5), test::bicone(3)}) {
    for (int levels : {1, 3}) {
      const SemiRegularMesh mesh = canonical_order(refine_linear(base, levels));
      const SemiRegularHierarchy& h = mesh.hierarchy;
      for (Scheme scheme : {Scheme::linear, Scheme::butterfly, Scheme::loop})
        for (bool update : {false, true}) {
          EncodeOptions options;
          options.scheme = scheme;
          options.mean_preserving_update = update;
          options.local_frames = false;
          const StreamInfo info = inspect(encode(mesh, options));
          REQUIRE(info.level_weights.size() == static_cast<std::size_t>(levels) + 1);
          const WaveletTransform transform(h, {scheme, update && scheme != Scheme::loop});
          for (int j = 0; j <= levels; ++j) {
            std::vector<double> impulse(h.vertex_count(levels), 0.0);
            const std::uint32_t begin = j == 0 ? 0 : h.vertex_count(j - 1);
            impulse[begin + (h.vertex_count(j) - begin) / 2] = 1.0;
            transform.synthesize(impulse, 1);
            double sum = 0.0;
            for (const double x : impulse) sum += x * x;
            INFO("scheme " << to_string(scheme) << ", update " << update << ", levels " << levels << ", level " << j);
            // The header holds the norm rounded to a float (FORMAT.md §3).
            const double expected = static_cast<double>(static_cast<float>(std::sqrt(sum)));
            REQUIRE(std::memcmp(&info.level_weights[static_cast<std::size_t>(j)], &expected, sizeof expected) == 0);
          }
        }
    }
  }
}
