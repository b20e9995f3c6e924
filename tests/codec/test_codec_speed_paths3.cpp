// The codec's fast paths of issue 3's fourth round against the plain computations they replace,
// bit for bit: the local frames' test for an edge along the normal without its square root
// against FORMAT.md §3's formula; the decoder's normals reusing one array across levels;
// decode_into, reusing its caller's arrays, against decode(); the encoder's quantizer four
// coefficients at a time against FORMAT.md §5's formulas one by one.
#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "../../codec/canonical_order.h"
#include "../../codec/concurrent.h"
#include "../../codec/local_frames.h"
#include "../../codec/quantize.h"
#include "../../codec/zerotree_coder.h"
#include "meshlift/codec.h"
#include "meshlift/lifting.h"
#include "decode_results.h"
#include "test_meshes.h"

using namespace meshlift;

namespace {

using test::same_bits;
using test::same_result;

/// FORMAT.md §3: the edge is (nearly) along the normal when !(|t1| > 1e-12 |edge|).
bool spec_along_normal(double t1_length, double edge_squared) { return !(t1_length > 1e-12 * std::sqrt(edge_squared)); }

/// A semi-regular mesh with detail at every level and two channels, in canonical order.
SemiRegularMesh mesh_with_channels(int levels) {
  SemiRegularMesh m = refine_linear(test::icosahedron(), levels);
  const std::vector<double> noise = test::random_values(m.positions.size(), 4);
  for (std::size_t i = 0; i < m.positions.size(); ++i) m.positions[i] *= 1 + 0.05 * noise[i];
  VertexChannel scalar{1, {}}, colour{3, {}};
  for (std::size_t v = 0; v < m.positions.size() / 3; ++v) {
    scalar.values.push_back(std::sin(3 * m.positions[3 * v]));
    for (int k = 0; k < 3; ++k) colour.values.push_back(std::cos(2 * m.positions[3 * v + k]));
  }
  m.channels = {scalar, colour};
  return canonical_order(m);
}

/// `channels` values for each of `vertices` vertices, vertex-major: `noise` first, then 0.25 (what
/// the syntheses on one and two threads start from).
std::vector<double> channel_values(const std::vector<double>& noise, std::uint32_t vertices, int channels) {
  std::vector<double> values(noise.begin(), noise.end());
  values.resize(std::size_t{vertices} * static_cast<std::size_t>(channels), 0.25);
  return values;
}

}  // namespace

TEST_CASE("the edge-along-normal test without its square root decides as FORMAT.md's formula", "[frames]") {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> exponent(-330, 330), unit(0, 1);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  const double denormal = std::numeric_limits<double>::denorm_min(), largest = std::numeric_limits<double>::max();
  int near = 0, along = 0;
  auto check = [&](double t1_length, double edge_squared) {
    INFO("|t1| " << t1_length << ", edge . edge " << edge_squared);
    const bool expected = spec_along_normal(t1_length, edge_squared);
    REQUIRE(frames::edge_along_normal(t1_length, edge_squared) == expected);
    along += expected;
  };
  // Specials: zeros, denormals, the largest double, infinities, NaN, on both sides.
  for (double t : {0.0, denormal, 1e-300, 1e-162, 1e-12, 1.0, 1e154, largest, inf, nan})
    for (double e : {0.0, denormal, 1e-320, 1e-300, 1e-200, 1e-199, 1.0, 1e300, largest, inf, nan}) check(t, e);
  // At the threshold: |t1| within a few ulps of the spec's 1e-12 * sqrt(edge . edge), where only
  // the exact path decides, over the whole exponent range (the fast path must never answer there).
  for (int i = 0; i < 200000; ++i) {
    const double edge_squared = std::pow(10.0, exponent(rng)) * (1 + unit(rng));
    double t1_length = 1e-12 * std::sqrt(edge_squared);
    const int ulps = static_cast<int>(rng() % 9) - 4;
    for (int k = 0; k < std::abs(ulps); ++k) t1_length = std::nextafter(t1_length, ulps > 0 ? inf : 0.0);
    near += std::abs(ulps) <= 1;
    check(t1_length, edge_squared);
    // Around twice the threshold, where the fast path's own comparison decides.
    check(2 * t1_length, edge_squared);
    check(std::nextafter(2 * t1_length, 0.0), edge_squared);
    check(std::nextafter(2 * t1_length, inf), edge_squared);
  }
  // Ordinary edges of all proportions.
  for (int i = 0; i < 200000; ++i) check(std::pow(10.0, exponent(rng)), std::pow(10.0, exponent(rng)));
  REQUIRE(near > 10000);
  REQUIRE(along > 1000);  // both answers were exercised near the threshold
}

