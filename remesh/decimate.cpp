// Base mesh by quadric-error halfedge collapse: seed 002 §8.3.5 (edge collapse, the merged
// vertex placed at one of the old ones, Figure 8.15a) with Garland & Heckbert's priority
// ("Surface Simplification Using Quadric Error Metrics", SIGGRAPH 1997), run by OpenMesh's
// DecimaterT, whose is_collapse_legal() keeps the topology (link condition, no tetrahedron
// collapse, boundary vertices only along boundary edges).
#include "meshlift/decimate.h"

#include <OpenMesh/Core/Utils/vector_traits.hh>  // QuadricT.hh uses it without including it
#include <OpenMesh/Core/Geometry/QuadricT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModAspectRatioT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/Observer.hh>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <numeric>
#include <span>
#include <stdexcept>
#include <string>

#include "meshlift/features.h"
#include "meshlift/validate.h"
#include "halfedge_mesh.h"

namespace meshlift {

namespace {

using Quadric = OpenMesh::Geometry::Quadricd;

// Weight of a boundary edge's constraint plane relative to a face plane of the same size
// (both scale with length²). Garland & Heckbert §6.2 give boundary edges a perpendicular plane
// "weighted by a large penalty factor"; 10 keeps boundary corners against flat-region collapses
// without letting boundary edges dominate the curvature of the interior.
constexpr double kBoundaryPlaneWeight = 10.0;

/// Priority module: Garland-Heckbert quadrics as in OpenMesh's ModQuadricT (area-weighted face
/// planes summed at the vertices, Q(v1) += Q(v0) after each collapse, cost Q(v0)+Q(v1) at p1),
/// plus one constraint plane per boundary edge, perpendicular to its face and through the edge,
/// added to both ends. ModQuadricT has no boundary term and keeps its quadrics private, hence
/// this copy of its few lines.
template <typename MeshT>
class ModBoundaryQuadricT : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModBoundaryQuadricT, MeshT, BoundaryQuadric);

  explicit ModBoundaryQuadricT(MeshT& mesh) : Base(mesh, false) { mesh.add_property(quadrics_); }
  ~ModBoundaryQuadricT() override { Base::mesh().remove_property(quadrics_); }

  void initialize() override {
    MeshT& m = Base::mesh();
    for (const auto v : m.vertices()) m.property(quadrics_, v).clear();
    // Face plane n·x + d = 0 weighted by the face area (ModQuadricT_impl.hh).
    for (const auto f : m.faces()) {
      auto corner = m.cfv_begin(f);
      const auto v0 = *corner, v1 = *++corner, v2 = *++corner;
      const auto& p0 = m.point(v0);
      OpenMesh::Vec3d n = (m.point(v1) - p0) % (m.point(v2) - p0);
      const double twice_area = n.norm();
      if (twice_area <= DBL_MIN) continue;  // a zero-area face has no plane
      n /= twice_area;
      Quadric q(n[0], n[1], n[2], -(n | p0));
      q *= 0.5 * twice_area;
      m.property(quadrics_, v0) += q;
      m.property(quadrics_, v1) += q;
      m.property(quadrics_, v2) += q;
    }
    // Boundary edge a→b of face f (normal n): plane with normal (b − a) × n through a, weight
    // kBoundaryPlaneWeight·|b − a|² (Garland & Heckbert §6.2).
    for (const auto h : m.halfedges()) {
      if (!m.is_boundary(h)) continue;
      const auto inner = m.opposite_halfedge_handle(h);
      const auto a = m.from_vertex_handle(inner), b = m.to_vertex_handle(inner);
      const OpenMesh::Vec3d edge = m.point(b) - m.point(a);
      const OpenMesh::Vec3d n = m.calc_face_normal(m.face_handle(inner));
      OpenMesh::Vec3d across = edge % n;
      const double length = across.norm();
      if (length <= DBL_MIN) continue;
      across /= length;
      Quadric q(across[0], across[1], across[2], -(across | m.point(a)));
      q *= kBoundaryPlaneWeight * edge.sqrnorm();
      m.property(quadrics_, a) += q;
      m.property(quadrics_, b) += q;
    }
  }

