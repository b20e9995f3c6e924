// Geometry image files: 16-bit PNG through libspng, and the float .gim format (both specified in
// geometry_image_file.h). Writers and readers side by side.
#include "meshlift/geometry_image_file.h"

#include <spng.h>

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>

#include "meshlift/mesh_io.h"

namespace meshlift {

namespace {

constexpr char kBoxKeyword[] = "meshlift-bbox";
constexpr char kLayoutKeyword[] = "meshlift-layout";
constexpr char kGimMagic[4] = {'M', 'G', 'I', 'M'};
constexpr std::uint32_t kGimVersion = 1;
constexpr std::size_t kGimHeaderBytes = 20;

struct SpngDeleter {
  void operator()(spng_ctx* ctx) const { spng_ctx_free(ctx); }
};
using SpngContext = std::unique_ptr<spng_ctx, SpngDeleter>;

void check_image(const GeometryImage& image) {
  geometry_image_levels(image.size);
  const std::size_t expected = 3 * static_cast<std::size_t>(image.size) * static_cast<std::size_t>(image.size);
  if (image.samples.size() != expected) throw MeshError("geometry image holds the wrong number of samples");
  for (const double x : image.samples)
    if (!std::isfinite(x)) throw MeshError("geometry image has a non-finite sample");
}

/// A side read from a file: valid, or a MeshIOError.
void check_side(std::uint64_t side, const char* format) {
  bool valid = false;
  for (int levels = 0; levels <= 11; ++levels) valid = valid || side == static_cast<std::uint64_t>(geometry_image_size(levels));
  if (!valid)
    throw MeshIOError(std::string(format) + ": image side " + std::to_string(side) + " is not 2^(L+1) + 1 <= " +
                      std::to_string(kMaxGeometryImageSize));
}

std::string spng_message(const char* what, int error) { return std::string("PNG: ") + what + ": " + spng_strerror(error); }

void put_u32(std::vector<std::uint8_t>& out, std::uint32_t x) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(x >> (8 * i)));
}
std::uint32_t get_u32(std::span<const std::uint8_t> in, std::size_t offset) {
  std::uint32_t x = 0;
  for (int i = 0; i < 4; ++i) x |= static_cast<std::uint32_t>(in[offset + static_cast<std::size_t>(i)]) << (8 * i);
  return x;
}
std::uint64_t get_u64(std::span<const std::uint8_t> in, std::size_t offset) {
  std::uint64_t x = 0;
  for (int i = 0; i < 8; ++i) x |= static_cast<std::uint64_t>(in[offset + static_cast<std::size_t>(i)]) << (8 * i);
  return x;
}

std::string lowercase_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace

