#include "station/calibration_report.h"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "processing/io/atomic_file.h"
#include "station/plot_drawing.h"

namespace ts {
namespace {

const cv::Scalar kWhite(255, 255, 255), kBlue(200, 80, 0), kRed(0, 0, 210), kInk(30, 30, 30);
constexpr double kFrameScale = 0.5;  // frame pictures at half the image's size
constexpr int kMargin = 60;

cv::Mat FrameCanvas(const CameraIntrinsics& c) {
  cv::Mat image(static_cast<int>(c.height_px * kFrameScale) + 2 * kMargin,
                static_cast<int>(c.width_px * kFrameScale) + 2 * kMargin, CV_8UC3, kWhite);
  cv::rectangle(image, cv::Point(kMargin, kMargin),
                cv::Point(image.cols - kMargin, image.rows - kMargin), kInk);
  return image;
}

cv::Point OnFrame(const Eigen::Vector2d& pixel) {
  return {kMargin + static_cast<int>(std::lround(pixel.x() * kFrameScale)),
          kMargin + static_cast<int>(std::lround(pixel.y() * kFrameScale))};
}

// Arrows magnified so that three RMS are 20 pixels of the picture.
cv::Mat ResidualVectors(const std::string& name, const CameraCalibration& c) {
  cv::Mat image = FrameCanvas(c.intrinsics);
  const double magnify = 20.0 / std::max(3.0 * c.rms_px, 1e-6);
  for (const ObservedResidual& r : c.residuals) {
    const cv::Point from = OnFrame(r.pixel);
    const Eigen::Vector2d d = magnify * r.residual;
    const cv::Point to = from + cv::Point(static_cast<int>(std::lround(d.x())),
                                          static_cast<int>(std::lround(d.y())));
    cv::line(image, from, to, r.rejected ? kRed : kBlue, 1, cv::LINE_AA);
    cv::circle(image, from, 1, kInk, cv::FILLED);
  }
  DrawText(image, name + ": residuals x" + fmt::format("{:.0f}", magnify) + ", red: rejected",
           cv::Point(kMargin, kMargin - 20));
  return image;
}

// The x and y components together, bins of sigma0 / 4 over +-5 sigma0, the normal curve.
cv::Mat Histogram(const std::string& name, const CameraCalibration& c) {
  constexpr int kBins = 40;
  const double sigma = std::max(c.sigma0_px, 1e-6), width = 10.0 * sigma / kBins;
  std::vector<int> counts(kBins, 0);
  int n = 0;
  for (const ObservedResidual& r : c.residuals) {
    if (r.rejected) continue;
    for (double v : {r.residual.x(), r.residual.y()}) {
      const int bin = static_cast<int>(std::floor((v + 5.0 * sigma) / width));
      if (bin >= 0 && bin < kBins) ++counts[bin];
      ++n;
    }
  }
  const double peak = n * width / (sigma * std::sqrt(2.0 * M_PI));
  const double y_max =
      1.1 * std::max<double>(peak, *std::max_element(counts.begin(), counts.end()));
  cv::Mat image(520, 800, CV_8UC3, kWhite);
  const PlotAxes axes{cv::Rect(80, 60, 690, 400), 10.0, y_max};
  DrawAxes(image, axes, "5 + residual / sigma0", "count");
  for (int b = 0; b < kBins; ++b)
    cv::rectangle(image, axes.At(b * 10.0 / kBins, counts[b]), axes.At((b + 1) * 10.0 / kBins, 0),
                  kBlue, cv::FILLED);
  std::vector<cv::Point> curve;
  for (int k = 0; k <= 200; ++k) {
    const double x = k / 20.0, z = x - 5.0;
    curve.push_back(axes.At(x, peak * std::exp(-0.5 * z * z)));
  }
  cv::polylines(image, curve, false, kRed, 2, cv::LINE_AA);
  DrawText(image,
           name + ": x and y residuals against the normal curve, sigma0 " +
               fmt::format("{:.3f}", c.sigma0_px) + " px",
           cv::Point(80, 30));
  return image;
}

cv::Mat ViewRms(const std::string& name, const CameraCalibration& c) {
  const int n = static_cast<int>(c.view_rms_px.size());
  const double y_max =
      1.1 * std::max(1e-6, *std::max_element(c.view_rms_px.begin(), c.view_rms_px.end()));
  cv::Mat image(520, std::max(500, 120 + 14 * n), CV_8UC3, kWhite);
  const PlotAxes axes{cv::Rect(80, 60, image.cols - 110, 400), static_cast<double>(n), y_max};
  DrawAxes(image, axes, "view", "RMS (px)");
  for (int v = 0; v < n; ++v)
    cv::rectangle(image, axes.At(v + 0.15, c.view_rms_px[v]), axes.At(v + 0.85, 0), kBlue,
                  cv::FILLED);
  DrawText(image, name + ": RMS per view", cv::Point(80, 30));
  return image;
}

cv::Mat Coverage(const std::string& name, const CameraCalibration& c) {
  cv::Mat image = FrameCanvas(c.intrinsics);
  const FrameCoverage& f = c.coverage;
  const int most = std::max(1, *std::max_element(f.counts.begin(), f.counts.end()));
  const double cw = c.intrinsics.width_px / double(FrameCoverage::kColumns);
  const double ch = c.intrinsics.height_px / double(FrameCoverage::kRows);
  for (int j = 0; j < FrameCoverage::kRows; ++j)
    for (int i = 0; i < FrameCoverage::kColumns; ++i) {
      const int count = f.counts[j * FrameCoverage::kColumns + i];
      const cv::Point a = OnFrame({i * cw, j * ch}), b = OnFrame({(i + 1) * cw, (j + 1) * ch});
      const double t = count == 0 ? 0.0 : 0.25 + 0.75 * count / most;
      const cv::Scalar fill = count == 0 ? cv::Scalar(190, 190, 255)
                                         : cv::Scalar(255 - 155 * t, 255 - 75 * t, 255 - 255 * t);
      cv::rectangle(image, a, b, fill, cv::FILLED);
      cv::rectangle(image, a, b, kInk);
      DrawText(image, std::to_string(count), a + cv::Point(8, 22), 0.45);
    }
  DrawText(image,
           name + ": observations per cell (red: none); edges " +
               fmt::format("{:.0f}", 100.0 * f.border_share) + " % covered",
           cv::Point(kMargin, kMargin - 20));
  return image;
}

// Each distance's sigma map side by side, cells coloured from white (0) to red (twice the good
// uncertainty or the largest sigma), values written; grey where not validated.
cv::Mat Uncertainty(const CalibrationValidation& v, const CameraIntrinsics& camera) {
  const int panel = static_cast<int>(camera.width_px * kFrameScale) + kMargin;
  cv::Mat image(static_cast<int>(camera.height_px * kFrameScale) + 2 * kMargin,
                kMargin + panel * static_cast<int>(v.maps.size()), CV_8UC3, kWhite);
  double top = 0.0;
  for (const MapValidation& m : v.maps) top = std::max(top, m.max_sigma_px);
  const double cw = camera.width_px * kFrameScale / v.columns;
  const double ch = camera.height_px * kFrameScale / v.rows;
  for (size_t k = 0; k < v.maps.size(); ++k) {
    const MapValidation& m = v.maps[k];
    const cv::Point origin(kMargin + static_cast<int>(k) * panel, kMargin);
    for (int j = 0; j < v.rows; ++j)
      for (int i = 0; i < v.columns; ++i) {
        const double s = m.sigma_px[j * v.columns + i];
        const cv::Point a = origin + cv::Point(static_cast<int>(i * cw), static_cast<int>(j * ch));
        const cv::Point b =
            origin + cv::Point(static_cast<int>((i + 1) * cw), static_cast<int>((j + 1) * ch));
        const double t = std::isfinite(s) ? std::min(1.0, s / std::max(top, 1e-9)) : 0.0;
        const cv::Scalar fill = std::isfinite(s) ? cv::Scalar(255 * (1 - t), 255 * (1 - t), 255)
                                                 : cv::Scalar(200, 200, 200);
        cv::rectangle(image, a, b, fill, cv::FILLED);
        if (std::isfinite(s)) DrawText(image, fmt::format("{:.2f}", s), a + cv::Point(4, 26), 0.35);
      }
    DrawText(
        image,
        (m.distance_m > 0 ? "at " + fmt::format("{:.0f}", m.distance_m) + " m: " : std::string()) +
            "sigma (px), at most " + fmt::format("{:.3f}", m.max_sigma_px),
        origin + cv::Point(0, -20));
  }
  DrawText(image, v.verdict, cv::Point(kMargin, image.rows - 20), 0.6);
  return image;
}

}  // namespace

std::string CalibrationReportDir(const std::string& calibration_file) {
  std::filesystem::path p(calibration_file);
  return (p.parent_path() / (p.stem().string() + ".report")).string();
}

Result<std::vector<std::string>> WriteCalibrationReport(const CalibrationReport& report,
                                                        const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return Error{dir + ": " + ec.message()};
  std::vector<std::string> written;
  const auto write = [&](const std::string& file, const cv::Mat& image) -> Status {
    const std::string path = (std::filesystem::path(dir) / file).string();
    if (Status s = WritePng(image, path); !s) return s;
    written.push_back(path);
    return {};
  };
  for (const auto& [name, camera] : report.cameras) {
    if (camera->residuals.empty()) continue;
    for (const auto& [file, image] :
         {std::pair{"residuals_" + name + ".png", ResidualVectors(name, *camera)},
          std::pair{"histogram_" + name + ".png", Histogram(name, *camera)},
          std::pair{"view_rms_" + name + ".png", ViewRms(name, *camera)},
          std::pair{"coverage_" + name + ".png", Coverage(name, *camera)}})
      if (Status s = write(file, image); !s) return Error{s.error()};
  }
  if (report.validation && !report.validation->maps.empty() && !report.cameras.empty())
    if (Status s = write("uncertainty.png",
                         Uncertainty(*report.validation, report.cameras[0].second->intrinsics));
        !s)
      return Error{s.error()};
  const std::string json = (std::filesystem::path(dir) / "report.json").string();
  if (Status s = WriteFileAtomically(json, report.summary.dump(2) + "\n"); !s)
    return Error{s.error()};
  written.push_back(json);
  return written;
}

}  // namespace ts
