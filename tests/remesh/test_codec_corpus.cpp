// The codec on a real mesh of the corpus: every prefix of its stream decodes, the error falls
// with the bytes read, and the whole file is within the quantization bound.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>

#include "meshlift/codec.h"
#include "meshlift/mesh_io.h"
#include "test_meshes.h"
#include "test_prefixes.h"

using namespace meshlift;

TEST_CASE("real-mesh stream: 60 prefixes decode and the error falls with the bytes read", "[corpus][codec]") {
  const TriangleMesh cow = to_triangle_mesh(read_mesh(test::corpus_mesh_path("cow")));
  // The cow as the base, Loop-subdivided twice (46,434 vertices), coded with butterfly wavelets.
  SemiRegularMesh mesh = refine_linear(cow, 2);
  std::fill(mesh.positions.begin() + static_cast<std::ptrdiff_t>(cow.positions.size()), mesh.positions.end(), 0.0);
  WaveletTransform(mesh.hierarchy, {Scheme::loop, false}).synthesize(mesh.positions);
  mesh = canonical_order(mesh);
  EncodeOptions options;
  options.scheme = Scheme::butterfly;
  const auto file = encode(mesh, options);
  const StreamInfo info = inspect(file);
  REQUIRE(info.status == Status::ok);
  const double diagonal = bounding_box_diagonal(mesh.positions);
  const auto errors = test::check_prefixes(file, mesh.positions, 60);
  CHECK(errors.size() >= 50);
  for (std::size_t k = 0; k < errors.size(); k += 12)
    std::printf("cow L2 butterfly: %7zu of %zu bytes -> PSNR %.1f dB\n", errors[k].first, file.size(),
                20 * std::log10(diagonal / errors[k].second));
  const DecodeResult whole = decode(file);
  REQUIRE(whole.complete);
  // Every coefficient within its component's step (FORMAT.md §5): with local frames the tangents'
  // step is 2^tangent_shift times the normal's.
  REQUIRE(info.local_frames);
  CHECK(test::rms_error(whole.mesh.positions, mesh.positions) <= info.step * std::ldexp(1.0, info.tangent_shift));
}