std::vector<std::uint8_t> encode_geometry_image_png(const GeometryImage& image) {
  check_image(image);
  const auto pixels = static_cast<std::size_t>(image.size) * static_cast<std::size_t>(image.size);
  std::array<double, 3> lo{}, hi{};
  for (std::size_t k = 0; k < 3; ++k) {
    lo[k] = hi[k] = image.samples[k];
    for (std::size_t p = 0; p < pixels; ++p) {
      lo[k] = std::min(lo[k], image.samples[3 * p + k]);
      hi[k] = std::max(hi[k], image.samples[3 * p + k]);
    }
  }
  // Q = round((x − lo) / (hi − lo) · 65535), host-endian as SPNG_FMT_PNG expects.
  std::vector<std::uint16_t> quantized(3 * pixels);
  for (std::size_t p = 0; p < pixels; ++p)
    for (std::size_t k = 0; k < 3; ++k) {
      const double extent = hi[k] - lo[k];
      const double q = extent > 0 ? std::round((image.samples[3 * p + k] - lo[k]) / extent * 65535.0) : 0.0;
      quantized[3 * p + k] = static_cast<std::uint16_t>(std::clamp(q, 0.0, 65535.0));
    }
  char box[256];
  std::snprintf(box, sizeof box, "%.17g %.17g %.17g %.17g %.17g %.17g", lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
  char layout[] = "octahedral";

  SpngContext ctx(spng_ctx_new(SPNG_CTX_ENCODER));
  if (!ctx) throw MeshError("PNG: cannot create an encoder");
  spng_set_option(ctx.get(), SPNG_ENCODE_TO_BUFFER, 1);
  spng_ihdr ihdr{};
  ihdr.width = ihdr.height = static_cast<std::uint32_t>(image.size);
  ihdr.bit_depth = 16;
  ihdr.color_type = SPNG_COLOR_TYPE_TRUECOLOR;
  if (const int e = spng_set_ihdr(ctx.get(), &ihdr)) throw MeshError(spng_message("header", e));
  spng_text text[2]{};
  std::strcpy(text[0].keyword, kBoxKeyword);
  text[0].type = SPNG_TEXT;
  text[0].text = box;
  text[0].length = std::strlen(box);
  std::strcpy(text[1].keyword, kLayoutKeyword);
  text[1].type = SPNG_TEXT;
  text[1].text = layout;
  text[1].length = std::strlen(layout);
  if (const int e = spng_set_text(ctx.get(), text, 2)) throw MeshError(spng_message("text chunk", e));
  if (const int e = spng_encode_image(ctx.get(), quantized.data(), quantized.size() * sizeof(std::uint16_t), SPNG_FMT_PNG,
                                      SPNG_ENCODE_FINALIZE))
    throw MeshError(spng_message("encode", e));
  std::size_t length = 0;
  int error = 0;
  void* buffer = spng_get_png_buffer(ctx.get(), &length, &error);
  if (buffer == nullptr) throw MeshError(spng_message("encode", error));
  const auto* bytes = static_cast<const std::uint8_t*>(buffer);
  std::vector<std::uint8_t> out(bytes, bytes + length);
  std::free(buffer);
  return out;
}

GeometryImage decode_geometry_image_png(std::span<const std::uint8_t> bytes) {
  SpngContext ctx(spng_ctx_new(0));
  if (!ctx) throw MeshIOError("PNG: cannot create a decoder");
  spng_set_image_limits(ctx.get(), kMaxGeometryImageSize, kMaxGeometryImageSize);
  spng_set_chunk_limits(ctx.get(), std::size_t{1} << 26, std::size_t{1} << 26);
  spng_set_crc_action(ctx.get(), SPNG_CRC_ERROR, SPNG_CRC_ERROR);
  if (const int e = spng_set_png_buffer(ctx.get(), bytes.data(), bytes.size())) throw MeshIOError(spng_message("buffer", e));
  spng_ihdr ihdr{};
  if (const int e = spng_get_ihdr(ctx.get(), &ihdr)) throw MeshIOError(spng_message("header", e));
  if (ihdr.width != ihdr.height) throw MeshIOError("PNG: geometry images are square, this one is " + std::to_string(ihdr.width) + " x " + std::to_string(ihdr.height));
  check_side(ihdr.width, "PNG");
  if (ihdr.bit_depth != 16 || ihdr.color_type != SPNG_COLOR_TYPE_TRUECOLOR)
    throw MeshIOError("PNG: a geometry image is 16-bit RGB; this one has bit depth " + std::to_string(ihdr.bit_depth) +
                      " and colour type " + std::to_string(ihdr.color_type));

  std::uint32_t count = 0;
  std::array<double, 6> box{};
  bool have_box = false;
  if (spng_get_text(ctx.get(), nullptr, &count) == 0 && count > 0) {
    std::vector<spng_text> texts(count);
    if (const int e = spng_get_text(ctx.get(), texts.data(), &count)) throw MeshIOError(spng_message("text chunks", e));
    for (const spng_text& t : texts) {
      if (std::strcmp(t.keyword, kBoxKeyword) != 0) continue;
      const char* p = t.text;
      const char* end = t.text + t.length;
      for (std::size_t i = 0; i < 6; ++i) {
        if (i > 0) {
          if (p == end || *p != ' ') throw MeshIOError("PNG: malformed meshlift-bbox text");
          ++p;
        }
        const auto [next, ec] = std::from_chars(p, end, box[i]);
        if (ec != std::errc() || !std::isfinite(box[i])) throw MeshIOError("PNG: malformed meshlift-bbox text");
        p = next;
      }
      if (p != end) throw MeshIOError("PNG: malformed meshlift-bbox text (trailing characters)");
      have_box = true;
    }
  }
  if (!have_box) throw MeshIOError("PNG: no meshlift-bbox text chunk: not a meshlift geometry image");

  std::size_t length = 0;
  if (const int e = spng_decoded_image_size(ctx.get(), SPNG_FMT_PNG, &length)) throw MeshIOError(spng_message("size", e));
  const auto pixels = static_cast<std::size_t>(ihdr.width) * ihdr.height;
  if (length != 3 * pixels * sizeof(std::uint16_t)) throw MeshIOError("PNG: unexpected decoded size");
  std::vector<std::uint16_t> quantized(3 * pixels);
  if (const int e = spng_decode_image(ctx.get(), quantized.data(), length, SPNG_FMT_PNG, 0))
    throw MeshIOError(spng_message("decode", e));
  // The chunks after the image data, through IEND: a file cut short there is still an error.
  if (const int e = spng_decode_chunks(ctx.get())) throw MeshIOError(spng_message("after the image data", e));
  GeometryImage image;
  image.size = static_cast<int>(ihdr.width);
  image.samples.resize(3 * pixels);
  for (std::size_t p = 0; p < pixels; ++p)
    for (std::size_t k = 0; k < 3; ++k)
      image.samples[3 * p + k] = box[k] + quantized[3 * p + k] / 65535.0 * (box[3 + k] - box[k]);
  return image;
}

std::vector<std::uint8_t> encode_geometry_image_gim(const GeometryImage& image, int bytes_per_sample) {
  check_image(image);
  if (bytes_per_sample != 4 && bytes_per_sample != 8) throw MeshError(".gim samples are 4 or 8 bytes");
  std::vector<std::uint8_t> out(kGimMagic, kGimMagic + 4);
  put_u32(out, kGimVersion);
  put_u32(out, static_cast<std::uint32_t>(image.size));
  put_u32(out, 3);
  put_u32(out, static_cast<std::uint32_t>(bytes_per_sample));
  out.reserve(out.size() + image.samples.size() * static_cast<std::size_t>(bytes_per_sample));
  for (const double x : image.samples) {
    if (bytes_per_sample == 8) {
      const auto bits = std::bit_cast<std::uint64_t>(x);
      for (int i = 0; i < 8; ++i) out.push_back(static_cast<std::uint8_t>(bits >> (8 * i)));
    } else {
      put_u32(out, std::bit_cast<std::uint32_t>(static_cast<float>(x)));
    }
  }
  return out;
}

GeometryImage decode_geometry_image_gim(std::span<const std::uint8_t> bytes) {
  if (bytes.size() >= 4 && std::memcmp(bytes.data(), kGimMagic, 4) != 0)
    throw MeshIOError(".gim: bad magic (not a geometry image)");
  if (bytes.size() < kGimHeaderBytes) throw MeshIOError(".gim: truncated header");
  if (const std::uint32_t version = get_u32(bytes, 4); version != kGimVersion)
    throw MeshIOError(".gim: unsupported version " + std::to_string(version));
  const std::uint32_t side = get_u32(bytes, 8), channels = get_u32(bytes, 12), width = get_u32(bytes, 16);
  check_side(side, ".gim");
  if (channels != 3) throw MeshIOError(".gim: " + std::to_string(channels) + " channels, expected 3");
  if (width != 4 && width != 8) throw MeshIOError(".gim: samples of " + std::to_string(width) + " bytes, expected 4 or 8");
  const std::size_t count = 3 * static_cast<std::size_t>(side) * side;
  const std::size_t expected = kGimHeaderBytes + count * width;
  if (bytes.size() < expected) throw MeshIOError(".gim: truncated samples");
  if (bytes.size() > expected) throw MeshIOError(".gim: trailing bytes after the samples");
  GeometryImage image;
  image.size = static_cast<int>(side);
  image.samples.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t offset = kGimHeaderBytes + i * width;
    const double x = width == 8 ? std::bit_cast<double>(get_u64(bytes, offset))
                                : static_cast<double>(std::bit_cast<float>(get_u32(bytes, offset)));
    if (!std::isfinite(x)) throw MeshIOError(".gim: non-finite sample");
    image.samples[i] = x;
  }
  return image;
}

