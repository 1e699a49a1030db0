// Calibration (issue 20), ours beside the tools people use, in one table:
//  - OpenCV's stereo chessboard sample, the same detections for everyone: RMS per camera
//    against calibrateCamera's and stereo RMS against stereoCalibrate's, the focal lengths'
//    difference, the principal distance's sigma, the time; beside them mrcal
//    (mrcal-calibrate-cameras on the same corners, LENSMODEL_OPENCV5): its RMS (each view's
//    pose fitted to the same corners with its camera), its focal length, and the largest
//    projection difference between its camera and ours over the frame;
//  - the simulated control field, seeds 1-10 (rendered images, hand marks, the whole chain):
//    issue 20's targets (principal distance 0.05 %, principal point 0.3 px, distortion 0.1 px,
//    baseline 0.2 mm, angles 0.005 deg) as the largest error over the seeds, and the RMS of
//    error / sigma (0.7-1.5: honest sigmas); and the stage at the same field (issue 21):
//    each camera's place in the field within 0.01 deg and 2 mm, the offsets within 2 mm, their
//    RMS error / sigma;
//  - rendered board sessions (40 placements swept over each camera's frame), seeds 1-10, ours
//    (every view of each camera) beside OpenCV's (calibrateCamera on each camera's views,
//    stereoCalibrate on the points of the pairs both saw): ChArUco sessions (sim::CharucoSession:
//    boards off the frame's edges, 1-2.5 m) against the same targets; whole chessboards (1.5-3
//    m), which cannot reach the frame's corners, reported beside them; the corners' error
//    against their true projections;
//  - the hills station processed with the calibration recovered from the field and from the
//    board session (the stage kinematics the true ones): DEM RMSE and coverage against the
//    true calibration's (within 10 %, within 1 point).
#include <chrono>
#include <filesystem>
#include <fstream>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include "processing/calibration/calibration_board.h"
#include "processing/calibration/camera_calibration.h"
#include "processing/calibration/chessboard.h"
#include "processing/calibration/field_calibration.h"
#include "processing/calibration/opencv_camera.h"
#include "processing/calibration/rig_adjustment.h"
#include "processing/calibration/rig_control_field.h"
#include "processing/io/calibration_yaml.h"
#include "sim/calibration_field.h"
#include "sim/calibration_views.h"
#include "sim/noise.h"
#include "sim/sensor.h"
#include "tests/bench/bench_table.h"
#include "tests/common/calibration_errors.h"
#include "tests/common/field_session.h"
#include "tests/common/opencv_sample_boards.h"
#include "tests/common/stage_truth.h"
#include "tests/common/temp_dir.h"

