// A function on the sphere coded as an extra channel (issue 5, seed 003 Figure 5.17, after
// Schröder & Sweldens 1995, "Spherical wavelets"): the unit sphere as the octahedron refined L
// times (the octahedral geometry-image grid, geometry_image.h), a scalar or colour function
// sampled at its vertices, both coded by one embedded stream (the geometry and a channel,
// FORMAT.md §5). For each wavelet scheme, one encode, then prefixes at growing sizes: the
// function's PSNR (peak = its value range, RMS over the grid's vertices) and the geometry's
// (peak = bbox diagonal) against the bytes read. Also writes the decoded function unfolded on the
// n x n octahedral image at a few sizes (PPM/PGM), for tools/plot_sphere_function.py.
//
// Usage: bench_sphere_function [--image earth.ppm|.pgm] [--levels 7] [--bits 12] [-o DIR]
//   --image: an equirectangular image (binary PGM P5 or PPM P6, 8 or 16 bit), longitude -180..180
//            left to right, latitude 90..-90 top to bottom; without it a procedural pattern.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "meshlift/codec.h"
#include "meshlift/geometry_image.h"

using namespace meshlift;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<double> values;  // channels per pixel, row-major, in [0, 1]
};

/// Binary PGM (P5) or PPM (P6), maxval up to 65535 (16-bit samples big-endian, as Netpbm says).
Image read_netpbm(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::string magic;
  in >> magic;
  Image image;
  image.channels = magic == "P5" ? 1 : magic == "P6" ? 3 : 0;
  if (image.channels == 0) throw std::runtime_error(path + ": not a binary PGM (P5) or PPM (P6)");
  auto number = [&] {
    in >> std::ws;
    while (in.peek() == '#') {
      std::string comment;
      std::getline(in, comment);
      in >> std::ws;
    }
    long value = -1;
    in >> value;
    return value;
  };
  const long width = number(), height = number(), maxval = number();
  if (!in || width < 2 || height < 2 || width > 65536 || height > 65536 || maxval < 1 || maxval > 65535)
    throw std::runtime_error(path + ": bad PGM/PPM header");
  in.get();  // the single whitespace before the samples
  image.width = static_cast<int>(width);
  image.height = static_cast<int>(height);
  const std::size_t count = static_cast<std::size_t>(width * height * image.channels);
  const int bytes = maxval > 255 ? 2 : 1;
  // The samples must be in the file before anything is allocated for them.
  const std::streampos start = in.tellg();
  in.seekg(0, std::ios::end);
  const std::streamoff available = in.tellg() - start;
  in.seekg(start);
  if (available < static_cast<std::streamoff>(count * bytes))
    throw std::runtime_error(path + ": the header claims more samples than the file holds");
  std::vector<unsigned char> raw(count * bytes);
  if (!in.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(raw.size())))
    throw std::runtime_error(path + ": truncated samples");
  image.values.resize(count);
  for (std::size_t i = 0; i < count; ++i)
    image.values[i] = (bytes == 2 ? raw[2 * i] * 256.0 + raw[2 * i + 1] : raw[i]) / static_cast<double>(maxval);
  return image;
}

/// Bilinear lookup of an equirectangular image at unit vector p (longitude wraps around).
void sample_equirectangular(const Image& image, const std::array<double, 3>& p, double* out) {
  const double longitude = std::atan2(p[1], p[0]), latitude = std::asin(std::clamp(p[2], -1.0, 1.0));
  const double u = (longitude + kPi) / (2 * kPi) * image.width - 0.5;
  const double v = std::clamp((kPi / 2 - latitude) / kPi * image.height - 0.5, 0.0, image.height - 1.0);
  const int u0 = static_cast<int>(std::floor(u)), v0 = std::min(static_cast<int>(v), image.height - 2);
  const double fu = u - u0, fv = v - v0;
  for (int c = 0; c < image.channels; ++c) {
    auto at = [&](int row, int column) {
      column = ((column % image.width) + image.width) % image.width;
      return image.values[(static_cast<std::size_t>(row) * image.width + column) * image.channels + c];
    };
    out[c] = (1 - fv) * ((1 - fu) * at(v0, u0) + fu * at(v0, u0 + 1)) + fv * ((1 - fu) * at(v0 + 1, u0) + fu * at(v0 + 1, u0 + 1));
  }
}

