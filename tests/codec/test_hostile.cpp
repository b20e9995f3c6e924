// Hostile and damaged streams (issue 7): every cut, bit flip and byte replacement of a real file
// ends in a valid mesh or a numbered error; tiny files claiming huge meshes are refused before
// any large allocation, which a counting global operator new measures; the memory budget of
// DecodeLimits is honoured and the stated bytes per vertex hold on real decodes.
#include <atomic>
#include <bit>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <random>

#include "meshlift/byte_io.h"
#include "meshlift/codec.h"
#include "meshlift/container.h"
#include "test_meshes.h"
#include "test_streams.h"

// ---- Allocation counter: every operator new of this test executable goes through here ----
namespace {
std::atomic<std::size_t> g_current{0}, g_peak{0};
constexpr std::size_t kHeader = alignof(std::max_align_t);  // keeps the user pointer aligned

void* counted_new(std::size_t size) {
  void* block = std::malloc(size + kHeader);
  if (block == nullptr) throw std::bad_alloc();
  *static_cast<std::size_t*>(block) = size;
  const std::size_t now = g_current.fetch_add(size) + size;
  for (std::size_t peak = g_peak.load(); now > peak && !g_peak.compare_exchange_weak(peak, now);) {
  }
  return static_cast<char*>(block) + kHeader;
}
void counted_delete(void* p) noexcept {
  if (p == nullptr) return;
  void* block = static_cast<char*>(p) - kHeader;
  g_current.fetch_sub(*static_cast<std::size_t*>(block));
  std::free(block);
}

/// Peak bytes held through operator new while `f` runs, above what was held when it started.
template <class F>
std::size_t peak_allocation(F&& f) {
  const std::size_t start = g_current.load();
  g_peak.store(start);
  f();
  return g_peak.load() - start;
}
}  // namespace

