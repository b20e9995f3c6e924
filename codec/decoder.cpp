// .mlz stream -> mesh, for whole files and for any prefix (bitstream/FORMAT.md §3-5). Mirrors
// encoder.cpp. Untrusted bytes: every count is checked against the caller's limits and the bytes
// present before anything is allocated; failures are numbered statuses, never exceptions.
// A decode is prepare() (header, base mesh, hierarchy), the base part and the bit planes, then
// dequantize() and synthesize(): decode() runs them in turn; the streaming Decoder (at the end)
// runs the middle on a thread of its own as bytes arrive, and the last two at each mesh().
#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <new>
#include <thread>
#include <optional>

#include "base_mesh_coder.h"
#include "base_values.h"
#include "concurrent.h"
#include "large_array.h"
#include "local_frames.h"
#include "meshlift/codec.h"
#include "meshlift/container.h"
#include "stream_header.h"
#include "zerotree_coder.h"

namespace meshlift {
namespace {

/// Every base face costs at least one modelled decision (its gate's boundary bit, or a new
/// component's start bits), and the cheapest decision costs -log2(kProbMax / kProbOne) =
/// -log2(32640 / 32768) = 0.00565 bits (range_coder.h), so a byte holds at most 8 / 0.00565 =
/// 1417 faces. A base chunk claiming more faces than this allows is corrupt (checked before
/// allocating). (A bound of 64 refused real regular meshes, whose faces cost ~0.01 bits each.)
constexpr std::uint64_t kMaxFacesPerBaseByte = 1420;

DecodeResult failure(Status status, std::string message) {
  DecodeResult r;
  r.status = status;
  r.message = std::move(message);
  return r;
}

struct ParsedStream {
  ContainerReader container;
  StreamHeader header;
  const Chunk* base = nullptr;
  std::vector<std::span<const std::uint8_t>> coefficient_payloads;  ///< of the COEF chunks, in order
  std::vector<std::uint8_t> coefficients;  ///< those concatenated (parse() only)
};

/// Reads the header and finds the chunks in out.container, whose parse of `bytes` returned
/// `container_status`; on success fills `out` but for `coefficients`, else returns the failure.
DecodeResult read_chunks(Status container_status, std::span<const std::uint8_t> bytes, const DecodeLimits& limits,
                         ParsedStream& out) {
  out.header = StreamHeader();
  out.base = nullptr;
  out.coefficient_payloads.clear();
  if (container_status != Status::ok) {
    const ContainerError& e = out.container.error();
    const std::uint8_t version = out.container.version();
    // unsupported_version is also an unknown critical chunk (FORMAT.md §2.4): only another
    // version number gets the version's own explanation.
    if (container_status == Status::unsupported_version && version != container::kFormatVersion)
      return failure(container_status,
                     "the stream is format version " + std::to_string(version) + "; this build reads only version " +
                         std::to_string(container::kFormatVersion) +
                         (version == 0 ? ""
                          : version < container::kFormatVersion
                              ? " (an earlier meshlift wrote it, whose coefficients are coded differently: re-encode "
                                "it from the source mesh with this build)"
                              : " (a later meshlift wrote it: upgrade meshlift)") +
                         " (at byte " + std::to_string(e.offset) + ")");
    return failure(container_status, std::string(describe(container_status)) + " (at byte " + std::to_string(e.offset) +
                                         ", chunk " + std::to_string(e.chunk_index) + ")");
  }
  const auto& chunks = out.container.chunks();
  if (chunks.empty() || !chunks[0].complete)
    return failure(Status::truncated, "the stream ends inside its header chunk (at byte " + std::to_string(bytes.size()) + ")");
  if (chunks[0].tag != kTagHeader)
    return failure(Status::corrupt, "the first chunk (at byte 8) is " + tag_to_string(chunks[0].tag) + ", not HEAD");
  std::string message;
  const Status header_status = out.header.read(chunks[0].payload, limits, message);
  if (header_status != Status::ok) return failure(header_status, message + " (HEAD chunk at byte 8)");
  for (std::size_t i = 1; i < chunks.size(); ++i) {
    const Chunk& c = chunks[i];
    if (c.tag == kTagBaseMesh && i == 1) {
      out.base = &c;
    } else if (c.tag == kTagCoefficients && i >= 2) {
      out.coefficient_payloads.push_back(c.payload);
    } else if (c.tag == 0 && !c.complete) {
      // cut inside a chunk's tag: nothing of it is usable
    } else if (c.tag == kTagHeader || c.tag == kTagBaseMesh || c.tag == kTagCoefficients) {
      return failure(Status::corrupt, "chunk " + tag_to_string(c.tag) + " out of place at byte " + std::to_string(c.offset));
    } else if (is_critical_tag(c.tag)) {
      return failure(Status::unsupported_version,
                     "unknown critical chunk " + tag_to_string(c.tag) + " at byte " + std::to_string(c.offset));
    }  // unknown ancillary chunks are skipped (FORMAT.md §2.4)
  }
  if (out.base == nullptr || !out.base->complete)
    return failure(Status::truncated, "the stream ends before its base mesh is complete (at byte " +
                                          std::to_string(bytes.size()) + ")");
  return {};
}

/// Parses container and header; on success fills `out`, else returns the failure.
DecodeResult parse(std::span<const std::uint8_t> bytes, const DecodeLimits& limits, ParsedStream& out) {
  DecodeResult r = read_chunks(out.container.parse(bytes), bytes, limits, out);
  for (const std::span<const std::uint8_t> payload : out.coefficient_payloads)
    out.coefficients.insert(out.coefficients.end(), payload.begin(), payload.end());
  return r;
}


/// Output arrays handed over by decode_into's caller: their storage is used where large enough.
struct Storage {
  std::vector<double> positions;
  std::vector<std::uint32_t> faces;
  std::vector<VertexChannel> channels;
};

/// What a decode knows before its first coefficient: the header, and the hierarchy its base
/// refines to, checked against the caller's limits.
struct Prepared {
  StreamHeader header;
  std::optional<SemiRegularHierarchy> hierarchy;
  /// With the mean-preserving update, its weights of levels 0, 1, ... (update_weights(), lifting.h),
  /// kept by a streaming Decoder from its first mesh for the next. (A one-time decode lets
  /// synthesize_level make each level's beside the turning of its details, on two threads: made
  /// beside the coefficients' decoding instead, they made a 3.3 M-vertex file at 0.58 bpv slower,
  /// 0.334-0.360 -> 0.355-0.417 s, its coefficients being too few to hide them.)
  std::vector<std::vector<double>> update_weights;
  int components() const { return header.components(); }
  bool has_update() const { return header.scheme != Scheme::loop && header.mean_preserving_update; }
  /// Makes update_weights of levels below `level` (those not made yet).
  void make_update_weights(int level) {
    while (static_cast<int>(update_weights.size()) < level)
      update_weights.push_back(meshlift::update_weights(*hierarchy, header.scheme, static_cast<int>(update_weights.size())));
  }
};

/// Decodes the base mesh and builds the hierarchy (FORMAT.md §3-4), every count checked against
/// the limits and the bytes present before the allocation it sizes. On success fills `out`.
DecodeResult prepare(const ParsedStream& stream, const DecodeLimits& limits, Prepared& out) {
  const StreamHeader& header = stream.header;
  if (header.base_faces > kMaxFacesPerBaseByte * stream.base->payload.size() + 1024)
    return failure(Status::corrupt, "the BASE chunk at byte " + std::to_string(stream.base->offset) + " is too short for " +
                                        std::to_string(header.base_faces) + " faces");
  if (header.base_vertices > 3 * std::uint64_t{header.base_faces})
    return failure(Status::corrupt, std::to_string(header.base_vertices) + " base vertices cannot all lie on " +
                                        std::to_string(header.base_faces) + " faces");
  if (kDecodeBytesPerBaseFace * header.base_faces > limits.max_memory_bytes)
    return failure(Status::limit_exceeded, "decoding " + std::to_string(header.base_faces) + " base faces may take " +
                                               std::to_string(kDecodeBytesPerBaseFace * header.base_faces) +
                                               " bytes, above the memory budget of " +
                                               std::to_string(limits.max_memory_bytes));
  std::vector<std::uint32_t> triangles;
  if (!base_mesh::decode_faces(stream.base->payload, header.base_vertices, header.base_faces, triangles))
    return failure(Status::corrupt, "the base mesh connectivity in the BASE chunk at byte " +
                                        std::to_string(stream.base->offset) + " does not decode to " +
                                        std::to_string(header.base_faces) + " faces");
  // Labels follow first use (§4), so the vertices no face uses are the last ones: none allowed.
  if (const std::uint32_t used = 1 + *std::max_element(triangles.begin(), triangles.end()); used != header.base_vertices)
    return failure(Status::corrupt, "the base mesh in the BASE chunk at byte " + std::to_string(stream.base->offset) +
                                        " leaves " + std::to_string(header.base_vertices - used) + " of its " +
                                        std::to_string(header.base_vertices) + " vertices on no face");
  TriangleTopology base;
  try {
    base = TriangleTopology::build(header.base_vertices, triangles);
  } catch (const MeshError& e) {
    return failure(Status::corrupt, "the base mesh in the BASE chunk at byte " + std::to_string(stream.base->offset) +
                                        " is not a manifold mesh: " + e.what());
  }
  const RefinedSize refined = refined_size(base, header.levels);
  const double vertices = refined.vertices;
  if (vertices > static_cast<double>(limits.max_vertices))
    return failure(Status::limit_exceeded, "the stream refines to " + std::to_string(static_cast<std::uint64_t>(vertices)) +
                                               " vertices (limit " + std::to_string(limits.max_vertices) + ")");
  // max_vertices <= 2^64 / kDecodeBytesPerVertex is not assumed: compare in double.
  const int K = header.components();
  const double per_vertex = static_cast<double>(kDecodeBytesPerVertex) +
                            static_cast<double>(kDecodeBytesPerChannelComponent) * (K - zerotree::kGeometryComponents);
  const double memory = per_vertex * std::max(vertices, refined.faces / 2);
  if (memory > static_cast<double>(limits.max_memory_bytes))
    return failure(Status::limit_exceeded, "decoding " + std::to_string(static_cast<std::uint64_t>(vertices)) +
                                               " vertices may take " + std::to_string(static_cast<std::uint64_t>(memory)) +
                                               " bytes, above the memory budget of " +
                                               std::to_string(limits.max_memory_bytes));
  try {
    // Without the finest level's faces until the end (the largest array; nothing reads it before)
    // and without the stored coefficient tree (the Forest reads it off the topologies). Without
    // the topology of level L - 1 either: the synthesis (the mean-preserving update's too), the
    // frames and the output faces read it off level L - 2 (a quarter of the size), and the
    // Forest never reads it.
    out.hierarchy.emplace(std::move(base), header.levels, false, false, false);
  } catch (const std::bad_alloc&) {
    return failure(Status::limit_exceeded, "not enough memory to decode this stream");
  } catch (const MeshError& e) {
    return failure(Status::corrupt, e.what());
  }
  out.header = header;
  return {};
}

DecodeResult corrupt_base_part() {
  return failure(Status::corrupt, "the base part of the coefficient stream holds a value out of range, or an "
                                  "invalid integer code");
}

/// The level a decode synthesizes to (DecodeOptions::max_level, at most the stream's).
int output_level(const DecodeOptions& options, int levels) {
  return options.max_level < 0 ? levels : std::min(options.max_level, levels);
}

/// Whether a decode of hierarchy `h` to its output level runs on two threads (DecodeOptions::threads).
bool concurrent_decode(const DecodeOptions& options, const SemiRegularHierarchy& h) {
  return options.threads == 0 ? std::thread::hardware_concurrency() > 1 &&
                                    h.vertex_count(output_level(options, h.levels())) >= DecodeOptions::kConcurrentDecodeVertices
                              : options.threads > 1;
}

/// The faces of the output level, for a decode that makes them on a second thread while the first
/// decodes the coefficients (into `storage`'s array where a caller lent one).
std::vector<std::uint32_t> output_faces(const SemiRegularHierarchy& h, const DecodeOptions& options, Storage* storage) {
  std::vector<std::uint32_t> faces;
  if (storage != nullptr) faces = std::move(storage->faces);
  h.copy_triangles(output_level(options, h.levels()), faces);
  return faces;
}

/// The significant coefficients dequantized into `values` (K per vertex, vertex-major, the others
/// 0): value = midpoint * step_c / w_j (FORMAT.md §5).
void dequantize(const Prepared& p, const zerotree::Decoded& decoded, std::vector<double>& values, bool zeroed = false) {
  const StreamHeader& header = p.header;
  const int K = p.components();
  const std::size_t k_stride = static_cast<std::size_t>(K);
  std::vector<double> base_step(k_stride), detail_step(k_stride);
  for (int c = 0; c < K; ++c) {
    base_step[static_cast<std::size_t>(c)] = header.component_step(c, 0);
    detail_step[static_cast<std::size_t>(c)] = header.component_step(c, 1);
  }
  // Insignificant coefficients are 0 (the zeros the vector starts with, or already holds if
  // `zeroed`: a second thread made it while the coefficients were decoded).
  // Made resident in one system call (large_array.h): the values are the largest array written here.
  if (!zeroed) assign_large(values, std::size_t{p.hierarchy->vertex_count(header.levels)} * k_stride);
  decoded.for_each([&](const zerotree::Decoded::Coefficient& x) {
    const auto c = static_cast<std::size_t>(x.component);
    values[k_stride * x.vertex + c] = zerotree::dequantize(x.steps(), (x.level == 0 ? base_step : detail_step)[c],
                                                           header.level_weights[static_cast<std::size_t>(x.level)]);
  });
}

/// The base part, then the bit planes (FORMAT.md §5), from `decoder` into `out`
/// (zerotree::decode_into: current at every decision). A stream cut inside the base part leaves
/// the later base vertices at their predictions, and the bit planes then stop at their first
/// decision. `between(n)` is called once the base part is done, with the base vertices decoded
/// whole. Returns false for a corrupt base part (nothing decoded into `out`).
template <class Between>
bool decode_coefficients(const Prepared& p, const zerotree::Forest& forest, RangeDecoder& decoder,
                         zerotree::Decoded& out, Between&& between) {
  const StreamHeader& header = p.header;
  std::vector<std::int64_t> base_high;
  bool corrupt = false;
  const std::uint32_t base = base_values::decode(p.hierarchy->topology(0), p.components(), header.base_plane,
                                                 header.top_plane, decoder, base_high, corrupt);
  if (corrupt) return false;
  between(base);
  zerotree::decode_into(forest, p.components(), header.top_plane, header.base_plane, base_high, decoder, out);
  return true;
}

/// How far the coefficient stream got, for the result.
struct Progress {
  int last_plane = -1;
  bool all_planes = false;  ///< every plane decoded
  std::uint32_t base_decoded = 0;
  std::size_t prefix_bytes = 0;
  bool container_truncated = false;
};

/// The dequantized values synthesized level by level (to options.max_level) into the result's
/// mesh and channels. `release` lets the finest faces be taken from the hierarchy (a decode
/// that does not need it again) instead of copied; `faces_made`, if given, holds the output's
/// faces, made already (output_faces). On two threads (concurrent_decode) each level above the
/// base has its rows split between them (synthesize_level: the block paths): the same bits.
DecodeResult synthesize(Prepared& p, bool release, std::vector<double> values, const Progress& progress,
                        const DecodeOptions& options, Storage* storage, std::vector<std::uint32_t>* faces_made = nullptr) {
  const StreamHeader& header = p.header;
  SemiRegularHierarchy& h = *p.hierarchy;
  const int L = header.levels;
  const int K = p.components();
  const std::size_t k_stride = static_cast<std::size_t>(K);
  DecodeResult result;
  result.levels = L;
  result.level = output_level(options, L);
  const bool concurrent = concurrent_decode(options, h);
  // Level by level (synthesize_level: at most one level's stencil tables in memory at once, for
  // Loop a block of them). With local frames, the details of level j + 1 are in the frames of
  // the level-j mesh just synthesized (encoder.cpp computes them from the same values at full
  // rate).
  const WaveletOptions wavelets{header.scheme, header.mean_preserving_update};
  // The vertex normals of every level in one array, sized for the largest (the last) level.
  std::vector<frames::Vec3> normals;
  if (header.local_frames && result.level > 0) reserve_large(normals, h.vertex_count(result.level - 1));
  // The update's weights: made here once and kept for the next mesh where the decode is a
  // streaming Decoder's (`release` false); a one-time decode lets synthesize_level make each
  // level's beside its details' turning.
  if (p.has_update() && !release) p.make_update_weights(result.level);
  for (int j = 0; j < result.level; ++j) {
    const std::span<const double> weights =
        j < static_cast<int>(p.update_weights.size()) ? std::span<const double>(p.update_weights[static_cast<std::size_t>(j)])
                                                      : std::span<const double>();
    if (!header.local_frames) {
      synthesize_level(h, wavelets, j, values, K, {}, concurrent, weights);
    } else {
      // Each block of details turned to (x, y, z) just before the synthesis reads it, in cache
      // (LevelFrames::rotate is const: the two threads rotate their own blocks).
      frames::LevelFrames level_frames(h, j, values, K, std::move(normals));
      const std::uint32_t first_odd = h.vertex_count(j);
      synthesize_level(
          h, wavelets, j, values, K,
          [&](std::uint32_t first, std::uint32_t count) {
            level_frames.rotate(first - first_odd, first - first_odd + count, values, frames::Direction::to_global);
          },
          concurrent, weights);
      normals = std::move(level_frames).release_storage();
    }
  }
  normals = std::vector<frames::Vec3>();  // freed (not `= {}`, which would keep the storage)
  // The centres back (synthesis reproduces constants, so adding them after it is adding them
  // to the base values; the encoder's closed loop works on the centred values too).
  const std::uint32_t n = h.vertex_count(result.level);
  std::size_t offset = zerotree::kGeometryComponents;
  for (const ChannelQuantization& c : header.channels) {
    const std::size_t m = static_cast<std::size_t>(c.components);
    VertexChannel channel{c.components, {}, result.channels.empty() && header.colour};
    if (storage != nullptr && result.channels.size() < storage->channels.size())
      channel.values = std::move(storage->channels[result.channels.size()].values);
    assign_large(channel.values, std::size_t{n} * m);
    for (std::uint32_t v = 0; v < n; ++v)
      for (std::size_t k = 0; k < m; ++k) channel.values[m * v + k] = values[k_stride * v + offset + k] + c.center[k];
    offset += m;
    result.channels.push_back(std::move(channel));
  }
  // The positions compacted in place (3v + k <= Kv + k: every read is ahead of the writes), so
  // no second copy of the values at the peak.
  for (std::size_t v = 0; v < n; ++v)
    for (std::size_t k = 0; k < 3; ++k) values[3 * v + k] = values[k_stride * v + k] + header.center[k];
  values.resize(std::size_t{n} * 3);
  // A no-op at full level without channels; else the result holds no spare room (unless the
  // caller hands its arrays over again: then the room is theirs to keep).
  if (storage == nullptr) values.shrink_to_fit();
  result.mesh.positions = std::move(values);
  if (faces_made != nullptr) {
    result.mesh.triangles = std::move(*faces_made);
  } else if (result.level == L && release) {
    if (storage != nullptr) result.mesh.triangles = std::move(storage->faces);
    std::move(h).release_finest_triangles(result.mesh.triangles);
  } else {
    result.mesh.triangles = output_faces(h, options, storage);
  }
  result.bit_plane = progress.last_plane;
  result.base_vertices_decoded = progress.base_decoded;
  result.bytes_used = progress.prefix_bytes;
  result.complete = progress.all_planes && !progress.container_truncated;
  return result;
}

/// decode(), its output arrays in `storage`'s (taken from it) when a caller hands some over: then
/// they keep their capacity (no shrink_to_fit), which the next call reuses.
DecodeResult decode_with(std::span<const std::uint8_t> bytes, const DecodeOptions& options, Storage* storage) {
  const std::span<const std::uint8_t> prefix = bytes.first(std::min(bytes.size(), options.max_bytes));
  ParsedStream stream;
  if (DecodeResult r = parse(prefix, options.limits, stream); r.status != Status::ok) return r;
  Prepared p;
  if (DecodeResult r = prepare(stream, options.limits, p); r.status != Status::ok) return r;
  try {
    RangeDecoder decoder(stream.coefficients);
    zerotree::Decoded decoded;
    std::uint32_t base_decoded = 0;
    std::vector<double> values;
    if (storage != nullptr) values = std::move(storage->positions);
    // On two threads, the output's faces and the values' zeros are made while the coefficients
    // are decoded (a serial chain of decisions), instead of after the synthesis and before the
    // dequantization: the faces are then held during the synthesis (peak memory measured in
    // docs/RESULTS.md).
    const SemiRegularHierarchy& h = *p.hierarchy;
    const bool concurrent = concurrent_decode(options, h);
    std::vector<std::uint32_t> faces;
    {
      const zerotree::Forest forest(h);  // freed before the values are made (on one thread)
      bool base_part_whole = false;
      // A failure to allocate there is reported after the base part's verdict, as on one thread
      // (which allocates them after it): a corrupt base part is `corrupt` whatever the threads.
      std::exception_ptr allocation_failed;
      run_both(
          concurrent,
          [&] {
            if (!concurrent) return;
            try {
              faces = output_faces(h, options, storage);
              assign_large(values, std::size_t{h.vertex_count(p.header.levels)} * static_cast<std::size_t>(p.components()));
            } catch (...) {
              allocation_failed = std::current_exception();
            }
          },
          [&] {
            base_part_whole = decode_coefficients(p, forest, decoder, decoded, [&](std::uint32_t n) { base_decoded = n; });
          });
      if (!base_part_whole) return corrupt_base_part();
      if (allocation_failed) std::rethrow_exception(allocation_failed);
    }
    dequantize(p, decoded, values, concurrent);
    const Progress progress{decoded.last_plane, decoded.complete, base_decoded, prefix.size(),
                            stream.container.truncated()};
    decoded = {};  // freed before the stencil tables are built: lower peak memory
    return synthesize(p, true, std::move(values), progress, options, storage, concurrent ? &faces : nullptr);
  } catch (const std::bad_alloc&) {
    return failure(Status::limit_exceeded, "not enough memory to decode this stream");
  } catch (const MeshError& e) {
    return failure(Status::corrupt, e.what());
  }
}

/// decode_into's handing over of the caller's arrays around `decode` (a call of decode_with).
template <class Decode>
void decode_into_result(DecodeResult& result, Decode&& decode) {
  Storage storage{std::move(result.mesh.positions), std::move(result.mesh.triangles), std::move(result.channels)};
  result = decode(&storage);
  if (result.status == Status::ok) return;
  // Nothing decoded: the caller's arrays back, empty, with the storage they still hold (none
  // where the failure came after decode_with took it).
  result.mesh.positions = std::move(storage.positions);
  result.mesh.triangles = std::move(storage.faces);
  result.channels = std::move(storage.channels);
  result.mesh.positions.clear();
  result.mesh.triangles.clear();
  result.channels.clear();
}

}  // namespace

DecodeResult decode(std::span<const std::uint8_t> bytes, const DecodeOptions& options) {
  return decode_with(bytes, options, nullptr);
}

void decode_into(std::span<const std::uint8_t> bytes, const DecodeOptions& options, DecodeResult& result) {
  decode_into_result(result, [&](Storage* storage) { return decode_with(bytes, options, storage); });
}

// The streaming Decoder. The caller's thread parses the container on every push (cheap: chunk
// headers and checksums) and hands the coefficient bytes on; a worker thread runs the base part
// and the bit planes (the same code as decode()) on a RangeDecoder that waits in more() for
// bytes. While it waits, what it has decoded is exactly what decode() of the bytes so far would
// have (RangeDecoder's prefix contract; zerotree::decode_into keeps its Decoded current at every
// decision), so mesh() reads it there, under the mutex, and synthesizes from it.
struct Decoder::State final : ByteSource {
  explicit State(DecodeOptions o) : options(std::move(o)) {}
  ~State() {
    if (!worker.joinable()) return;
    {
      const std::lock_guard lock(mutex);
      closed = true;
    }
    changed.notify_all();
    worker.join();
  }