  float collapse_priority(const CollapseInfo& ci) override {
    Quadric q = Base::mesh().property(quadrics_, ci.v0);
    q += Base::mesh().property(quadrics_, ci.v1);
    return static_cast<float>(q(ci.p1));
  }

  void postprocess_collapse(const CollapseInfo& ci) override {
    Base::mesh().property(quadrics_, ci.v1) += Base::mesh().property(quadrics_, ci.v0);
  }

 private:
  OpenMesh::VPropHandleT<Quadric> quadrics_;
};

/// Binary module: no face may turn away from the input surface at its corners. A face is
/// refused when its normal after the collapse makes an angle of 90° or more with the input's
/// area-weighted vertex normal at one of its corners (vertices keep their identity, so the input
/// normals stay valid). ModNormalFlippingT only bounds the turn of one collapse against the
/// normals just before it, so turns can accumulate over many collapses; this bounds the result.
template <typename MeshT>
class ModInputNormalT : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModInputNormalT, MeshT, InputNormal);

  explicit ModInputNormalT(MeshT& mesh) : Base(mesh, true) { mesh.add_property(input_normal_); }
  ~ModInputNormalT() override { Base::mesh().remove_property(input_normal_); }

  void initialize() override {
    MeshT& m = Base::mesh();
    for (const auto v : m.vertices()) m.property(input_normal_, v) = OpenMesh::Vec3d(0, 0, 0);
    for (const auto f : m.faces()) {
      auto corner = m.cfv_begin(f);
      const auto v0 = *corner, v1 = *++corner, v2 = *++corner;
      const OpenMesh::Vec3d area_vector = (m.point(v1) - m.point(v0)) % (m.point(v2) - m.point(v0));
      for (const auto v : {v0, v1, v2}) m.property(input_normal_, v) += area_vector;
    }
  }

  float collapse_priority(const CollapseInfo& ci) override {
    MeshT& m = Base::mesh();
    bool legal = true;
    m.set_point(ci.v0, ci.p1);  // simulate the collapse, as ModNormalFlippingT does
    for (auto face = m.cvf_begin(ci.v0); legal && face.is_valid(); ++face) {
      if (*face == ci.fl || *face == ci.fr) continue;
      auto corner = m.cfv_begin(*face);
      const auto v0 = *corner, v1 = *++corner, v2 = *++corner;
      const OpenMesh::Vec3d area_vector = (m.point(v1) - m.point(v0)) % (m.point(v2) - m.point(v0));
      for (const auto v : {v0, v1, v2})
        if ((area_vector | m.property(input_normal_, v == ci.v0 ? ci.v1 : v)) <= 0) legal = false;
    }
    m.set_point(ci.v0, ci.p0);
    return legal ? float(Base::LEGAL_COLLAPSE) : float(Base::ILLEGAL_COLLAPSE);
  }

 private:
  OpenMesh::VPropHandleT<OpenMesh::Vec3d> input_normal_;
};