void* operator new(std::size_t size) { return counted_new(size); }
void* operator new[](std::size_t size) { return counted_new(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return counted_new(size);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, const std::nothrow_t& tag) noexcept { return operator new(size, tag); }
void operator delete(void* p) noexcept { counted_delete(p); }
void operator delete[](void* p) noexcept { counted_delete(p); }
void operator delete(void* p, std::size_t) noexcept { counted_delete(p); }
void operator delete[](void* p, std::size_t) noexcept { counted_delete(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { counted_delete(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { counted_delete(p); }

using namespace meshlift;

namespace {

/// A small real stream: a bumpy disk (boundary and interior vertices), 2 levels.
std::vector<std::uint8_t> small_file() {
  SemiRegularMesh mesh = refine_linear(test::disk(6), 2);
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) mesh.positions[i] += 0.02 * std::sin(1.7 * static_cast<double>(i));
  EncodeOptions options;
  options.precision_bits = 12;
  return encode(mesh, options);
}

/// The decode contract: ok with finite coordinates and every index in range, or a numbered
/// error with a message and no mesh.
void require_valid_outcome(const DecodeResult& r) {
  if (r.status == Status::ok) {
    REQUIRE(r.mesh.positions.size() % 3 == 0);
    REQUIRE(r.mesh.triangles.size() % 3 == 0);
    REQUIRE_FALSE(r.mesh.triangles.empty());
    for (double x : r.mesh.positions) REQUIRE(std::isfinite(x));
    for (std::uint32_t i : r.mesh.triangles) REQUIRE(i < r.mesh.vertex_count());
  } else {
    REQUIRE(static_cast<int>(r.status) >= 1);
    REQUIRE(static_cast<int>(r.status) <= 8);
    REQUIRE_FALSE(r.message.empty());
    REQUIRE(r.mesh.positions.empty());
    REQUIRE(r.mesh.triangles.empty());
  }
}

}  // namespace

TEST_CASE("hostile: every-byte truncation of a real file gives a prefix mesh or truncated", "[codec][hostile]") {
  const auto file = small_file();
  const DecodeResult whole = decode(file);
  REQUIRE(whole.status == Status::ok);
  REQUIRE(whole.complete);
  std::size_t meshes = 0;
  for (std::size_t cut = 0; cut <= file.size(); ++cut) {
    const DecodeResult r = decode(std::span(file).first(cut));
    INFO("cut at byte " << cut << " of " << file.size());
    require_valid_outcome(r);
    if (r.status != Status::ok) {
      // Before the base mesh is complete only 'truncated' is possible; never a crash or 'corrupt'.
      CHECK(r.status == Status::truncated);
      continue;
    }
    ++meshes;
    CHECK(r.mesh.triangles == whole.mesh.triangles);  // the connectivity is all there once ok
    CHECK(r.complete == (cut == file.size()));
  }
  CHECK(meshes > file.size() / 2);  // the base mesh and header are a small part of the file
}

TEST_CASE("hostile: 1000 single-bit flips and 1000 byte replacements end in a mesh or a numbered error", "[codec][hostile]") {
  const auto file = small_file();
  std::mt19937 rng(2026);
  int counts[9] = {};
  for (int trial = 0; trial < 2000; ++trial) {
    auto damaged = file;
    const std::size_t at = rng() % damaged.size();
    if (trial < 1000) {
      damaged[at] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
    } else {
      const auto old = damaged[at];
      while (damaged[at] == old) damaged[at] = static_cast<std::uint8_t>(rng());
    }
    INFO("trial " << trial << ": byte " << at);
    const DecodeResult r = decode(damaged);
    require_valid_outcome(r);
    ++counts[static_cast<int>(r.status)];
  }
  std::printf("2000 damaged copies of a %zu-byte file: ok %d, truncated %d, bad_magic %d, unsupported_version %d, "
              "corrupt %d, checksum_mismatch %d, limit_exceeded %d, reserved_bits_set %d\n",
              file.size(), counts[0], counts[1], counts[2], counts[3], counts[4], counts[5], counts[6], counts[7]);
  // Every byte after the 8-byte file header is a chunk tag, length, payload or checksum: a flip
  // in a payload or checksum must be caught by the checksum (tags and lengths fail otherwise).
  CHECK(counts[static_cast<int>(Status::checksum_mismatch)] > 1500);
  CHECK(counts[static_cast<int>(Status::bad_magic)] > 0);
}

TEST_CASE("hostile: a 34-byte file claiming 2^40 vertices is refused without a large allocation", "[codec][hostile]") {
  // 17 bytes of container framing, 17 of HEAD (two 6-byte varints): the smallest such claim.
  const auto file = test::claiming(std::uint64_t{1} << 40, std::uint64_t{1} << 40, 4);
  CHECK(file.size() == 34);
  DecodeResult r;
  const std::size_t peak = peak_allocation([&] { r = decode(file); });
  CHECK(r.status == Status::limit_exceeded);
  CHECK_THAT(r.message, Catch::Contains("1099511627776"));
  CHECK(peak < 64 * 1024);
  const std::size_t inspect_peak = peak_allocation([&] { CHECK(inspect(file).status == Status::limit_exceeded); });
  CHECK(inspect_peak < 64 * 1024);
}

TEST_CASE("hostile: a file claiming 200 levels is refused without a large allocation", "[codec][hostile]") {
  const auto file = test::claiming(12, 20, 200);
  CHECK(file.size() == 24);
  DecodeResult r;
  const std::size_t peak = peak_allocation([&] { r = decode(file); });
  CHECK(r.status == Status::limit_exceeded);
  CHECK_THAT(r.message, Catch::Contains("200 levels"));
  CHECK(peak < 64 * 1024);
}

TEST_CASE("hostile: a base chunk too short for its declared faces is refused before decoding it", "[codec][hostile]") {
  // 2^22 base vertices and 2^23 faces are within the default caps, but 100 bytes cannot code them.
  ByteWriter head;
  for (std::uint8_t b : {std::uint8_t{2}, std::uint8_t{0}, std::uint8_t{0}, std::uint8_t{1}, std::uint8_t{1}}) head.u8(b);
  head.varint(std::uint64_t{1} << 22);
  head.varint(std::uint64_t{1} << 23);
  head.u64(std::bit_cast<std::uint64_t>(1.0));                              // step
  for (int i = 0; i < 4; ++i) head.u32(std::bit_cast<std::uint32_t>(1.0f));  // centre, weight
  ContainerWriter writer;
  writer.add_chunk(kTagHeader, head.data());
  writer.add_chunk(kTagBaseMesh, std::vector<std::uint8_t>(100, 0));
  const auto file = writer.finish();
  DecodeResult r;
  const std::size_t peak = peak_allocation([&] { r = decode(file); });
  CHECK(r.status == Status::corrupt);
  CHECK_THAT(r.message, Catch::Contains("BASE chunk at byte"));
  CHECK(peak < 64 * 1024);
}

TEST_CASE("hostile: the caller's memory budget refuses a decode before it allocates", "[codec][hostile]") {
  const SemiRegularMesh mesh = refine_linear(test::icosahedron(), 4);  // 2562 vertices
  const auto file = encode(mesh, {});
  const std::uint64_t vertices = mesh.hierarchy.vertex_count(4);
  DecodeOptions options;
  options.limits.max_memory_bytes = kDecodeBytesPerVertex * vertices - 1;
  DecodeResult r;
  const std::size_t refused_peak = peak_allocation([&] { r = decode(file, options); });
  CHECK(r.status == Status::limit_exceeded);
  CHECK_THAT(r.message, Catch::Contains("memory"));
  CHECK(refused_peak < kDecodeBytesPerVertex * vertices / 4);  // stopped before the hierarchy
  options.limits.max_memory_bytes = kDecodeBytesPerVertex * vertices + kDecodeBytesPerBaseFace * 20;
  CHECK(decode(file, options).status == Status::ok);
}

TEST_CASE("hostile: a decode allocates at most the stated bytes per output vertex", "[codec][hostile]") {
  // The bound codec.h states (kDecodeBytesPerVertex per output vertex plus the base decoder's
  // kDecodeBytesPerBaseFace per base face plus a copy of the input) holds on real decodes.
  for (const auto& [name, base, levels] :
       {std::tuple{"icosahedron", test::icosahedron(), 6}, std::tuple{"torus", test::torus(12, 8), 4},
        std::tuple{"disk", test::disk(7), 5}, std::tuple{"grid", test::grid(20), 3},
        std::tuple{"torus 120x80, base only", test::torus(120, 80), 0}}) {
    SemiRegularMesh mesh = refine_linear(base, levels);
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) mesh.positions[i] += 0.01 * std::sin(0.37 * static_cast<double>(i));
    const auto file = encode(mesh, {});
    const std::size_t vertices = mesh.hierarchy.vertex_count(levels);
    DecodeResult r;
    const std::size_t peak = peak_allocation([&] { r = decode(file); });
    INFO(r.message);
    REQUIRE(r.status == Status::ok);
    std::printf("decode peak allocation, %s (%zu vertices, %zu base faces, %zu bytes): %.1f bytes per output vertex, "
                "%.1f per base face\n", name, vertices, base.face_count(), file.size(),
                static_cast<double>(peak) / static_cast<double>(vertices), static_cast<double>(peak) / static_cast<double>(base.face_count()));
    CHECK(peak <= kDecodeBytesPerVertex * vertices + kDecodeBytesPerBaseFace * base.face_count() + file.size());
  }
}