namespace {

using namespace ts;

// The value, or the error on stderr and the run ended.
template <typename T>
T Must(Result<T> r, const std::string& what) {
  if (!r) {
    std::fprintf(stderr, "%s: %s\n", what.c_str(), r.error().c_str());
    std::exit(1);
  }
  return *std::move(r);
}

double Since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The largest distance over the frame between where our camera and OpenCV's model (k, d) put
// the same direction.
double ProjectionDifferencePx(const CameraIntrinsics& ours, const cv::Mat& k, const cv::Mat& d) {
  const CameraModel model(ours);
  const OpenCvCamera other{ours.width_px, ours.height_px, k, d};
  double worst = 0.0;
  for (int j = 0; j <= 20; ++j)
    for (int i = 0; i <= 20; ++i) {
      const Eigen::Vector2d u((ours.width_px - 1) * i / 20.0, (ours.height_px - 1) * j / 20.0);
      worst = std::max(worst, (ProjectOpenCv(other, model.RayFromPixel(u)) - u).norm());
    }
  return worst;
}

// RMS (OpenCV's definition) of a fixed camera on the views, each view's pose fitted.
double RmsWithFixedCamera(const OpenCvCorners& c, const cv::Mat& k, const cv::Mat& d) {
  double sum = 0.0;
  size_t n = 0;
  for (size_t v = 0; v < c.object.size(); ++v) {
    cv::Mat rvec, tvec;
    cv::solvePnP(c.object[v], c.image[v], k, d, rvec, tvec);
    std::vector<cv::Point2f> projected;
    cv::projectPoints(c.object[v], rvec, tvec, k, d, projected);
    for (size_t i = 0; i < projected.size(); ++i) {
      const cv::Point2f e = projected[i] - c.image[v][i];
      sum += e.dot(e);
      ++n;
    }
  }
  return std::sqrt(sum / n);
}

// mrcal-calibrate-cameras on the views' corners; its OpenCV-5 camera (k, d), time in seconds.
bool Mrcal(const TargetViews& views, int columns, int rows, double spacing, double focal,
           cv::Mat* k, cv::Mat* d, double* seconds) {
  testing::TempDir dir;
  {
    std::ofstream cache(dir / "corners.vnl");
    cache << "# filename x y level\n";
    for (const TargetView& v : views.views)
      for (const Eigen::Vector2d& p : v.pixels)
        cache << "view-" << v.name << ".png " << p.x() << " " << p.y() << " 0\n";
  }
  const auto t0 = std::chrono::steady_clock::now();
  const std::string run =
      "cd " + dir.path().string() +
      " && mrcal-calibrate-cameras --corners-cache corners.vnl --lensmodel LENSMODEL_OPENCV5 "
      "--focal " +
      std::to_string(focal) + " --object-spacing " + std::to_string(spacing) +
      " --object-width-n " + std::to_string(columns) + " --object-height-n " +
      std::to_string(rows) + " --imagersize " + std::to_string(views.width_px) + " " +
      std::to_string(views.height_px) + " --outdir . 'view-*.png' > mrcal.log 2>&1";
  if (std::system(run.c_str()) != 0) return false;
  *seconds = Since(t0);
  const std::string read = "/usr/bin/python3 -c \"import mrcal; print(*mrcal.cameramodel('" +
                           (dir / "camera-0.cameramodel") + "').intrinsics()[1])\" > " +
                           (dir / "intrinsics.txt");
  if (std::system(read.c_str()) != 0) return false;
  std::ifstream in(dir / "intrinsics.txt");
  double p[9];
  for (double& x : p)
    if (!(in >> x)) return false;
  *k = (cv::Mat_<double>(3, 3) << p[0], 0, p[2], 0, p[1], p[3], 0, 0, 1);
  *d = (cv::Mat_<double>(1, 5) << p[4], p[5], p[6], p[7], p[8]);
  return true;
}

void RealSet(bench::Table* table) {
  const ChessboardOptions board;  // the sample's: 9 x 6, unit squares
  TargetViews left, right;
  DetectSamplePairs(&left, &right);
  const cv::Size size(left.width_px, left.height_px);
  cv::Mat k[2], d[2];
  double opencv_rms[2];
  for (int c = 0; c < 2; ++c) {
    const TargetViews& views = c == 0 ? left : right;
    const std::string name = c == 0 ? "real left: " : "real right: ";
    const OpenCvCorners corners = ToOpenCvCorners(views);
    std::vector<cv::Mat> rv, tv;
    auto t0 = std::chrono::steady_clock::now();
    opencv_rms[c] = cv::calibrateCamera(corners.object, corners.image, size, k[c], d[c], rv, tv);
    const double opencv_s = Since(t0);
    t0 = std::chrono::steady_clock::now();
    const CameraCalibration ours = Must(CalibrateCamera(views, {}), name + "ours");
    const double ours_s = Since(t0);
    table->Add({name + "RMS ours", ours.rms_px, "px", "<= 1.02 OpenCV",
                ours.rms_px <= 1.02 * opencv_rms[c]});
    table->Add({name + "RMS OpenCV calibrateCamera", opencv_rms[c], "px", ""});
    const double fx_difference = ours.fx() / k[c].at<double>(0, 0) - 1.0;
    table->Add({name + "fx ours / OpenCV - 1", fx_difference, "", "|x| <= 0.005",
                std::abs(fx_difference) <= 0.005});
    table->Add({name + "c sigma ours", ours.sigma[0], "px", ""});
    table->Add({name + "projection ours vs OpenCV, largest",
                ProjectionDifferencePx(ours.intrinsics, k[c], d[c]), "px", ""});
    table->Add({name + "time ours", ours_s, "s", ""});
    table->Add({name + "time OpenCV", opencv_s, "s", ""});
    cv::Mat mk, md;
    double mrcal_s = 0.0;
    if (!Mrcal(views, board.columns, board.rows, board.square, ours.fx(), &mk, &md, &mrcal_s)) {
      table->Add({name + "mrcal ran", 0.0, "", "== 1", false});
      continue;
    }
    table->Add(
        {name + "RMS mrcal (poses refitted)", RmsWithFixedCamera(corners, mk, md), "px", ""});
    table->Add({name + "fx ours / mrcal - 1", ours.fx() / mk.at<double>(0, 0) - 1.0, "", ""});
    table->Add({name + "projection ours vs mrcal, largest",
                ProjectionDifferencePx(ours.intrinsics, mk, md), "px", ""});
    table->Add({name + "time mrcal-calibrate-cameras", mrcal_s, "s", ""});
  }
  const OpenCvCorners l = ToOpenCvCorners(left), r = ToOpenCvCorners(right);
  cv::Mat rr, tt, e, f;
  const double opencv_stereo =
      cv::stereoCalibrate(l.object, l.image, r.image, k[0], d[0], k[1], d[1], size, rr, tt, e, f,
                          cv::CALIB_USE_INTRINSIC_GUESS);
  const StereoCalibration ours = Must(CalibrateStereo(left, right, {}), "real stereo");
  table->Add({"real stereo: RMS ours", ours.rms_px, "px", "<= 1.02 OpenCV",
              ours.rms_px <= 1.02 * opencv_stereo});
  table->Add({"real stereo: RMS OpenCV stereoCalibrate", opencv_stereo, "px", ""});
  table->Add({"real stereo: baseline ours (squares)", ours.baseline, "", ""});
  table->Add({"real stereo: baseline OpenCV (squares)", cv::norm(tt), "", ""});
}

void AddErrors(const std::string& name, const StereoErrors& e, bool targets, bench::Table* table) {
  const auto row = [&](const std::string& what, double value, const char* unit, double limit) {
    char target[32] = "";
    if (targets) std::snprintf(target, sizeof(target), "<= %g", limit);
    table->Add({name + what, value, unit, target, !targets || value <= limit});
  };
  row("largest c error", 100 * e.c_rel.MaxAbs(), "%", 0.05);
  row("largest principal point error", e.pp.MaxAbs(), "px", 0.3);
  row("largest distortion error over the frame", e.distortion_px, "px", 0.1);
  row("largest baseline error", 1e3 * e.baseline.MaxAbs(), "mm", 0.2);
  row("largest angle error", e.angles.MaxAbs(), "deg", 0.005);
  for (const auto& [what, errors] : {std::pair{"c", &e.c_rel}, std::pair{"principal point", &e.pp},
                                     std::pair{"baseline", &e.baseline}}) {
    const double n = errors->NormalisedRms();
    table->Add({name + "RMS error/sigma, " + what, n, "", targets ? "0.7-1.5" : "",
                !targets || (n >= 0.7 && n <= 1.5)});
  }
}

// The stage at the same field (issue 21, calibrate rig --field-session): its kinematics
// adjusted on the session's stage poses with the cameras just calibrated, the design stage the
// start. Each camera's place in the field's frame against the truth's, and the stage's offsets
// (in the tilted and pan frames, which the calibration's own definition of the rig frame does
// not turn) against the truth in the estimate's gauge. With the cameras held, their
// calibration's covariance is carried into the offsets' sigmas; refined (--refine-cameras),
// their errors are unknowns of the adjustment, though it weighs the same target images that
// calibrated the cameras a second time.
struct FieldStageErrors {
  testing::CameraErrors cameras;  // the largest over the seeds
  double offset_m = 0.0;          // the largest over the seeds and the offsets determined
  double ratio_squares = 0.0;     // of (estimate - truth) / sigma, over the offsets determined
  int offsets = 0;
  double seconds = 0.0;
};

void AdjustStageAtField(const sim::SimRig& rig, const sim::FieldSession& s, FieldViews views,
                        const StereoCalibration& c, bool refine_cameras, FieldStageErrors* e) {
  const auto t0 = std::chrono::steady_clock::now();
  const Calibration calibrated = CalibrationOf(c, rig.nominal);
  views.start = {calibrated.rig.left, calibrated.rig.right};
  views.second_from_first = calibrated.rig.RightFromLeftCamera();
  FieldReport report;
  const std::vector<TargetViews> measured =
      Must(MeasureFieldTargets(s.surveyed, views, {}, &report), "field targets");
  std::vector<RigPose> poses;
  for (const StagePose& p : s.poses) poses.push_back({p.pan_deg, p.tilt_deg, 0});
  RigAdjustmentOptions options;
  options.refine_cameras = refine_cameras;
  const RigAdjustment r =
      Must(AdjustRig(Must(ControlFieldInput(calibrated, measured, poses), "field input"), options),
           "stage at the field");
  e->seconds += Since(t0);
  const Calibration adjusted = r.Adjusted(calibrated);
  // The measured targets are about the surveyed field's centroid (MeasureFieldTargets).
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const FieldTarget& t : s.surveyed.targets) centroid += t.position_m;
  centroid /= static_cast<double>(s.surveyed.targets.size());
  const Eigen::Isometry3d centred_from_station =
      Eigen::Translation3d(-centroid) * s.field_from_station;
  const testing::CameraErrors cameras = testing::FieldPlacementErrors(
      rig.truth, centred_from_station, s.poses, adjusted, r.control[0].l_from_field, poses);
  e->cameras.deg = std::max(e->cameras.deg, cameras.deg);
  e->cameras.m = std::max(e->cameras.m, cameras.m);
  const StageVector estimate = StageVectorOf(r.stage);
  const StageVector truth = testing::TruthInTheEstimatesGauge(rig.truth, r);
  for (int i = 0; i < kStageParameterCount; ++i) {
    if (!testing::IsStageOffset(i) || r.sigma[i] == 0.0) continue;
    e->offset_m = std::max(e->offset_m, std::abs(estimate[i] - truth[i]));
    e->ratio_squares += std::pow((estimate[i] - truth[i]) / r.sigma[i], 2);
    ++e->offsets;
  }
}