  DecodeOptions options;
  std::vector<std::uint8_t> received;

  // The caller's thread only.
  enum class Mode {
    before_worker,  ///< the header or base mesh is not complete yet: mesh() decodes the prefix
    worker,         ///< the worker decodes the coefficients as they arrive
    again,          ///< no worker (a malformed container, header or base; no thread): mesh() decodes the prefix
  };
  Mode mode = Mode::before_worker;
  ParsedStream stream;  ///< the prefix so far (its container parsed a push at a time)
  Prepared prepared;
  std::optional<zerotree::Forest> forest;

  // Shared with the worker, under `mutex`; `changed` is notified on every change of it.
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<std::uint8_t> arrived;  ///< the coefficient bytes (COEF payloads) so far
  bool closed = false;                ///< no more bytes will come (the Decoder is going away)
  bool waiting = false;               ///< the worker waits in more() for bytes past `taken`
  bool in_bit_planes = false;         ///< the base part is decoded, base_decoded set
  bool finished = false;              ///< the worker has returned
  std::uint32_t base_decoded = 0;
  DecodeResult worker_failure;  ///< status not ok: the worker's decode failed (a corrupt base part, no memory)
  zerotree::Decoded decoded;
  std::vector<std::uint8_t> taken;  ///< the worker's copy of `arrived`, as far as it has read