/// Binary module: refuses a collapse that would take a connected component below its floor.
///
/// DecimaterT evaluates the modules only when it (re)queues a vertex, and at the pop re-checks
/// just is_collapse_legal(), so a count that changes far away (the component's) needs more than
/// a veto: once a component reaches its floor, all its vertices are locked, which
/// is_collapse_legal() does check at the pop.
template <typename MeshT>
class ModComponentFloorT : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModComponentFloorT, MeshT, ComponentFloor);

  explicit ModComponentFloorT(MeshT& mesh) : Base(mesh, true) { mesh.add_property(component_); }
  ~ModComponentFloorT() override { Base::mesh().remove_property(component_); }

  /// `component[v]` for every vertex handle index v, `floor[c]` the fewest vertices component c
  /// may keep. Locks the components already at their floor.
  void set_components(const std::vector<std::uint32_t>& component, const std::vector<std::size_t>& floor) {
    members_.assign(floor.size(), {});
    for (const auto v : Base::mesh().vertices()) {
      Base::mesh().property(component_, v) = component[v.idx()];
      members_[component[v.idx()]].push_back(v);
    }
    floor_ = floor;
    remaining_.clear();
    for (std::size_t c = 0; c < floor_.size(); ++c) {
      remaining_.push_back(members_[c].size());
      if (remaining_[c] <= floor_[c]) lock(c);
    }
  }

  float collapse_priority(const CollapseInfo& ci) override {
    const std::uint32_t c = Base::mesh().property(component_, ci.v0);
    return remaining_[c] > floor_[c] ? float(Base::LEGAL_COLLAPSE) : float(Base::ILLEGAL_COLLAPSE);
  }

  void postprocess_collapse(const CollapseInfo& ci) override {
    const std::uint32_t c = Base::mesh().property(component_, ci.v0);
    if (--remaining_[c] <= floor_[c]) lock(c);
  }

 private:
  void lock(std::size_t c) {
    for (const auto v : members_[c]) Base::mesh().status(v).set_locked(true);
  }

  OpenMesh::VPropHandleT<std::uint32_t> component_;
  std::vector<std::vector<typename MeshT::VertexHandle>> members_;
  std::vector<std::size_t> remaining_;
  std::vector<std::size_t> floor_;
};

/// Binary module: the feature lines stay (features.h). A corner of the lines (a vertex with one
/// or three or more feature edges) is locked; a vertex inside a line collapses only along it,
/// into one of its two neighbours on the line, and not where that would close a line into a loop
/// of two (its other neighbour already the target's neighbour on a line). So the base keeps every
/// line, each as the chain of its vertices that remain, in their order along it.
template <typename MeshT>
class ModFeatureLinesT : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModFeatureLinesT, MeshT, FeatureLines);

  explicit ModFeatureLinesT(MeshT& mesh) : Base(mesh, true) {}

  /// `lines` over the input vertices, `handle_of[v]` the half-edge mesh's vertex of input vertex
  /// v (or an invalid handle). Locks the corners.
  void set_lines(const FeatureLines& lines, const std::vector<typename MeshT::VertexHandle>& handle_of) {
    neighbours_.assign(Base::mesh().n_vertices(), {});
    for (std::uint32_t v = 0; v + 1 < lines.offsets.size(); ++v) {
      if (lines.degree(v) == 0 || !handle_of[v].is_valid()) continue;
      auto& list = neighbours_[handle_of[v].idx()];
      for (std::uint32_t k = lines.offsets[v]; k < lines.offsets[v + 1]; ++k) list.push_back(handle_of[lines.neighbours[k]].idx());
      if (lines.is_corner(v)) Base::mesh().status(handle_of[v]).set_locked(true);
    }
  }

  float collapse_priority(const CollapseInfo& ci) override {
    const auto& line = neighbours_[ci.v0.idx()];
    if (line.empty()) return float(Base::LEGAL_COLLAPSE);
    // A corner or a kink (also locked, which is_collapse_legal() refuses before any module).
    if (line.size() != 2) return float(Base::ILLEGAL_COLLAPSE);
    const int target = ci.v1.idx(), other = line[0] == target ? line[1] : line[0];
    if (line[0] != target && line[1] != target) return float(Base::ILLEGAL_COLLAPSE);
    const auto& beyond = neighbours_[other];
    return std::find(beyond.begin(), beyond.end(), target) == beyond.end() ? float(Base::LEGAL_COLLAPSE)
                                                                           : float(Base::ILLEGAL_COLLAPSE);
  }

  void postprocess_collapse(const CollapseInfo& ci) override {
    auto& line = neighbours_[ci.v0.idx()];
    if (line.empty()) return;
    const int removed = ci.v0.idx(), target = ci.v1.idx(), other = line[0] == target ? line[1] : line[0];
    std::replace(neighbours_[target].begin(), neighbours_[target].end(), removed, other);
    std::replace(neighbours_[other].begin(), neighbours_[other].end(), removed, target);
    line.clear();
  }

 private:
  std::vector<std::vector<int>> neighbours_;  // per vertex handle index: its neighbours on the lines
};

