// Spherical parametrization, octahedral geometry images and their files.
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <optional>
#include <set>
#include <string>

#include "meshlift/geometry_image.h"
#include "meshlift/geometry_image_file.h"
#include "meshlift/mesh_io.h"
#include "meshlift/semi_regular.h"
#include "meshlift/spherical_parametrization.h"
#include "test_meshes.h"

using namespace meshlift;

namespace {

/// Icosahedron refined `levels` times with its vertices pushed onto the unit sphere (an icosphere).
TriangleMesh icosphere(int levels) {
  TriangleMesh m = refine_linear(test::icosahedron(), levels).finest();
  for (std::size_t v = 0; v < m.vertex_count(); ++v) {
    double* p = &m.positions[3 * v];
    const double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int k = 0; k < 3; ++k) p[k] /= r;
  }
  return m;
}

constexpr std::array<double, 3> kAxes = {2.0, 1.0, 0.5};

/// The icosphere with its vertices on the ellipsoid x²/4 + y² + 4z² = 1.
TriangleMesh ellipsoid(int levels) {
  TriangleMesh m = icosphere(levels);
  for (std::size_t i = 0; i < m.positions.size(); ++i) m.positions[i] *= kAxes[i % 3];
  return m;
}

/// An elongated, bumpy closed surface: the icosphere stretched 4x along x into a finger whose
/// radius swells and narrows (0.15 .. 0.45) with bumps around it.
TriangleMesh bumpy_finger(int levels) {
  TriangleMesh m = icosphere(levels);
  for (std::size_t v = 0; v < m.vertex_count(); ++v) {
    double* p = &m.positions[3 * v];
    const double x = p[0], angle = std::atan2(p[2], p[1]);
    const double radius = 0.3 + 0.15 * std::sin(5 * x) + 0.03 * std::cos(6 * angle);
    p[0] = 4 * x;
    p[1] *= radius;
    p[2] *= radius;
  }
  return m;
}

/// Distance of x from the ellipsoid with semi-axes kAxes, to first order: |F| / |∇F| for
/// F = Σ x_k² / a_k² − 1 (exact to O(d²) near the surface).
double ellipsoid_distance(const double* x) {
  double f = -1, g2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double a2 = kAxes[k] * kAxes[k];
    f += x[k] * x[k] / a2;
    g2 += 4 * x[k] * x[k] / (a2 * a2);
  }
  return std::fabs(f) / std::sqrt(g2);
}

void require_bijective(const SphericalParametrization& p) {
  INFO("flipped " << p.check.flipped_triangles << ", degenerate " << p.check.degenerate_triangles << ", coverage "
                  << p.check.coverage);
  REQUIRE(p.check.flipped_triangles == 0);
  REQUIRE(p.check.degenerate_triangles == 0);
  REQUIRE(p.check.coverage == Approx(1.0).epsilon(1e-9));
  REQUIRE(p.check.bijective());
}

}  // namespace

TEST_CASE("sphere map check counts flipped triangles and the coverage of the sphere", "[sphere]") {
  const TriangleMesh sphere = icosphere(2);
  SphereMapCheck identity = check_sphere_map(sphere, sphere.positions);
  CHECK(identity.flipped_triangles == 0);
  CHECK(identity.degenerate_triangles == 0);
  CHECK(identity.coverage == Approx(1.0).epsilon(1e-12));
  // Mirroring the sphere turns every triangle clockwise: all flipped, coverage −1.
  std::vector<double> mirrored = sphere.positions;
  for (std::size_t v = 0; v < sphere.vertex_count(); ++v) mirrored[3 * v] = -mirrored[3 * v];
  const SphereMapCheck mirror = check_sphere_map(sphere, mirrored);
  CHECK(mirror.flipped_triangles == sphere.face_count());
  CHECK(mirror.coverage == Approx(-1.0).epsilon(1e-12));
  CHECK_FALSE(mirror.bijective());
  // Moving one vertex across its ring folds its triangles over their neighbours.
  std::vector<double> folded = sphere.positions;
  for (int k = 0; k < 3; ++k) folded[k] = -folded[k];
  CHECK(check_sphere_map(sphere, folded).flipped_triangles > 0);
}