/// Procedural test pattern: smooth bands (low-order harmonics) plus sharp-edged "continents"
/// (a thresholded sum of waves), so that both smooth and discontinuous content are present.
double procedural(const std::array<double, 3>& p) {
  const double x = p[0], y = p[1], z = p[2];
  const double smooth = 0.3 * z + 0.2 * (3 * z * z - 1) / 2 + 0.15 * x * y;
  const double waves = std::sin(5 * x + 1) + std::sin(4 * y - 2) + std::sin(6 * z + 0.5) + 0.5 * std::sin(11 * x * y);
  return 0.5 + smooth + (waves > 0.6 ? 0.25 : 0.0);
}

double psnr(const std::vector<double>& a, const std::vector<double>& b, std::size_t count, double peak) {
  double sum = 0;
  for (std::size_t i = 0; i < count; ++i) sum += (a[i] - b[i]) * (a[i] - b[i]);
  const double rms = std::sqrt(sum / static_cast<double>(count));
  return rms > 0 ? 20 * std::log10(peak / rms) : 999.0;
}

/// The decoded channel unfolded on the octahedral image, as 8-bit PGM/PPM (values clamped to [0, 1]).
void write_unfolded(const std::string& path, const std::vector<std::uint32_t>& pixel_vertex, int size,
                    const VertexChannel& channel) {
  std::ofstream out(path, std::ios::binary);
  out << (channel.components == 1 ? "P5" : "P6") << "\n" << size << " " << size << "\n255\n";
  for (std::uint32_t v : pixel_vertex)
    for (int c = 0; c < channel.components; ++c) {
      const double x = std::clamp(channel.values[static_cast<std::size_t>(v) * channel.components + c], 0.0, 1.0);
      out.put(static_cast<char>(std::lround(255 * x)));
    }
}

}  // namespace