  std::thread worker;

  std::span<const std::uint8_t> prefix() const {
    return std::span(received).first(std::min(received.size(), options.max_bytes));
  }

  // The worker's byte source: waits until bytes past `have` (= taken.size()) arrive.
  std::span<const std::uint8_t> more(std::size_t have) override {
    std::unique_lock lock(mutex);
    while (!closed && arrived.size() <= have) {
      waiting = true;
      changed.notify_all();
      changed.wait(lock);
    }
    waiting = false;
    taken.insert(taken.end(), arrived.begin() + static_cast<std::ptrdiff_t>(taken.size()), arrived.end());
    return taken;
  }

  void finish(DecodeResult result) {
    {
      const std::lock_guard lock(mutex);
      worker_failure = std::move(result);
      finished = true;
    }
    changed.notify_all();
  }

  // The worker: decode_coefficients() as decode_with runs it, on bytes that arrive.
  void run() {
    try {
      RangeDecoder decoder(*this);
      const bool ok = decode_coefficients(prepared, *forest, decoder, decoded, [&](std::uint32_t n) {
        const std::lock_guard lock(mutex);
        base_decoded = n;
        in_bit_planes = true;
      });
      finish(ok ? DecodeResult{} : corrupt_base_part());
    } catch (const std::bad_alloc&) {
      finish(failure(Status::limit_exceeded, "not enough memory to decode this stream"));
    } catch (const std::exception& e) {
      finish(failure(Status::corrupt, e.what()));
    }
  }