void Field(bench::Table* table) {
  StereoErrors errors;
  FieldStageErrors stage, refined;
  double seconds = 0.0;
  for (int seed = 1; seed <= 10; ++seed) {
    const sim::SimRig rig = sim::MakeSimRig(seed, 1.5);
    const sim::FieldSessionOptions o;
    const sim::FieldSession s = sim::PlanFieldSession(rig, seed, o);
    const FieldViews views = SimulatedFieldViews(rig, s, seed, o);
    FieldReport report;
    const auto t0 = std::chrono::steady_clock::now();
    const StereoCalibration c = Must(CalibrateStereoAtField(s.surveyed, views, {}, {}, &report),
                                     "field seed " + std::to_string(seed));
    seconds += Since(t0);
    errors.Add(c, rig.truth.rig);
    AdjustStageAtField(rig, s, views, c, false, &stage);
    AdjustStageAtField(rig, s, views, c, true, &refined);
  }
  AddErrors("field, 10 seeds: ", errors, true, table);
  table->Add({"field: calibrate stereo, mean per session", seconds / 10, "s", ""});
  table->Add({"field stage: largest camera angle error in the field", stage.cameras.deg, "deg",
              "<= 0.01", stage.cameras.deg <= 0.01});
  table->Add({"field stage: largest camera position error in the field", 1e3 * stage.cameras.m,
              "mm", "<= 2", stage.cameras.m <= 0.002});
  table->Add({"field stage: largest offset error", 1e3 * stage.offset_m, "mm", "<= 2",
              stage.offset_m <= 0.002});
  const double ratio = std::sqrt(stage.ratio_squares / std::max(1, stage.offsets));
  table->Add({"field stage: RMS error/sigma, offsets", ratio, "", "0.7-1.5",
              ratio >= 0.7 && ratio <= 1.5});
  table->Add({"field stage: calibrate rig, mean per session", stage.seconds / 10, "s", ""});
  const double refined_ratio = std::sqrt(refined.ratio_squares / std::max(1, refined.offsets));
  table->Add(
      {"field stage, cameras refined: largest offset error", 1e3 * refined.offset_m, "mm", ""});
  table->Add({"field stage, cameras refined: RMS error/sigma, offsets", refined_ratio, "", ""});
  table->Add({"field stage, cameras refined: calibrate rig, mean per session", refined.seconds / 10,
              "s", ""});
}