TEST_CASE("frames with one normals array reused level after level give the bits of fresh arrays", "[frames]") {
  // Levels of growing and shrinking size in one array: each LevelFrames must start its normals
  // from zero, whatever the array held before.
  const TriangleMesh base = test::icosahedron();
  const SemiRegularHierarchy h(TriangleTopology::build(static_cast<std::uint32_t>(base.vertex_count()), base.triangles), 3);
  const std::vector<double> values = test::random_values(std::size_t{h.vertex_count(3)} * 4, 3);
  std::vector<frames::Vec3> storage;
  for (int level : {2, 0, 1, 2, 1}) {
    std::vector<double> fresh = values, reused = values;
    frames::rotate_details(h, level, values, fresh, 4, frames::Direction::to_global);
    frames::LevelFrames level_frames(h, level, values, 4, std::move(storage));
    level_frames.rotate(0, level_frames.edge_count(), reused, frames::Direction::to_global);
    storage = std::move(level_frames).release_storage();
    INFO("level " << level);
    REQUIRE(std::memcmp(fresh.data(), reused.data(), fresh.size() * sizeof(double)) == 0);
    REQUIRE(fresh != values);  // the details did turn
  }
}

TEST_CASE("decode_into reusing one result gives decode()'s bits for any prefix, level and order of calls", "[codec]") {
  const SemiRegularMesh with_channels = mesh_with_channels(4);
  const SemiRegularMesh plain = [&] {
    SemiRegularMesh m = with_channels;
    m.channels.clear();
    return m;
  }();
  for (const SemiRegularMesh* mesh : {&plain, &with_channels})
    for (Scheme scheme : {Scheme::loop, Scheme::butterfly})
      for (bool local_frames : {true, false}) {
        EncodeOptions e;
        e.scheme = scheme;
        e.local_frames = local_frames;
        const std::vector<std::uint8_t> file = encode(*mesh, e);
        // Growing prefixes as a viewer sees them, then shrinking ones, level limits, and cuts that
        // do not decode (inside the header, before the base is complete) in between.
        std::vector<std::pair<std::size_t, int>> calls;
        for (std::size_t bytes : {std::size_t{5}, file.size() / 8, file.size() / 4, file.size() / 2, file.size()})
          calls.emplace_back(bytes, -1);
        for (std::size_t bytes : {file.size(), file.size() / 3, std::size_t{20}, file.size() / 2, file.size()})
          for (int level : {2, 0, -1}) calls.emplace_back(bytes, level);
        DecodeResult reused;
        const double* storage = nullptr;
        for (const auto& [bytes, level] : calls) {
          DecodeOptions o;
          o.max_bytes = bytes;
          o.max_level = level;
          const DecodeResult expected = decode(file, o);
          decode_into(file, o, reused);
          INFO("scheme " << to_string(scheme) << ", frames " << local_frames << ", channels " << mesh->channels.size()
                         << ", " << bytes << " of " << file.size() << " bytes, level " << level);
          REQUIRE(same_result(reused, expected));
          if (expected.status != Status::ok) REQUIRE(reused.mesh.positions.empty());
          // After the first whole decode, every later one fits in its storage: no new arrays.
          if (storage != nullptr) REQUIRE(reused.mesh.positions.data() == storage);
          if (bytes == file.size() && level == -1 && expected.status == Status::ok) storage = reused.mesh.positions.data();
        }
        REQUIRE(storage != nullptr);
        // The streaming decoder's form of it.
        Decoder decoder;
        DecodeResult streamed;
        for (std::size_t at = 0; at < file.size(); at += file.size() / 3 + 1) {
          decoder.push(std::span(file).subspan(at, std::min(file.size() - at, file.size() / 3 + 1)));
          decoder.mesh(streamed);
          REQUIRE(same_result(streamed, decoder.mesh()));
        }
      }
}