  // Called after each push: parses the new bytes of the prefix (ContainerReader::parse_more),
  // starts the worker once the header and base mesh are in, and hands it the coefficient bytes
  // that came.
  void update() {
    if (mode == Mode::again) return;
    const std::span<const std::uint8_t> bytes = prefix();
    if (read_chunks(stream.container.parse_more(bytes, {}), bytes, options.limits, stream).status != Status::ok) {
      // Before the base mesh is in, a later push may complete it; after, the stream is broken
      // for good (a checksum, a chunk out of place): every mesh() reports it, from decode().
      if (mode == Mode::worker) stop_worker();
      return;
    }
    if (mode == Mode::before_worker) {
      if (prepare(stream, options.limits, prepared).status != Status::ok) {
        mode = Mode::again;
        return;
      }
      try {
        forest.emplace(*prepared.hierarchy);
        worker = std::thread([this] { run(); });
      } catch (const std::exception&) {  // no memory for the forest, or no thread: decode() each time
        mode = Mode::again;
        return;
      }
      mode = Mode::worker;
    }
    {
      // The COEF payloads' bytes past those handed on already (they only grow at their end as
      // bytes come: container.h).
      const std::lock_guard lock(mutex);
      std::size_t handed = arrived.size();
      for (const std::span<const std::uint8_t> payload : stream.coefficient_payloads) {
        const std::size_t from = std::min(handed, payload.size());
        arrived.insert(arrived.end(), payload.begin() + static_cast<std::ptrdiff_t>(from), payload.end());
        handed -= from;
      }
    }
    changed.notify_all();
  }

