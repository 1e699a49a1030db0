#pragma once
// What a calibration adjusts: a target of known points (a chessboard's corners in its plane, a
// control field's surveyed targets) and one camera's views of it. A view may show only a part
// of the target (a ChArUco board at the frame's edge, the field's targets in one direction):
// each pixel carries the id of its target point. Views of one camera that share a placement
// with views of another (the two images of a stereo pair) saw the target in the same pose.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/result.h"

namespace ts {

struct TargetView {
  std::string name;   // the image's file name, for the report
  int placement = 0;  // one pose of the target; shared by the images of a stereo pair
  std::vector<int> ids;
  std::vector<Eigen::Vector2d> pixels;
};

// Where in the frame the views put observations: a grid of cells over the frame, each cell's
// count. The distortion is only measured where there are observations; elsewhere, the frame's
// edges and corners above all, it is extrapolated.
struct FrameCoverage {
  static constexpr int kColumns = 8, kRows = 6;
  std::vector<int> counts;    // row-major, kColumns x kRows
  double share = 0.0;         // of the cells holding an observation
  double border_share = 0.0;  // of the cells along the frame's edges holding one
};

struct TargetViews {
  int width_px = 0;
  int height_px = 0;
  std::vector<Eigen::Vector3d> target;
  // Per target point, the sigma of its surveyed coordinates (a control field's, in the
  // target's unit): the adjustment moves it as far as that allows. Empty, or 0: exact (a
  // printed board).
  std::vector<double> target_sigma;
  // A priori sigma of a measured pixel (a control field's targets: their matching's), which
  // weighs the surveyed coordinates against the images.
  double pixel_sigma_px = 0.0;
  std::vector<TargetView> views;

  // A view of the whole target, in the order of `target`.
  void AddFullView(const std::string& name, int placement,
                   const std::vector<Eigen::Vector2d>& pixels);
  int Observations() const;
  // Every target point at z = 0 (a board), which Zhang's closed form needs.
  bool Planar() const;
  FrameCoverage Coverage() const;
  // Ids within the target, finite pixels and sigmas, a size, a name per view.
  Status Check() const;
};

}  // namespace ts