TEST_CASE("the quantizer four coefficients at a time gives the bits of FORMAT.md's formulas one by one", "[codec]") {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> exponent(-40, 40), unit(-1, 1);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  for (int components : {1, 3, 4, 7})
    for (std::size_t vertices : {std::size_t{1}, std::size_t{5}, std::size_t{64}, std::size_t{333}})
      for (int variant = 0; variant < 3; ++variant) {
        const std::size_t n = vertices * static_cast<std::size_t>(components);
        std::vector<double> steps;
        for (int c = 0; c < components; ++c) steps.push_back(std::ldexp(1.0 + 0.37 * c, -10 + c));
        const double weight = variant == 2 ? 3.0e9 : 1.7;
        std::vector<double> x(n);
        for (std::size_t i = 0; i < n; ++i) {
          x[i] = unit(rng) * std::pow(2.0, exponent(rng));
          // Zeros of both signs, values on the dead zone's edge and at 2^31 - 1 and 2^31 steps,
          // infinities and NaN (which the encoder never hands over, but then no bits differ).
          switch (rng() % 12) {
            case 0: x[i] = 0.0; break;
            case 1: x[i] = -0.0; break;
            case 2: x[i] = (rng() % 2 ? -1 : 1) * steps[i % static_cast<std::size_t>(components)] / weight; break;
            case 3: x[i] = -2147483647.0 * steps[i % static_cast<std::size_t>(components)] / weight; break;
            case 4: x[i] = 2147483648.0 * steps[i % static_cast<std::size_t>(components)] / weight; break;
            case 5: x[i] = variant == 1 ? (rng() % 2 ? inf : nan) : x[i]; break;
            default: break;
          }
        }
        using Coefficient = zerotree::Quantized::Coefficient;
        std::vector<Coefficient> out(n, Coefficient{7, true, 7, 7});
        std::vector<std::uint32_t> expected_magnitude(n);
        std::vector<std::uint8_t> expected_negative(n);
        std::vector<double> reconstruction(n, 7.0), expected_reconstruction(n);
        bool expected_too_fine = false;
        for (std::size_t i = 0; i < n; ++i) {
          const double step = steps[i % static_cast<std::size_t>(components)];
          const double scaled = std::abs(x[i]) * weight / step;
          expected_too_fine |= scaled >= 2147483648.0;
          expected_magnitude[i] = scaled < 2147483647.0 ? static_cast<std::uint32_t>(scaled) : scaled >= 2147483647.0 ? 2147483647u : 0u;
          expected_negative[i] = x[i] < 0 && expected_magnitude[i] > 0;
          expected_reconstruction[i] = zerotree::dequantize(
              zerotree::Decoded::midpoint(expected_magnitude[i], 0, expected_negative[i] != 0), step, weight);
        }
        auto same_records = [&] {
          for (std::size_t i = 0; i < n; ++i)
            if (out[i].magnitude != expected_magnitude[i] || out[i].negative != (expected_negative[i] != 0) ||
                out[i].descendants_width != 0 || out[i].grandchildren_width != 0)
              return false;
          return true;
        };
        INFO(components << " components, " << vertices << " vertices, variant " << variant);
        const bool too_fine = quantize(x.data(), n, components, steps.data(), weight, out.data(), reconstruction.data());
        REQUIRE(too_fine == expected_too_fine);
        REQUIRE(same_records());
        REQUIRE(same_bits(reconstruction, expected_reconstruction));
        // In place, as the encoder's closed loop calls it, and without a reconstruction.
        std::vector<double> in_place = x;
        quantize(in_place.data(), n, components, steps.data(), weight, out.data(), in_place.data());
        REQUIRE(same_bits(in_place, expected_reconstruction));
        std::fill(out.begin(), out.end(), Coefficient{7, true, 7, 7});
        REQUIRE(quantize(x.data(), n, components, steps.data(), weight, out.data(), nullptr) == expected_too_fine);
        REQUIRE(same_records());
      }
}

namespace {

/// `base` with its vertices numbered backwards: not the base coder's traversal order.
TriangleMesh backwards(const TriangleMesh& base) {
  const std::uint32_t n = static_cast<std::uint32_t>(base.positions.size() / 3);
  TriangleMesh out = base;
  for (std::uint32_t v = 0; v < n; ++v)
    for (int k = 0; k < 3; ++k) out.positions[3 * (n - 1 - v) + k] = base.positions[3 * v + k];
  for (std::uint32_t& v : out.triangles) v = n - 1 - v;
  return out;
}

}  // namespace