// The ids both views saw, in the left view's order: stereoCalibrate needs the same points in
// both images of a pair.
void AddCommonPoints(const TargetView& l, const TargetView& r, TargetViews* left_pairs,
                     TargetViews* right_pairs) {
  TargetView a{l.name, l.placement, {}, {}}, b{r.name, r.placement, {}, {}};
  for (size_t i = 0; i < l.ids.size(); ++i)
    for (size_t j = 0; j < r.ids.size(); ++j)
      if (l.ids[i] == r.ids[j]) {
        a.ids.push_back(l.ids[i]);
        a.pixels.push_back(l.pixels[i]);
        b.ids.push_back(r.ids[j]);
        b.pixels.push_back(r.pixels[j]);
      }
  if (a.ids.size() < 6) return;
  left_pairs->views.push_back(std::move(a));
  right_pairs->views.push_back(std::move(b));
}

// The corners' distances from their true projections (a chessboard's detector may number the
// corners from the board's opposite corner: the nearer numbering is taken).
void AddCornerErrors(const TargetView& view, const std::vector<Eigen::Vector3d>& target,
                     const CameraIntrinsics& camera, const Eigen::Isometry3d& camera_from_board,
                     std::vector<double>* errors) {
  const CameraModel model(camera);
  const size_t n = view.ids.size();
  std::vector<Eigen::Vector2d> projected(n);
  for (size_t i = 0; i < n; ++i)
    model.Project(camera_from_board * target[view.ids[i]], &projected[i]);
  double direct = 0.0, reversed = 0.0;
  for (size_t i = 0; i < n; ++i) {
    direct += (projected[i] - view.pixels[i]).squaredNorm();
    reversed += (projected[i] - view.pixels[n - 1 - i]).squaredNorm();
  }
  for (size_t i = 0; i < n; ++i)
    errors->push_back((projected[i] - view.pixels[reversed < direct ? n - 1 - i : i]).norm());
}