GeometryImage read_geometry_image(const std::string& path) {
  const std::string ext = lowercase_extension(path);
  if (ext != ".png" && ext != ".gim") throw MeshIOError(path + ": unknown geometry image extension (use .png or .gim)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MeshIOError(path + ": cannot open");
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw MeshIOError(path + ": read error");
  try {
    return ext == ".png" ? decode_geometry_image_png(bytes) : decode_geometry_image_gim(bytes);
  } catch (const MeshIOError& e) {
    throw MeshIOError(path + ": " + e.what());
  }
}

void write_geometry_image(const std::string& path, const GeometryImage& image) {
  const std::string ext = lowercase_extension(path);
  if (ext != ".png" && ext != ".gim") throw MeshIOError(path + ": unknown geometry image extension (use .png or .gim)");
  std::vector<std::uint8_t> bytes;
  try {
    bytes = ext == ".png" ? encode_geometry_image_png(image) : encode_geometry_image_gim(image);
  } catch (const MeshError& e) {
    throw MeshIOError(path + ": " + e.what());
  }
  std::random_device seed;
  char suffix[32];
  std::snprintf(suffix, sizeof suffix, ".tmp-%08x", static_cast<unsigned>(seed()));
  const std::string temporary = path + suffix;
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!out) {
      std::error_code ignored;
      std::filesystem::remove(temporary, ignored);
      throw MeshIOError(path + ": cannot write");
    }
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw MeshIOError(path + ": cannot rename into place: " + ec.message());
  }
}

}  // namespace meshlift
