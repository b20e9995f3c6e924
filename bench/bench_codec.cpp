// Codec throughput on a >= 2 M-vertex semi-regular mesh: encode and decode (whole file and a
// ~2 bits/vertex prefix), the decode split into its stages, and the peak memory of a decode.
//   cmake -B build -DMESHLIFT_BENCH=ON && cmake --build build --target bench_codec && ./build/bench_codec [runs]
// Every figure is the best of `runs` (default 5) runs, as wall time and as this process's user
// CPU time (getrusage): on a machine shared with other jobs the CPU time is the steadier one.
// Each line also gives the first run's wall time: later runs reuse memory the process has just
// freed, which a process that encodes or decodes once (the CLI) does not have.
#include <malloc.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>

#include "test_meshes.h"
#include "meshlift/codec.h"
#include "meshlift/container.h"
// The coefficient coder (and the base part before it) is internal to the codec library (no public header): timed alone here.
#include "../codec/base_values.h"
#include "../codec/zerotree_coder.h"

using namespace meshlift;

namespace {

struct Timing {
  double wall = 1e300, user = 1e300, system = 1e300;
  double first_wall = 0;  ///< the first run's
};

double cpu_seconds(const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); }

/// Runs f `runs` times; the best wall, user and system times (each its own minimum).
template <class F>
Timing best_of(int runs, F&& f) {
  Timing best;
  for (int r = 0; r < runs; ++r) {
    rusage before{}, after{};
    getrusage(RUSAGE_SELF, &before);
    const auto t0 = std::chrono::steady_clock::now();
    f();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    getrusage(RUSAGE_SELF, &after);
    if (r == 0) best.first_wall = wall;
    best.wall = std::min(best.wall, wall);
    best.user = std::min(best.user, cpu_seconds(after.ru_utime) - cpu_seconds(before.ru_utime));
    best.system = std::min(best.system, cpu_seconds(after.ru_stime) - cpu_seconds(before.ru_stime));
  }
  return best;
}

void print_timing(const char* what, const Timing& t, double vertices, const std::string& extra = "") {
  std::printf("  %-22s wall %6.3f s  user %6.3f s  sys %6.3f s  %6.2f M vertices/s (wall)  first run %6.3f s  %s\n", what,
              t.wall, t.user, t.system, vertices / t.wall / 1e6, t.first_wall, extra.c_str());
}

/// FNV-1a of the decoded positions' and faces' bytes: a speed change must leave them alone.
std::uint64_t output_hash(const DecodeResult& r) {
  std::uint64_t hash = 14695981039346656037ull;
  auto mix = [&hash](const void* data, std::size_t bytes) {
    for (std::size_t i = 0; i < bytes; ++i) hash = (hash ^ static_cast<const unsigned char*>(data)[i]) * 1099511628211ull;
  };
  mix(r.mesh.positions.data(), r.mesh.positions.size() * sizeof(double));
  mix(r.mesh.triangles.data(), r.mesh.triangles.size() * sizeof(std::uint32_t));
  return hash;
}

/// VmRSS or VmHWM of this process in bytes (Linux /proc/self/status).
double status_bytes(const char* field) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind(field, 0) == 0) return 1024.0 * std::strtod(line.c_str() + std::string(field).size() + 1, nullptr);
  return -1;
}

/// Peak resident bytes f adds above what the process holds before it: freed heap is returned to
/// the system first (malloc_trim), then the high-water mark is reset to the current resident size
/// (/proc/self/clear_refs, Linux >= 4.0). -1 where that is not available.
template <class F>
double peak_bytes_added(F&& f) {
  malloc_trim(0);
  {
    std::ofstream clear("/proc/self/clear_refs");
    clear << "5";
    if (!clear) return -1;
  }
  const double before = status_bytes("VmRSS:");
  f();
  return status_bytes("VmHWM:") - before;
}