TEST_CASE("the encoder writes the same bytes on 1 and 2 threads, and from a mesh in canonical order already", "[codec]") {
  // Channels, a boundary, and each scheme with and without local frames (the closed loop's two
  // halves of each level's edges run side by side on 2 threads).
  SemiRegularMesh given = refine_linear(backwards(test::disk(7)), 3);
  const std::vector<double> noise = test::random_values(given.positions.size(), 9);
  for (std::size_t i = 0; i < given.positions.size(); ++i) given.positions[i] += 0.01 * noise[i];
  VertexChannel scalar{1, {}};
  for (std::size_t v = 0; v < given.positions.size() / 3; ++v) scalar.values.push_back(std::sin(5 * given.positions[3 * v]));
  given.channels = {scalar};
  const SemiRegularMesh ordered = canonical_order(given);
  REQUIRE_FALSE(is_canonical(given));  // else the two inputs would take the same path
  REQUIRE(is_canonical(ordered));
  REQUIRE(is_canonical(mesh_with_channels(2)));
  for (const Scheme scheme : {Scheme::linear, Scheme::butterfly, Scheme::loop}) {
    for (const bool frames : {false, true}) {
      INFO("scheme " << static_cast<int>(scheme) << ", frames " << frames);
      EncodeOptions o;
      o.scheme = scheme;
      o.local_frames = frames;
      o.threads = 1;
      const std::vector<std::uint8_t> reference = encode(given, o);
      CHECK(encode(ordered, o) == reference);
      o.threads = 2;
      CHECK(encode(given, o) == reference);
      CHECK(encode(ordered, o) == reference);
      o.threads = 0;
      CHECK(encode(ordered, o) == reference);
    }
  }
  // A precision too fine for a few finest details alone is refused, on either thread count: the
  // mesh in a speck at the centre but for a few of the finest level's odd vertices, spread over
  // the box, first the level's first ones, then its last ones (in the closed loop's first and
  // its second half of the level's edges, the vertices' order being the canonical one).
  const SemiRegularMesh icosahedron3 = canonical_order(refine_linear(test::icosahedron(), 3));
  const std::uint32_t finest_odd = icosahedron3.hierarchy.vertex_count(2), V = icosahedron3.hierarchy.vertex_count(3);
  // Butterfly without its update step: the base values are the speck's own, whatever the details.
  // The four spread vertices at opposite corners of [-1, 1]^3, so the box is centred on the speck.
  const double corners[4][3] = {{1, 1, 1}, {-1, -1, -1}, {1, -1, 1}, {-1, 1, -1}};
  for (const std::uint32_t first_spread : {finest_odd, V - 4}) {
    SemiRegularMesh speck = icosahedron3;
    for (std::size_t i = 0; i < speck.positions.size(); ++i) {
      const std::size_t v = i / 3;
      speck.positions[i] = v >= first_spread && v < first_spread + 4 ? corners[v - first_spread][i % 3]
                                                                     : 1e-6 * speck.positions[i];
    }
    for (const bool frames : {false, true}) {
      EncodeOptions fine;
      fine.scheme = Scheme::butterfly;
      fine.mean_preserving_update = false;  // no update step (see above)
      fine.local_frames = frames;
      fine.precision_bits = 34;  // details of ~the diagonal pass 2^31 steps; the speck's do not
      for (const unsigned threads : {1u, 2u}) {
        INFO("spread from vertex " << first_spread << ", frames " << frames << ", threads " << threads);
        fine.threads = threads;
        CHECK_THROWS_WITH(encode(speck, fine), Catch::Contains("too fine"));
      }
      fine.precision_bits = 24;
      CHECK_NOTHROW(encode(speck, fine));
    }
  }
}