TEST_CASE("stretch is 1 for a similarity and grows with distortion", "[sphere]") {
  const TriangleMesh sphere = icosphere(3);
  // The identity map of a fine icosphere is a near-similarity (only the gnomonic flattening differs).
  CHECK(spherical_stretch(sphere, sphere.positions) == Approx(1.0).epsilon(0.01));
  TriangleMesh scaled = sphere;
  for (double& x : scaled.positions) x *= 3;  // normalization removes scale
  CHECK(spherical_stretch(scaled, sphere.positions) == Approx(1.0).epsilon(0.01));
  CHECK(spherical_stretch(ellipsoid(3), sphere.positions) > 1.05);
}

TEST_CASE("spherical parametrization of a sphere stays a near-similarity", "[sphere]") {
  const TriangleMesh sphere = icosphere(3);
  const SphericalParametrization p = parametrize_sphere(sphere);
  require_bijective(p);
  CHECK(p.base_vertices == 4);
  CHECK(p.collapses == sphere.vertex_count() - 4);
  CHECK(p.stretch < 1.03);
}

TEST_CASE("spherical parametrization of an ellipsoid and a bumpy finger is bijective", "[sphere]") {
  for (const auto& [name, mesh] : {std::pair{"ellipsoid", ellipsoid(3)}, std::pair{"bumpy finger", bumpy_finger(4)}}) {
    INFO(name);
    const SphericalParametrization p = parametrize_sphere(mesh);
    require_bijective(p);
    // Both meshes are deformed icospheres, so the icosphere itself is a bijective map onto the
    // sphere: the optimized map must stretch less than that one.
    const double deformation_stretch = spherical_stretch(mesh, icosphere(std::string(name) == "ellipsoid" ? 3 : 4).positions);
    INFO("stretch " << p.stretch << ", of the deformation " << deformation_stretch);
    CHECK(p.stretch < deformation_stretch);
    // Every parametrized vertex is on the unit sphere.
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
      REQUIRE(std::hypot(p.sphere[3 * v], p.sphere[3 * v + 1], p.sphere[3 * v + 2]) == Approx(1.0).epsilon(1e-12));
  }
}

TEST_CASE("unsuitable meshes are named and pointed to the decimation remesher", "[sphere]") {
  const auto problem = [](const TriangleMesh& m) { return sphere_parametrization_problem(m); };
  CHECK(problem(icosphere(1)).empty());
  const std::string torus = problem(test::torus());
  CHECK_THAT(torus, Catch::Contains("genus 1, not 0"));
  CHECK_THAT(torus, Catch::Contains("--remesh decimate"));
  CHECK_THAT(problem(test::grid(4)), Catch::Contains("not closed (12 boundary edges"));
  TriangleMesh two = icosphere(0);
  const TriangleMesh second = icosphere(0);
  for (std::size_t i = 0; i < second.positions.size(); ++i) two.positions.push_back(second.positions[i] + (i % 3 == 0 ? 5 : 0));
  for (const std::uint32_t v : second.triangles) two.triangles.push_back(v + 12);
  CHECK_THAT(problem(two), Catch::Contains("not one component (2 components)"));
  // Two icosahedra glued at one vertex: a pinch (non-manifold vertex), one component.
  TriangleMesh pinched = two;
  for (std::uint32_t& v : pinched.triangles)
    if (v == 12) v = 0;
  CHECK_THAT(problem(pinched), Catch::Contains("not manifold (0 non-manifold edges, 1 non-manifold vertices)"));
  REQUIRE_THROWS_AS(parametrize_sphere(test::torus()), MeshError);
  REQUIRE_THROWS_AS(remesh_sphere(icosphere(1), 12), MeshError);
  // Isolated vertices are allowed and left out: they get (0, 0, 1), the rest stays bijective.
  TriangleMesh isolated = icosphere(1);
  isolated.positions.insert(isolated.positions.begin(), {9.0, 9.0, 9.0});
  for (std::uint32_t& v : isolated.triangles) ++v;
  CHECK(problem(isolated).empty());
  const SphericalParametrization p = parametrize_sphere(isolated);
  require_bijective(p);
  CHECK((p.sphere[0] == 0.0 && p.sphere[1] == 0.0 && p.sphere[2] == 1.0));
  const SemiRegularMesh remeshed = remesh_sphere(isolated, 2);
  REQUIRE(remeshed.positions.size() == 3 * 66);
  for (const double x : remeshed.positions) REQUIRE(std::fabs(x) <= 1.0);  // never the isolated (9, 9, 9)
  REQUIRE_THROWS_WITH(remesh_sphere(test::grid(4), 3), Catch::Contains("--remesh decimate"));
}