// Rendered board sessions (seeds 1-10 unless --seeds): our calibration on every view of each camera
// against issue 20's targets (`targets`), beside OpenCV's calibrateCamera on the same views and
// stereoCalibrate on the points both images of a pair saw; the corners' error against their
// true projections (sharp views of the left camera).
void Boards(const std::string& kind, const sim::BoardSessionOptions& o, bool targets,
            const std::vector<uint64_t>& seeds, bench::Table* table) {
  StereoErrors ours, opencv;
  std::vector<double> corner_errors;
  CalibrationBoard board{o.Board(), std::nullopt};
  if (o.charuco) board.charuco = o.Charuco();
  for (const uint64_t seed : seeds) {
    const sim::SimRig rig = sim::MakeSimRig(seed, 1.5);
    const std::vector<sim::BoardPlacement> session = sim::RenderBoardSession(rig, seed, o);
    // Each camera's views (ours, OpenCV's calibrateCamera) and the points of the pairs both saw
    // (stereoCalibrate needs them).
    TargetViews left, right, left_pairs, right_pairs;
    for (TargetViews* v : {&left, &right, &left_pairs, &right_pairs}) {
      v->target = ChessboardCorners(o.Board());
      v->width_px = rig.truth.rig.left.width_px;
      v->height_px = rig.truth.rig.left.height_px;
    }
    for (size_t k = 0; k < session.size(); ++k) {
      const int placement = static_cast<int>(k);
      auto l = DetectBoard(session[k].left, board);
      auto r = DetectBoard(session[k].right, board);
      for (auto* v : {&l, &r})
        if (*v) {
          (*v)->name = session[k].name;
          (*v)->placement = placement;
        }
      if (l) left.views.push_back(*l);
      if (r) right.views.push_back(*r);
      if (l && session[k].board && !session[k].blurred)
        AddCornerErrors(*l, left.target, rig.truth.rig.left, session[k].left_from_board,
                        &corner_errors);
      if (l && r) AddCommonPoints(*l, *r, &left_pairs, &right_pairs);
    }
    const StereoCalibration s = Must(CalibrateStereo(left, right, {}), kind);
    ours.Add(s, rig.truth.rig);
    const OpenCvCorners lc = ToOpenCvCorners(left), rc = ToOpenCvCorners(right);
    const OpenCvCorners lp = ToOpenCvCorners(left_pairs), rp = ToOpenCvCorners(right_pairs);
    const cv::Size size(left.width_px, left.height_px);
    cv::Mat k1, d1, k2, d2, r, t, e, f;
    std::vector<cv::Mat> rv, tv;
    cv::calibrateCamera(lc.object, lc.image, size, k1, d1, rv, tv);
    cv::calibrateCamera(rc.object, rc.image, size, k2, d2, rv, tv);
    cv::stereoCalibrate(lp.object, lp.image, rp.image, k1, d1, k2, d2, size, r, t, e, f,
                        cv::CALIB_USE_INTRINSIC_GUESS);
    const StereoRig& truth = rig.truth.rig;
    for (const auto& [k, camera] : {std::pair{&k1, &truth.left}, std::pair{&k2, &truth.right}}) {
      opencv.c_rel.Add(k->at<double>(1, 1) / camera->principal_distance_px - 1.0, 1.0);
      opencv.pp.Add(k->at<double>(0, 2) - camera->principal_point_x_px, 1.0);
      opencv.pp.Add(k->at<double>(1, 2) - camera->principal_point_y_px, 1.0);
    }
    opencv.baseline.Add(cv::norm(t) - truth.baseline_m, 1.0);
    Eigen::Matrix3d rotation;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) rotation(i, j) = r.at<double>(i, j);
    const Opk opk = OpkFromRotation(rotation.transpose());
    const Eigen::Vector3d angles(DegFromRad(opk.omega_rad), DegFromRad(opk.phi_rad),
                                 DegFromRad(opk.kappa_rad));
    for (int j = 0; j < 3; ++j) opencv.angles.Add(angles[j] - RelativeAnglesDeg(truth)[j], 1.0);
  }
  const std::string over = ", " + std::to_string(seeds.size()) + " seeds, ";
  AddErrors(kind + over + "ours: ", ours, targets, table);
  std::sort(corner_errors.begin(), corner_errors.end());
  double sum = 0.0;
  for (double e : corner_errors) sum += e * e;
  table->Add({kind + ": corners' RMS error against the truth",
              std::sqrt(sum / corner_errors.size()), "px", ""});
  table->Add({kind + ": corners' 95th percentile error",
              corner_errors[corner_errors.size() * 95 / 100], "px", ""});
  const auto row = [&](const std::string& what, double v, const char* unit) {
    table->Add({kind + over + "OpenCV: " + what, v, unit, ""});
  };
  row("largest c error", 100 * opencv.c_rel.MaxAbs(), "%");
  row("largest principal point error", opencv.pp.MaxAbs(), "px");
  row("largest baseline error", 1e3 * opencv.baseline.MaxAbs(), "mm");
  row("largest angle error", opencv.angles.MaxAbs(), "deg");
}