TEST_CASE("a flat mesh of signed zeros encodes as its canonical order does", "[codec]") {
  // Every z and every channel value a zero, +0 at the input's first vertex and -0 elsewhere: the
  // extremes are taken in the input's order, but the centre's sign must be the one a pass in
  // canonical order gives (that of canonical vertex 0's zero), or the two inputs' headers differ.
  TriangleMesh base = test::disk(7);
  for (std::size_t v = 0; v < base.positions.size() / 3; ++v) base.positions[3 * v + 2] = 0.0;
  SemiRegularMesh given = refine_linear(backwards(base), 2);
  VertexChannel zeros{2, std::vector<double>(2 * given.positions.size() / 3, -0.0)};
  for (std::size_t v = 0; v < given.positions.size() / 3; ++v) given.positions[3 * v + 2] = v == 0 ? 0.0 : -0.0;
  zeros.values[0] = zeros.values[1] = 0.0;
  given.channels = {zeros};
  const SemiRegularMesh ordered = canonical_order(given);
  REQUIRE_FALSE(is_canonical(given));
  REQUIRE(std::signbit(ordered.positions[2]));  // canonical vertex 0 is not the input's first
  for (const unsigned threads : {1u, 2u}) {
    EncodeOptions o;
    o.threads = threads;
    CHECK(encode(given, o) == encode(ordered, o));
  }
}

TEST_CASE("a mesh in another order than the canonical one is never taken for canonical", "[codec]") {
  const SemiRegularMesh ordered = canonical_order(refine_linear(test::torus(), 2));
  REQUIRE(is_canonical(ordered));
  const std::vector<std::uint8_t> reference = encode(ordered, {});
  const std::vector<std::uint32_t>& faces = ordered.hierarchy.triangles(0);
  const std::uint32_t V0 = ordered.hierarchy.vertex_count(0);
  auto with_base = [&](TriangleTopology base) {
    SemiRegularMesh m{SemiRegularHierarchy(std::move(base), ordered.hierarchy.levels()), ordered.positions, {}};
    return m;
  };
  // The same labels, two faces swapped: the finer levels are numbered from the faces, so the
  // positions (given in the canonical order) no longer match; only the flag is checked here.
  std::vector<std::uint32_t> swapped = faces;
  std::swap_ranges(swapped.begin(), swapped.begin() + 3, swapped.begin() + 3);
  CHECK_FALSE(is_canonical(with_base(TriangleTopology::build(V0, swapped))));
  // The same faces, the first one's corners turned.
  std::vector<std::uint32_t> turned = faces;
  std::rotate(turned.begin(), turned.begin() + 1, turned.begin() + 3);
  CHECK_FALSE(is_canonical(with_base(TriangleTopology::build(V0, turned))));
  // The same faces and labels, the base's first two edges numbered the other way round: the
  // finer levels' vertices follow the edge numbering, so this is another order as well.
  TriangleTopology renumbered = TriangleTopology::build(V0, faces);
  const std::uint32_t e0 = 0, e1 = 1;
  for (int k = 0; k < 2; ++k) {
    std::swap(renumbered.edge_vertices[2 * e0 + k], renumbered.edge_vertices[2 * e1 + k]);
    std::swap(renumbered.edge_faces[2 * e0 + k], renumbered.edge_faces[2 * e1 + k]);
  }
  for (std::uint32_t& e : renumbered.face_edges) e = e == e0 ? e1 : e == e1 ? e0 : e;
  const SemiRegularMesh other = with_base(renumbered);
  CHECK_FALSE(is_canonical(other));
  // Encoded through the canonical hierarchy, it gives the bytes of its canonical order.
  CHECK(encode(other, {}) == encode(canonical_order(other), {}));
  CHECK(encode(ordered, {}) == reference);
}

TEST_CASE("run_both hands a throw on either thread to the caller, after both have ended", "[codec]") {
  for (const bool concurrent : {false, true}) {
    int ran = 0;
    CHECK_THROWS_WITH(run_both(
                          concurrent, [&] { throw std::runtime_error("first"); }, [&] { ++ran; }),
                      "first");
    CHECK(ran == 1);
    CHECK_THROWS_WITH(run_both(
                          concurrent, [&] { ++ran; }, [&] { throw std::runtime_error("second"); }),
                      "second");
    CHECK(ran == 2);
    std::atomic<int> both{0};
    run_both(concurrent, [&] { ++both; }, [&] { ++both; });
    CHECK(both == 2);
  }
}