TEST_CASE("octahedral unfolding: sizes, identified border pixels and the hierarchy's vertices", "[sphere]") {
  CHECK(geometry_image_size(7) == 257);
  CHECK(geometry_image_levels(129) == 6);
  CHECK_THROWS_AS(geometry_image_levels(128), MeshError);
  CHECK_THROWS_AS(geometry_image_size(12), MeshError);
  for (const int levels : {0, 1, 3}) {
    const int n = geometry_image_size(levels);
    const auto size = static_cast<std::size_t>(n);
    const std::vector<std::uint32_t> vertex = pixel_vertices(n);
    const std::set<std::uint32_t> distinct(vertex.begin(), vertex.end());
    // 4^(L+1) + 2 distinct vertices, every one of the hierarchy's.
    REQUIRE(distinct.size() == (std::size_t{1} << (2 * levels + 2)) + 2);
    REQUIRE(*distinct.rbegin() == distinct.size() - 1);
    auto at = [&](std::size_t r, std::size_t c) { return vertex[r * size + c]; };
    // Centre +z (vertex 4), the four corners −z (vertex 5), side midpoints +y, −x, +x, −y.
    CHECK(at(size / 2, size / 2) == 4);
    CHECK((at(0, 0) == 5 && at(0, size - 1) == 5 && at(size - 1, 0) == 5 && at(size - 1, size - 1) == 5));
    CHECK(at(0, size / 2) == 1);
    CHECK(at(size / 2, 0) == 2);
    CHECK(at(size / 2, size - 1) == 0);
    CHECK(at(size - 1, size / 2) == 3);
    // Each side folds at its midpoint; interior pixels are all distinct.
    for (std::size_t i = 0; i < size; ++i) {
      CHECK(at(0, i) == at(0, size - 1 - i));
      CHECK(at(size - 1, i) == at(size - 1, size - 1 - i));
      CHECK(at(i, 0) == at(size - 1 - i, 0));
      CHECK(at(i, size - 1) == at(size - 1 - i, size - 1));
    }
    std::set<std::uint32_t> interior;
    for (std::size_t r = 1; r + 1 < size; ++r)
      for (std::size_t c = 1; c + 1 < size; ++c) interior.insert(at(r, c));
    CHECK(interior.size() == (size - 2) * (size - 2));
  }
}

TEST_CASE("octahedral image of the octahedron's own points is a positively oriented covering", "[sphere]") {
  // Sample the identity: pixel -> its octahedron point; the mesh built from that image must have
  // every finest triangle counter-clockwise on the sphere and cover it once, which holds only if
  // pixels and hierarchy vertices correspond.
  const int n = 33;
  GeometryImage image{n, std::vector<double>(3 * n * n)};
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      const auto o = octahedron_point(r, c, n);
      const double length = std::sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]);
      for (int k = 0; k < 3; ++k) image.samples[3 * (r * n + c) + k] = o[k] / length;
    }
  const SemiRegularMesh mesh = image_to_mesh(image);
  const TriangleMesh finest = mesh.finest();
  const SphereMapCheck check = check_sphere_map(finest, finest.positions);
  CHECK(check.flipped_triangles == 0);
  CHECK(check.degenerate_triangles == 0);
  CHECK(check.coverage == Approx(1.0).epsilon(1e-12));
  CHECK(mesh_to_image(mesh).samples == image.samples);
}

