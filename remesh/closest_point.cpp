// Closest point on a triangle (Ericson §5.1.5) and closest point on a mesh (Embree 3 BVH,
// rtcPointQuery with an exact double-precision callback). The float caveat is in closest_point.h.
#include "meshlift/closest_point.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "vec3.h"

namespace meshlift {

namespace {

using vec3::Vec3;
using vec3::closest_on_segment;
using vec3::cross;
using vec3::dot;
using vec3::sub;

/// a + v·ab + w·ac
Vec3 combine(const Vec3& a, const Vec3& ab, double v, const Vec3& ac, double w) {
  return {a[0] + v * ab[0] + w * ac[0], a[1] + v * ab[1] + w * ac[1], a[2] + v * ab[2] + w * ac[2]};
}
double squared_distance(const Vec3& u, const Vec3& v) {
  const Vec3 d = sub(u, v);
  return dot(d, d);
}

/// A degenerate triangle is the union of its edges: the best of the three segment projections
/// (ties to the first edge tried, so the answer is deterministic).
TrianglePoint closest_on_degenerate_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3* corners[3] = {&a, &b, &c};
  TrianglePoint best{};
  double best_distance2 = std::numeric_limits<double>::infinity();
  for (int edge = 0; edge < 3; ++edge) {
    const int i = edge, j = (edge + 1) % 3;
    const double t = closest_on_segment(p, *corners[i], *corners[j]);
    const Vec3 d = sub(*corners[j], *corners[i]);
    const Vec3 q = {(*corners[i])[0] + t * d[0], (*corners[i])[1] + t * d[1], (*corners[i])[2] + t * d[2]};
    const double distance2 = squared_distance(p, q);
    if (distance2 < best_distance2) {
      best_distance2 = distance2;
      best.point = q;
      best.barycentric = {0, 0, 0};
      best.barycentric[i] = 1 - t;
      best.barycentric[j] = t;
    }
  }
  return best;
}

}  // namespace

TrianglePoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = sub(b, a), ac = sub(c, a);
  // Collinear or coincident corners: Ericson's region tests divide by |ab|², |ac|², |bc|² or
  // |ab × ac|², one of which is (nearly) zero; sin²(angle at a) < 1e-24 counts as degenerate.
  const Vec3 normal = cross(ab, ac);
  if (!(dot(normal, normal) > 1e-24 * dot(ab, ab) * dot(ac, ac))) return closest_on_degenerate_triangle(p, a, b, c);

  // Ericson §5.1.5: classify p against the Voronoi regions of the corners, the edges and the face.
  const Vec3 ap = sub(p, a);
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return {a, {1, 0, 0}};  // vertex region A

  const Vec3 bp = sub(p, b);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return {b, {0, 1, 0}};  // vertex region B

  // Edge region AB: vc = d1·d4 − d3·d2 ≤ 0, projection v = d1 / (d1 − d3) (d1 − d3 = |ab|² > 0).
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return {combine(a, ab, v, ac, 0), {1 - v, v, 0}};
  }

  const Vec3 cp = sub(p, c);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return {c, {0, 0, 1}};  // vertex region C

  // Edge region AC: vb = d5·d2 − d1·d6 ≤ 0, w = d2 / (d2 − d6) (d2 − d6 = |ac|² > 0).
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return {combine(a, ab, 0, ac, w), {1 - w, 0, w}};
  }

  // Edge region BC: va = d3·d6 − d5·d4 ≤ 0, w = (d4 − d3) / ((d4 − d3) + (d5 − d6)) (sum = |bc|²).
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    const Vec3 bc = sub(c, b);
    return {{b[0] + w * bc[0], b[1] + w * bc[1], b[2] + w * bc[2]}, {0, 1 - w, w}};
  }

  // Face region: va, vb, vc > 0 here; barycentrics (va, vb, vc) / (va + vb + vc).
  const double denominator = 1 / (va + vb + vc);
  const double v = vb * denominator, w = vc * denominator;
  return {combine(a, ab, v, ac, w), {1 - v - w, v, w}};
}

