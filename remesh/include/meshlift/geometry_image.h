// Spherical geometry images (seed 003 §5.1.3, CODEC-NOTES §6; Praun & Hoppe 2003 §5): the sphere
// is mapped onto the octahedron |x| + |y| + |z| = 1, the octahedron is unfolded onto the square
// [-1, 1]², and the square is sampled on an n × n grid. The same samples are a semi-regular mesh
// whose base is the octahedron refined L times, n = 2^(L+1) + 1.
//
// Octahedron base (octahedron()): vertices 0 +x, 1 +y, 2 −x, 3 −y, 4 +z, 5 −z; faces
// (0 1 4) (1 2 4) (2 3 4) (3 0 4) (1 0 5) (2 1 5) (3 2 5) (0 3 5), counter-clockwise from outside.
//
// Sphere <-> octahedron: central projection, o = s / (|s_x| + |s_y| + |s_z|), s = o / |o|.
//
// Octahedron <-> square (the standard octahedral unfolding): a point o = (x, y, z) goes to
//   (u, v) = (x, y)                                  if z >= 0 (the upper half: the inner diamond |u| + |v| <= 1),
//   (u, v) = (sgn x · (1 − |y|), sgn y · (1 − |x|))  if z < 0  (the lower half, folded into the four corners),
// with sgn 0 = +1; back: z = 1 − |u| − |v|, and (x, y) = (u, v) if z >= 0, else
// (sgn u · (1 − |v|), sgn v · (1 − |u|)). Each face goes affinely onto a right triangle of the
// square, so the regular 1:4 refinement of the octahedron is the regular grid triangulation.
// Pixel (row r, column c) of an n × n image sits at u = 2c/(n−1) − 1, v = 1 − 2r/(n−1) (row 0 at
// the top, v = +1). The unfolding identifies the two halves of each side of the square (mirror
// images about the side's midpoint) and the four corners (all −z): those pixels are one vertex
// of the mesh and hold identical samples.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "meshlift/mesh.h"
#include "meshlift/semi_regular.h"
#include "meshlift/spherical_parametrization.h"

namespace meshlift {

/// Largest supported image side (L = 11): 4097² samples.
inline constexpr int kMaxGeometryImageSize = 4097;

/// An n × n image of xyz samples, row-major: pixel (r, c) is samples[3 (r n + c) + k].
struct GeometryImage {
  int size = 0;
  std::vector<double> samples;
};

/// n = 2^(L+1) + 1.  \throw MeshError unless 0 <= levels <= 11.
int geometry_image_size(int levels);
/// L with n = 2^(L+1) + 1.  \throw MeshError if `size` is not of that form or exceeds kMaxGeometryImageSize.
int geometry_image_levels(int size);

/// The octahedron base mesh described above (unit vertices).
TriangleMesh octahedron();

/// The sphere point of octahedron point o (|x| + |y| + |z| = 1): the central projection o / |o|.
std::array<double, 3> octahedron_to_sphere(const std::array<double, 3>& o);

/// The octahedron point of pixel (row, column) of an n × n image (exact: dyadic coordinates).
std::array<double, 3> octahedron_point(int row, int column, int size);
/// The pixel an octahedron point unfolds to, (row, column), by the forward rule above (for a
/// point on a fold, the one side that rule picks). \pre |x| + |y| + |z| = 1 and the point is a grid point.
std::array<int, 2> octahedron_pixel(const std::array<double, 3>& point, int size);

/// For each pixel (row-major), its vertex in the semi-regular octahedron hierarchy with
/// geometry_image_levels(size) levels (vertices numbered as SemiRegularHierarchy numbers them;
/// identified border pixels share one vertex).
std::vector<std::uint32_t> pixel_vertices(int size);

/// The image as a semi-regular mesh: octahedron() refined L times, each vertex at the sample of
/// the pixel octahedron_pixel() gives it (on the border: the canonical one of the identified pixels).
SemiRegularMesh image_to_mesh(const GeometryImage& image);
/// The mesh as an image (every pixel the position of its vertex, so identified pixels are equal).
/// \throw MeshError if the mesh's base is not octahedron()'s connectivity or its positions do not
///        cover the finest level.
GeometryImage mesh_to_image(const SemiRegularMesh& mesh);

/// Samples the surface of `mesh` at the octahedron grid of `levels` refinements: each vertex's
/// octahedron point is projected to the sphere, located in the spherical triangulation given by
/// `sphere` (a point-location walk over chord triangles, coherent from one grid sample to the
/// next), and interpolated with its barycentric coordinates on the input triangle (seed 002 ch. 9;
/// the weights of point s in chord triangle abc are det(s,b,c) : det(a,s,c) : det(a,b,s), i.e.
/// barycentrics of the ray through s on the flat triangle). \pre `sphere` is bijective.
SemiRegularMesh sample_sphere_remesh(const TriangleMesh& mesh, std::span<const double> sphere, int levels);

/// The semi-regular remesh of a closed genus-0 mesh through its spherical parametrization.
struct SphereRemesh {
  SemiRegularMesh mesh;
  SphericalParametrization parametrization;
};
/// \throw MeshError when the mesh is unsuitable (sphere_parametrization_problem()'s message) or
///        levels is outside 0..11.
SphereRemesh remesh_sphere_detailed(const TriangleMesh& mesh, int levels,
                                    const SphericalParametrizationOptions& options = {});
/// Same, the mesh only: 6 base vertices, 8 base faces, refined `levels` times, 4^(L+1) + 2 vertices.
SemiRegularMesh remesh_sphere(const TriangleMesh& mesh, int levels);

}  // namespace meshlift
