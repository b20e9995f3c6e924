// `meshlift rd IN [IN...] -o DIR`: the rate-distortion sweep. For each input mesh: remesh to a
// semi-regular mesh, then per wavelet scheme one encode at the highest rate whose prefixes are
// decoded at each bits-per-vertex budget (and, with --separate, one encode per budget), and, when
// Draco's tools are on PATH, Draco at each quantization. Every decoded mesh is compared with the
// ORIGINAL input by the surface metric (metric.h; CODEC-NOTES §7). Rows go to DIR/rd.csv and
// DIR/rd.json, rewritten after every row, so a failure later in the sweep keeps what came before.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "commands.h"
#include "json_text.h"
#include "remesh_options.h"
#include "files.h"
#include "meshlift/codec.h"
#include "meshlift/mesh_io.h"
#include "meshlift/metric.h"
#include "meshlift/remesh.h"

namespace meshlift::cli {
namespace {

namespace fs = std::filesystem;

struct RdOptions {
  std::vector<std::string> inputs;
  std::vector<std::string> schemes{"linear", "butterfly", "loop"};
  std::vector<double> bpv{0.25, 0.5, 1, 2, 4, 8};
  RemeshCliOptions remesh;  // --remesh, --levels, --base-vertices, --fit, as encode has them
  int bits = 16;
  FrameArgs frames;
  bool separate = false;
  std::vector<int> draco_qp{6, 8, 10, 12, 14, 16};
  std::string output_dir;
  std::size_t samples = 0;
  unsigned threads = 0;
};

/// One row of the table. Numeric fields hold NaN when absent (written as empty / null).
struct Row {
  std::string mesh;
  std::size_t input_vertices = 0;
  std::string codec, scheme, kind, param;
  double bytes = NAN, bpv = NAN, psnr_db = NAN, rms_rel = NAN, hausdorff_rel = NAN;
  double encode_s = NAN, decode_s = NAN, peak_rss_mb = NAN;
  std::string error;
  /// meshlift rows: "1" where the stream has the mean-preserving update (header flag bit 0:
  /// linear and butterfly unless --no-update), else "0"; empty for Draco's.
  std::string update;
  /// meshlift rows with local frames: the tangent shift coded (--tangent-shift, or
  /// choose_tangent_shift()'s where the remesh follows feature lines); empty otherwise.
  std::string tangent_shift;
};

constexpr const char* kColumns =
    "mesh,input_vertices,codec,scheme,kind,param,bytes,bpv,psnr_db,rms_rel,hausdorff_rel,encode_s,decode_s,"
    "peak_rss_mb,error,update,tangent_shift";

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string format_number(double x, const char* format = "%.6g") {
  if (std::isnan(x)) return "";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, x);
  return buffer;
}

/// RFC 4180: a field with a comma, quote or line break is quoted, quotes doubled.
std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

/// JSON numbers: absent (NaN) and infinite values become null.
std::string json_number(double x) { return std::isfinite(x) ? format_number(x, "%.10g") : "null"; }

std::vector<std::string> numeric_fields(const Row& r) {
  return {format_number(r.bytes, "%.0f"),   format_number(r.bpv, "%.4f"),       format_number(r.psnr_db, "%.3f"),
          format_number(r.rms_rel, "%.6e"), format_number(r.hausdorff_rel, "%.6e"), format_number(r.encode_s, "%.4f"),
          format_number(r.decode_s, "%.4f"), format_number(r.peak_rss_mb, "%.1f")};
}

/// Rewrites DIR/rd.csv and DIR/rd.json with every row so far (atomic writes).
bool write_tables(const std::string& dir, const std::vector<Row>& rows, std::string& error) {
  std::ostringstream csv, json;
  csv << kColumns << "\n";
  json << "[\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    const auto numbers = numeric_fields(r);
    csv << csv_field(r.mesh) << "," << r.input_vertices << "," << r.codec << "," << r.scheme << "," << r.kind << ","
        << r.param;
    for (const auto& n : numbers) csv << "," << n;
    csv << "," << csv_field(r.error) << "," << r.update << "," << r.tangent_shift << "\n";
    json << "  {\"mesh\": " << json_string(r.mesh) << ", \"input_vertices\": " << r.input_vertices
         << ", \"codec\": " << json_string(r.codec) << ", \"scheme\": " << json_string(r.scheme)
         << ", \"kind\": " << json_string(r.kind) << ", \"param\": " << (r.param.empty() ? std::string("null") : r.param)
         << ", \"bytes\": " << json_number(r.bytes) << ", \"bpv\": " << json_number(r.bpv)
         << ", \"psnr_db\": " << json_number(r.psnr_db) << ", \"rms_rel\": " << json_number(r.rms_rel)
         << ", \"hausdorff_rel\": " << json_number(r.hausdorff_rel) << ", \"encode_s\": " << json_number(r.encode_s)
         << ", \"decode_s\": " << json_number(r.decode_s) << ", \"peak_rss_mb\": " << json_number(r.peak_rss_mb)
         << ", \"error\": " << json_string(r.error)
         << ", \"update\": " << (r.update.empty() ? std::string("null") : r.update == "1" ? "true" : "false")
         << ", \"tangent_shift\": " << (r.tangent_shift.empty() ? std::string("null") : r.tangent_shift) << "}"
         << (i + 1 < rows.size() ? "," : "") << "\n";
  }
  json << "]\n";
  const std::string c = csv.str(), j = json.str();
  return write_bytes((fs::path(dir) / "rd.csv").string(), {c.begin(), c.end()}, error) &&
         write_bytes((fs::path(dir) / "rd.json").string(), {j.begin(), j.end()}, error);
}

