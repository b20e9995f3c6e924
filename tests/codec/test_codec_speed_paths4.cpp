// The encoder without the transform's tables (issue 3's encode speed): analyze_level() against
// the tables' analysis, and stencils::LevelRows (rows read one at a time by target) against the
// tables' rows and the levels' own incident edges, over bases with extraordinary vertices, boundaries and a two-face pillow.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>
#include <vector>

#include "../../codec/stencils.h"
#include "decode_results.h"
#include "lifting_rows.h"
#include "meshlift/lifting.h"
#include "test_meshes.h"

using namespace meshlift;

namespace {

using test::same_bits;
using test::topology_of;

std::vector<TriangleMesh> bases() {
  const TriangleMesh pillow{{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2, 0, 2, 1}};
  const TriangleMesh open_fan{{0, 0, 0, 1, 0, 0, 0.5, 0.8, 0, -0.5, 0.8, 0, -1, 0, 0, -0.5, -0.8, 0, 0.5, -0.8, 0},
                              {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5, 0, 5, 6}};
  return {test::icosahedron(), test::grid(4), test::disk(5), test::bicone(3), test::bicone(4), test::torus(), pillow, open_fan};
}

}  // namespace

TEST_CASE("analyze_level and synthesize_level are the tables' analysis and synthesis level by level, bit for bit", "[lifting]") {
  constexpr int L = 3;
  for (const TriangleMesh& base : bases()) {
    const SemiRegularHierarchy h(topology_of(base), L);
    for (const Scheme scheme : {Scheme::linear, Scheme::butterfly, Scheme::loop})
      for (const bool update : {false, true}) {
        const WaveletOptions options{scheme, update};
        const WaveletTransform tables(h, options);
        for (const int channels : {1, 3, 4})
          for (const bool concurrent : {false, true}) {
            const std::vector<double> input = test::random_values(std::size_t{h.vertex_count(L)} * channels, 7);
            std::vector<double> expected = input, level_by_level = input, weights_given = input;
            tables.analyze(expected, channels);
            for (int j = L - 1; j >= 0; --j) {
              analyze_level(h, options, j, level_by_level, channels, concurrent);
              // The update's weights handed over, as the encoder makes them once for both directions.
              std::vector<double> weights;
              if (update && scheme != Scheme::loop) weights = update_weights(h, scheme, j);
              analyze_level(h, options, j, weights_given, channels, concurrent, weights);
            }
            INFO(to_string(scheme) << (update ? " with the update" : "") << ", " << h.vertex_count(0)
                                   << " base vertices, " << channels << " channels" << (concurrent ? ", two threads" : ""));
            REQUIRE(same_bits(level_by_level, expected));
            REQUIRE(same_bits(weights_given, expected));
            // And synthesize_level from the same values: the tables' synthesis, bit for bit.
            std::vector<double> by_tables = input, synthesized = input;
            tables.synthesize(by_tables, channels);
            for (int j = 0; j < L; ++j) synthesize_level(h, options, j, synthesized, channels, {}, concurrent);
            REQUIRE(same_bits(synthesized, by_tables));
            // And it is the inverse of synthesize_level, to rounding (amplified by the pillow's
            // valence-2 vertices under Loop).
            for (int j = 0; j < L; ++j) synthesize_level(h, options, j, level_by_level, channels);
            for (std::size_t i = 0; i < input.size(); ++i) REQUIRE(std::abs(level_by_level[i] - input[i]) < 1e-9);
          }
      }
    std::vector<double> values(std::size_t{h.vertex_count(L)} * 3);
    CHECK_THROWS_AS(analyze_level(h, {}, L, values), std::invalid_argument);
    CHECK_THROWS_AS(analyze_level(h, {}, -1, values), std::invalid_argument);
    values.resize(values.size() - 1);
    CHECK_THROWS_AS(analyze_level(h, {}, L - 1, values), std::invalid_argument);
    std::vector<double> enough(std::size_t{h.vertex_count(L)} * 3), short_weights(1);
    CHECK_THROWS_AS(analyze_level(h, {Scheme::butterfly, true}, 1, enough, 3, false, short_weights), std::invalid_argument);
  }
}