int main(int argc, char** argv) {
  std::string image_path, directory;
  int levels = 7, bits = 12;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--image" && i + 1 < argc) image_path = argv[++i];
    else if (arg == "--levels" && i + 1 < argc) levels = std::atoi(argv[++i]);
    else if (arg == "--bits" && i + 1 < argc) bits = std::atoi(argv[++i]);
    else if (arg == "-o" && i + 1 < argc) directory = argv[++i];
    else {
      std::fprintf(stderr, "usage: bench_sphere_function [--image EQUIRECT.ppm|.pgm] [--levels 7] [--bits 12] [-o DIR]\n");
      return 2;
    }
  }
  if (levels < 1 || levels > 9 || bits < 1 || bits > 24) {
    std::fprintf(stderr, "bench_sphere_function: --levels 1..9, --bits 1..24\n");
    return 2;
  }
  try {
    // The sphere: every grid point of the octahedron projected centrally (geometry_image.h).
    const int size = geometry_image_size(levels);
    GeometryImage grid{size, std::vector<double>(3 * static_cast<std::size_t>(size) * size)};
    for (int r = 0; r < size; ++r)
      for (int c = 0; c < size; ++c) {
        const auto s = octahedron_to_sphere(octahedron_point(r, c, size));
        std::copy(s.begin(), s.end(), grid.samples.begin() + 3 * (static_cast<std::ptrdiff_t>(r) * size + c));
      }
    SemiRegularMesh sphere = image_to_mesh(grid);
    const std::size_t V = sphere.positions.size() / 3;

    Image image;
    if (!image_path.empty()) image = read_netpbm(image_path);
    VertexChannel function{image_path.empty() ? 1 : image.channels, {}};
    function.values.resize(V * static_cast<std::size_t>(function.components));
    for (std::size_t v = 0; v < V; ++v) {
      const std::array<double, 3> p{sphere.positions[3 * v], sphere.positions[3 * v + 1], sphere.positions[3 * v + 2]};
      if (image_path.empty()) function.values[v] = procedural(p);
      else sample_equirectangular(image, p, &function.values[v * function.components]);
    }
    double low = function.values[0], high = low;
    for (double x : function.values) low = std::min(low, x), high = std::max(high, x);
    const double peak = high > low ? high - low : 1.0;
    sphere.channels = {function};
    sphere = canonical_order(sphere);
    // Each pixel's vertex in the order the stream decodes to: pixel_vertices() numbers them as
    // image_to_mesh() does, canonical_order() renumbers; an index channel carries the mapping.
    std::vector<std::uint32_t> pixel_vertex = pixel_vertices(size);
    {
      SemiRegularMesh indexed = image_to_mesh(grid);
      VertexChannel index{1, std::vector<double>(V)};
      for (std::size_t v = 0; v < V; ++v) index.values[v] = static_cast<double>(v);
      indexed.channels = {index};
      const SemiRegularMesh ordered = canonical_order(indexed);
      std::vector<std::uint32_t> to_canonical(V);
      for (std::uint32_t v = 0; v < V; ++v) to_canonical[static_cast<std::size_t>(ordered.channels[0].values[v])] = v;
      for (std::uint32_t& v : pixel_vertex) v = to_canonical[v];
    }

    std::printf("sphere: octahedron refined %d times (%d x %d image), %zu vertices; function: %s, %d component(s), range %.4g\n",
                levels, size, size, V, image_path.empty() ? "procedural" : image_path.c_str(), function.components, peak);
    std::FILE* csv = nullptr;
    if (!directory.empty()) {
      csv = std::fopen((directory + "/sphere_function.csv").c_str(), "w");
      if (csv == nullptr) throw std::runtime_error(directory + "/sphere_function.csv: cannot write");
      std::fprintf(csv, "scheme,bytes,bits_per_sample,function_psnr_db,geometry_psnr_db\n");
    }
    std::printf("%-9s %9s %8s %12s %12s\n", "scheme", "bytes", "bits/smp", "function dB", "geometry dB");
    const double diagonal = bounding_box_diagonal(sphere.positions);
    for (Scheme scheme : {Scheme::linear, Scheme::butterfly, Scheme::loop}) {
      EncodeOptions options;
      options.scheme = scheme;
      options.precision_bits = bits;
      options.channel_precision_bits = bits;
      const std::vector<std::uint8_t> file = encode(sphere, options);
      SemiRegularMesh geometry_only{sphere.hierarchy, sphere.positions, {}};
      const std::size_t geometry_bytes = encode(geometry_only, options).size();
      std::printf("%-9s whole stream %zu bytes; the sphere's geometry alone, same precision: %zu bytes (%.1f %%)\n",
                  to_string(scheme), file.size(), geometry_bytes, 100.0 * static_cast<double>(geometry_bytes) / static_cast<double>(file.size()));
      const StreamInfo info = inspect(file);
      const std::size_t first = info.chunks.size() > 2 ? info.chunks[2].offset + 16 : file.size();
      std::vector<std::size_t> cuts;
      for (double bps : {0.05, 0.1, 0.2, 0.4, 0.8, 1.6, 3.2, 6.4})
        cuts.push_back(std::max(first, static_cast<std::size_t>(bps * static_cast<double>(V) / 8)));
      cuts.push_back(file.size());
      for (std::size_t cut : cuts) {
        if (cut > file.size()) continue;
        DecodeOptions o;
        o.max_bytes = cut;
        const DecodeResult r = decode(file, o);
        if (r.status != Status::ok || r.channels.size() != 1) throw std::runtime_error("decode failed: " + r.message);
        const double f_psnr = psnr(r.channels[0].values, sphere.channels[0].values, sphere.channels[0].values.size(), peak);
        const double g_psnr = psnr(r.mesh.positions, sphere.positions, sphere.positions.size(), diagonal);
        const double bps = 8.0 * static_cast<double>(cut) / static_cast<double>(V);
        std::printf("%-9s %9zu %8.3f %12.2f %12.2f\n", to_string(scheme), cut, bps, f_psnr, g_psnr);
        if (csv != nullptr) {
          std::fprintf(csv, "%s,%zu,%.4f,%.3f,%.3f\n", to_string(scheme), cut, bps, f_psnr, g_psnr);
          if (scheme == Scheme::butterfly)
            write_unfolded(directory + "/function_" + std::to_string(cut) + (function.components == 1 ? ".pgm" : ".ppm"),
                           pixel_vertex, size, r.channels[0]);
        }
      }
    }
    if (csv != nullptr) {
      std::fclose(csv);
      write_unfolded(directory + "/function_original" + (function.components == 1 ? ".pgm" : ".ppm"), pixel_vertex, size,
                     sphere.channels[0]);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_sphere_function: %s\n", e.what());
    return 1;
  }
  return 0;
}
