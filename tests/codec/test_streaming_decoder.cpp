// The streaming Decoder (codec.h), whose thread decodes the coefficient stream as it arrives,
// against decode() of the same prefixes: every field of every answer, bit for bit, for bytes
// pushed in chunks of 1 byte to a few hundred, with options, corrupt bytes, and a Decoder moved
// or destroyed while its thread waits for bytes.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "decode_results.h"
#include "meshlift/codec.h"
#include "meshlift/container.h"
#include "meshlift/lifting.h"
#include "test_meshes.h"

using namespace meshlift;
using test::same_result;

namespace {

/// A semi-regular mesh with detail at every level: `base` refined `levels` times, moved off its
/// midpoints by noise.
SemiRegularMesh noisy(const TriangleMesh& base, int levels, unsigned seed) {
  SemiRegularMesh m = refine_linear(base, levels);
  const std::vector<double> noise = test::random_values(m.positions.size(), seed);
  for (std::size_t i = 0; i < m.positions.size(); ++i) m.positions[i] += 0.01 * noise[i];
  return m;
}

/// Pushes `file` in chunks of 1 to max_chunk bytes (runs of single bytes among them), asking for
/// the mesh after every push, both ways, and checks each answer against decode() of the bytes
/// pushed so far. Returns how many answers had status ok.
int check_stream(std::span<const std::uint8_t> file, const DecodeOptions& options, unsigned seed, std::size_t max_chunk) {
  std::mt19937 rng(seed);
  Decoder decoder(options);
  DecodeResult reused;
  int ok = 0;
  for (std::size_t at = 0; at < file.size();) {
    const std::size_t n = std::min<std::size_t>(file.size() - at, rng() % 4 == 0 ? 1 : 1 + rng() % max_chunk);
    decoder.push(file.subspan(at, n));
    at += n;
    REQUIRE(decoder.bytes_received() == at);
    const DecodeResult expected = decode(file.first(at), options);
    INFO(at << " of " << file.size() << " bytes: " << expected.message);
    REQUIRE(same_result(decoder.mesh(), expected));
    decoder.mesh(reused);
    REQUIRE(same_result(reused, expected));
    ok += expected.status == Status::ok;
  }
  return ok;
}

}  // namespace

TEST_CASE("streaming decoder: after every push, mesh() is decode() of the bytes so far", "[codec][stream]") {
  struct Case {
    const char* name;
    SemiRegularMesh mesh;
    EncodeOptions options;
  };
  std::vector<Case> cases;
  {
    SemiRegularMesh sphere = noisy(test::icosahedron(), 4, 3);
    VertexChannel scalar{1, {}};
    for (std::size_t v = 0; v < sphere.positions.size() / 3; ++v) scalar.values.push_back(std::sin(5 * sphere.positions[3 * v]));
    sphere.channels = {scalar};
    cases.push_back({"closed, Loop, a channel", sphere, {}});
  }
  {
    EncodeOptions butterfly;
    butterfly.scheme = Scheme::butterfly;
    cases.push_back({"open grid, butterfly", noisy(test::grid(4), 3, 4), butterfly});
  }
  {
    EncodeOptions linear;
    linear.scheme = Scheme::linear;
    linear.local_frames = false;
    linear.precision_bits = 12;
    cases.push_back({"torus, linear, x y z details", noisy(test::torus(), 3, 5), linear});
  }
  for (const Case& c : cases) {
    INFO(c.name);
    const std::vector<std::uint8_t> file = encode(c.mesh, c.options);
    const int answers = check_stream(file, {}, 1, 300);
    CHECK(answers > 10);  // most prefixes past the header and base mesh are meshes
    DecodeOptions coarser;
    coarser.max_level = 1;
    check_stream(file, coarser, 2, 200);
    DecodeOptions half;
    half.max_bytes = file.size() / 2;
    check_stream(file, half, 3, 200);
    // Limits the base already breaks: every answer is decode()'s refusal.
    DecodeOptions small;
    small.limits.max_vertices = 100;
    CHECK(check_stream(file, small, 4, 500) == 0);
  }
}

TEST_CASE("streaming decoder: corrupt coefficient bytes give what decode() gives, a checksum_mismatch once their chunk is whole",
          "[codec][stream]") {
  const std::vector<std::uint8_t> file = encode(noisy(test::icosahedron(), 4, 6), {});
  ContainerReader reader;
  REQUIRE(reader.parse(file) == Status::ok);
  const Chunk* coefficients = nullptr;
  for (const Chunk& c : reader.chunks())
    if (c.tag == kTagCoefficients) coefficients = &c;
  REQUIRE(coefficients != nullptr);
  for (double where : {0.1, 0.5, 0.9}) {
    std::vector<std::uint8_t> bad = file;
    const std::size_t at = static_cast<std::size_t>(coefficients->payload.data() - file.data()) +
                           static_cast<std::size_t>(where * static_cast<double>(coefficients->payload.size()));
    bad[at] ^= 0x24;
    check_stream(bad, {}, 7, 150);
    CHECK(decode(bad).status == Status::checksum_mismatch);
  }
}

TEST_CASE("streaming decoder: moved, or destroyed, while its thread waits for bytes", "[codec][stream]") {
  const std::vector<std::uint8_t> file = encode(noisy(test::icosahedron(), 4, 8), {});
  const std::span<const std::uint8_t> bytes(file);
  const std::size_t half = file.size() / 2;
  Decoder first;
  first.push(bytes.first(half));
  REQUIRE(same_result(first.mesh(), decode(bytes.first(half))));
  Decoder second = std::move(first);  // the thread goes on with the state it decodes into
  REQUIRE(same_result(second.mesh(), decode(bytes.first(half))));
  second.push(bytes.subspan(half));
  const DecodeResult whole = second.mesh();
  REQUIRE(same_result(whole, decode(file)));
  CHECK(whole.complete);
  {
    Decoder abandoned;
    abandoned.push(bytes.first(half));  // its thread waits for the rest, which never comes
  }
  Decoder assigned;
  assigned.push(bytes.first(10));
  assigned = std::move(second);  // the assigned-over Decoder's thread ends
  REQUIRE(same_result(assigned.mesh(), whole));
}