void check_options(const DecimateOptions& options) {
  if (options.levels < 0 || options.levels > 15)
    throw std::invalid_argument("decimate: levels must be in 0..15, got " + std::to_string(options.levels));
  if (!(options.max_normal_deviation_degrees > 0 && options.max_normal_deviation_degrees <= 180))
    throw std::invalid_argument("decimate: max_normal_deviation_degrees must be in (0, 180], got " +
                                std::to_string(options.max_normal_deviation_degrees));
  if (!(options.min_aspect_ratio >= 1 && std::isfinite(options.min_aspect_ratio)))
    throw std::invalid_argument("decimate: min_aspect_ratio must be finite and >= 1, got " +
                                std::to_string(options.min_aspect_ratio));
}

/// check_options() and the indices that need the mesh.
void check_options(const DecimateOptions& options, const TriangleMesh& mesh) {
  check_options(options);
  for (const std::uint32_t v : options.keep)
    if (v >= mesh.vertex_count())
      throw std::invalid_argument("decimate: keep names vertex " + std::to_string(v) + " of " +
                                  std::to_string(mesh.vertex_count()));
}

MeshReport checked_report(const TriangleMesh& mesh) {
  MeshReport report = validate_mesh(mesh);
  if (const std::string problem = first_problem_for_triangle_codec(report); !problem.empty()) throw MeshError(problem);
  return report;
}

/// Connected components of the referenced vertices (joined through faces), numbered in the
/// order of validate_mesh's component list.
struct Components {
  std::vector<std::uint32_t> of_vertex;  // kNone for isolated vertices
  std::vector<std::size_t> vertices;     // per component
  std::vector<std::size_t> topological_floor;
};