TEST_CASE("geometry image of an ellipsoid lies on the ellipsoid and keeps its borders through mesh round trips", "[sphere]") {
  // Input: the L = 4 icosphere on the ellipsoid (2562 vertices); its flat faces are at most
  // ~2.5e-3 from the analytic surface (measured at face centroids below), and every sample is
  // a point of one of them.
  const TriangleMesh input = ellipsoid(4);
  double chord_error = 0;
  for (std::size_t f = 0; f < input.face_count(); ++f) {
    double centroid[3] = {0, 0, 0};
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) centroid[k] += input.positions[3 * input.triangles[3 * f + i] + k] / 3;
    chord_error = std::max(chord_error, ellipsoid_distance(centroid));
  }
  CHECK(chord_error < 2.5e-3);
  const SphereRemesh remesh = remesh_sphere_detailed(input, 5);
  require_bijective(remesh.parametrization);
  const TriangleMesh finest = remesh.mesh.finest();
  REQUIRE(finest.vertex_count() == 4098);
  double worst = 0;
  for (std::size_t v = 0; v < finest.vertex_count(); ++v) worst = std::max(worst, ellipsoid_distance(&finest.positions[3 * v]));
  INFO("worst sample distance " << worst << ", input chord error " << chord_error);
  CHECK(worst <= chord_error * 1.01);
  // The remeshed surface is oriented like the input: positive enclosed volume (4/3 π abc ≈ 4.19).
  double volume = 0;
  for (std::size_t f = 0; f < finest.face_count(); ++f) {
    const double* a = &finest.positions[3 * finest.triangles[3 * f]];
    const double* b = &finest.positions[3 * finest.triangles[3 * f + 1]];
    const double* c = &finest.positions[3 * finest.triangles[3 * f + 2]];
    volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
  }
  CHECK(volume == Approx(4.0 / 3.0 * M_PI).epsilon(0.01));

  // Image -> mesh -> image: identical, and identified border pixels equal.
  const GeometryImage image = mesh_to_image(remesh.mesh);
  REQUIRE(image.size == 65);
  const GeometryImage again = mesh_to_image(image_to_mesh(image));
  CHECK(again.samples == image.samples);
  const std::vector<std::uint32_t> vertex = pixel_vertices(image.size);
  std::vector<double> first(3 * vertex.size(), NAN);
  for (std::size_t p = 0; p < vertex.size(); ++p)
    for (std::size_t k = 0; k < 3; ++k) {
      double& seen = first[3 * vertex[p] + k];
      if (std::isnan(seen)) seen = again.samples[3 * p + k];
      REQUIRE(again.samples[3 * p + k] == seen);
    }
  // An image whose mirrored border pixels disagree comes back with them equal.
  GeometryImage broken = image;
  broken.samples[3 * 1] += 0.5;  // row 0, column 1: mirror of column n − 2
  const GeometryImage repaired = mesh_to_image(image_to_mesh(broken));
  for (int k = 0; k < 3; ++k) CHECK(repaired.samples[3 * 1 + k] == repaired.samples[3 * (image.size - 2) + k]);
}

TEST_CASE("sphere remesh is a level-ordered octahedron hierarchy that recover_level_ordered finds", "[sphere]") {
  const SemiRegularMesh remesh = remesh_sphere(bumpy_finger(2), 3);
  REQUIRE(remesh.positions.size() == 3 * 258);
  const std::optional<SemiRegularMesh> recovered = recover_level_ordered(remesh.finest());
  REQUIRE(recovered.has_value());
  CHECK(recovered->hierarchy.levels() == 3);
  CHECK(recovered->hierarchy.triangles(0) == octahedron().triangles);
  CHECK(recovered->positions == remesh.positions);
  // Nested sampling: a coarser remesh from the same parametrization is the prefix of the finer
  // one (level j's vertices are the same octahedron points at every L >= j).
  const TriangleMesh finger = bumpy_finger(2);
  const SphericalParametrization p = parametrize_sphere(finger);
  const SemiRegularMesh coarse = sample_sphere_remesh(finger, p.sphere, 1);
  const SemiRegularMesh fine = sample_sphere_remesh(finger, p.sphere, 3);
  REQUIRE(coarse.positions.size() == 3 * 18);
  CHECK(std::equal(coarse.positions.begin(), coarse.positions.end(), fine.positions.begin()));
}

TEST_CASE("mesh_to_image refuses a mesh whose base is not the octahedron", "[sphere]") {
  CHECK_THROWS_AS(mesh_to_image(refine_linear(test::icosahedron(), 2)), MeshError);
}

