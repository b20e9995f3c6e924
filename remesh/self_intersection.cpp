// Self-intersections of a triangle mesh (self_intersection.h): Embree's rtcCollide proposes the
// pairs of faces whose boxes meet; orientation tests decide them.
#include "meshlift/self_intersection.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <string>

#include "adjacency.h"
#include "vec3.h"

namespace meshlift {
namespace {

using namespace vec3;  // Vec3, at, sub, dot, cross
using Vec = Vec3;

/// Sign of x.
int sign(double x) { return (x > 0) - (x < 0); }

/// The orientation of tetrahedra (a, b, c, d) for one triangle abc and several points d: the sign
/// of det[b - a, c - a, d - a] = (b - a) × (c - a) · (d - a), positive when d is on the side of
/// abc's plane that abc's counter-clockwise normal points to. The normal is computed once.
struct Plane {
  Vec a, normal;
  Plane(const Vec& a_, const Vec& b, const Vec& c) : a(a_), normal(cross(sub(b, a_), sub(c, a_))) {}
  int side(const Vec& d) const { return sign(dot(normal, sub(d, a))); }
};

/// Segment pq crosses the inside of triangle abc (strictly: no touching), given the sides sp,
/// sq of p and q against abc's plane.
bool crosses(int sp, int sq, const Vec& p, const Vec& q, const Vec& a, const Vec& b, const Vec& c) {
  if (sp == 0 || sq == 0 || sp == sq) return false;
  const int s1 = Plane(p, q, a).side(b), s2 = Plane(p, q, b).side(c), s3 = Plane(p, q, c).side(a);
  return s1 != 0 && s1 == s2 && s2 == s3;
}

struct Collide {
  const TriangleMesh* mesh;
  std::mutex lock;
  std::vector<std::array<std::uint32_t, 2>> pairs;

  bool intersect(std::uint32_t f, std::uint32_t g) const {
    const std::uint32_t* s = &mesh->triangles[3 * std::size_t{f}];
    const std::uint32_t* t = &mesh->triangles[3 * std::size_t{g}];
    int shared = 0, is = -1, it = -1;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (s[i] == t[j]) ++shared, is = i, it = j;
    if (shared >= 2) return false;
    const std::vector<double>& x = mesh->positions;
    const Vec S[3] = {at(x, s[0]), at(x, s[1]), at(x, s[2])}, T[3] = {at(x, t[0]), at(x, t[1]), at(x, t[2])};
    // Each corner's side of the other triangle's plane, once (an edge crosses a triangle only
    // between corners on strictly opposite sides: most box pairs end here).
    const Plane s_plane(S[0], S[1], S[2]), t_plane(T[0], T[1], T[2]);
    const int s_side[3] = {t_plane.side(S[0]), t_plane.side(S[1]), t_plane.side(S[2])};
    const int t_side[3] = {s_plane.side(T[0]), s_plane.side(T[1]), s_plane.side(T[2])};
    auto s_edge_crosses_t = [&](int i) {
      const int j = (i + 1) % 3;
      return crosses(s_side[i], s_side[j], S[i], S[j], T[0], T[1], T[2]);
    };
    auto t_edge_crosses_s = [&](int i) {
      const int j = (i + 1) % 3;
      return crosses(t_side[i], t_side[j], T[i], T[j], S[0], S[1], S[2]);
    };
    if (shared == 0) {
      for (int i = 0; i < 3; ++i)
        if (s_edge_crosses_t(i) || t_edge_crosses_s(i)) return true;
      return false;
    }
    // One common corner: the edges opposite it.
    return s_edge_crosses_t((is + 1) % 3) || t_edge_crosses_s((it + 1) % 3);
  }
};

void bounds(const RTCBoundsFunctionArguments* args) {
  const auto* c = static_cast<const Collide*>(args->geometryUserPtr);
  const std::uint32_t* t = &c->mesh->triangles[3 * std::size_t{args->primID}];
  const std::vector<double>& x = c->mesh->positions;
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::min({x[3 * t[0] + k], x[3 * t[1] + k], x[3 * t[2] + k]});
    hi[k] = std::max({x[3 * t[0] + k], x[3 * t[1] + k], x[3 * t[2] + k]});
  }
  // Rounded outwards to floats, so that the float boxes contain the double triangles.
  RTCBounds* b = args->bounds_o;
  b->lower_x = std::nextafter(static_cast<float>(lo[0]), -INFINITY);
  b->lower_y = std::nextafter(static_cast<float>(lo[1]), -INFINITY);
  b->lower_z = std::nextafter(static_cast<float>(lo[2]), -INFINITY);
  b->upper_x = std::nextafter(static_cast<float>(hi[0]), INFINITY);
  b->upper_y = std::nextafter(static_cast<float>(hi[1]), INFINITY);
  b->upper_z = std::nextafter(static_cast<float>(hi[2]), INFINITY);
}

void collided(void* user, RTCCollision* collisions, unsigned int count) {
  auto* c = static_cast<Collide*>(user);
  std::vector<std::array<std::uint32_t, 2>> found;
  for (unsigned int i = 0; i < count; ++i) {
    const std::uint32_t f = std::min(collisions[i].primID0, collisions[i].primID1);
    const std::uint32_t g = std::max(collisions[i].primID0, collisions[i].primID1);
    if (f != g && c->intersect(f, g)) found.push_back({f, g});
  }
  if (found.empty()) return;
  const std::lock_guard<std::mutex> guard(c->lock);
  c->pairs.insert(c->pairs.end(), found.begin(), found.end());
}

}  // namespace

