// meshlift encode / decode / truncate / stream: the codec's commands (public headers only).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <future>
#include <iostream>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "files.h"
#include "meshlift/codec.h"
#include "meshlift/container.h"
#include "meshlift/lifting.h"
#include "meshlift/metric.h"
#include "remesh_options.h"

namespace meshlift::cli {
namespace {

/// ", base part 312 of 813 vertices" while a decode's base part (FORMAT.md §5.1) is incomplete.
std::string base_part_note(const DecodeResult& r, std::uint64_t base_vertices) {
  if (r.base_vertices_decoded >= base_vertices) return "";
  return ", base part " + std::to_string(r.base_vertices_decoded) + " of " + std::to_string(base_vertices) + " vertices";
}

/// PSNR of `test` against `reference` with the same vertices in the same order:
/// 20 log10(diagonal / RMS vertex distance) (CODEC-NOTES §7, on vertices instead of surfaces).
double vertex_psnr(const std::vector<double>& reference, const std::vector<double>& test) {
  double sum = 0;
  for (std::size_t i = 0; i < reference.size(); ++i) sum += (reference[i] - test[i]) * (reference[i] - test[i]);
  const double rms = std::sqrt(sum / static_cast<double>(reference.size() / 3));
  return rms > 0 ? 20 * std::log10(bounding_box_diagonal(reference) / rms) : std::numeric_limits<double>::infinity();
}

/// A mesh the decoded ones are measured against by the metric every figure of meshlift uses
/// (METRIC.md: symmetric surface RMS, the reference's bounding-box diagonal as peak), PSNR only,
/// with the sample count `meshlift compare` takes for meshes of `test_faces` faces, so that it
/// prints the same PSNR; `searching` adds the same on 100,000 area samples a side (±0.012 dB over
/// seeds, metric.h), the quick measure of a search. One per reference and face count: encode's
/// cut, truncate's, and stream's snapshots.
class ReferenceSurface {
 public:
  /// \throw MeshError if the metric cannot take `reference` (no faces, non-finite coordinates).
  ReferenceSurface(const TriangleMesh& reference, std::size_t test_faces, bool searching = false)
      : metric_(psnr_options(default_sample_count(reference.face_count(), test_faces))),
        search_(psnr_options(std::min<std::size_t>(metric_.samples, 100'000))),
        full_(reference, metric_.samples, metric_.seed, metric_.threads, metric_.vertices) {
    if (searching && search_.samples < metric_.samples)
      sparse_.emplace(reference, search_.samples, search_.seed, search_.threads, search_.vertices);
  }
  double psnr(const TriangleMesh& test) const { return surface_distance(full_, test, metric_).psnr_db(); }
  /// On the sparser samples where there are some, else psnr().
  double quick_psnr(const TriangleMesh& test) const {
    return sparse_ ? surface_distance(*sparse_, test, search_).psnr_db() : psnr(test);
  }
  bool has_quick() const { return sparse_.has_value(); }

 private:
  static MetricOptions psnr_options(std::size_t samples) {
    MetricOptions o;
    o.samples = samples;
    o.vertices = false;  // the vertices enter only the Hausdorff distance
    return o;
  }
  MetricOptions metric_, search_;
  SampledSurface full_;
  std::optional<SampledSurface> sparse_;
};

/// `measure` of the decode of the first `bytes` bytes of `file`; -infinity where that prefix does
/// not decode (a cut inside the header or the base mesh).
double prefix_psnr(const std::vector<std::uint8_t>& file, std::size_t bytes,
                   const std::function<double(const TriangleMesh&)>& measure) {
  DecodeOptions o;
  o.max_bytes = bytes;
  const DecodeResult r = decode(file, o);
  return r.status == Status::ok ? measure(r.mesh) : -std::numeric_limits<double>::infinity();
}

/// The faces of `mesh`'s finest level: what a ReferenceSurface is prepared for.
std::size_t finest_faces(const SemiRegularMesh& mesh) { return mesh.hierarchy.triangles(mesh.hierarchy.levels()).size() / 3; }

/// Where `encode --psnr` cut the stream, and how close that prefix's decode is to the input.
struct PsnrCut {
  std::size_t bytes = 0;
  double psnr_db = 0;  ///< of the decode of the first `bytes` bytes against the input
  bool reached = false;
};

/// The shortest cut of `file`, to within 1/256 of its length, whose decode is within `target_db`
/// of the input `reference` holds (made with `searching`). The target is the error against what
/// the user gave, not against the semi-regular mesh coded: the remesh's own error counts, and the
/// tangential quantization, which moves vertices along the surface more than it moves the
/// surface, does not (camel, 65 dB asked: 2,284 bytes against the 3,993 that a vertex PSNR of
/// 65 dB against the remesh took, docs/RESULTS.md). By bisection over prefix lengths (the error
/// against the input falls with the bytes read: tests/codec, "prefixes") on the quick measure;
/// the cut is then measured on the full one, and where that falls short (by the sparser samples'
/// spread, ~0.04 dB) the search goes on above it with the full one. The whole file if no prefix
/// reaches the target (its PSNR is then the closest the stream comes).
PsnrCut cut_for_psnr(const std::vector<std::uint8_t>& file, const ReferenceSurface& reference, double target_db) {
  auto psnr_at = [&](std::size_t bytes, bool quick) {
    return prefix_psnr(file, bytes, [&](const TriangleMesh& m) { return quick ? reference.quick_psnr(m) : reference.psnr(m); });
  };
  const PsnrCut whole{file.size(), psnr_at(file.size(), false), true};
  if (!(whole.psnr_db >= target_db)) return {whole.bytes, whole.psnr_db, false};
  // Bisection of (lo, hi.bytes]: the cut at hi.bytes reaches the target by that measure, the
  // one at lo does not (or is 0).
  auto bisect = [&](std::size_t lo, PsnrCut hi, bool quick) {
    while (hi.bytes - lo > std::max<std::size_t>(1, hi.bytes / 256)) {
      const std::size_t mid = lo + (hi.bytes - lo) / 2;
      if (const double psnr = psnr_at(mid, quick); psnr >= target_db)
        hi = {mid, psnr, true};
      else
        lo = mid;
    }
    return hi;
  };
  const PsnrCut found = bisect(0, whole, true);
  if (!reference.has_quick() || found.bytes == whole.bytes) return found;  // measured on the full samples
  const double psnr = psnr_at(found.bytes, false);
  if (psnr >= target_db) return {found.bytes, psnr, true};
  // Short by the sparser samples' spread: the first cut above that reaches it on the full
  // samples, by steps doubling from the resolution, then bisection.
  std::size_t lo = found.bytes;
  for (std::size_t step = std::max<std::size_t>(1, found.bytes / 256);; step *= 2) {
    const std::size_t at = std::min(whole.bytes, lo + step);
    const double at_psnr = at == whole.bytes ? whole.psnr_db : psnr_at(at, false);
    if (at_psnr >= target_db) return bisect(lo, {at, at_psnr, true}, false);
    lo = at;
  }
}

/// `--scheme auto`: the wavelet whose details of `mesh` (all levels, x, y, z) have the least
/// energy, the one that predicts the mesh best: zero for Loop on a Loop-subdivided mesh; on
/// remeshes butterfly, whose prediction the remesher's normal lines go through (armadillo, ~2x:
/// linear 5.1e3, butterfly 2.4e3, Loop 1.0e5, measured without the update; at 2 bits per input
/// vertex butterfly gives 64.4 dB against Loop's 53.6, docs/RESULTS.md). Ties go to the first of
/// butterfly, Loop, linear. With the update (the default) the interpolating schemes are measured
/// with it (Loop has its own update); on the remeshes it still picks butterfly.
/// Butterfly (the costliest) on a second thread while Loop and then linear go on this one, in one
/// buffer (resident after the first copy); each analyzed a level at a time without the
/// transform's tables (analyze_level: the same values as the tables' analysis).
Scheme least_energy_scheme(const SemiRegularMesh& mesh, bool mean_preserving_update) {
  const SemiRegularHierarchy& h = mesh.hierarchy;
  auto energy = [&](Scheme scheme, std::vector<double>& values) {
    values.assign(mesh.positions.begin(), mesh.positions.end());
    for (int j = h.levels() - 1; j >= 0; --j) analyze_level(h, {scheme, mean_preserving_update}, j, values);
    double sum = 0;
    for (std::size_t i = 3 * std::size_t{h.vertex_count(0)}; i < values.size(); ++i) sum += values[i] * values[i];
    return sum;
  };
  // Where no thread can be started, the deferred policy runs it at get().
  std::future<double> butterfly = std::async(std::launch::async | std::launch::deferred, [&] {
    std::vector<double> values;
    return energy(Scheme::butterfly, values);
  });
  std::vector<double> values;
  const double loop = energy(Scheme::loop, values), linear = energy(Scheme::linear, values);
  const double energies[3] = {butterfly.get(), loop, linear};
  const Scheme schemes[3] = {Scheme::butterfly, Scheme::loop, Scheme::linear};
  std::size_t best = 0;
  for (std::size_t k = 1; k < 3; ++k)
    if (energies[k] < energies[best]) best = k;
  return schemes[best];
}

struct EncodeArgs {
  std::string input, output, scheme = "auto";
  /// 0: chosen from the remesh's error (precision_bits_for).
  int bits = 0;
  /// The colour channel's precision: a step of 2^-9 of each component's range (at most 1/512) by
  /// default: byte colours of a semi-regular input decoded whole come back within one byte, 98 %
  /// of them the same byte (docs/RESULTS.md, "Vertex colours").
  int colour_bits = 9;
  FrameArgs frames;
  RemeshCliOptions remesh;
  double bpv = 0, psnr = 0;
  std::size_t bytes = 0;
};

/// `encode`'s precision where --bits is not given: 2^-15 of the diagonal for a remesh farther than
/// 85 dB from its input, else 2^-16. The finest plane is then far below the remesh's own error:
/// on the twelve development meshes (remeshes 75.3-81.7 dB from their inputs) 15 bits take 16-26 %
/// fewer bytes than 16 and decode 0.01-0.09 dB farther from the input; blade's 88.9 dB remesh
/// would lose 0.24 dB, and an input taken over as it is has no remesh error: both keep 16
/// (docs/RESULTS.md, "A remesh's file to 15 bits").
int precision_bits_for(double remesh_psnr_db) { return remesh_psnr_db < 85 ? 15 : 16; }

/// What `encode` makes of one semi-regular mesh: the file (cut for --psnr), how, and where it cut.
struct Encoded {
  std::vector<std::uint8_t> file;
  EncodeOptions options;
  std::optional<PsnrCut> cut;
  std::size_t whole_bytes = 0;
  double seconds = 0;  ///< encoding and the cut's search
};

/// Encodes `mesh` as `a` asks: the input's colours read off its surface first, the scheme, the
/// precision, the budget or the --psnr cut against `reference` (the input prepared for meshes of
/// `mesh`'s faces, searching; given with --psnr). Prints the error and returns nullopt on failure.
std::optional<Encoded> encode_for_cli(const EncodeArgs& a, SemiRegularMesh& mesh, double remesh_psnr,
                                      bool follows_features, const TriangleMesh& input,
                                      const std::optional<InputColours>& colours, const ReferenceSurface* reference) {
  Encoded out;
  EncodeOptions& options = out.options;
  if (colours) {
    // The input's vertex colours, read off its surface at each vertex of the semi-regular mesh,
    // coded as the stream's first channel and marked as the colour (FORMAT.md §3).
    std::optional<std::vector<double>> at = colours_at(a.input, *colours, mesh.positions);
    if (!at) return std::nullopt;
    mesh.channels.insert(mesh.channels.begin(), VertexChannel{3, std::move(*at), true});
    options.channel_precision_bits = a.colour_bits;
  }
  options.scheme = a.scheme == "auto" ? least_energy_scheme(mesh, a.frames.update) : parse_scheme(a.scheme);
  // With a --psnr target the finest plane stays 2^-16: the prefixes are those of the 15-bit file,
  // and its last plane lets a target within ~0.1 dB of the remesh's own error be met.
  options.precision_bits = a.bits > 0 ? a.bits : a.psnr > 0 ? 16 : precision_bits_for(remesh_psnr);
  apply_frame_options(a.frames, options);
  if (a.bytes > 0) options.max_bytes = a.bytes;
  if (a.bpv > 0) options.max_bytes = static_cast<std::size_t>(std::ceil(a.bpv * static_cast<double>(input.vertex_count()) / 8));
  const auto t0 = std::chrono::steady_clock::now();
  try {
    if (a.frames.tangent_shift < 0 && options.local_frames && follows_features) {
      // A CAD part: finer tangents where they measure closer to the input (choose_tangent_shift),
      // by the --psnr search's quick measure (100,000 samples a side: ±0.04 dB, where the two
      // shifts part by ~1 dB on fandisk and blade; a large mesh's full count would cost more than
      // its encodes), or the same one made here.
      std::optional<ReferenceSurface> own;
      if (reference == nullptr) own.emplace(input, finest_faces(mesh), true);
      const ReferenceSurface& measure = reference != nullptr ? *reference : *own;
      const TangentChoice choice = choose_tangent_shift(mesh, options, input.vertex_count(),
                                                        [&](const TriangleMesh& m) { return measure.quick_psnr(m); });
      options.tangent_shift = choice.shift;
      std::fprintf(stderr,
                   "%s: the remesh follows feature lines: tangent shift %d (prefixes at 1-8 bits per input vertex: "
                   "%.2f dB from the input on average, against %.2f with shift %d)\n",
                   a.input.c_str(), choice.shift, choice.db, choice.other_db, choice.other_shift);
    }
    out.file = encode(mesh, options);
  } catch (const MeshError& e) {
    std::cerr << "meshlift: " << a.input << ": " << e.what() << "\n";
    return std::nullopt;
  }
  out.whole_bytes = out.file.size();
  if (reference != nullptr) {
    out.cut = cut_for_psnr(out.file, *reference, a.psnr);
    std::vector<std::uint8_t> truncated;
    if (out.cut->bytes < out.file.size() && truncate_file(out.file, out.cut->bytes, truncated) == Status::ok)
      out.file = std::move(truncated);
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

/// `encode --psnr` with the automatic density: where the remesh it chose is less than this many dB
/// closer to the input than the target asks (or farther than the target), the next denser
/// densities are remeshed and coded too, and the smallest file that reaches the target is kept. Measured on the
/// development meshes (docs/RESULTS.md, "encode --psnr against the input"): fandisk at 75 dB, 0.3
/// dB under its 1x remesh's 75.31, takes 16 % fewer bytes at 1.5x; where the target is 5 dB or
/// more under the remesh's error the automatic density's file is the smallest (fandisk at 70 dB,
/// camel at 60-70).
constexpr double kDenserRemeshWithinDb = 3;
/// The densities tried, in turn, above the automatic one (remesh vertices per input vertex): at
/// most kDenserRemeshes of them, and none of more than kDenserRemeshVertices vertices.
constexpr double kDenserForTarget[] = {1.5, 2, 3, 4, 6, 8, 12, 16};
constexpr int kDenserRemeshes = 3;
constexpr double kDenserRemeshVertices = 1 << 22;

int run_encode(const EncodeArgs& a) {
  if (!check_distinct_output(a.input, a.output)) return kOutputError;
  std::optional<PolygonMesh> loaded = load_mesh(a.input);
  if (!loaded) return kBadInput;
  const std::optional<InputColours> colours = input_colours(*loaded);
  TriangleMesh input = triangles_of(a.input, std::move(*loaded), {a.remesh.weld, a.remesh.orient});
  loaded.reset();
  // Any triangle mesh: taken over if it already is semi-regular, else remeshed (remesh.h). A mesh
  // the codec cannot take is refused there, with validate.h's message (validated once: that is
  // 1.2 s on a 1.66 M-vertex mesh).
  const auto t_remesh = std::chrono::steady_clock::now();
  std::optional<RemeshResult> remeshed = remesh_for_cli(a.input, input, a.remesh);
  if (!remeshed) return kBadInput;
  double remesh_psnr = print_remesh_summary(
      a.input, input, *remeshed, std::chrono::duration<double>(std::chrono::steady_clock::now() - t_remesh).count());
  const std::size_t vertices = input.vertex_count();
  // With --psnr, the input prepared for the metric of meshes of `remesh`'s faces.
  auto reference_for = [&](const RemeshResult& remesh) {
    return a.psnr > 0 ? std::make_optional<ReferenceSurface>(input, finest_faces(remesh.mesh), true) : std::nullopt;
  };
  std::optional<ReferenceSurface> reference = reference_for(*remeshed);
  std::optional<Encoded> encoded =
      encode_for_cli(a, remeshed->mesh, remesh_psnr, remeshed->feature_vertices > 0, input, colours,
                     reference ? &*reference : nullptr);
  if (!encoded) return kBadInput;
  const bool may_go_denser = a.psnr > 0 && a.remesh.density == "auto" && a.remesh.base_vertices == 0 &&
                             remeshed->method == RemeshMethod::decimate && !remeshed->recognized &&
                             !remeshed->input_refined && remeshed->density > 0;
  if (may_go_denser && remesh_psnr < a.psnr + kDenserRemeshWithinDb) {
    const std::size_t folds = remeshed->flipped_triangles + remeshed->degenerate_triangles;
    int tried = 0;
    for (const double density : kDenserForTarget) {
      if (density <= remeshed->density) continue;
      if (++tried > kDenserRemeshes || density * static_cast<double>(vertices) > kDenserRemeshVertices) break;
      std::fprintf(stderr, "%s: --psnr %g: the remesh is %.2f dB from the input, %s the target: remeshing at ~%gx too\n",
                   a.input.c_str(), a.psnr, remesh_psnr, remesh_psnr < a.psnr ? "short of" : "close to", density);
      RemeshCliOptions denser = a.remesh;
      char text[32];
      std::snprintf(text, sizeof text, "%g", density);
      denser.density = text;
      std::optional<RemeshResult> candidate = remesh_for_cli(a.input, input, denser);
      if (!candidate) break;
      const std::optional<ReferenceSurface> candidate_reference = reference_for(*candidate);
      const double candidate_psnr = candidate_reference->psnr(candidate->mesh.finest());
      const std::size_t candidate_folds = candidate->flipped_triangles + candidate->degenerate_triangles;
      std::optional<Encoded> other =
          encode_for_cli(a, candidate->mesh, candidate_psnr, candidate->feature_vertices > 0, input, colours,
                         &*candidate_reference);
      if (!other) break;
      const bool better = candidate_folds <= folds &&
                          (other->cut->reached ? !encoded->cut->reached || other->file.size() < encoded->file.size()
                                               : !encoded->cut->reached && other->cut->psnr_db > encoded->cut->psnr_db);
      std::fprintf(stderr, "%s: ~%gx: %zu vertices, %.2f dB from the input, %zu flipped or degenerate; %s %zu bytes (%.2f dB): %s\n",
                   a.input.c_str(), density, candidate->mesh.positions.size() / 3, candidate_psnr, candidate_folds,
                   other->cut->reached ? "cut at" : "whole stream", other->file.size(), other->cut->psnr_db,
                   better ? "kept" : "not kept");
      if (!better) {
        // Denser would cost more still; or the decimation stopped at the same base (a small
        // input at its topology's floor), and denser densities make the same remesh.
        if (encoded->cut->reached || candidate_folds > folds ||
            candidate->mesh.positions.size() == remeshed->mesh.positions.size())
          break;
        continue;
      }
      remeshed = std::move(candidate);
      encoded = std::move(other);
      remesh_psnr = candidate_psnr;
      if (remesh_psnr >= a.psnr + kDenserRemeshWithinDb) break;
    }
  }
  const SemiRegularMesh& mesh = remeshed->mesh;
  const EncodeOptions& options = encoded->options;
  const std::vector<std::uint8_t>& file = encoded->file;
  std::string error;
  if (!write_bytes(a.output, file, error)) {
    std::cerr << "meshlift: " << error << "\n";
    return kOutputError;
  }
  const StreamInfo info = inspect(file);
  const auto percent = [&](std::size_t n) { return 100.0 * static_cast<double>(n) / static_cast<double>(file.size()); };
  std::fprintf(stderr,
               "%s: %zu vertices, %d levels, %s, %d-bit precision -> %s: %zu bytes, %.3f bits/vertex (header + base "
               "connectivity %.1f %%, base part %.1f %%), %.2f s\n",
               a.input.c_str(), vertices, mesh.hierarchy.levels(),
               (a.scheme == "auto" ? std::string("auto: ") + to_string(options.scheme) : a.scheme).c_str(),
               options.precision_bits, a.output.c_str(), file.size(), 8.0 * static_cast<double>(file.size()) / static_cast<double>(vertices),
               percent(info.header_and_connectivity_bytes), percent(info.base_part_bytes), encoded->seconds);
  const std::optional<PsnrCut>& cut = encoded->cut;
  if (cut && cut->reached)
    std::fprintf(stderr,
                 "%s: --psnr %g: cut at %zu of %zu bytes, whose decode is %.2f dB from the input (METRIC.md, as "
                 "`meshlift compare` measures it)\n",
                 a.input.c_str(), a.psnr, file.size(), encoded->whole_bytes, cut->psnr_db);
  else if (cut) {
    char why[160] = " (a finer precision takes a larger --bits)";
    if (std::isfinite(remesh_psnr))
      std::snprintf(why, sizeof why, " (the remesh itself is %.2f dB from it: a closer one takes %smore --levels or --snap)",
                    remesh_psnr, may_go_denser ? "" : "a denser --density, ");
    std::fprintf(stderr, "%s: note: --psnr %g is out of reach: the whole stream decodes to %.2f dB from the input, written whole%s\n",
                 a.input.c_str(), a.psnr, cut->psnr_db, why);
  }
  return kOk;
}

/// Reads a .mlz file; prints the one-line error and returns false on failure.
bool load_stream(const std::string& path, std::vector<std::uint8_t>& bytes) {
  std::string error;
  if (read_bytes(path, bytes, error)) return true;
  std::cerr << "meshlift: " << error << "\n";
  return false;
}

void print_failure(const std::string& path, const DecodeResult& r) {
  std::cerr << "meshlift: " << path << ": " << to_string(r.status) << " (error " << static_cast<int>(r.status)
            << "): " << r.message << "\n";
}

struct DecodeArgs {
  std::string input, output;
  std::size_t bytes = 0;
  int level = -1;
  unsigned threads = 0;
  bool stats = false, binary = false;
};

int run_decode(const DecodeArgs& a) {
  if (!check_distinct_output(a.input, a.output)) return kOutputError;
  std::vector<std::uint8_t> file;
  if (!load_stream(a.input, file)) return kBadInput;
  DecodeOptions options;
  if (a.bytes > 0) options.max_bytes = a.bytes;
  options.max_level = a.level;
  options.threads = a.threads;
  const auto t0 = std::chrono::steady_clock::now();
  const DecodeResult r = decode(file, options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (r.status != Status::ok) {
    print_failure(a.input, r);
    return kBadInput;
  }
  if (!save_mesh(a.output, r.mesh, a.binary, decoded_colours(r.channels))) return kOutputError;
  if (a.stats)
    std::fprintf(stderr,
                 "%s: %zu of %zu bytes, level %d of %d, bit plane %d%s%s: %zu vertices, %zu faces; decode %.3f ms "
                 "(%.2f M vertices/s, file I/O excluded, --threads %u)\n",
                 a.input.c_str(), r.bytes_used, file.size(), r.level, r.levels, r.bit_plane,
                 base_part_note(r, inspect(file).base_vertices).c_str(), r.complete ? " (complete)" : "", r.mesh.vertex_count(), r.mesh.face_count(), seconds * 1e3,
                 static_cast<double>(r.mesh.vertex_count()) / seconds / 1e6, a.threads);
  return kOk;
}

struct TruncateArgs {
  std::string input, output, reference;
  std::size_t bytes = 0;
  double psnr = 0;
};

int run_truncate(const TruncateArgs& a) {
  if (a.bytes == 0 && !(a.psnr > 0)) {
    std::cerr << "meshlift truncate: give --bytes N, or --psnr DB with --reference MESH\n";
    return kUsage;
  }
  if (!check_distinct_output(a.input, a.output) || (!a.reference.empty() && !check_distinct_output(a.reference, a.output)))
    return kOutputError;
  std::vector<std::uint8_t> file, cut;
  if (!load_stream(a.input, file)) return kBadInput;
  std::size_t bytes = a.bytes;
  if (a.psnr > 0) {
    // The shortest prefix within the target of the mesh the file was made from, as encode --psnr
    // cuts (the whole file, with a note, if none is).
    // A file that does not decode whole is refused as it is, before its prefixes are measured.
    if (const DecodeResult whole = decode(file); whole.status != Status::ok) {
      print_failure(a.input, whole);
      return kBadInput;
    }
    std::optional<PolygonMesh> loaded = load_mesh(a.reference);
    if (!loaded) return kBadInput;
    std::optional<ReferenceSurface> reference;
    try {
      reference.emplace(triangles_of(a.reference, std::move(*loaded)), inspect(file).faces, true);
    } catch (const MeshError& e) {  // a reference the metric cannot take (no faces, bad coordinates)
      std::cerr << "meshlift: " << a.reference << ": " << e.what() << "\n";
      return kBadInput;
    }
    const PsnrCut found = cut_for_psnr(file, *reference, a.psnr);
    if (found.reached)
      std::fprintf(stderr, "%s: --psnr %g: the first %zu bytes decode %.2f dB from %s (METRIC.md)\n", a.input.c_str(),
                   a.psnr, found.bytes, found.psnr_db, a.reference.c_str());
    else
      std::fprintf(stderr, "%s: note: --psnr %g is out of reach: the whole file decodes to %.2f dB from %s, kept whole\n",
                   a.input.c_str(), a.psnr, found.psnr_db, a.reference.c_str());
    bytes = found.bytes;
  }
  const Status status = truncate_file(file, bytes, cut);
  // A cut inside the file header (truncate_file: truncated), or inside the header or base mesh
  // chunks, which it would re-frame as complete but short chunks that read as corrupt, is refused
  // (the streaming decoder shows nothing before them either) where the file itself is sound;
  // otherwise the file's own problem is named.
  if (status != Status::ok || decode(cut).status != Status::ok) {
    const Status whole = decode(file).status;
    if (whole == Status::ok) {
      std::cerr << "meshlift: " << a.input << ": a cut at " << bytes
                << " bytes falls inside the header or the base mesh, before anything decodes; `meshlift info "
                << a.input << "` lists the chunk sizes\n";
    } else {
      std::cerr << "meshlift: " << a.input << ": " << to_string(whole) << " (error " << static_cast<int>(whole)
                << "): " << describe(whole) << "\n";
    }
    return kBadInput;
  }
  std::string error;
  if (!write_bytes(a.output, cut, error)) {
    std::cerr << "meshlift: " << error << "\n";
    return kOutputError;
  }
  std::fprintf(stderr, "%s: %zu bytes -> %s: %zu bytes\n", a.input.c_str(), file.size(), a.output.c_str(), cut.size());
  return kOk;
}

struct StreamArgs {
  std::string input, directory, reference, csv;
  std::size_t every = 0;
};


int run_stream(const StreamArgs& a) {
  if (!a.csv.empty() && !(check_distinct_output(a.input, a.csv) && (a.reference.empty() || check_distinct_output(a.reference, a.csv))))
    return kOutputError;
  std::vector<std::uint8_t> file;
  if (!load_stream(a.input, file)) return kBadInput;
  if (!a.directory.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(a.directory, ec);
    if (ec) {
      std::cerr << "meshlift: " << a.directory << ": cannot create the directory: " << ec.message() << "\n";
      return kOutputError;
    }
  }
  // The reference: the encoded semi-regular mesh itself (its vertices against the decoded ones:
  // the codec's own error), or any other mesh, such as the one the file was encoded from (the
  // surface metric of METRIC.md, as `compare` and `encode --psnr` measure: the remesh's error too).
  std::vector<double> reference;
  std::optional<ReferenceSurface> reference_surface;
  const StreamInfo info = inspect(file);
  if (!a.reference.empty()) {
    std::optional<PolygonMesh> loaded = load_mesh(a.reference);
    if (!loaded) return kBadInput;
    // The stream holds its vertices in canonical order: put the reference in that order too.
    std::optional<SemiRegularMesh> recovered;
    if (loaded->is_triangle_mesh()) recovered = recover_level_ordered(to_triangle_mesh(*loaded));
    if (recovered && recovered->hierarchy.vertex_count(recovered->hierarchy.levels()) == info.vertices) {
      reference = canonical_order(*recovered).positions;
      std::fprintf(stderr, "%s: the encoded mesh: PSNR of the decoded vertices against its own\n", a.reference.c_str());
    } else {
      try {
        reference_surface.emplace(triangles_of(a.reference, std::move(*loaded)), info.faces);
      } catch (const MeshError& e) {  // no faces, bad coordinates
        std::cerr << "meshlift: " << a.reference << ": " << e.what() << "\n";
        return kBadInput;
      }
      std::fprintf(stderr, "%s: not the encoded mesh: PSNR of the decoded surface against it (METRIC.md, as `compare`)\n",
                   a.reference.c_str());
    }
  }
  // The CSV is collected and written once at the end, atomically like every other output.
  std::string csv = "bytes,bits_per_vertex,vertices,bit_plane,psnr_db\n";
  const std::uint64_t base_vertices = info.base_vertices;  // for the base part notes
  Decoder decoder;
  DecodeResult r;  // kept: each mesh reuses the arrays of the one before (Decoder::mesh(DecodeResult&))
  std::size_t written = 0;
  for (std::size_t at = 0; at < file.size();) {
    const std::size_t n = std::min(a.every, file.size() - at);
    decoder.push(std::span(file).subspan(at, n));
    at += n;
    decoder.mesh(r);
    if (r.status == Status::truncated) {
      std::fprintf(stderr, "%8zu bytes: nothing to show yet (%s)\n", at, r.message.c_str());
      continue;
    }
    if (r.status != Status::ok) {
      print_failure(a.input, r);
      return kBadInput;
    }
    char name[64];
    std::snprintf(name, sizeof name, "prefix_%09zu.ply", at);
    if (!a.directory.empty()) {
      const std::string path = (std::filesystem::path(a.directory) / name).string();
      if (!check_distinct_output(a.input, path) || (!a.reference.empty() && !check_distinct_output(a.reference, path)))
        return kOutputError;
      if (!save_mesh(path, r.mesh, true, decoded_colours(r.channels))) return kOutputError;
      ++written;
    }
    const double bpv = 8.0 * static_cast<double>(at) / static_cast<double>(r.mesh.vertex_count());
    const double psnr = reference_surface                                ? reference_surface->psnr(r.mesh)
                        : reference.size() == r.mesh.positions.size() ? vertex_psnr(reference, r.mesh.positions)
                                                                      : std::numeric_limits<double>::quiet_NaN();
    std::fprintf(stderr, "%8zu bytes (%.3f bpv): %s (%zu vertices, bit plane %d%s%s)", at, bpv, name,
                 r.mesh.vertex_count(), r.bit_plane, base_part_note(r, base_vertices).c_str(), r.complete ? ", complete" : "");
    if (!a.reference.empty()) std::fprintf(stderr, ", PSNR %.2f dB", psnr);
    std::fprintf(stderr, "\n");
    char row[128];
    std::snprintf(row, sizeof row, "%zu,%.4f,%zu,%d,%.3f\n", at, bpv, r.mesh.vertex_count(), r.bit_plane, psnr);
    csv += row;
  }
  if (!a.csv.empty()) {
    std::string error;
    if (!write_bytes(a.csv, std::vector<std::uint8_t>(csv.begin(), csv.end()), error)) {
      std::cerr << "meshlift: " << error << "\n";
      return kOutputError;
    }
  }
  if (!a.directory.empty()) std::fprintf(stderr, "%zu meshes written to %s\n", written, a.directory.c_str());
  return kOk;
}

}  // namespace

TangentChoice choose_tangent_shift(const SemiRegularMesh& mesh, EncodeOptions options, std::size_t input_vertices,
                                   const std::function<double(const TriangleMesh&)>& psnr) {
  constexpr std::size_t kRates = std::size(kTangentChoiceBpv);
  constexpr int kShifts[2] = {kDefaultTangentShift, kCreaseTangentShift};
  double psnr_at[2][kRates];
  options.max_bytes = std::numeric_limits<std::size_t>::max();  // the whole stream, cut below
  for (int k = 0; k < 2; ++k) {
    options.tangent_shift = kShifts[k];
    const std::vector<std::uint8_t> file = encode(mesh, options);
    for (std::size_t r = 0; r < kRates; ++r)
      psnr_at[k][r] = prefix_psnr(
          file, static_cast<std::size_t>(std::ceil(kTangentChoiceBpv[r] * static_cast<double>(input_vertices) / 8)), psnr);
  }
  // Means over the rates both decode at (a cut inside the header and base decodes at neither:
  // the shift changes nothing there).
  double mean[2] = {0, 0};
  int rates = 0;
  for (std::size_t r = 0; r < kRates; ++r)
    if (std::isfinite(psnr_at[0][r]) && std::isfinite(psnr_at[1][r])) {
      for (int k = 0; k < 2; ++k) mean[k] += psnr_at[k][r];
      ++rates;
    }
  for (double& m : mean) m = rates > 0 ? m / rates : 0;
  const int chosen = mean[1] > mean[0] ? 1 : 0;  // a tie keeps the default
  return {kShifts[chosen], mean[chosen], kShifts[1 - chosen], mean[1 - chosen]};
}

void add_frame_options(CLI::App& cmd, FrameArgs& args) {
  cmd.add_option("--frames", args.frames,
                 "coordinates of the geometry details: local (normal and two tangents of the coarser level) or xyz")
      ->check(CLI::IsMember({"local", "xyz"}))
      ->capture_default_str();
  cmd.add_option("--tangent-shift", args.tangent_shift,
                 "local frames: quantize the tangential components 2^N times more coarsely than the normal; by default 2, "
                 "or 1 where the remesh follows the input's feature lines (CAD parts) and its prefixes at 1-8 bits per "
                 "input vertex decode closer to the input with it")
      ->check(CLI::Range(0, 16));
  cmd.add_flag("--no-base-prediction", args.no_base_prediction,
               "code every bit plane of the base vertices in the embedded planes instead of their top planes "
               "predicted first (FORMAT.md 5.1; for rate-distortion experiments: more bits at every rate above "
               "the base part's)");
  cmd.add_flag("--update,!--no-update", args.update,
               "linear and butterfly: the lifting's mean-preserving update step, on by default (coarser levels smoothed, "
               "not sampled: closer prefixes; 0.3-13 % fewer bits at equal PSNR on the nine rate-distortion meshes, "
               "for a butterfly decode about a third slower); --no-update leaves it out")
      ->capture_default_str();
}

void register_encode(CLI::App& app, int& exit_code) {
  auto a = std::make_shared<EncodeArgs>();
  auto* cmd = app.add_subcommand("encode", "Encode a semi-regular mesh into an embedded .mlz stream");
  cmd->add_option("input", a->input, "triangle mesh (remeshed unless it already is semi-regular)")->required();
  cmd->add_option("-o,--output", a->output, "output .mlz file")->required();
  cmd->add_option("--scheme", a->scheme,
                 "wavelet: linear, butterfly, loop, or auto: the one whose details of the mesh have the least energy "
                 "(butterfly on remeshes, Loop on Loop-subdivided meshes)")
      ->check(CLI::IsMember({"auto", "linear", "butterfly", "loop"}))
      ->capture_default_str();
  add_remesh_options(*cmd, a->remesh, "--remesh");
  cmd->add_option("--bits", a->bits,
                  "precision of the finest bit plane: step = diagonal * 2^-bits (default: 15 for a remesh farther than "
                  "85 dB from its input, whose own error is far above that step, unless --psnr is given; else 16)")
      ->check(CLI::Range(1, 40));
  cmd->add_option("--colour-bits", a->colour_bits,
                  "an input with vertex colours: their step, 2^-B of each component's range (9: a byte decoded whole "
                  "comes back within one, mostly the same; fewer: smaller files, coarser colours)")
      ->check(CLI::Range(1, 16))
      ->capture_default_str();
  add_frame_options(*cmd, a->frames);
  auto* bpv = cmd->add_option("--bpv", a->bpv, "cut the stream at this many bits per input vertex")
                  ->check(CLI::PositiveNumber & kFinite);
  auto* bytes = cmd->add_option("--bytes", a->bytes, "cut the stream at this many bytes")->check(CLI::PositiveNumber)->excludes(bpv);
  cmd->add_option("--psnr", a->psnr,
                  "cut the stream at the shortest prefix (within 1/256 of its length) whose decode is within this "
                  "PSNR in dB of the input mesh: symmetric surface RMS, bounding-box diagonal as peak, as `compare` "
                  "measures it (docs/METRIC.md); the whole stream, with a note, if it never gets that close")
      ->check(CLI::PositiveNumber & kFinite)
      ->excludes(bpv)
      ->excludes(bytes);
  cmd->callback([a, &exit_code] { exit_code = run_encode(*a); });
}

void register_decode(CLI::App& app, int& exit_code) {
  auto a = std::make_shared<DecodeArgs>();
  auto* cmd = app.add_subcommand("decode", "Decode a .mlz stream (or a prefix of it) into a mesh");
  cmd->add_option("input", a->input, "input .mlz file")->required();
  cmd->add_option("-o,--output", a->output, "output mesh (obj, off, ply, stl)")->required();
  cmd->add_option("--bytes", a->bytes, "decode only this prefix")->check(CLI::PositiveNumber);
  cmd->add_option("--level", a->level, "stop at this refinement level")->check(CLI::Range(0, 12));
  cmd->add_option("--threads", a->threads,
                  "threads: 1, or 2 and more for two (the same mesh); 0 for two on a machine with two cores or more "
                  "and an output of 32,768 vertices or more")
      ->capture_default_str();
  cmd->add_flag("--stats", a->stats, "print decode time (file I/O excluded) and vertices per second");
  cmd->add_flag("--binary", a->binary, "binary PLY/STL output");
  cmd->callback([a, &exit_code] { exit_code = run_decode(*a); });
}

void register_truncate(CLI::App& app, int& exit_code) {
  auto a = std::make_shared<TruncateArgs>();
  auto* cmd = app.add_subcommand("truncate", "Cut a .mlz stream to a valid, smaller file (no re-encoding)");
  cmd->add_option("input", a->input, "input .mlz file")->required();
  auto* bytes =
      cmd->add_option("--bytes", a->bytes, "prefix length to keep (the file may end up to 4 bytes longer: the last chunk's checksum)")
          ->check(CLI::PositiveNumber);
  auto* psnr = cmd->add_option("--psnr", a->psnr,
                               "instead: keep the shortest prefix (within 1/256 of its length) whose decode is within this PSNR "
                               "in dB of the --reference mesh, as `compare` measures it (docs/METRIC.md), as `encode --psnr` cuts")
                   ->check(CLI::PositiveNumber & kFinite)
                   ->excludes(bytes);
  auto* reference = cmd->add_option("--reference", a->reference, "with --psnr: the mesh the file was encoded from")->needs(psnr);
  psnr->needs(reference);
  cmd->add_option("-o,--output", a->output, "output .mlz file")->required();
  cmd->callback([a, &exit_code] { exit_code = run_truncate(*a); });
}

void register_stream(CLI::App& app, int& exit_code) {
  auto a = std::make_shared<StreamArgs>();
  auto* cmd = app.add_subcommand("stream", "Write the mesh a streaming viewer holds after every N bytes");
  cmd->add_option("input", a->input, "input .mlz file")->required();
  cmd->add_option("--every", a->every, "bytes between snapshots")->required()->check(CLI::PositiveNumber);
  cmd->add_option("-o,--output", a->directory, "directory for the meshes (none written without it)");
  cmd->add_option("--reference", a->reference,
                  "print the PSNR of each snapshot against this mesh: the encoded semi-regular mesh (its vertices "
                  "against the decoded ones), or any other, such as the one the file was encoded from (the surface "
                  "metric of docs/METRIC.md, as `compare` measures)");
  cmd->add_option("--csv", a->csv, "write bytes, bits per vertex, bit plane and PSNR per snapshot to this file");
  cmd->callback([a, &exit_code] { exit_code = run_stream(*a); });
}

}  // namespace meshlift::cli