/// An executable named `name` in a PATH directory, or empty.
std::string find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (!path) return {};
  std::stringstream dirs(path);
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    if (dir.empty()) continue;
    const fs::path candidate = fs::path(dir) / name;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
  }
  return {};
}

/// Single-quoted for /bin/sh.
std::string shell_quote(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

/// Runs a command through the shell with its output in `log`; returns its exit status (-1 if
/// it did not exit normally).
int run_command(const std::string& command, const std::string& log) {
  const int status = std::system((command + " > " + shell_quote(log) + " 2>&1").c_str());
  return status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string first_line_of(const std::string& path) {
  std::vector<std::uint8_t> bytes;
  std::string error;
  if (!read_bytes(path, bytes, error)) return {};
  std::string text(bytes.begin(), bytes.end());
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  const auto last_break = text.find_last_of('\n');
  return last_break == std::string::npos ? text : text.substr(last_break + 1);
}

/// Progress on stderr, only when it is a terminal; one line rewritten in place.
class Progress {
 public:
  explicit Progress(std::size_t total) : total_(total), enabled_(::isatty(STDERR_FILENO) != 0) {}
  void step(const std::string& what) {
    ++done_;
    if (enabled_) std::fprintf(stderr, "\r\033[K[%zu/%zu] %s", done_, total_, what.c_str());
  }
  /// Counts steps that were skipped (a mesh that failed early) as done.
  void skip_to(std::size_t done) { done_ = std::max(done_, done); }
  void finish() {
    if (enabled_) std::fprintf(stderr, "\r\033[K");
  }

 private:
  std::size_t total_, done_ = 0;
  bool enabled_;
};

/// The original mesh prepared for comparisons (BVH and samples built once per input).
struct Reference {
  std::string name;
  TriangleMesh mesh;
  std::optional<SampledSurface> surface;
  std::size_t samples = 0;
};

/// Fills the distortion fields of `row` from a decoded mesh against the reference.
void measure(const Reference& reference, const TriangleMesh& decoded, const RdOptions& options, Row& row) {
  const SampledSurface test(decoded, reference.samples, MetricOptions{}.seed ^ 0x5555555555555555ULL, options.threads);
  const SurfaceDistance d = surface_distance(*reference.surface, test, options.threads);
  row.psnr_db = d.psnr_db();
  row.rms_rel = d.rms_relative();
  row.hausdorff_rel = d.hausdorff_relative();
  if (!d.warning.empty()) std::cerr << "meshlift: warning: " << reference.name << " " << row.kind << " " << row.param
                                    << ": " << d.warning << "\n";
}

/// A row that failed: the message, no figures.
Row failed(Row row, const std::string& message) {
  row.bytes = row.bpv = row.psnr_db = row.rms_rel = row.hausdorff_rel = row.encode_s = row.decode_s = NAN;
  row.peak_rss_mb = NAN;
  row.error = message;
  return row;
}

/// `message` led by `prefix` unless it already starts with it.
std::string with_prefix(const std::string& prefix, const std::string& message) {
  return message.rfind(prefix, 0) == 0 ? message : prefix + message;
}

std::string param_text(double x) { return format_number(x, "%g"); }

std::size_t bytes_for_bpv(double bpv, std::size_t vertices) {
  return static_cast<std::size_t>(std::floor(bpv * static_cast<double>(vertices) / 8));
}

class Sweep {
 public:
  explicit Sweep(const RdOptions& options) : options_(options) {}

  int run() {
    std::error_code ec;
    fs::create_directories(options_.output_dir, ec);
    if (ec || !fs::is_directory(options_.output_dir)) {
      std::cerr << "meshlift: cannot create the output directory " << options_.output_dir << ": " << ec.message()
                << "\n";
      return kOutputError;
    }
    draco_encoder_ = find_on_path("draco_encoder");
    draco_decoder_ = find_on_path("draco_decoder");
    const bool draco = !draco_encoder_.empty() && !draco_decoder_.empty() && !options_.draco_qp.empty();
    if (!draco && !options_.draco_qp.empty())
      std::cerr << "meshlift: draco_encoder/draco_decoder not on PATH (Debian package draco): no Draco rows\n";
    const std::size_t per_mesh = options_.schemes.size() * options_.bpv.size() * (options_.separate ? 2 : 1) +
                                 (draco ? options_.draco_qp.size() : 0);
    Progress progress(per_mesh * options_.inputs.size());
    progress_ = &progress;

    for (std::size_t i = 0; i < options_.inputs.size(); ++i) {
      if (!sweep_mesh(options_.inputs[i], draco)) return kOutputError;
      progress.skip_to((i + 1) * per_mesh);
    }
    progress.finish();
    std::size_t failures = 0;
    for (const Row& r : rows_) failures += !r.error.empty();
    std::fprintf(stderr, "meshlift rd: %zu rows (%zu failed) in %s/rd.csv and rd.json\n", rows_.size(), failures,
                 options_.output_dir.c_str());
    std::error_code ignored;
    fs::remove_all(scratch_dir(), ignored);
    return kOk;
  }

 private:
  fs::path scratch_dir() const { return fs::path(options_.output_dir) / ".rd_scratch"; }

  /// Appends a row and rewrites the tables; false when they cannot be written.
  bool add(Row row) {
    if (!row.error.empty())
      std::cerr << (::isatty(STDERR_FILENO) ? "\r\033[K" : "") << "meshlift: " << row.mesh << " " << row.codec
                << (row.scheme.empty() ? "" : " " + row.scheme) << (row.kind.empty() ? "" : " " + row.kind)
                << (row.param.empty() ? "" : " " + row.param) << ": " << row.error << "\n";
    rows_.push_back(std::move(row));
    std::string error;
    if (!write_tables(options_.output_dir, rows_, error)) {
      std::cerr << "meshlift: " << error << "\n";
      return false;
    }
    return true;
  }

  bool sweep_mesh(const std::string& input, bool draco) {
    Reference reference;
    reference.name = fs::path(input).stem().string();
    Row base;
    base.mesh = reference.name;
    base.codec = "meshlift";

    // Load and prepare the original; a failure here is one row for the mesh.
    std::optional<PolygonMesh> loaded = load_mesh(input);  // prints its own message
    if (!loaded) return add(failed(base, "cannot read " + input + " as a mesh"));
    base.input_vertices = loaded->vertex_count();
    try {
      reference.mesh = triangles_of(input, std::move(*loaded), {options_.remesh.weld, options_.remesh.orient});
    } catch (const MeshError& e) {
      return add(failed(base, e.what()));
    }
    if (reference.mesh.face_count() == 0 || reference.mesh.vertex_count() == 0)
      return add(failed(base, "the mesh has no faces"));

    std::optional<SemiRegularMesh> semi_regular;
    bool follows_features = false;  // RemeshResult::feature_vertices: choose_tangent_shift() applies
    std::string remesh_error;
    try {
      RemeshResult remeshed = remesh(reference.mesh, to_remesh_options(options_.remesh));
      follows_features = remeshed.feature_vertices > 0;
      semi_regular = std::move(remeshed.mesh);
    } catch (const std::exception& e) {
      remesh_error = std::string("remesh: ") + e.what();
    }
    const std::size_t finest_faces =
        semi_regular ? semi_regular->hierarchy.triangles(semi_regular->hierarchy.levels()).size() / 3 : 0;
    reference.samples =
        options_.samples > 0 ? options_.samples : default_sample_count(reference.mesh.face_count(), finest_faces);
    try {
      reference.surface.emplace(reference.mesh, reference.samples, MetricOptions{}.seed, options_.threads);
    } catch (const MeshError& e) {
      return add(failed(base, std::string("reference: ") + e.what()));
    }

    if (semi_regular) {
      for (const std::string& scheme : options_.schemes)
        if (!sweep_scheme(reference, base, *semi_regular, follows_features, scheme)) return false;
    } else {
      // Every meshlift row of this mesh fails for the same reason: one row says it.
      if (!add(failed(base, remesh_error))) return false;
    }
    if (draco)
      for (int qp : options_.draco_qp)
        if (!draco_row(reference, base, qp)) return false;
    return true;
  }

  bool sweep_scheme(const Reference& reference, const Row& base, const SemiRegularMesh& mesh, bool follows_features,
                    const std::string& scheme) {
    Row row = base;
    row.scheme = scheme;
    EncodeOptions encode_options;
    encode_options.scheme = parse_scheme(scheme);
    encode_options.precision_bits = options_.bits;
    apply_frame_options(options_.frames, encode_options);
    if (options_.frames.tangent_shift < 0 && encode_options.local_frames && follows_features) {
      // As `encode` chooses (choose_tangent_shift), by this sweep's metric.
      try {
        encode_options.tangent_shift = choose_tangent_shift(mesh, encode_options, base.input_vertices, [&](const TriangleMesh& m) {
                                         Row measured;
                                         measure(reference, m, options_, measured);
                                         return measured.psnr_db;
                                       }).shift;
      } catch (const std::exception&) {
        // The encode below fails the same way and says why in its rows.
      }
    }
    row.update = encode_options.mean_preserving_update && encode_options.scheme != Scheme::loop ? "1" : "0";
    row.tangent_shift = encode_options.local_frames ? std::to_string(encode_options.tangent_shift) : "";

    // One encode at the highest rate; prefixes of it at each budget.
    std::vector<std::uint8_t> file;
    double encode_s = 0;
    std::string encode_error;
    try {
      const auto t0 = std::chrono::steady_clock::now();
      file = encode(mesh, encode_options);
      encode_s = seconds_since(t0);
    } catch (const std::exception& e) {
      encode_error = with_prefix("encode: ", e.what());
    }
    row.kind = "prefix";
    for (double bpv : options_.bpv) {
      row.param = param_text(bpv);
      progress_->step(reference.name + " " + scheme + " prefix " + row.param + " bpv");
      if (!encode_error.empty()) {
        if (!add(failed(row, encode_error))) return false;
        continue;
      }
      const std::size_t cut = std::min(file.size(), bytes_for_bpv(bpv, base.input_vertices));
      DecodeOptions decode_options;
      decode_options.max_bytes = cut;
      if (!add(decoded_row(reference, row, file, decode_options, encode_s, cut))) return false;
    }
    if (!options_.separate) return true;

    // Separate encodes, one per budget: what the embedded stream's prefixes cost against them.
    row.kind = "separate";
    for (double bpv : options_.bpv) {
      row.param = param_text(bpv);
      progress_->step(reference.name + " " + scheme + " separate " + row.param + " bpv");
      EncodeOptions budget = encode_options;
      budget.max_bytes = bytes_for_bpv(bpv, base.input_vertices);
      std::vector<std::uint8_t> separate;
      double seconds = 0;
      try {
        const auto t0 = std::chrono::steady_clock::now();
        separate = encode(mesh, budget);
        seconds = seconds_since(t0);
      } catch (const std::exception& e) {
        if (!add(failed(row, with_prefix("encode: ", e.what())))) return false;
        continue;
      }
      if (!add(decoded_row(reference, row, separate, {}, seconds, separate.size()))) return false;
    }
    return true;
  }

  /// Decodes `file` (or its prefix) and measures it.
  Row decoded_row(const Reference& reference, Row row, const std::vector<std::uint8_t>& file,
                  const DecodeOptions& decode_options, double encode_s, std::size_t bytes) {
    const auto t0 = std::chrono::steady_clock::now();
    const DecodeResult decoded = decode(file, decode_options);
    const double decode_s = seconds_since(t0);
    if (decoded.status != Status::ok || decoded.mesh.face_count() == 0) {
      std::string message = "decode of " + std::to_string(bytes) + " bytes: " + to_string(decoded.status);
      if (!decoded.message.empty()) message += ": " + decoded.message;
      if (decoded.status == Status::truncated) message += " (the budget is below the header and base mesh)";
      return failed(row, message);
    }
    row.bytes = static_cast<double>(bytes);
    row.bpv = 8.0 * static_cast<double>(bytes) / static_cast<double>(row.input_vertices);
    row.encode_s = encode_s;
    row.decode_s = decode_s;
    try {
      measure(reference, decoded.mesh, options_, row);
    } catch (const std::exception& e) {
      return failed(row, std::string("metric: ") + e.what());
    }
    row.peak_rss_mb = peak_rss_mb();
    return row;
  }

  bool draco_row(const Reference& reference, const Row& base, int qp) {
    Row row = base;
    row.codec = "draco";
    row.kind = "draco";
    row.param = std::to_string(qp);
    progress_->step(reference.name + " draco qp " + row.param);
    std::error_code ec;
    fs::create_directories(scratch_dir(), ec);
    const std::string stem = (scratch_dir() / (reference.name + "_qp" + row.param)).string();
    const std::string in_ply = (scratch_dir() / (reference.name + ".ply")).string();
    // Binary PLY, float coordinates (mesh_io.h; any faces, non-manifold ones too, as Draco takes them).
    if (!fs::exists(in_ply)) {
      try {
        write_mesh(in_ply, reference.mesh, true);
      } catch (const MeshIOError& e) {
        return add(failed(row, std::string("cannot write the input for draco_encoder: ") + e.what()));
      }
    }
    const std::string drc = stem + ".drc", out_ply = stem + "_decoded.ply", log = stem + ".log";

    auto t0 = std::chrono::steady_clock::now();
    int status = run_command(shell_quote(draco_encoder_) + " -i " + shell_quote(in_ply) + " -o " + shell_quote(drc) +
                                 " -qp " + row.param + " -cl 7",
                             log);
    const double encode_s = seconds_since(t0);
    if (status != 0)
      return add(failed(row, "draco_encoder exited with " + std::to_string(status) + ": " + first_line_of(log)));
    t0 = std::chrono::steady_clock::now();
    status = run_command(shell_quote(draco_decoder_) + " -i " + shell_quote(drc) + " -o " + shell_quote(out_ply), log);
    const double decode_s = seconds_since(t0);
    if (status != 0)
      return add(failed(row, "draco_decoder exited with " + std::to_string(status) + ": " + first_line_of(log)));
    const std::optional<PolygonMesh> decoded = load_mesh(out_ply);
    if (!decoded) return add(failed(row, "cannot read draco_decoder's output " + out_ply));
    row.bytes = static_cast<double>(fs::file_size(drc, ec));
    row.bpv = 8.0 * row.bytes / static_cast<double>(row.input_vertices);
    row.encode_s = encode_s;
    row.decode_s = decode_s;
    try {
      measure(reference, to_triangle_mesh(*decoded), options_, row);
    } catch (const std::exception& e) {
      return add(failed(row, std::string("metric: ") + e.what()));
    }
    row.peak_rss_mb = peak_rss_mb();
    return add(row);
  }

  const RdOptions& options_;
  std::vector<Row> rows_;
  std::string draco_encoder_, draco_decoder_;
  Progress* progress_ = nullptr;
};

}  // namespace

void register_rd(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<RdOptions>();
  CLI::App* cmd = app.add_subcommand(
      "rd", "Rate-distortion sweep: meshlift prefixes (and separate encodes) per scheme, and Draco, against the "
            "original meshes; writes DIR/rd.csv and DIR/rd.json");
  cmd->add_option("IN", options->inputs, "Input meshes")->required();
  cmd->add_option("--schemes", options->schemes, "Wavelet schemes, comma-separated")
      ->delimiter(',')
      ->check(CLI::IsMember({"linear", "butterfly", "loop"}))
      ->capture_default_str();
  cmd->add_option("--bpv", options->bpv, "Budgets in bits per original input vertex, comma-separated")
      ->delimiter(',')
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str();
  add_remesh_options(*cmd, options->remesh, "--remesh");
  cmd->add_option("--bits", options->bits,
                  "Finest quantization step diagonal*2^-B of the encodes (`encode --bits`; its default is 15 for a "
                  "remesh farther than 85 dB from its input, whose prefixes are those of 16 less the last plane); the "
                  "prefixes' highest rate")
      ->capture_default_str();
  add_frame_options(*cmd, options->frames);
  cmd->add_flag("--separate", options->separate, "Also encode separately at each budget (the embedded stream's cost)");
  cmd->add_option("--draco-qp", options->draco_qp,
                  "Draco quantization bits, comma-separated (rows only when draco_encoder/draco_decoder are on PATH)")
      ->delimiter(',')
      ->check(CLI::Range(1, 30))
      ->capture_default_str();
  cmd->add_option("--samples", options->samples, "Metric area samples per surface (0: the metric's default)");
  cmd->add_option("--threads", options->threads, "Metric threads (0: all cores)");
  cmd->add_option("-o,--output", options->output_dir, "Output directory for rd.csv and rd.json")->required();
  cmd->callback([options, &exit_code] { exit_code = Sweep(*options).run(); });
}

}  // namespace meshlift::cli