std::vector<std::array<std::uint32_t, 2>> self_intersections(const TriangleMesh& mesh, std::size_t max_pairs,
                                                             std::size_t* total) {
  const std::size_t vertices = mesh.vertex_count();
  for (const double v : mesh.positions)
    if (!std::isfinite(v) || std::abs(v) > 1e30) throw MeshError("self_intersections: a coordinate is not finite or too large");
  for (const std::uint32_t i : mesh.triangles)
    if (i >= vertices) throw MeshError("self_intersections: index " + std::to_string(i) + " names no vertex");
  Collide c{&mesh, {}, {}};
  if (mesh.face_count() > 1) {
    RTCDevice device = rtcNewDevice(nullptr);
    if (!device) throw MeshError("self_intersections: Embree device creation failed");
    RTCScene scene = rtcNewScene(device);
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(geometry, static_cast<unsigned int>(mesh.face_count()));
    rtcSetGeometryUserData(geometry, &c);
    rtcSetGeometryBoundsFunction(geometry, bounds, nullptr);
    // Embree's quickest build: the collision query reports every pair of overlapping boxes
    // whatever the tree, and one query does not pay for a finer one (a 3.3 M-vertex mesh: 8.0 s
    // for `meshlift info` with the default MEDIUM, 6.4-7.8 with LOW; docs/RESULTS.md).
    rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_LOW);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_LOW);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene);
    rtcCollide(scene, scene, collided, &c);
    const bool failed = rtcGetDeviceError(device) != RTC_ERROR_NONE;
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
    if (failed) throw MeshError("self_intersections: Embree's collision query failed");
  }
  std::sort(c.pairs.begin(), c.pairs.end());
  c.pairs.erase(std::unique(c.pairs.begin(), c.pairs.end()), c.pairs.end());
  if (total) *total = c.pairs.size();
  if (c.pairs.size() > max_pairs) c.pairs.resize(max_pairs);
  return std::move(c.pairs);
}

std::vector<std::uint8_t> faces_near_marked(const TriangleMesh& mesh, const std::vector<std::uint8_t>& marked, int rings) {
  // Rings grown a corner at a time: a face reached joins the ring, and its corners the next front.
  const Adjacency adjacency(static_cast<std::uint32_t>(mesh.positions.size() / 3), mesh.triangles);
  std::vector<std::uint8_t> near(mesh.face_count(), 0), reached(marked.begin(), marked.end());
  std::vector<std::uint32_t> front;
  for (std::uint32_t f = 0; f < mesh.face_count(); ++f)
    if (marked[f]) front.push_back(f);
  for (int ring = 0; ring < rings && !front.empty(); ++ring) {
    std::vector<std::uint32_t> next;
    for (const std::uint32_t f : front)
      for (int i = 0; i < 3; ++i) {
        const std::uint32_t v = mesh.triangles[3 * std::size_t{f} + static_cast<std::size_t>(i)];
        for (std::uint32_t k = adjacency.face_offsets[v]; k < adjacency.face_offsets[v + 1]; ++k) {
          const std::uint32_t g = adjacency.faces[k];
          if (!reached[g]) reached[g] = near[g] = 1, next.push_back(g);
        }
      }
    front = std::move(next);
  }
  return near;
}

}  // namespace meshlift
