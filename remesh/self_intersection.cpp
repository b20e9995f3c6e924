// Self-intersections of a triangle mesh (self_intersection.h): Embree's rtcCollide proposes the
// pairs of faces whose boxes meet; orientation tests decide them.
#include "meshlift/self_intersection.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <string>

#include "vec3.h"

namespace meshlift {
namespace {

using namespace vec3;  // Vec3, at, sub, dot, cross
using Vec = Vec3;

/// Sign of the volume of tetrahedron (a, b, c, d): det[b - a, c - a, d - a], positive when d is
/// on the side of abc's plane that abc's counter-clockwise normal points to.
int orient(const Vec& a, const Vec& b, const Vec& c, const Vec& d) {
  const double v = dot(cross(sub(b, a), sub(c, a)), sub(d, a));
  return (v > 0) - (v < 0);
}

/// Segment pq crosses the inside of triangle abc (strictly: no touching).
bool crosses(const Vec& p, const Vec& q, const Vec& a, const Vec& b, const Vec& c) {
  const int sp = orient(a, b, c, p), sq = orient(a, b, c, q);
  if (sp == 0 || sq == 0 || sp == sq) return false;
  const int s1 = orient(p, q, a, b), s2 = orient(p, q, b, c), s3 = orient(p, q, c, a);
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
    const std::vector<double>& x = mesh->positions;
    const Vec S[3] = {at(x, s[0]), at(x, s[1]), at(x, s[2])}, T[3] = {at(x, t[0]), at(x, t[1]), at(x, t[2])};
    if (shared == 0) {
      for (int i = 0; i < 3; ++i)
        if (crosses(S[i], S[(i + 1) % 3], T[0], T[1], T[2]) || crosses(T[i], T[(i + 1) % 3], S[0], S[1], S[2])) return true;
      return false;
    }
    if (shared == 1)  // the edges opposite the common corner
      return crosses(S[(is + 1) % 3], S[(is + 2) % 3], T[0], T[1], T[2]) ||
             crosses(T[(it + 1) % 3], T[(it + 2) % 3], S[0], S[1], S[2]);
    return false;
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
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
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

}  // namespace meshlift