TEST_CASE("synthesis with each large step in two halves on two threads gives the bits of one pass", "[lifting]") {
  // Level 6 -> 7 of the refined icosahedron has 122,880 odd vertices and 40,962 even ones: its
  // predict and update steps are split (from 2^14 rows; one pass below, and without `concurrent`).
  SemiRegularMesh m = refine_linear(test::icosahedron(), 7);
  REQUIRE(m.hierarchy.vertex_count(6) >= (1u << 14));
  const std::vector<double> noise = test::random_values(m.positions.size(), 11);
  for (const WaveletOptions options : {WaveletOptions{Scheme::linear, false}, WaveletOptions{Scheme::linear, true},
                                       WaveletOptions{Scheme::butterfly, false}, WaveletOptions{Scheme::butterfly, true},
                                       WaveletOptions{Scheme::loop, false}}) {
    const WaveletTransform transform(m.hierarchy, options);
    for (const int channels : {1, 3, 5}) {
      INFO("scheme " << static_cast<int>(options.scheme) << ", update " << options.mean_preserving_update << ", "
                     << channels << " channels");
      std::vector<double> one = channel_values(noise, m.hierarchy.vertex_count(7), channels);
      std::vector<double> two = one;
      transform.synthesize(one, channels, -1, 0, false);
      transform.synthesize(two, channels, -1, 0, true);
      CHECK(same_bits(one, two));
    }
  }
}

TEST_CASE("the two-thread encoder's queue of decisions wraps many times and gives the one-thread bytes", "[codec]") {
  // 163,842 vertices with noise at every level: far more decisions than the queue's 8 slots of
  // 32,768 (the file's ~1 MB of bit planes is several million), so the writer waits for the
  // reader again and again; its level 6 (30,720 vertices with children) has its widths filled in
  // two halves.
  SemiRegularMesh m = refine_linear(test::icosahedron(), 7);
  const std::vector<double> noise = test::random_values(m.positions.size(), 12);
  for (std::size_t i = 0; i < m.positions.size(); ++i) m.positions[i] *= 1 + 0.02 * noise[i];
  EncodeOptions o;
  o.scheme = Scheme::butterfly;
  o.mean_preserving_update = false;  // the file the sizes above were measured on
  o.threads = 1;
  const std::vector<std::uint8_t> one = encode(m, o);
  REQUIRE(one.size() > 500000);
  o.threads = 2;
  CHECK(encode(m, o) == one);
  o.threads = 0;  // above kConcurrentEncodeVertices: both cores where there are two
  CHECK(encode(m, o) == one);
}

namespace {

/// Synthesizes level `level` of `one` on one thread and of `two` on two (synthesize_level), and
/// checks that the second hands each odd vertex of the level to before_odd exactly once.
void synthesize_level_both_ways(const SemiRegularHierarchy& h, WaveletOptions options, int level, std::vector<double>& one,
                                std::vector<double>& two, int channels) {
  const std::uint32_t first = h.vertex_count(level), last = h.vertex_count(level + 1);
  std::vector<std::atomic<int>> handed(last - first);
  synthesize_level(h, options, level, one, channels);
  synthesize_level(
      h, options, level, two, channels,
      [&](std::uint32_t begin, std::uint32_t count) {
        for (std::uint32_t v = begin; v < begin + count; ++v) ++handed[v - first];
      },
      true);
  CHECK(std::all_of(handed.begin(), handed.end(), [](const std::atomic<int>& n) { return n == 1; }));
}

}  // namespace