// Icosahedron refined twice (320 faces), Loop-subdivided 7 levels and displaced by a smooth
// bumpy field plus a small deterministic roughness: 2.6 M vertices with detail at every level.
SemiRegularMesh test_mesh(int levels) {
  const TriangleMesh m = test::icosahedron();
  const TriangleMesh base = refine_linear(m, 2).finest();
  SemiRegularMesh mesh = refine_linear(base, levels);
  std::fill(mesh.positions.begin() + static_cast<std::ptrdiff_t>(base.positions.size()), mesh.positions.end(), 0.0);
  WaveletTransform(mesh.hierarchy, {Scheme::loop, false}).synthesize(mesh.positions);
  for (std::size_t i = 0; i < mesh.positions.size(); i += 3) {
    const double x = mesh.positions[i], y = mesh.positions[i + 1], z = mesh.positions[i + 2];
    const std::uint64_t hash = (i * 0x9E3779B97F4A7C15ull) >> 40;
    const double rough = 2e-4 * (static_cast<double>(hash % 1000) / 1000.0 - 0.5);
    const double bump = 1 + 0.05 * std::sin(7 * x + 1) * std::cos(5 * y) + 0.02 * std::sin(23 * z) + rough;
    for (int k = 0; k < 3; ++k) mesh.positions[i + k] *= bump;
  }
  return mesh;
}

}  // namespace

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  // Every array of 256 KiB or more is mapped fresh and returned on release, as in a process that
  // decodes once: its page faults count in every run, not only in the first (glibc would
  // otherwise raise this threshold and recycle freed arrays between runs).
  mallopt(M_MMAP_THRESHOLD, 256 * 1024);
  constexpr int levels = 7;
  const SemiRegularMesh mesh = test_mesh(levels);
  const double V = mesh.hierarchy.vertex_count(levels);
  std::printf("mesh: %.0f vertices, %d levels, base %u vertices; best of %d runs\n", V, levels,
              mesh.hierarchy.vertex_count(0), runs);

  std::vector<std::uint8_t> file;
  const Timing encode_time = best_of(runs, [&] { file = encode(mesh, {}); });
  std::printf("end to end:\n");
  print_timing("encode", encode_time, V,
               std::to_string(file.size()) + " bytes, " + std::to_string(8.0 * file.size() / V).substr(0, 4) +
                   " bits/vertex at 16-bit precision");
  {
    EncodeOptions one;
    one.threads = 1;
    std::vector<std::uint8_t> same;
    const Timing t = best_of(runs, [&] { same = encode(mesh, one); });
    print_timing("encode, 1 thread", t, V, same == file ? "(the same bytes)" : "(BYTES DIFFER)");
  }
  {
    // The same mesh in the stream's own order (canonical_order(), the order a decode returns):
    // the encoder reads it as it is, without building a hierarchy in that order.
    const SemiRegularMesh ordered = canonical_order(mesh);
    std::vector<std::uint8_t> same;
    const Timing t = best_of(runs, [&] { same = encode(ordered, {}); });
    print_timing("encode, canonical input", t, V, same == file ? "(the same bytes)" : "(BYTES DIFFER)");
  }
  const std::size_t two_bpv = static_cast<std::size_t>(2 * V / 8);
  {
    // To a budget of 2 bits per vertex, the rate of the decode lines below: the bit planes stop
    // past the coefficient chunk the cut falls in (encoder.cpp), and the file is the whole one
    // cut there.
    std::vector<std::uint8_t> expected;
    truncate_file(file, two_bpv - container::kChecksumBytes, expected);
    for (const unsigned threads : {0u, 1u}) {
      EncodeOptions budget;
      budget.max_bytes = two_bpv;
      budget.threads = threads;
      std::vector<std::uint8_t> cut;
      const Timing t = best_of(runs, [&] { cut = encode(mesh, budget); });
      print_timing(threads == 1 ? "encode to 2 bpv, 1 thread" : "encode to 2 bpv", t, V,
                   cut == expected ? "(the whole file cut there)" : "(BYTES DIFFER)");
    }
  }

  Timing whole_file;
  std::string output_hashes;
  auto add_hash = [&output_hashes](const std::string& what, std::uint64_t hash) {
    char line[96];
    std::snprintf(line, sizeof line, "  %-22s %016llx\n", (what + " hash").c_str(), static_cast<unsigned long long>(hash));
    output_hashes += line;
  };
  std::uint64_t cold_hashes[2] = {};
  // Decodes the first `budget` bytes of `stream` `runs` times on `threads` threads (DecodeOptions);
  // prints the best time as "decode N bpv<label>".
  auto timed_decode = [&](const std::vector<std::uint8_t>& stream, std::size_t budget, const std::string& label,
                          DecodeResult& r, unsigned threads = 1) {
    DecodeOptions o;
    o.max_bytes = budget;
    o.threads = threads;
    const Timing t = best_of(runs, [&] { r = decode(stream, o); });
    const std::string what = "decode " + std::to_string(8.0 * r.bytes_used / V).substr(0, 4) + " bpv" + label;
    print_timing(what.c_str(), t, V, "bit plane " + std::to_string(r.bit_plane));
    return std::pair{t, what};
  };
  for (std::size_t budget : {two_bpv, file.size()}) {
    DecodeResult r;
    const auto [t, what] = timed_decode(file, budget, "", r);
    if (budget == file.size()) whole_file = t;
    cold_hashes[budget == file.size()] = output_hash(r);
    add_hash(what, cold_hashes[budget == file.size()]);
  }
  // The same on two threads (DecodeOptions::threads; the default, 0, takes two on this machine):
  // the output's faces made while the coefficients are decoded, each level's synthesis split.
  for (std::size_t budget : {two_bpv, file.size()}) {
    DecodeResult r;
    timed_decode(file, budget, ", 2 threads", r, 2);
    if (output_hash(r) != cold_hashes[budget == file.size()]) std::printf("  2 THREADS: OUTPUT DIFFERS\n");
  }
  // The same decodes into one result kept across calls (decode_into): its output arrays reused,
  // as by a viewer that asks for the mesh again and again; the figures above are a fresh
  // process's (every output page faulted in), these what each later call pays.
  for (std::size_t budget : {two_bpv, file.size()}) {
    DecodeOptions o;
    o.max_bytes = budget;
    o.threads = 1;
    DecodeResult r;
    decode_into(file, o, r);  // the first call, which allocates
    const Timing t = best_of(runs, [&] { decode_into(file, o, r); });
    const std::string what = "decode " + std::to_string(8.0 * r.bytes_used / V).substr(0, 4) + " bpv reused";
    print_timing(what.c_str(), t, V,
                 output_hash(r) == cold_hashes[budget == file.size()] ? "(decode_into: the same output)"
                                                                       : "(decode_into: OUTPUT DIFFERS)");
  }
  {
    // A viewer receiving the whole file in 16 pieces and asking for the mesh after each
    // (Decoder::mesh into one kept result), against decoding each of those prefixes again
    // (decode_into, what mesh() did before the Decoder kept its own decode going).
    constexpr std::size_t kPieces = 16;
    const std::size_t piece = (file.size() + kPieces - 1) / kPieces;
    DecodeResult streamed, again;
    // The Decoder's own thread decodes the bytes as they come in both; mesh() runs on the
    // caller's thread alone (threads = 1) or beside a second (threads = 2).
    auto stream_time = [&](unsigned threads) {
      DecodeOptions o;
      o.threads = threads;
      return best_of(runs, [&] {
        Decoder decoder(o);
        for (std::size_t at = 0; at < file.size(); at += piece) {
          decoder.push(std::span(file).subspan(at, std::min(piece, file.size() - at)));
          decoder.mesh(streamed);
        }
      });
    };
    const Timing one_thread = stream_time(1);
    const bool streamed_same = output_hash(streamed) == cold_hashes[1];
    const Timing two_threads = stream_time(2);
    const Timing again_time = best_of(runs, [&] {
      for (std::size_t at = 0; at < file.size(); at += piece) {
        DecodeOptions o;
        o.max_bytes = std::min(at + piece, file.size());
        o.threads = 1;
        decode_into(file, o, again);
      }
    });
    const bool same = streamed_same && output_hash(streamed) == cold_hashes[1] && output_hash(again) == cold_hashes[1];
    print_timing("stream, 16 meshes", one_thread, V * kPieces,
                 same ? "(Decoder::mesh after each 16th of the file; the whole file's output at the end)"
                      : "(OUTPUT DIFFERS from the whole file's)");
    print_timing("stream, 2 threads", two_threads, V * kPieces, "(the same, mesh() on two threads)");
    print_timing("16 prefixes again", again_time, V * kPieces, "(decode_into of the same 16 prefixes)");
  }
  {
    // The wavelet `meshlift encode --scheme auto` takes on remeshes, butterfly (its normal lines
    // go through butterfly's prediction), with its mean-preserving update (the default): the same
    // mesh and budget, decoded (the whole file is 1.87 bpv: below the budget). Its stencil rows (8
    // sources each) are applied as they are read off the level below, with no table, as Loop's
    // are; the update's column sums take a first pass over them.
    EncodeOptions butterfly;
    butterfly.scheme = Scheme::butterfly;
    DecodeResult r;
    const std::vector<std::uint8_t> stream = encode(mesh, butterfly);
    const std::string what = timed_decode(stream, two_bpv, ", butterfly", r).second;
    const std::uint64_t hash = output_hash(r);
    add_hash(what, hash);  // after the decode (arguments are evaluated in no set order)
    timed_decode(stream, two_bpv, ", butterfly, 2 threads", r, 2);
    if (output_hash(r) != hash) std::printf("  2 THREADS: OUTPUT DIFFERS\n");
  }
  std::printf("decoded output (positions and faces, FNV-1a):\n%s", output_hashes.c_str());
  {
    // The encoded bytes too: a speed change must leave the stream alone as well.
    std::uint64_t hash = 14695981039346656037ull;
    for (const std::uint8_t b : file) hash = (hash ^ b) * 1099511628211ull;
    std::printf("encoded bytes (FNV-1a):\n  %-22s %016llx\n", "stream hash", static_cast<unsigned long long>(hash));
  }

  // The stages of a decode (and analysis, the encoder's counterpart of synthesis), timed alone.
  std::printf("stages:\n");
  std::optional<SemiRegularHierarchy> h;
  const Timing hierarchy_time = best_of(runs, [&] {
    h.reset();
    h.emplace(mesh.hierarchy.topology(0), levels);
  });
  const Timing lean_hierarchy_time = best_of(runs, [&] {
    h.reset();
    h.emplace(mesh.hierarchy.topology(0), levels, false);
  });
  std::vector<std::uint32_t> triangles;
  const Timing triangles_time = best_of(runs, [&] { triangles = h->copy_triangles(levels); });
  triangles = {};
  const Timing decoder_hierarchy_time = best_of(runs, [&] {
    h.reset();
    h.emplace(mesh.hierarchy.topology(0), levels, false, false);
  });
  const Timing loop_decoder_hierarchy_time = best_of(runs, [&] {
    h.reset();
    h.emplace(mesh.hierarchy.topology(0), levels, false, false, false);
  });
  h.reset();
  h.emplace(mesh.hierarchy.topology(0), levels);
  std::optional<WaveletTransform> transform;
  const Timing tables_time = best_of(runs, [&] {
    transform.reset();
    transform.emplace(*h, WaveletOptions{Scheme::loop, false});
  });
  std::vector<double> values;
  const Timing synthesis_time = best_of(runs, [&] {
    values = mesh.positions;  // the copy is part of the figure (a decoder fills its values too)
    transform->synthesize(values);
  });
  const Timing analysis_time = best_of(runs, [&] {
    values = mesh.positions;
    transform->analyze(values);
  });
  print_timing("hierarchy", hierarchy_time, V);
  print_timing("  without finest faces", lean_hierarchy_time, V, "(SemiRegularHierarchy(base, L, false): what a decoder");
  print_timing("  + copy_triangles(L)", triangles_time, V, "could build, making the output's faces at its end)");
  print_timing("  and without the tree", decoder_hierarchy_time, V, "(SemiRegularHierarchy(base, L, false, false): the decoder's)");
  print_timing("  and without level L-1", loop_decoder_hierarchy_time, V,
               "(SemiRegularHierarchy(base, L, false, false, false): the decoder's)");
  print_timing("stencil tables", tables_time, V);
  print_timing("synthesis", synthesis_time, V);
  print_timing("analysis", analysis_time, V);
  const Timing rest{whole_file.wall - hierarchy_time.wall - tables_time.wall - synthesis_time.wall,
                    whole_file.user - hierarchy_time.user - tables_time.user - synthesis_time.user,
                    whole_file.system - hierarchy_time.system - tables_time.system - synthesis_time.system};
  print_timing("rest of a decode", rest, V, "(whole-file decode minus the three stages above: container, base mesh,");
  std::printf("  %-22s %s\n", "", "coefficient tree and decoding, dequantization)");

  // The coefficient coder alone (SPIHT and the range coder, zerotree_coder.h): on the coefficient
  // bytes a decode of the ~2 bpv prefix and of the whole file gets, over the forest of the
  // canonically ordered mesh (the encoder's); then encoding what the whole file decodes to,
  // which must give the file's bytes back.
  {
    const SemiRegularMesh ordered = canonical_order(mesh);
    const zerotree::Forest forest(ordered.hierarchy);
    const StreamInfo info = inspect(file);
    const int top = info.top_plane, base_plane = info.base_plane;
    const TriangleTopology& base = ordered.hierarchy.topology(0);
    auto coefficient_bytes = [&](std::size_t budget) {
      ContainerReader reader;
      std::vector<std::uint8_t> bytes;
      if (reader.parse(std::span(file).first(std::min(budget, file.size()))) != Status::ok) return bytes;
      for (const Chunk& c : reader.chunks())
        if (c.tag == kTagCoefficients) bytes.insert(bytes.end(), c.payload.begin(), c.payload.end());
      return bytes;
    };
    zerotree::Decoded decoded;
    for (std::size_t budget : {two_bpv, file.size()}) {
      const std::vector<std::uint8_t> bytes = coefficient_bytes(budget);
      const Timing t = best_of(runs, [&] {
        RangeDecoder decoder(bytes);
        std::vector<std::int64_t> base_high;
        bool corrupt = false;
        base_values::decode(base, zerotree::kGeometryComponents, base_plane, top, decoder, base_high, corrupt);
        decoded = zerotree::decode(forest, zerotree::kGeometryComponents, top, base_plane, base_high, decoder);
      });
      const std::string what = "SPIHT decode " + std::to_string(8.0 * std::min(budget, file.size()) / V).substr(0, 4) + " bpv";
      print_timing(what.c_str(), t, V, "(coefficient bytes only)");
    }
    zerotree::Quantized q;
    q.allocate(static_cast<std::size_t>(V) * zerotree::kGeometryComponents);
    std::fill(q.coefficients.get(), q.coefficients.get() + q.size, zerotree::Quantized::Coefficient{});
    decoded.for_each([&](const zerotree::Decoded::Coefficient& x) {
      const std::size_t i = std::size_t{x.vertex} * zerotree::kGeometryComponents + static_cast<std::size_t>(x.component);
      q.coefficients[i].magnitude = x.known;
      q.coefficients[i].negative = x.negative;
    });
    decoded = {};
    for (const bool concurrent : {false, true}) {
      std::vector<std::uint8_t> bytes;
      const Timing t = best_of(runs, [&] {
        RangeEncoder encoder;
        base_values::encode(base, q, base_plane, top, encoder);
        zerotree::encode(forest, q, top, base_plane, encoder, concurrent);
        bytes = encoder.finish();
      });
      const bool same = bytes == coefficient_bytes(file.size());
      print_timing(concurrent ? "SPIHT encode, 2 threads" : "SPIHT encode", t, V,
                   same ? "(the file's coefficient bytes)" : "(BYTES DIFFER FROM THE FILE'S)");
    }
  }

  std::printf("memory:\n");
  std::printf("  hierarchy %.1f bytes/vertex, stencil tables %.1f bytes/vertex (their own accounting)\n",
              h->memory_bytes() / V, transform->memory_bytes() / V);
  h.reset();
  transform.reset();
  values = {};
  for (const unsigned threads : {1u, 2u})
    for (std::size_t budget : {two_bpv, file.size()}) {
      DecodeOptions o;
      o.max_bytes = budget;
      o.threads = threads;
      const double peak = peak_bytes_added([&] { const DecodeResult r = decode(file, o); });
      std::printf("  decode of %.2f bpv, %u thread%s: peak %.0f MiB above the bench's own data, %.0f bytes per output vertex\n",
                  8.0 * std::min(budget, file.size()) / V, threads, threads > 1 ? "s" : "", peak / (1 << 20), peak / V);
    }
  // The encoder's own peak (two threads, the default), for the mesh in its own order and in the
  // stream's: what it allocates above the mesh it is given.
  {
    const SemiRegularMesh ordered = canonical_order(mesh);
    for (const bool canonical : {false, true}) {
      const double peak = peak_bytes_added([&] { const std::vector<std::uint8_t> f = encode(canonical ? ordered : mesh, {}); });
      std::printf("  encode%s: peak %.0f MiB above the bench's own data, %.0f bytes per vertex\n",
                  canonical ? " of the mesh in canonical order" : "", peak / (1 << 20), peak / V);
    }
  }
  const double hierarchy_peak =
      peak_bytes_added([&] { const SemiRegularHierarchy alone(mesh.hierarchy.topology(0), levels); });
  const SemiRegularHierarchy hierarchy(mesh.hierarchy.topology(0), levels);
  const double tables_peak =
      peak_bytes_added([&] { const WaveletTransform alone(hierarchy, WaveletOptions{Scheme::loop, false}); });
  std::printf("  construction alone: hierarchy peak %.0f, stencil tables peak %.0f bytes per vertex\n",
              hierarchy_peak / V, tables_peak / V);
  // The geometry path of a decode with the hierarchy's lean options, each array released as soon
  // as the next step no longer needs it: values in, mesh out, no coefficient decoding.
  Timing path_time;
  const double path_peak = peak_bytes_added([&] {
    path_time = best_of(1, [&] {
      SemiRegularHierarchy lean(mesh.hierarchy.topology(0), levels, false);
      std::vector<double> positions = mesh.positions;
      {
        const WaveletTransform synthesis(lean, WaveletOptions{Scheme::loop, false});
        synthesis.synthesize(positions);
      }
      TriangleMesh out{std::move(positions), std::move(lean).release_finest_triangles()};
    });
  });
  std::printf("  geometry path of a decode (hierarchy without finest faces, tables, synthesis of the values,\n"
              "  tables freed, release_finest_triangles()): peak %.0f bytes per vertex, %.3f s user, %.3f s sys\n",
              path_peak / V, path_time.user, path_time.system);
  // The same as the decoder runs it now: no stored tree, synthesize_level() (Loop rows a block at
  // a time, no tables kept).
  // Peak of the decoder's geometry path with or without the topology of level L - 1.
  auto decoder_path_peak = [&](bool keep_topology_below_finest) {
    return peak_bytes_added([&] {
      path_time = best_of(1, [&] {
        SemiRegularHierarchy lean(mesh.hierarchy.topology(0), levels, false, false, keep_topology_below_finest);
        std::vector<double> positions = mesh.positions;
        for (int j = 0; j < levels; ++j) synthesize_level(lean, WaveletOptions{Scheme::loop, false}, j, positions);
        TriangleMesh out{std::move(positions), std::move(lean).release_finest_triangles()};
      });
    });
  };
  const double level_path_peak = decoder_path_peak(true);
  std::printf("  the decoder's geometry path (no tree, synthesize_level() per level): peak %.0f bytes per vertex,\n"
              "  %.3f s user, %.3f s sys\n",
              level_path_peak / V, path_time.user, path_time.system);
  // As the decoder runs it now (every scheme): also without the topology of level L - 1 (its
  // frames, synthesis and faces read off level L - 2).
  const double lean_path_peak = decoder_path_peak(false);
  std::printf("  ... and without the topology of level L-1 (the decoder's): peak %.0f bytes per vertex,\n"
              "  %.3f s user, %.3f s sys\n",
              lean_path_peak / V, path_time.user, path_time.system);
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf("  whole bench (encoder, decoder, test mesh): peak %.0f MiB, %.0f bytes per vertex\n",
              usage.ru_maxrss / 1024.0, usage.ru_maxrss * 1024.0 / V);
  return 0;
}
