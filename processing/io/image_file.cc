#include "processing/io/image_file.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "processing/io/atomic_file.h"
#include "processing/io/sha256.h"

namespace ts {

Result<std::string> WritePngAtomically(const cv::Mat& image, const std::string& path) {
  if (image.empty() ||
      (image.type() != CV_8UC1 && image.type() != CV_16UC1 && image.type() != CV_8UC3))
    return Error{path + ": image must be a non-empty Mono8, Mono16 or 8-bit BGR matrix"};
  std::vector<uchar> png;
  // Fast compression: raw images are written during capture, on the critical path.
  if (!cv::imencode(".png", image, png, {cv::IMWRITE_PNG_COMPRESSION, 1}))
    return Error{path + ": PNG encoding failed"};
  const std::string_view bytes(reinterpret_cast<const char*>(png.data()), png.size());
  if (Status s = WriteFileAtomically(path, bytes); !s) return Error{s.error()};
  return Sha256Hex(bytes);
}

Status CheckMonoPngHeader(const std::string& path, PixelFormat format, int width_px,
                          int height_px) {
  // Signature, then the IHDR chunk: length, "IHDR", width, height (big-endian), bit depth,
  // colour type (0: greyscale).
  std::ifstream in(path, std::ios::binary);
  unsigned char b[26] = {};
  in.read(reinterpret_cast<char*>(b), sizeof b);
  static const unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (!in || std::memcmp(b, kSignature, 8) != 0 || std::memcmp(b + 12, "IHDR", 4) != 0) {
    const bool jpeg = b[0] == 0xff && b[1] == 0xd8;
    return Error{path + ": not a PNG image by its content" + (jpeg ? " (a JPEG)" : "")};
  }
  auto big_endian = [](const unsigned char* p) {
    return (uint64_t{p[0]} << 24) | (uint64_t{p[1]} << 16) | (uint64_t{p[2]} << 8) | p[3];
  };
  const uint64_t width = big_endian(b + 16), height = big_endian(b + 20);
  if (width != static_cast<uint64_t>(width_px) || height != static_cast<uint64_t>(height_px))
    return Error{path + ": image is " + std::to_string(width) + "x" + std::to_string(height) +
                 ", manifest says " + std::to_string(width_px) + "x" + std::to_string(height_px)};
  const int depth = format == PixelFormat::kMono8 ? 8 : 16;
  if (b[24] != depth || b[25] != 0)
    return Error{path + ": expected " + PixelFormatName(format) + " single-channel image"};
  return {};
}

Result<cv::Mat> ReadMonoPng(const std::string& path, PixelFormat format, int width_px,
                            int height_px) {
  if (!std::filesystem::is_regular_file(path)) return Error{path + ": missing image"};
  if (Status header = CheckMonoPngHeader(path, format, width_px, height_px); !header)
    return Error{header.error()};
  cv::Mat image;
  try {
    image = cv::imread(path, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception&) {
    image.release();
  }
  if (image.empty()) return Error{path + ": not a readable PNG image"};
  const int expected_type = format == PixelFormat::kMono8 ? CV_8UC1 : CV_16UC1;
  if (image.type() != expected_type)
    return Error{path + ": expected " + PixelFormatName(format) + " single-channel image"};
  if (image.cols != width_px || image.rows != height_px)
    return Error{path + ": image is " + std::to_string(image.cols) + "x" +
                 std::to_string(image.rows) + ", manifest says " + std::to_string(width_px) + "x" +
                 std::to_string(height_px)};
  return image;
}

}  // namespace ts
