#pragma once
// Calibrations in OpenCV's FileStorage YAML, for the tools that read them: one camera as
// calibrateCamera's users write it (image_width, image_height, cameraMatrix, distCoeffs), a
// stereo pair as stereoCalibrate's (cameraMatrix1, distCoeffs1, cameraMatrix2, distCoeffs2, R,
// T with x_right = R x_left + T; the stereo_calib sample's M1 D1 M2 D2 are read too). The lens
// models are converted by processing/calibration/opencv_camera.h, which reports how far apart
// the two still project.
#include <string>

#include "core/result.h"
#include "processing/calibration/opencv_camera.h"
#include "processing/geometry/calibration.h"

namespace ts {

struct OpenCvExport {
  ModelConversion left, right;
};

Status SaveOpenCvCamera(const CameraIntrinsics& camera, const std::string& file,
                        ModelConversion* conversion);
Status SaveOpenCvStereo(const Calibration& calibration, const std::string& file,
                        OpenCvExport* conversion);

// A stereo file becomes a calibration with the ideal stage (the rig's roll about its baseline
// levels the mean viewing axis, StereoRig::FromStereoCalibration). Errors name file and field.
Result<Calibration> LoadOpenCvStereo(const std::string& file, OpenCvExport* conversion);
Result<CameraIntrinsics> LoadOpenCvCamera(const std::string& file, ModelConversion* conversion);

}  // namespace ts
