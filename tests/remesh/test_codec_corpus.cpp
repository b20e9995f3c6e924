// The codec on a real mesh of the corpus: every prefix of its stream decodes, the error falls
// with the bytes read, and the whole file is within the quantization bound.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>

#include "meshlift/codec.h"
#include "meshlift/mesh_io.h"
#include "test_meshes.h"

using namespace meshlift;

TEST_CASE("real-mesh stream: 60 prefixes decode and the error falls with the bytes read", "[corpus][codec]") {
  const TriangleMesh cow = to_triangle_mesh(read_mesh((test::corpus_directory() / "cow.off").string()));
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
  auto rms = [&](const std::vector<double>& p) {
    double sum = 0;
    for (std::size_t i = 0; i < p.size(); ++i) sum += (p[i] - mesh.positions[i]) * (p[i] - mesh.positions[i]);
    return std::sqrt(sum / static_cast<double>(p.size() / 3));
  };
  const std::size_t first = info.chunks[2].offset + 8;  // HEAD and BASE complete
  double previous = 1e300;
  int cuts = 0;
  for (std::size_t cut = first; cut <= file.size(); cut += (file.size() - first) / 59) {
    DecodeOptions o;
    o.max_bytes = cut;
    const DecodeResult r = decode(file, o);
    INFO("cut " << cut);
    REQUIRE(r.status == Status::ok);
    REQUIRE(r.mesh.positions.size() == mesh.positions.size());
    const double error = rms(r.mesh.positions);
    CHECK(error <= previous * 1.05 + 1e-15);  // non-increasing within 5 %
    previous = std::min(previous, error);
    if (cuts % 12 == 0)
      std::printf("cow L2 butterfly: %7zu of %zu bytes -> PSNR %.1f dB\n", cut, file.size(),
                  20 * std::log10(diagonal / error));
    ++cuts;
  }
  CHECK(cuts >= 50);
  const DecodeResult whole = decode(file);
  REQUIRE(whole.complete);
  CHECK(rms(whole.mesh.positions) <= info.step);
}