struct SurfaceQuery::Impl {
  TriangleMesh mesh;
  double max_coordinate = 0;  // largest |coordinate| of the mesh (for the float margin)
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

/// State of one query, handed to the callback through userPtr.
struct QueryState {
  const TriangleMesh* mesh;
  Vec3 p;
  double margin;  // 4δ of the header's caveat
  SurfacePoint best;
  double best_distance2 = std::numeric_limits<double>::infinity();
};

Vec3 vertex(const TriangleMesh& mesh, std::uint32_t v) {
  return {mesh.positions[3 * std::size_t(v)], mesh.positions[3 * std::size_t(v) + 1],
          mesh.positions[3 * std::size_t(v) + 2]};
}

/// Smallest float ≥ x (x ≥ 0).
float float_at_least(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

bool closest_point_callback(RTCPointQueryFunctionArguments* args) {
  auto& state = *static_cast<QueryState*>(args->userPtr);
  const std::uint32_t face = args->primID;
  const TriangleMesh& mesh = *state.mesh;
  const Vec3 a = vertex(mesh, mesh.triangles[3 * std::size_t(face)]), b = vertex(mesh, mesh.triangles[3 * std::size_t(face) + 1]),
             c = vertex(mesh, mesh.triangles[3 * std::size_t(face) + 2]);
  // The triangle's bounding box is no nearer than the triangle: when even the box is farther
  // than the best point so far, the exact test cannot win (Embree only culls whole leaves).
  double box_distance2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double gap = std::max({std::min({a[k], b[k], c[k]}) - state.p[k], state.p[k] - std::max({a[k], b[k], c[k]}), 0.0});
    box_distance2 += gap * gap;
  }
  if (box_distance2 > state.best_distance2) return false;
  const TrianglePoint candidate = closest_point_on_triangle(state.p, a, b, c);
  const double distance2 = squared_distance(state.p, candidate.point);
  // Ties go to the lowest face index, whatever order the BVH visits faces in.
  if (distance2 < state.best_distance2 || (distance2 == state.best_distance2 && face < state.best.face)) {
    state.best_distance2 = distance2;
    state.best.point = candidate.point;
    state.best.barycentric = candidate.barycentric;
    state.best.face = face;
    // Shrink to the conservative radius (d + 4δ)(1 + 2^-20) of the header's caveat, never below.
    const float radius = float_at_least((std::sqrt(distance2) + state.margin) * (1 + 0x1p-20));
    if (radius < args->query->radius) {
      args->query->radius = radius;
      return true;
    }
  }
  return false;
}

}  // namespace

SurfaceQuery::SurfaceQuery(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
  if (mesh.face_count() == 0) throw MeshError("closest-point query: the mesh has no faces");
  if (mesh.positions.size() % 3 != 0 || mesh.triangles.size() % 3 != 0)
    throw MeshError("closest-point query: position or index array length is not a multiple of 3");
  if (mesh.face_count() > std::numeric_limits<unsigned>::max() - 1)
    throw MeshError("closest-point query: too many faces for Embree");
  for (double x : mesh.positions) {
    if (!std::isfinite(x) || std::abs(x) > 1e30)
      throw MeshError("closest-point query: a vertex coordinate is not finite (or beyond 1e30)");
    impl_->max_coordinate = std::max(impl_->max_coordinate, std::abs(x));
  }
  const std::size_t vertex_count = mesh.vertex_count();
  for (std::size_t f = 0; f < mesh.face_count(); ++f)
    for (int i = 0; i < 3; ++i)
      if (mesh.triangles[3 * f + i] >= vertex_count)
        throw MeshError("closest-point query: face " + std::to_string(f) + " names vertex " +
                        std::to_string(mesh.triangles[3 * f + i]) + " of " + std::to_string(vertex_count));
  impl_->mesh = mesh;

  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device) throw MeshError("closest-point query: Embree device creation failed");
  impl_->scene = rtcNewScene(impl_->device);
  RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  // Embree reads 16 bytes for the last vertex (SSE loads): one padding float.
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                                               RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                               vertex_count + 1));
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0,
                                                                 RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                                                 mesh.face_count()));
  if (!vertices || !indices) {
    rtcReleaseGeometry(geometry);
    throw MeshError("closest-point query: Embree could not allocate the mesh buffers");
  }
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) vertices[i] = static_cast<float>(mesh.positions[i]);
  vertices[mesh.positions.size()] = vertices[mesh.positions.size() + 1] = vertices[mesh.positions.size() + 2] = 0;
  std::copy(mesh.triangles.begin(), mesh.triangles.end(), indices);
  // Embree's quickest build: the remesh builds a BVH of its own mesh every least-squares round,
  // and its queries start from a hint face, so a finer tree does not pay for its build (measured,
  // armadillo's automatic remesh, identical results: LOW 2.66-2.87 s, the default MEDIUM
  // 2.86-3.22 s, HIGH 3.5-4.0 s; docs/RESULTS.md).
  rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_LOW);
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(impl_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_LOW);
  rtcCommitScene(impl_->scene);
  if (rtcGetDeviceError(impl_->device) != RTC_ERROR_NONE)
    throw MeshError("closest-point query: Embree failed to build the BVH");
}

