// Procedural meshes for tests: nothing here is read from disk.
#pragma once

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "meshlift/mesh.h"
#include "meshlift/semi_regular.h"

namespace meshlift::test {

/// The connectivity of a triangle mesh, for tests that build hierarchies from procedural bases.
inline TriangleTopology topology_of(const TriangleMesh& m) {
  return TriangleTopology::build(static_cast<std::uint32_t>(m.vertex_count()), m.triangles);
}

/// The real-mesh corpus (libcgal-demo's data/meshes, fetched by scripts/corpus.sh): the directory
/// in MESHLIFT_CORPUS. Fails the calling test with instructions when it is not set.
inline std::filesystem::path corpus_directory() {
  const char* corpus = std::getenv("MESHLIFT_CORPUS");
  if (corpus == nullptr || *corpus == '\0')
    FAIL("MESHLIFT_CORPUS is not set: point it at the directory of libcgal-demo's .off meshes "
         "(scripts/corpus.sh prints it; set it before running cmake so ctest passes it on), "
         "or exclude this test with the filter ~[corpus]");
  return corpus;
}

/// Path of corpus mesh `name` (e.g. "cow" for cow.off); fails the test if it is missing.
inline std::string corpus_mesh_path(const std::string& name) {
  const std::string path = (corpus_directory() / (name + ".off")).string();
  INFO(path);
  REQUIRE(std::filesystem::exists(path));
  return path;
}

/// Regular icosahedron on the unit sphere (12 vertices of valence 5, 20 faces).
inline TriangleMesh icosahedron() {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleMesh m;
  m.positions = {-1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, 0, 0, -1, t, 0, 1, t,
                 0, -1, -t, 0, 1, -t, t, 0, -1, t, 0, 1, -t, 0, -1, -t, 0, 1};
  for (std::size_t i = 0; i < m.positions.size(); i += 3) {
    const double n = std::sqrt(m.positions[i] * m.positions[i] + m.positions[i + 1] * m.positions[i + 1] +
                               m.positions[i + 2] * m.positions[i + 2]);
    for (int k = 0; k < 3; ++k) m.positions[i + k] /= n;
  }
  m.triangles = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8,
                 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
  return m;
}

/// The icosahedron refined `levels` times by 1:4 midpoint splits, every vertex pushed onto the
/// unit sphere after each split (20·4^levels faces).
inline TriangleMesh icosphere(int levels) {
  TriangleMesh m = icosahedron();
  for (int level = 0; level < levels; ++level) {
    m = refine_linear(m, 1).finest();
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
      double* p = &m.positions[3 * v];
      const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
      for (int k = 0; k < 3; ++k) p[k] /= n;
    }
  }
  return m;
}

/// The icosahedron refined `levels` times by 1:4 midpoint splits as a semi-regular mesh, then
/// every vertex pushed onto the unit sphere: a polyhedron inscribed in the sphere, so all its
/// chord error is inside.
inline SemiRegularMesh sphere_refinement(int levels) {
  SemiRegularMesh s = refine_linear(icosahedron(), levels);
  for (std::size_t v = 0; v < s.positions.size() / 3; ++v) {
    double* p = &s.positions[3 * v];
    const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int k = 0; k < 3; ++k) p[k] /= n;
  }
  return s;
}

/// A smooth closed surface: the icosahedron refined 4 times (2,562 vertices, in level order, so
/// remesh() recognizes it unless told not to), pushed onto the bumpy sphere
/// r = 1 + 0.15 sin(3x) sin(2y) sin(2z).
inline TriangleMesh bumpy_sphere() {
  SemiRegularMesh s = refine_linear(icosahedron(), 4);
  for (std::size_t v = 0; v < s.positions.size() / 3; ++v) {
    double* p = &s.positions[3 * v];
    const double len = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    const double x = p[0] / len, y = p[1] / len, z = p[2] / len;
    const double r = 1 + 0.15 * std::sin(3 * x) * std::sin(2 * y) * std::sin(2 * z);
    p[0] = r * x, p[1] = r * y, p[2] = r * z;
  }
  return s.finest();
}