  void stop_worker() {
    mode = Mode::again;
    {
      const std::lock_guard lock(mutex);
      closed = true;
    }
    changed.notify_all();
    if (worker.joinable()) worker.join();
  }

  void mesh(DecodeResult& result, Storage* storage) {
    if (mode == Mode::worker) {
      std::unique_lock lock(mutex);
      changed.wait(lock, [&] { return finished || (waiting && taken.size() >= arrived.size()); });
      if (worker_failure.status != Status::ok) {
        result = worker_failure;
        return;
      }
      if (in_bit_planes) {
        // As decode_with's: no exception leaves a decode, a numbered status instead.
        try {
          std::vector<double> values;
          if (storage != nullptr) values = std::move(storage->positions);
          // On two threads, the output's faces beside the dequantization (the worker waits).
          const SemiRegularHierarchy& h = *prepared.hierarchy;
          const bool concurrent = concurrent_decode(options, h);
          std::vector<std::uint32_t> faces;
          run_both(
              concurrent, [&] { if (concurrent) faces = output_faces(h, options, storage); },
              [&] { dequantize(prepared, decoded, values); });
          const Progress progress{decoded.last_plane, finished && decoded.complete, base_decoded, prefix().size(),
                                  stream.container.truncated()};
          lock.unlock();
          result = synthesize(prepared, false, std::move(values), progress, options, storage, concurrent ? &faces : nullptr);
        } catch (const std::bad_alloc&) {
          result = failure(Status::limit_exceeded, "not enough memory to decode this stream");
        } catch (const MeshError& e) {
          result = failure(Status::corrupt, e.what());
        }
        return;
      }
      // Still in the base part (a few bytes per base vertex): decoded again below.
    }
    result = decode_with(prefix(), options, storage);
  }
};

Decoder::Decoder(DecodeOptions options) : state_(std::make_unique<State>(std::move(options))) {}
Decoder::~Decoder() = default;
Decoder::Decoder(Decoder&&) noexcept = default;
Decoder& Decoder::operator=(Decoder&&) noexcept = default;

void Decoder::push(std::span<const std::uint8_t> bytes) {
  state_->received.insert(state_->received.end(), bytes.begin(), bytes.end());
  state_->update();
}

std::size_t Decoder::bytes_received() const { return state_->received.size(); }

DecodeResult Decoder::mesh() const {
  DecodeResult result;
  state_->mesh(result, nullptr);
  return result;
}

void Decoder::mesh(DecodeResult& result) const {
  decode_into_result(result, [&](Storage* storage) {
    DecodeResult r;
    state_->mesh(r, storage);
    return r;
  });
}

StreamInfo inspect(std::span<const std::uint8_t> bytes) {
  StreamInfo info;
  ParsedStream stream;
  const DecodeResult r = parse(bytes, DecodeLimits{}, stream);
  for (const Chunk& c : stream.container.chunks()) {
    info.chunks.push_back({tag_to_string(c.tag), c.offset, c.payload.size(), c.complete});
    if (c.tag == kTagHeader || c.tag == kTagBaseMesh) info.header_and_connectivity_bytes += c.payload.size();
  }
  info.status = r.status;
  info.message = r.message;
  if (r.status != Status::ok && stream.header.level_weights.empty()) return info;
  const StreamHeader& h = stream.header;
  info.scheme = h.scheme;
  info.mean_preserving_update = h.mean_preserving_update;
  info.levels = h.levels;
  info.base_vertices = h.base_vertices;
  info.base_faces = h.base_faces;
  info.faces = std::uint64_t{h.base_faces} << (2 * h.levels);
  info.step = h.step;
  info.level_weights = h.level_weights;
  info.top_plane = h.top_plane;
  info.base_plane = h.base_plane;
  info.local_frames = h.local_frames;
  info.tangent_shift = h.tangent_shift;
  info.channels = h.channels;
  info.colour = h.colour;
  if (r.status == Status::ok) {
    std::vector<std::uint32_t> triangles;
    if (base_mesh::decode_faces(stream.base->payload, h.base_vertices, h.base_faces, triangles)) {
      try {
        const TriangleTopology base = TriangleTopology::build(h.base_vertices, triangles);
        info.vertices = static_cast<std::uint64_t>(refined_size(base, h.levels).vertices);
        // The base part's length: decode it (a few symbols per base vertex).
        RangeDecoder decoder(stream.coefficients);
        std::vector<std::int64_t> high;
        bool corrupt = false;
        if (h.base_plane <= h.top_plane &&
            base_values::decode(base, h.components(), h.base_plane, h.top_plane, decoder, high, corrupt) ==
                h.base_vertices &&
            !corrupt)
          info.base_part_bytes = decoder.position();
      } catch (const MeshError&) {
      }
    }
  }
  return info;
}

}  // namespace meshlift