// The hills station processed with the true calibration and with the recovered ones.
void Hills(bench::Table* table) {
  testing::TempDir dir;
  const std::string exe = TS_TOPOSTATION_EXE, d = dir.path().string();
  const auto run = [](const std::string& command) {
    if (std::system((command + " > /dev/null").c_str()) != 0) {
      std::fprintf(stderr, "failed: %s\n", command.c_str());
      std::exit(1);
    }
  };
  run(exe + " sim render --scene hills --out " + d + "/station --truth " + d + "/truth");
  run(exe + " sim render --scene hills --calibration field --out " + d + "/field --truth " + d +
      "/ft");
  run(exe + " sim render --scene hills --calibration chessboard --out " + d + "/board --truth " +
      d + "/bt");
  const std::string stage = " --stage-from " + d + "/truth/calibration.yaml";
  run(exe + " calibrate stereo --left '" + d + "/field/left/*.png' --right '" + d +
      "/field/right/*.png' --control-field " + d + "/field/field.yaml --marks " + d +
      "/field/marks.yaml --start " + d + "/field/design.yaml" + stage + " --out " + d +
      "/field.yaml");
  run(exe + " calibrate stereo --left '" + d + "/board/left/*.png' --right '" + d +
      "/board/right/*.png' --chessboard 16x11 --square 0.07" + stage + " --out " + d +
      "/board.yaml 2>/dev/null");
  std::map<std::string, nlohmann::json> results;
  for (const std::string& name : std::vector<std::string>{"truth/calibration", "field", "board"}) {
    const std::string station = d + "/station-" + std::to_string(results.size());
    std::filesystem::copy(d + "/station", station, std::filesystem::copy_options::recursive);
    run(exe + " process " + station + " --calibration " + d + "/" + name + ".yaml");
    run(exe + " evaluate " + station + " --truth " + d + "/truth");
    results[name] = nlohmann::json::parse(std::ifstream(station + "/products/evaluation.json"));
  }
  const nlohmann::json& truth = results["truth/calibration"];
  table->Add({"hills, true calibration: DEM RMSE", truth["dem_rmse_m"].get<double>(), "m", ""});
  table->Add({"hills, true calibration: coverage within 30 m", truth["coverage_30m"].get<double>(),
              "", ""});
  for (const std::string& name : std::vector<std::string>{"field", "board"}) {
    const double ratio =
        results[name]["dem_rmse_m"].get<double>() / truth["dem_rmse_m"].get<double>();
    const double coverage =
        100 * (results[name]["coverage_30m"].get<double>() - truth["coverage_30m"].get<double>());
    table->Add({"hills, " + name + " calibration: DEM RMSE / true-calibration RMSE", ratio, "",
                "<= 1.10", ratio <= 1.10});
    table->Add({"hills, " + name + " calibration: coverage within 30 m - true's", coverage,
                "points", ">= -1", coverage >= -1.0});
  }
}

// --only SET,...: the sets to run (real, field, chessboards, charuco, marked, hills); all by
// default. --seeds 1,2,...: the board sessions' seeds (1-10 by default).
}  // namespace

int main(int argc, char** argv) {
  bench::Table table("bench_calibration: ours beside OpenCV and mrcal; the simulator's targets");
  if (bench::Wanted(argc, argv, "real")) RealSet(&table);
  if (bench::Wanted(argc, argv, "field")) Field(&table);
  std::vector<uint64_t> seeds = bench::SeedsArgument(argc, argv);
  if (seeds.empty()) seeds = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
  if (bench::Wanted(argc, argv, "chessboards"))
    Boards("chessboards", sim::BoardSessionOptions{}, false, seeds, &table);
  if (bench::Wanted(argc, argv, "charuco"))
    Boards("ChArUco boards", sim::CharucoSession(), true, seeds, &table);
  if (bench::Wanted(argc, argv, "marked"))
    Boards("chessboards with circle markers", sim::MarkedChessboardSession(), true, seeds, &table);
  if (bench::Wanted(argc, argv, "hills")) Hills(&table);
  return table.Finish(argc, argv);
}