TEST_CASE("synthesize_level on two threads gives the bits of one, and hands each odd vertex over once", "[lifting]") {
  // The block paths split between the threads (Loop above the base; linear and butterfly, with
  // and without the update, whose one before_odd call runs beside its column sums), and Loop's
  // base level, which runs on one whatever is asked; a boundary (the disk) and extraordinary
  // vertices (its centre, the icosahedron's corners); before_odd counted per vertex from both.
  for (const TriangleMesh& base : {test::disk(7), test::icosahedron()}) {
    const SemiRegularMesh m = refine_linear(base, 4);
    const std::vector<double> noise = test::random_values(m.positions.size(), 13);
    for (const WaveletOptions options : {WaveletOptions{Scheme::linear, false}, WaveletOptions{Scheme::butterfly, false},
                                         WaveletOptions{Scheme::linear, true}, WaveletOptions{Scheme::butterfly, true},
                                         WaveletOptions{Scheme::loop, false}}) {
      for (const int channels : {1, 3, 5}) {
        INFO("scheme " << static_cast<int>(options.scheme) << ", update " << options.mean_preserving_update << ", "
                       << channels << " channels");
        std::vector<double> one = channel_values(noise, m.hierarchy.vertex_count(4), channels);
        std::vector<double> two = one;
        for (int level = 0; level < 4; ++level) synthesize_level_both_ways(m.hierarchy, options, level, one, two, channels);
        CHECK(same_bits(one, two));
      }
    }
  }
  // A level large enough that each thread's half takes many blocks (8 Ki rows, 8 Ki chunks of
  // coarse edges and faces: level 6 of the refined icosahedron has 61,440 coarse edges and
  // 40,960 faces), so the second half starts inside a block's worth of rows.
  const SemiRegularMesh large = refine_linear(test::icosahedron(), 7);
  const std::vector<double> large_noise = test::random_values(large.positions.size(), 16);
  for (const WaveletOptions options : {WaveletOptions{Scheme::butterfly, false}, WaveletOptions{Scheme::loop, false},
                                       WaveletOptions{Scheme::linear, false}, WaveletOptions{Scheme::butterfly, true},
                                       WaveletOptions{Scheme::linear, true}}) {
    INFO("large, scheme " << static_cast<int>(options.scheme) << ", update " << options.mean_preserving_update);
    std::vector<double> one(large_noise.begin(), large_noise.end());
    std::vector<double> two = one;
    synthesize_level_both_ways(large.hierarchy, options, 6, one, two, 3);
    CHECK(same_bits(one, two));
  }
}

TEST_CASE("the decoder gives the same mesh on 1 and 2 threads: decode, decode_into and the streaming Decoder", "[codec]") {
  // Each scheme (butterfly also with the mean-preserving update, whose column sums run beside
  // the frames' turning of the details), local frames on and off, a boundary and a channel; the whole file, prefixes
  // that end in the base part and in the bit planes, and a coarser level. Two threads are asked
  // for (threads = 2), so the small mesh is split too; threads = 0 takes one thread below
  // kConcurrentDecodeVertices.
  SemiRegularMesh given = refine_linear(test::disk(7), 3);
  const std::vector<double> noise = test::random_values(given.positions.size(), 14);
  for (std::size_t i = 0; i < given.positions.size(); ++i) given.positions[i] += 0.01 * noise[i];
  VertexChannel scalar{1, {}};
  for (std::size_t v = 0; v < given.positions.size() / 3; ++v) scalar.values.push_back(std::cos(4 * given.positions[3 * v + 1]));
  given.channels = {scalar};
  for (const Scheme scheme : {Scheme::linear, Scheme::butterfly, Scheme::loop}) {
    for (const bool update : {false, true}) {
      if (update && scheme != Scheme::butterfly) continue;
      for (const bool frames : {false, true}) {
        EncodeOptions o;
        o.scheme = scheme;
        o.mean_preserving_update = update;
        o.local_frames = frames;
        const std::vector<std::uint8_t> file = encode(given, o);
        // Cuts in the base part (its middle) and in the bit planes (just after it, and halfway).
        const StreamInfo info = inspect(file);
        const auto coefficients = std::find_if(info.chunks.begin(), info.chunks.end(),
                                               [](const StreamInfo::Chunk& c) { return c.tag == "COEF"; });
        REQUIRE(coefficients != info.chunks.end());
        REQUIRE(info.base_part_bytes >= 12);
        // The payload after the tag and a length of at most 3 bytes (FORMAT.md §2).
        const std::size_t base_part = coefficients->offset + 7, planes = base_part + info.base_part_bytes + 40;
        const std::size_t in_base_part = base_part + info.base_part_bytes / 2;
        REQUIRE(planes < file.size());
        for (const std::size_t bytes : {file.size(), planes, (file.size() + planes) / 2, in_base_part}) {
          for (const int level : {-1, 2}) {
            INFO("scheme " << static_cast<int>(scheme) << ", update " << update << ", frames " << frames << ", "
                           << bytes << " bytes, level " << level);
            DecodeOptions one;
            one.max_bytes = bytes;
            one.max_level = level;
            one.threads = 1;
            DecodeOptions two = one;
            two.threads = 2;
            const DecodeResult reference = decode(file, one);
            REQUIRE(reference.status == Status::ok);
            if (bytes == in_base_part) CHECK(reference.base_vertices_decoded < info.base_vertices);
            CHECK(same_result(decode(file, two), reference));
            DecodeResult into;
            decode_into(file, two, into);
            CHECK(same_result(into, reference));
            decode_into(file, two, into);  // its arrays lent again
            CHECK(same_result(into, reference));
            // Fed in 97-byte pieces, asked for its mesh halfway (against decode() of that many
            // bytes on one thread) and at the end.
            Decoder streaming(two);
            const std::span<const std::uint8_t> prefix = std::span(file).first(bytes);
            for (std::size_t at = 0; at < prefix.size(); at += 97) {
              const std::size_t n = std::min<std::size_t>(97, prefix.size() - at);
              streaming.push(prefix.subspan(at, n));
              if (at / 97 == prefix.size() / 194) {
                DecodeOptions halfway = one;
                halfway.max_bytes = at + n;
                CHECK(same_result(streaming.mesh(), decode(file, halfway)));
              }
            }
            CHECK(same_result(streaming.mesh(), reference));
          }
        }
      }
    }
  }
}