TEST_CASE("LevelRows reads every row of every step as its table holds it, and the incident edges", "[lifting]") {
  constexpr int L = 3;
  for (const TriangleMesh& base : bases()) {
    const SemiRegularHierarchy h(topology_of(base), L);
    // Read off the whole hierarchy, and off one without the topology of the level below the
    // finest (the encoder's and the decoder's), whose rows and edges come from the level below.
    const SemiRegularHierarchy lean(topology_of(base), L, false, false, false);
    REQUIRE_FALSE(lean.has_topology(L - 1));
    for (const SemiRegularHierarchy* read : {&h, &lean})
    for (const Scheme scheme : {Scheme::linear, Scheme::butterfly, Scheme::loop})
      for (const bool update : {false, true}) {
        const WaveletOptions options{scheme, update};
        const WaveletTransform tables(h, options);
        std::vector<std::vector<double>> weights(L);
        std::vector<std::unique_ptr<stencils::LevelRows>> levels;
        for (int j = 0; j < L; ++j) {
          if (update && scheme != Scheme::loop && j > 0) weights[j] = update_weights(h, scheme, j);
          levels.push_back(
              std::make_unique<stencils::LevelRows>(*read, options, j, j > 0 ? levels.back().get() : nullptr, weights[j]));
          stencils::LevelRows& rows = *levels.back();
          const std::vector<LiftingStep>& steps = tables.steps(j);
          INFO(to_string(scheme) << (update ? " with the update" : "") << ", " << h.vertex_count(0) << " base vertices, level "
                                 << j << (read == &lean ? ", without the topology below the finest" : ""));
          // The incident edges derived from the level below are the level's own, in order, and
          // so are the edges' ends.
          const VertexEdges edges(h.topology(j));
          std::vector<std::uint32_t> incident;
          for (std::uint32_t v = 0; v < h.vertex_count(j); ++v) {
            const bool boundary = rows.incident_edges(v, incident);
            REQUIRE(incident == std::vector<std::uint32_t>(edges.edges.begin() + edges.offsets[v],
                                                           edges.edges.begin() + edges.offsets[v + 1]));
            REQUIRE(boundary == (edges.boundary[v] != 0));
          }
          for (std::uint32_t e = 0; e < h.topology(j).edge_count(); ++e) {
            std::uint32_t a = 0, b = 0;
            rows.edge_ends(e, a, b);
            REQUIRE(a == h.topology(j).edge_vertices[2 * e]);
            REQUIRE(b == h.topology(j).edge_vertices[2 * e + 1]);
          }
          REQUIRE(rows.steps().size() == steps.size());
          for (std::size_t s = 0; s < steps.size(); ++s) {
            REQUIRE(rows.steps()[s].first_target == steps[s].first_target);
            REQUIRE(rows.steps()[s].rows == steps[s].row_count);
            // Rows read in an order other than the table's (last first), as the encoder reads a few.
            const std::vector<std::vector<double>> expected = test::expand_rows(steps[s]);
            for (std::size_t k = expected.size(); k-- > 0;) {
              const auto target = static_cast<std::uint32_t>(expected[k][0]);
              const stencils::LevelRows::Row row = rows.row(s, target);
              std::vector<double> read{static_cast<double>(target), row.scale};
              REQUIRE(row.sources.size() == row.weights.size());
              for (std::size_t i = 0; i < row.sources.size(); ++i) {
                read.push_back(row.sources[i]);
                read.push_back(row.weights[i]);
              }
              REQUIRE(read.size() == expected[k].size());
              REQUIRE(std::memcmp(read.data(), expected[k].data(), read.size() * sizeof(double)) == 0);
            }
          }
        }
      }
  }
}

TEST_CASE("butterfly's column sums read near irregular vertices only are the table's, bit for bit, on deep levels",
          "[lifting]") {
  // Deep enough that most vertices lie far from every extraordinary and boundary vertex (their sum
  // is taken as 3), and the ones near them are summed from their rows: on a closed mesh with
  // valence-5 vertices, an open grid, a disk around a valence-5 centre, a valence-3 bicone and
  // a torus with no irregular vertex at all.
  for (const TriangleMesh& base : {test::icosahedron(), test::grid(4), test::disk(5), test::bicone(3), test::torus()}) {
    constexpr int L = 5;
    const SemiRegularHierarchy h(topology_of(base), L);
    for (int j = 1; j < L; ++j) {
      std::vector<double> sums(h.vertex_count(j), 0.0), expected(h.vertex_count(j), 0.0);
      stencils::add_column_sums(stencils::predict(h.topology(j), Scheme::butterfly), expected);
      stencils::RefinedPredictRows(h.topology(j - 1), Scheme::butterfly).add_column_sums(sums);
      INFO(h.vertex_count(0) << " base vertices, level " << j << ", " << std::count(expected.begin(), expected.end(), 3.0)
                             << " sums of 3 of " << expected.size());
      REQUIRE(same_bits(sums, expected));
    }
  }
}
