#include "processing/io/image_file.h"

#include <filesystem>
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

Result<cv::Mat> ReadMonoPng(const std::string& path, PixelFormat format, int width_px,
                            int height_px) {
  if (!std::filesystem::is_regular_file(path)) return Error{path + ": missing image"};
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