TEST_CASE("a large file decodes to the same mesh on 1 and 2 threads, whole and cut", "[codec]") {
  // 163,842 vertices: each thread's half of the finest levels spans many blocks, and threads = 0
  // takes two on a machine with two cores (above kConcurrentDecodeVertices).
  SemiRegularMesh m = refine_linear(test::icosahedron(), 7);
  const std::vector<double> noise = test::random_values(m.positions.size(), 17);
  for (std::size_t i = 0; i < m.positions.size(); ++i) m.positions[i] *= 1 + 0.02 * noise[i];
  REQUIRE(m.hierarchy.vertex_count(7) >= DecodeOptions::kConcurrentDecodeVertices);
  for (const Scheme scheme : {Scheme::butterfly, Scheme::loop}) {
    EncodeOptions o;
    o.scheme = scheme;
    const std::vector<std::uint8_t> file = encode(m, o);
    for (const std::size_t bytes : {file.size() / 5, file.size()}) {
      INFO("scheme " << static_cast<int>(scheme) << ", " << bytes << " bytes");
      DecodeOptions options;
      options.max_bytes = bytes;
      options.threads = 1;
      const DecodeResult reference = decode(file, options);
      REQUIRE(reference.status == Status::ok);
      for (const unsigned threads : {2u, 0u}) {
        options.threads = threads;
        CHECK(same_result(decode(file, options), reference));
      }
    }
  }
}

TEST_CASE("damaged files give the same mesh or numbered error on 1 and 2 threads", "[codec][hostile]") {
  // Bit flips and byte replacements (most caught by a chunk's checksum, some in tags, lengths
  // and the file header) and cuts at every 7th byte: the error paths of a two-thread decode, which
  // may stop while its second thread makes the faces, end as one thread's do.
  SemiRegularMesh m = refine_linear(test::disk(7), 3);
  const std::vector<double> noise = test::random_values(m.positions.size(), 15);
  for (std::size_t i = 0; i < m.positions.size(); ++i) m.positions[i] += 0.01 * noise[i];
  const std::vector<std::uint8_t> file = encode(m, {});
  DecodeOptions one, two;
  one.threads = 1;
  two.threads = 2;
  std::mt19937 rng(7);
  int errors = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::vector<std::uint8_t> damaged = file;
    const std::size_t at = rng() % damaged.size();
    if (trial % 2 == 0)
      damaged[at] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
    else
      damaged[at] = static_cast<std::uint8_t>(damaged[at] + 1 + rng() % 255);
    INFO("trial " << trial << ": byte " << at);
    const DecodeResult reference = decode(damaged, one);
    errors += reference.status != Status::ok;
    CHECK(same_result(decode(damaged, two), reference));
  }
  CHECK(errors > 300);
  for (std::size_t cut = 0; cut < file.size(); cut += 7) {
    INFO("cut at " << cut);
    const std::span<const std::uint8_t> prefix = std::span(file).first(cut);
    CHECK(same_result(decode(prefix, two), decode(prefix, one)));
  }
}
