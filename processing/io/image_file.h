#pragma once
// Raw images of a station directory: single-channel PNG, Mono8 (CV_8UC1) or Mono16
// (CV_16UC1), written atomically with their SHA-256.
#include <opencv2/core.hpp>
#include <string>

#include "core/pixel_format.h"
#include "core/result.h"

namespace ts {

// Encodes as PNG (Mono8, Mono16, or 8-bit BGR for products), writes atomically, returns the SHA-256
// of the file's bytes.
Result<std::string> WritePngAtomically(const cv::Mat& image, const std::string& path);
// Checks a raw image by its content, from its PNG header alone (no decoding): a PNG (not a JPEG
// or anything else named .png), single-channel of the given format, of the given size. A
// header declaring 30000 x 30000 was decoded in full (940 MB) before its size was refused.
Status CheckMonoPngHeader(const std::string& path, PixelFormat format, int width_px, int height_px);
// Reads a PNG once its header checks out (CheckMonoPngHeader), and checks the decoded image.
Result<cv::Mat> ReadMonoPng(const std::string& path, PixelFormat format, int width_px,
                            int height_px);

}  // namespace ts