TEST_CASE("geometry image files: PNG within 16-bit quantization and gim exact", "[sphere]") {
  const SemiRegularMesh remesh = remesh_sphere(ellipsoid(2), 4);
  const GeometryImage image = mesh_to_image(remesh);
  REQUIRE(image.size == 33);
  const std::vector<std::uint8_t> png = encode_geometry_image_png(image);
  const GeometryImage decoded = decode_geometry_image_png(png);
  REQUIRE(decoded.size == image.size);
  std::array<double, 3> lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
  for (std::size_t i = 0; i < image.samples.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], image.samples[i]);
    hi[i % 3] = std::max(hi[i % 3], image.samples[i]);
  }
  double worst_relative = 0;
  for (std::size_t i = 0; i < image.samples.size(); ++i)
    worst_relative = std::max(worst_relative, std::fabs(decoded.samples[i] - image.samples[i]) / (hi[i % 3] - lo[i % 3]));
  CHECK(worst_relative <= 0.5 / 65535 * (1 + 1e-9));
  CHECK(worst_relative > 0);  // it is quantized
  // The box's low corner is exact (Q = 0 decodes to lo).
  for (std::size_t k = 0; k < 3; ++k) {
    double decoded_lo = 1e9;
    for (std::size_t i = k; i < decoded.samples.size(); i += 3) decoded_lo = std::min(decoded_lo, decoded.samples[i]);
    CHECK(decoded_lo == lo[k]);
  }
  // Quantized borders stay identical: identified pixels held equal samples.
  const std::vector<std::uint32_t> vertex = pixel_vertices(image.size);
  for (std::size_t p = 0; p < vertex.size(); ++p)
    for (std::size_t q = p + 1; q < vertex.size(); ++q)
      if (vertex[p] == vertex[q])
        for (std::size_t k = 0; k < 3; ++k) REQUIRE(decoded.samples[3 * p + k] == decoded.samples[3 * q + k]);

  CHECK(decode_geometry_image_gim(encode_geometry_image_gim(image)).samples == image.samples);
  const GeometryImage single = decode_geometry_image_gim(encode_geometry_image_gim(image, 4));
  for (std::size_t i = 0; i < image.samples.size(); ++i)
    REQUIRE(single.samples[i] == static_cast<double>(static_cast<float>(image.samples[i])));
}

TEST_CASE("geometry image files: truncated and corrupted bytes are reported, never trusted", "[sphere]") {
  const GeometryImage image = mesh_to_image(remesh_sphere(icosphere(1), 2));
  const std::vector<std::uint8_t> png = encode_geometry_image_png(image);
  const std::vector<std::uint8_t> gim = encode_geometry_image_gim(image);
  for (std::size_t cut = 0; cut < png.size(); cut += 7)
    REQUIRE_THROWS_AS(decode_geometry_image_png(std::span(png.data(), cut)), MeshIOError);
  for (std::size_t cut = 0; cut < gim.size(); cut += 5)
    REQUIRE_THROWS_AS(decode_geometry_image_gim(std::span(gim.data(), cut)), MeshIOError);
  std::vector<std::uint8_t> longer = gim;
  longer.push_back(0);
  CHECK_THROWS_WITH(decode_geometry_image_gim(longer), Catch::Contains("trailing bytes"));
  std::vector<std::uint8_t> bad = gim;
  bad[0] = 'X';
  CHECK_THROWS_WITH(decode_geometry_image_gim(bad), Catch::Contains("bad magic"));
  bad = gim;
  bad[8] = 100;  // side 100
  CHECK_THROWS_WITH(decode_geometry_image_gim(bad), Catch::Contains("image side 100"));
  bad = gim;
  bad[4] = 2;
  CHECK_THROWS_WITH(decode_geometry_image_gim(bad), Catch::Contains("unsupported version 2"));
  // Every single corrupted byte of the PNG: an error or an image of the right size, never a crash.
  for (std::size_t i = 0; i < png.size(); ++i) {
    std::vector<std::uint8_t> corrupt = png;
    corrupt[i] ^= 0x5a;
    int size = image.size;
    try {
      size = decode_geometry_image_png(corrupt).size;
    } catch (const MeshIOError&) {
    }
    REQUIRE(size == image.size);
  }
}

TEST_CASE("corpus meshes: bijective spherical parametrization with bounded stretch", "[corpus][sphere]") {
  // Full resolution (2.9 k to 26 k vertices); about 12 s together on one core of the dev machine.
  for (const char* name : {"armadillo", "camel", "fandisk", "bear_bis", "cow", "homer"}) {
    INFO(name);
    const TriangleMesh mesh = to_triangle_mesh(read_mesh(test::corpus_mesh_path(name)));
    const SphericalParametrization p = parametrize_sphere(mesh);
    require_bijective(p);
    CHECK(p.stretch < 3.0);
    const SemiRegularMesh remesh = sample_sphere_remesh(mesh, p.sphere, 5);
    CHECK(remesh.positions.size() == 3 * 4098);
  }
}