SurfaceQuery::~SurfaceQuery() = default;
SurfaceQuery::SurfaceQuery(SurfaceQuery&&) noexcept = default;
SurfaceQuery& SurfaceQuery::operator=(SurfaceQuery&&) noexcept = default;

const TriangleMesh& SurfaceQuery::mesh() const { return impl_->mesh; }

SurfacePoint SurfaceQuery::closest(const std::array<double, 3>& p) const { return closest(p, kNone); }

SurfacePoint SurfaceQuery::closest(const std::array<double, 3>& p, std::uint32_t hint_face) const {
  if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
    throw MeshError("closest-point query: the query point is not finite");
  QueryState state{&impl_->mesh, p, 0, {}};
  if (std::max({std::abs(p[0]), std::abs(p[1]), std::abs(p[2])}) > 1e30) {
    // Beyond float range Embree cannot place the point: scan every face (same callback rule).
    for (std::uint32_t f = 0; f < impl_->mesh.face_count(); ++f) {
      RTCPointQuery unused{};
      unused.radius = std::numeric_limits<float>::infinity();
      RTCPointQueryFunctionArguments args{};
      args.query = &unused;
      args.userPtr = &state;
      args.primID = f;
      closest_point_callback(&args);
    }
    state.best.distance = std::sqrt(state.best_distance2);
    return state.best;
  }
  const double magnitude = std::max({impl_->max_coordinate, std::abs(p[0]), std::abs(p[1]), std::abs(p[2])});
  state.margin = 4 * std::sqrt(3.0) * 0x1p-24 * magnitude;  // 4δ, δ = √3·2^-24·M

  RTCPointQuery query;
  query.x = static_cast<float>(p[0]);
  query.y = static_cast<float>(p[1]);
  query.z = static_cast<float>(p[2]);
  query.time = 0;
  query.radius = std::numeric_limits<float>::infinity();
  if (hint_face < impl_->mesh.face_count()) {
    // The hint is a candidate like any visited face (same tie rule), and it shrinks the radius
    // before the traversal starts.
    RTCPointQueryFunctionArguments args{};
    args.query = &query;
    args.userPtr = &state;
    args.primID = hint_face;
    closest_point_callback(&args);
  }
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(impl_->scene, &query, &context, closest_point_callback, &state);

  state.best.distance = std::sqrt(state.best_distance2);
  return state.best;
}

SurfacePoint SurfaceQuery::first_hit(const std::array<double, 3>& origin, const std::array<double, 3>& direction,
                                     double max_distance) const {
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(origin[k]) || !std::isfinite(direction[k]))
      throw MeshError("ray query: the ray's origin or direction is not finite");
  const double length = std::sqrt(direction[0] * direction[0] + direction[1] * direction[1] + direction[2] * direction[2]);
  if (length == 0) throw MeshError("ray query: the ray's direction is zero");
  RTCRayHit ray{};
  ray.ray.org_x = static_cast<float>(origin[0]);
  ray.ray.org_y = static_cast<float>(origin[1]);
  ray.ray.org_z = static_cast<float>(origin[2]);
  ray.ray.dir_x = static_cast<float>(direction[0] / length);
  ray.ray.dir_y = static_cast<float>(direction[1] / length);
  ray.ray.dir_z = static_cast<float>(direction[2] / length);
  ray.ray.tnear = 0;
  ray.ray.tfar = static_cast<float>(std::min(max_distance * length, 1e30));
  ray.ray.mask = 0xFFFFFFFFu;
  ray.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersect1(impl_->scene, &context, &ray);
  SurfacePoint hit;
  if (ray.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.face = ray.hit.primID;
  // Embree's (u, v) weigh corners 1 and 2.
  const double u = ray.hit.u, v = ray.hit.v;
  hit.barycentric = {1 - u - v, u, v};
  const TriangleMesh& mesh = impl_->mesh;
  for (int i = 0; i < 3; ++i) {
    const Vec3 c = vertex(mesh, mesh.triangles[3 * std::size_t(hit.face) + i]);
    for (int k = 0; k < 3; ++k) hit.point[k] += hit.barycentric[i] * c[k];
  }
  hit.distance = std::sqrt(squared_distance(origin, hit.point));
  return hit;
}

}  // namespace meshlift