Components find_components(const TriangleMesh& mesh, const MeshReport& report) {
  const std::size_t n = mesh.vertex_count();
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  auto root = [&](std::uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (std::size_t i = 0; i < mesh.triangles.size(); i += 3)
    for (int k = 1; k < 3; ++k) {
      const std::uint32_t a = root(mesh.triangles[i]), b = root(mesh.triangles[i + k]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  Components components;
  std::vector<std::uint32_t> id_of_root(n, kNone);
  for (std::size_t c = 0; c < report.components.size(); ++c) {
    const ComponentReport& component = report.components[c];
    id_of_root[root(mesh.triangles[3 * std::size_t(component.first_face)])] = static_cast<std::uint32_t>(c);
    components.vertices.push_back(component.vertices);
    // Floor of the automatic target: 8 + 6·genus + 3·boundary loops (decimate.h).
    const std::size_t floor = 8 + 6 * std::size_t(component.genus) + 3 * component.boundary_loops;
    components.topological_floor.push_back(std::min<std::size_t>(component.vertices, floor));
  }
  components.of_vertex.assign(n, kNone);
  for (const std::uint32_t v : mesh.triangles) components.of_vertex[v] = id_of_root[root(v)];
  return components;
}

std::size_t automatic_target(std::size_t referenced_vertices, int levels, const Components& components) {
  // Loop refinement: V_{l+1} = V_l + E_l ≈ 4 V_l (E ≈ 3V on a closed mesh), so the refined base
  // has about 4^levels · V_base vertices.
  const std::size_t refinement = std::size_t{1} << (2 * levels);
  const std::size_t from_detail = (referenced_vertices + refinement - 1) / refinement;
  const std::size_t floor =
      std::accumulate(components.topological_floor.begin(), components.topological_floor.end(), std::size_t{0});
  return std::max(from_detail, floor);
}

}  // namespace

std::size_t automatic_base_vertices(const TriangleMesh& mesh, int levels) {
  check_options(DecimateOptions{.levels = levels});
  const MeshReport report = checked_report(mesh);
  return automatic_target(report.referenced_vertices, levels, find_components(mesh, report));
}

namespace {

/// The mesh as it stands: its live vertices in index order (deleted ones skipped), their faces.
DecimateResult live_mesh(const HalfedgeMesh& half_edge, const std::vector<std::uint32_t>& input_index,
                         std::size_t collapses) {
  DecimateResult result;
  result.collapses = collapses;
  std::vector<std::uint32_t> base_index(half_edge.n_vertices(), kNone);
  for (const auto v : half_edge.vertices()) {  // skips deleted vertices
    base_index[v.idx()] = static_cast<std::uint32_t>(result.original_vertex.size());
    result.original_vertex.push_back(input_index[v.idx()]);
    const auto& p = half_edge.point(v);
    result.base.positions.insert(result.base.positions.end(), {p[0], p[1], p[2]});
  }
  for (const auto f : half_edge.faces())
    for (const auto v : half_edge.fv_range(f)) result.base.triangles.push_back(base_index[v.idx()]);
  return result;
}

/// Takes the decimater's mesh as it stands after given numbers of collapses (increasing), as
/// the decimater notifies it after each one.
class Snapshots : public OpenMesh::Decimater::Observer {
 public:
  Snapshots(const HalfedgeMesh& half_edge, const std::vector<std::uint32_t>& input_index, std::vector<std::size_t> at)
      : Observer(1), half_edge_(half_edge), input_index_(input_index), at_(std::move(at)) {}
  void notify(std::size_t collapses) override {
    while (taken_.size() < at_.size() && at_[taken_.size()] == collapses)
      taken_.push_back(live_mesh(half_edge_, input_index_, collapses));
  }
  /// The snapshots, those not reached (the decimation stopped first) being the final mesh.
  std::vector<DecimateResult> finish(std::size_t collapses) {
    while (taken_.size() < at_.size()) taken_.push_back(live_mesh(half_edge_, input_index_, collapses));
    return std::move(taken_);
  }

 private:
  const HalfedgeMesh& half_edge_;
  const std::vector<std::uint32_t>& input_index_;
  std::vector<std::size_t> at_;
  std::vector<DecimateResult> taken_;
};

/// decimate() to each of `targets` (0: the automatic target, whose components keep their
/// topological floor), in one run; options.target_vertices is not read.
std::vector<DecimateResult> decimate_to_targets(const TriangleMesh& mesh, const DecimateOptions& options,
                                                std::span<const std::size_t> targets) {
  check_options(options, mesh);
  const MeshReport report = checked_report(mesh);
  const Components components = find_components(mesh, report);

  // Only referenced vertices enter the half-edge mesh; input_index maps back.
  HalfedgeMesh half_edge;
  std::vector<std::uint32_t> input_index;
  std::vector<HalfedgeMesh::VertexHandle> handle(mesh.vertex_count());
  std::vector<std::uint32_t> component_of_handle;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    if (components.of_vertex[v] == kNone) continue;
    handle[v] = half_edge.add_vertex({mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]});
    input_index.push_back(static_cast<std::uint32_t>(v));
    component_of_handle.push_back(components.of_vertex[v]);
  }
  for (std::size_t i = 0; i < mesh.triangles.size(); i += 3) {
    const auto face = half_edge.add_face(handle[mesh.triangles[i]], handle[mesh.triangles[i + 1]],
                                         handle[mesh.triangles[i + 2]]);
    // validate_mesh accepted the mesh as manifold and consistently oriented, so this is a bug.
    if (!face.is_valid())
      throw std::logic_error("decimate: OpenMesh refused face " + std::to_string(i / 3) + " of a validated mesh");
  }
  half_edge.request_face_normals();
  half_edge.update_face_normals();  // before ModNormalFlippingT, which otherwise logs that it does this
  // The decimater marks collapsed elements deleted in the status it requests and releases that
  // request when it goes; ours keeps the status alive for reading the result.
  half_edge.request_vertex_status();
  half_edge.request_face_status();

  const bool automatic = std::find(targets.begin(), targets.end(), std::size_t{0}) != targets.end();
  std::vector<std::size_t> floor(components.vertices.size());
  for (std::size_t c = 0; c < floor.size(); ++c)
    floor[c] = automatic ? components.topological_floor[c] : std::min<std::size_t>(components.vertices[c], 4);
  // The targets' collapse counts, fewest first: the decimater pops its heap in the same order
  // whatever its target, so the mesh after k collapses of a run to a smaller target is the one a
  // run to V - k vertices ends with.
  std::vector<std::size_t> at;
  for (const std::size_t target : targets) {
    const std::size_t t = target == 0 ? automatic_target(input_index.size(), options.levels, components) : target;
    at.push_back(input_index.size() - std::min(t, input_index.size()));
  }
  std::vector<std::size_t> order(at.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return at[a] < at[b]; });
  std::vector<std::size_t> sorted_at;
  for (const std::size_t i : order) sorted_at.push_back(at[i]);
  Snapshots snapshots(half_edge, input_index, sorted_at);
  snapshots.notify(0);  // targets the input already meets

  std::size_t collapses = 0;
  if (!sorted_at.empty() && sorted_at.back() > 0) {
    OpenMesh::Decimater::DecimaterT<HalfedgeMesh> decimater(half_edge);
    ModBoundaryQuadricT<HalfedgeMesh>::Handle quadric;
    OpenMesh::Decimater::ModNormalFlippingT<HalfedgeMesh>::Handle normal_flipping;
    OpenMesh::Decimater::ModAspectRatioT<HalfedgeMesh>::Handle aspect_ratio;
    ModInputNormalT<HalfedgeMesh>::Handle input_normal;
    ModComponentFloorT<HalfedgeMesh>::Handle component_floor;
    ModFeatureLinesT<HalfedgeMesh>::Handle feature_lines;
    // The binary modules are asked in the order added, and the first refusal ends it: the
    // cheapest first (the outcome is the same in any order: each only vetoes).
    decimater.add(quadric);
    for (const std::uint32_t v : options.keep)  // is_collapse_legal() refuses to move a locked vertex
      if (handle[v].is_valid()) half_edge.status(handle[v]).set_locked(true);
    decimater.add(component_floor);
    decimater.module(component_floor).set_components(component_of_handle, floor);
    if (options.feature_lines && !options.feature_lines->empty()) {
      decimater.add(feature_lines);
      decimater.module(feature_lines).set_lines(*options.feature_lines, handle);
    }
    decimater.add(aspect_ratio);
    decimater.module(aspect_ratio).set_aspect_ratio(static_cast<float>(options.min_aspect_ratio));
    decimater.add(normal_flipping);
    decimater.module(normal_flipping).set_max_normal_deviation(options.max_normal_deviation_degrees);
    decimater.add(input_normal);
    if (!decimater.initialize()) throw std::logic_error("decimate: OpenMesh's decimater did not initialize");
    decimater.set_observer(&snapshots);
    collapses = decimater.decimate(sorted_at.back());
    decimater.set_observer(nullptr);
  }
  std::vector<DecimateResult> taken = snapshots.finish(collapses);
  std::vector<DecimateResult> results(taken.size());
  for (std::size_t k = 0; k < order.size(); ++k) results[order[k]] = std::move(taken[k]);
  return results;
}

}  // namespace

DecimateResult decimate(const TriangleMesh& mesh, const DecimateOptions& options) {
  const std::size_t target = options.target_vertices;
  return std::move(decimate_to_targets(mesh, options, std::span(&target, 1)).front());
}

std::vector<DecimateResult> decimate_each(const TriangleMesh& mesh, const DecimateOptions& options,
                                          std::span<const std::size_t> targets) {
  for (const std::size_t target : targets)
    if (target == 0) throw std::invalid_argument("decimate_each: targets must be > 0");
  return decimate_to_targets(mesh, options, targets);
}

}  // namespace meshlift