/// Torus (genus 1) with `rings` x `sides` quads split into triangles; all vertices valence 6.
inline TriangleMesh torus(int rings = 8, int sides = 6, double major = 1.0, double minor = 0.35) {
  TriangleMesh m;
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sides; ++j) {
      const double u = 2 * M_PI * i / rings, v = 2 * M_PI * j / sides;
      m.positions.insert(m.positions.end(), {(major + minor * std::cos(v)) * std::cos(u),
                                             (major + minor * std::cos(v)) * std::sin(u), minor * std::sin(v)});
    }
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(((i + rings) % rings) * sides + (j + sides) % sides); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sides; ++j) {
      m.triangles.insert(m.triangles.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.insert(m.triangles.end(), {id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

/// Planar n x n vertex grid in z = 0 over [0,1]^2, each square split along one diagonal
/// (interior vertices valence 6): a mesh with one boundary loop.
inline TriangleMesh grid(int n = 5) {
  TriangleMesh m;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      m.positions.insert(m.positions.end(), {double(j) / (n - 1), double(i) / (n - 1), 0.0});
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(i * n + j); };
  for (int i = 0; i + 1 < n; ++i)
    for (int j = 0; j + 1 < n; ++j) {
      m.triangles.insert(m.triangles.end(), {id(i, j), id(i, j + 1), id(i + 1, j + 1)});
      m.triangles.insert(m.triangles.end(), {id(i, j), id(i + 1, j + 1), id(i + 1, j)});
    }
  return m;
}

/// A fan: one centre vertex of valence `valence` with a ring, closed into a double cone
/// (two apexes of valence `valence`, ring vertices of valence 4). Closed, genus 0.
inline TriangleMesh bicone(int valence) {
  TriangleMesh m;
  m.positions.insert(m.positions.end(), {0, 0, 1});
  m.positions.insert(m.positions.end(), {0, 0, -1});
  for (int i = 0; i < valence; ++i) {
    const double a = 2 * M_PI * i / valence;
    m.positions.insert(m.positions.end(), {std::cos(a), std::sin(a), 0.1 * std::sin(3 * a)});
  }
  for (int i = 0; i < valence; ++i) {
    const std::uint32_t r0 = 2 + i, r1 = 2 + (i + 1) % valence;
    m.triangles.insert(m.triangles.end(), {0, r0, r1});
    m.triangles.insert(m.triangles.end(), {1, r1, r0});
  }
  return m;
}

/// An open fan: centre vertex of the given valence and its ring (a disk with a boundary).
inline TriangleMesh disk(int valence) {
  TriangleMesh m;
  m.positions.insert(m.positions.end(), {0, 0, 0.2});
  for (int i = 0; i < valence; ++i) {
    const double a = 2 * M_PI * i / valence;
    m.positions.insert(m.positions.end(), {std::cos(a), std::sin(a), 0.05 * std::cos(2 * a)});
  }
  for (int i = 0; i < valence; ++i)
    m.triangles.insert(m.triangles.end(), {0, std::uint32_t(1 + i), std::uint32_t(1 + (i + 1) % valence)});
  return m;
}

/// Uniform random values in [-1, 1] (deterministic seed).
inline std::vector<double> random_values(std::size_t count, unsigned seed = 1) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> v(count);
  for (auto& x : v) x = u(rng);
  return v;
}

/// `mesh` with every coordinate moved by up to ±amplitude (deterministic, random_values(seed)).
template <typename Mesh>
Mesh perturbed(Mesh mesh, double amplitude, unsigned seed) {
  const std::vector<double> noise = random_values(mesh.positions.size(), seed);
  for (std::size_t i = 0; i < noise.size(); ++i) mesh.positions[i] += amplitude * noise[i];
  return mesh;
}

/// Unit cube as 6 quads (all vertices valence 3).
inline PolygonMesh cube_quads() {
  PolygonMesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
  m.face_indices = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
  m.face_offsets = {0, 4, 8, 12, 16, 20, 24};
  return m;
}

// Open n x n quad grid over [0,1]^2 with non-planar heights.
inline PolygonMesh open_quad_grid(int n) {
  PolygonMesh m;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double x = double(j) / n, y = double(i) / n;
      m.positions.insert(m.positions.end(), {x, y, 0.3 * std::sin(3 * x) * std::cos(2 * y) + 0.1 * x * y});
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const auto id = [n](int a, int b) { return static_cast<std::uint32_t>(a * (n + 1) + b); };
      m.face_indices.insert(m.face_indices.end(), {id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)});
      m.face_offsets.push_back(static_cast<std::uint32_t>(m.face_indices.size()));
    }
  return m;
}

// Closed pentagonal pyramid: apex of valence 5, five triangles and one pentagon.
inline PolygonMesh pentagonal_pyramid() {
  PolygonMesh m;
  m.positions = {0.1, -0.05, 1.2};
  for (int i = 0; i < 5; ++i) {
    const double a = 2 * M_PI * i / 5;
    m.positions.insert(m.positions.end(), {std::cos(a), 0.9 * std::sin(a), 0.1 * std::cos(2 * a)});
  }
  for (std::uint32_t i = 0; i < 5; ++i) {
    m.face_indices.insert(m.face_indices.end(), {0, 1 + i, 1 + (i + 1) % 5});
    m.face_offsets.push_back(static_cast<std::uint32_t>(m.face_indices.size()));
  }
  m.face_indices.insert(m.face_indices.end(), {5, 4, 3, 2, 1});
  m.face_offsets.push_back(static_cast<std::uint32_t>(m.face_indices.size()));
  return m;
}

}  // namespace meshlift::test
