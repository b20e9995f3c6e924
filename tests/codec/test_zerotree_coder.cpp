// The coefficient coder's prefix decodes against the magnitudes it coded (zerotree_coder.h):
// at every cut of the stream, each coefficient the decoder lists is known exactly down to the
// plane it reports, and what a plane has decided before the cut shows in that decode.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cstdint>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <vector>

#include "../../codec/zerotree_coder.h"
#include "meshlift/range_coder.h"
#include "meshlift/semi_regular.h"
#include "test_meshes.h"

using namespace meshlift;

TEST_CASE("zerotree: an encode told to stop after some bytes codes fewer planes, its first bytes the whole stream's",
          "[codec][zerotree]") {
  const SemiRegularMesh mesh = refine_linear(test::icosahedron(), 6);
  const zerotree::Forest forest(mesh.hierarchy);
  zerotree::Quantized q;
  q.allocate(std::size_t{forest.vertex_count()} * 3);
  std::mt19937 rng(7);
  std::geometric_distribution<std::uint32_t> magnitude(0.002);
  for (std::size_t i = 0; i < q.size; ++i) q.coefficients[i] = {magnitude(rng), (rng() & 1) != 0, 0, 0};
  const int top = zerotree::top_plane(q);
  auto coded = [&](bool concurrent, std::size_t stop_after, bool& complete) {
    zerotree::Quantized copy;  // encode() fills in the widths
    copy.allocate(q.size);
    std::copy_n(q.coefficients.get(), q.size, copy.coefficients.get());
    RangeEncoder encoder;
    complete = zerotree::encode(forest, copy, top, top + 1, encoder, concurrent, stop_after);
    return encoder.finish();
  };
  bool complete = false;
  const std::vector<std::uint8_t> whole = coded(false, std::numeric_limits<std::size_t>::max(), complete);
  CHECK(complete);
  REQUIRE(whole.size() > 100000);
  for (const bool concurrent : {false, true}) {
    for (const std::size_t stop_after : {std::size_t{0}, std::size_t{1000}, whole.size() / 2}) {
      INFO((concurrent ? "two threads" : "one thread") << ", stop after " << stop_after << " of " << whole.size());
      const std::vector<std::uint8_t> part = coded(concurrent, stop_after, complete);
      CHECK_FALSE(complete);
      CHECK(part.size() > stop_after);
      // Far short of the whole: both stop at the byte (on two threads the coding thread checks
      // before each decision it codes, the other thread's too).
      CHECK(part.size() < stop_after + 16);
      REQUIRE(part.size() <= whole.size());
      CHECK(std::equal(part.begin(), part.begin() + static_cast<std::ptrdiff_t>(stop_after), whole.begin()));
    }
    const std::vector<std::uint8_t> all = coded(concurrent, whole.size(), complete);
    CHECK(complete);
    CHECK(all == whole);
  }
}

TEST_CASE("zerotree: every prefix decode lists coefficients known exactly down to the plane it reports",
          "[codec][zerotree]") {
  const SemiRegularMesh mesh = refine_linear(test::icosahedron(), 3);
  const zerotree::Forest forest(mesh.hierarchy);
  for (const int K : {1, 3})
    for (const bool base_part : {false, true}) {
      zerotree::Quantized q;
      q.components = K;
      q.allocate(std::size_t{forest.vertex_count()} * static_cast<std::size_t>(K));
      std::mt19937 rng(3);
      std::geometric_distribution<std::uint32_t> magnitude(0.02);
      for (std::size_t i = 0; i < q.size; ++i) q.coefficients[i] = {magnitude(rng), (rng() & 1) != 0, 0, 0};
      const int top = zerotree::top_plane(q);
      REQUIRE(top >= 6);
      const int base_plane = base_part ? top - 2 : top + 1;
      INFO(K << " components, base plane " << base_plane << " of top plane " << top);
      // The base part's values (base_values.h codes them; here they are handed over as decoded).
      std::vector<std::int64_t> base_high;
      if (base_part)
        for (std::size_t i = 0; i < std::size_t{forest.roots} * static_cast<std::size_t>(K); ++i) {
          const auto high = static_cast<std::int64_t>(q.coefficients[i].magnitude >> base_plane);
          base_high.push_back(q.coefficients[i].negative ? -high : high);
        }
      zerotree::Quantized coded;  // a copy: encode() fills in its widths
      coded.components = K;
      coded.allocate(q.size);
      std::copy_n(q.coefficients.get(), q.size, coded.coefficients.get());
      RangeEncoder encoder;
      zerotree::encode(forest, coded, top, base_plane, encoder);
      const std::vector<std::uint8_t> bytes = encoder.finish();

      std::map<int, std::set<std::size_t>> listed_at;  // per last plane, the counts listed at its cuts
      for (std::size_t cut = 5; cut <= bytes.size(); cut += 1 + cut / 64) {
        RangeDecoder decoder(std::span<const std::uint8_t>(bytes).first(cut));
        const zerotree::Decoded d = zerotree::decode(forest, K, top, base_plane, base_high, decoder);
        std::size_t listed = 0, wrong = 0;
        d.for_each([&](const zerotree::Decoded::Coefficient& x) {
          const auto& truth = q.coefficients[std::size_t{x.vertex} * static_cast<std::size_t>(K) +
                                             static_cast<std::size_t>(x.component)];
          ++listed;
          // The sign, and the bits above the low plane: no more, no fewer.
          wrong += truth.negative != x.negative || x.known != (truth.magnitude >> x.low_plane) << x.low_plane;
        });
        INFO(cut << " of " << bytes.size() << " bytes, last plane " << d.last_plane);
        REQUIRE(wrong == 0);
        // Every coefficient significant at a plane above the last one is listed.
        std::size_t above = 0;
        for (std::size_t i = 0; i < q.size; ++i) above += (q.coefficients[i].magnitude >> (d.last_plane + 1)) != 0;
        REQUIRE(listed >= above);
        if (cut == bytes.size()) CHECK((d.complete && d.last_plane == 0 && listed == q.size - std::count_if(
                                            q.coefficients.get(), q.coefficients.get() + q.size,
                                            [](const auto& c) { return c.magnitude == 0; })));
        listed_at[d.last_plane].insert(listed);
      }
      // The coefficients a plane finds significant are listed from the decision on, not only
      // once the plane (or its component) is done: the cuts inside the planes see many counts.
      std::size_t counts = 0;
      for (const auto& [plane, seen] : listed_at) counts += seen.size();
      INFO(counts << " counts over " << listed_at.size() << " planes");
      CHECK(counts > 4 * static_cast<std::size_t>(K) * listed_at.size());
    }
}
