#pragma once
// Fills the unknown cells of a grid surface from the known ones, however sparse: a pull-push
// pyramid (each level the mean of the known cells below it, holes filled from the coarser
// level) followed by relaxation towards the harmonic (membrane) surface: known cells are
// honoured exactly, a plane between samples stays nearly a plane, and towards the grid's edge,
// beyond the last samples, the surface levels off (the membrane's free edge). (OpenCV's inpaint is
// made for thin scratches in photographs and smears isolated samples away.)
#include <opencv2/core.hpp>

namespace ts {

// surface: CV_32FC1; known: CV_8UC1, non-zero where the surface holds a value. Returns the
// filled surface (known cells unchanged). An all-unknown grid comes back as zeros.
cv::Mat FillHoles(const cv::Mat& surface, const cv::Mat& known, int relaxation_iterations = 50);

}  // namespace ts
