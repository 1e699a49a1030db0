#include "processing/calibration/field_calibration.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <optional>
#include <set>

namespace ts {
namespace {

// The adjustment works on the field centred on its centroid: survey coordinates far from the
// origin would cost the poses' digits.
Eigen::Vector3d Centroid(const ControlField& field) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const FieldTarget& t : field.targets) sum += t.position_m;
  return sum / static_cast<double>(std::max<size_t>(1, field.targets.size()));
}

TargetViews EmptyViews(const ControlField& field, const Eigen::Vector3d& centre,
                       const CameraIntrinsics& camera) {
  TargetViews views;
  views.width_px = camera.width_px;
  views.height_px = camera.height_px;
  for (const FieldTarget& t : field.targets) {
    views.target.push_back(t.position_m - centre);
    views.target_sigma.push_back(t.sigma_m);
  }
  return views;
}

// A view's pose in the (centred) field from its hand marks.
std::optional<Eigen::Isometry3d> ResectMarks(const ControlField& field,
                                             const Eigen::Vector3d& centre, const FieldImage& image,
                                             const CameraIntrinsics& camera, int min_marks,
                                             std::vector<std::string>* warnings) {
  std::vector<Eigen::Vector3d> target;
  std::vector<Eigen::Vector2d> pixels;
  for (const TargetMark& m : image.marks) {
    const int index = field.IndexOf(m.id);
    if (index < 0) {
      warnings->push_back(image.name + ": marked target " + std::to_string(m.id) +
                          " is not in the field; mark ignored");
      continue;
    }
    target.push_back(field.targets[index].position_m - centre);
    pixels.push_back(m.pixel);
  }
  if (static_cast<int>(target.size()) < min_marks) return std::nullopt;
  std::optional<Eigen::Isometry3d> pose = Resect(target, pixels, camera);
  if (!pose) warnings->push_back(image.name + ": the marks give no resection");
  return pose;
}

// Per stage pose, the first camera's pose in the field: from its own marks, else from the
// second camera's and the relative orientation.
std::vector<std::optional<Eigen::Isometry3d>> OrientPlacements(const ControlField& field,
                                                               const Eigen::Vector3d& centre,
                                                               const FieldViews& views,
                                                               const FieldCalibrationOptions& o,
                                                               std::vector<std::string>* warnings) {
  std::vector<std::optional<Eigen::Isometry3d>> poses(views.images[0].size());
  for (size_t k = 0; k < poses.size(); ++k) {
    for (size_t c = 0; c < views.images.size() && !poses[k]; ++c) {
      const auto pose =
          ResectMarks(field, centre, views.images[c][k], views.start[c], o.min_marks, warnings);
      if (pose) poses[k] = c == 0 ? *pose : views.second_from_first.inverse() * *pose;
    }
    if (!poses[k])
      warnings->push_back(views.images[0][k].name + ": fewer than " + std::to_string(o.min_marks) +
                          " targets marked in the view or its partner; the stage pose is skipped");
  }
  return poses;
}

struct Prediction {
  int index;
  Eigen::Vector2d pixel;
  double radius_px;
};

// Every target in front of the camera and in its frame, the points where they are thought to
// be (the surveyed ones, then the adjusted ones: a target disturbed since the survey is found
// where it is).
std::vector<Prediction> PredictTargets(const ControlField& field,
                                       const std::vector<Eigen::Vector3d>& points,
                                       const CameraIntrinsics& camera,
                                       const Eigen::Isometry3d& camera_from_field) {
  const CameraModel model(camera);
  std::vector<Prediction> predictions;
  for (size_t i = 0; i < field.targets.size(); ++i) {
    const Eigen::Vector3d p = camera_from_field * points[i];
    Eigen::Vector2d pixel;
    if (p.z() <= 0.0 || !model.Project(p, &pixel) || !model.InImage(pixel)) continue;
    predictions.push_back(
        {static_cast<int>(i), pixel,
         0.5 * field.targets[i].diameter_m * camera.principal_distance_px / p.z()});
  }
  return predictions;
}

// Two targets whose searches overlap (one behind the other, seen from this camera) cannot be
// told apart: neither is measured.
bool SharesSearch(const std::vector<Prediction>& predictions, size_t k, double search_px) {
  for (size_t j = 0; j < predictions.size(); ++j)
    if (j != k && (predictions[j].pixel - predictions[k].pixel).norm() <
                      search_px + 3.0 * (predictions[j].radius_px + predictions[k].radius_px))
      return true;
  return false;
}

// Every target predicted in the frame, sought near its prediction.
TargetView MeasureView(const ControlField& field, const std::vector<Eigen::Vector3d>& points,
                       const FieldImage& image, int placement, const CameraIntrinsics& camera,
                       const Eigen::Isometry3d& camera_from_field, double search_px,
                       const CircularTargetOptions& o, std::vector<double>* sigmas) {
  TargetView view{image.name, placement, {}, {}};
  const std::vector<Prediction> predictions =
      PredictTargets(field, points, camera, camera_from_field);
  for (size_t k = 0; k < predictions.size(); ++k) {
    if (SharesSearch(predictions, k, search_px)) continue;
    const Prediction& p = predictions[k];
    const TargetMeasurement m =
        MeasureCircularTarget(image.image, p.pixel, p.radius_px, search_px, o);
    if (!m.ok) continue;
    view.ids.push_back(p.index);
    view.pixels.push_back(m.pixel);
    sigmas->push_back(m.sigma_px);
  }
  return view;
}

// Every camera's views of the field, from the first camera's poses and the relative
// orientation.
std::vector<TargetViews> MeasureViews(const ControlField& field, const Eigen::Vector3d& centre,
                                      const FieldViews& views,
                                      const std::vector<CameraIntrinsics>& cameras,
                                      const std::vector<std::optional<Eigen::Isometry3d>>& poses,
                                      const Eigen::Isometry3d& second_from_first,
                                      const std::vector<Eigen::Vector3d>* adjusted_points,
                                      double search_px, const FieldCalibrationOptions& o,
                                      FieldReport* report) {
  std::vector<TargetViews> measured;
  std::vector<double> sigmas;
  for (size_t c = 0; c < views.images.size(); ++c) {
    TargetViews& camera = measured.emplace_back(EmptyViews(field, centre, cameras[c]));
    const std::vector<Eigen::Vector3d>& points = adjusted_points ? *adjusted_points : camera.target;
    for (size_t k = 0; k < poses.size(); ++k) {
      if (!poses[k]) continue;
      const Eigen::Isometry3d pose = c == 0 ? *poses[k] : second_from_first * *poses[k];
      TargetView view = MeasureView(field, points, views.images[c][k], static_cast<int>(k),
                                    cameras[c], pose, search_px, o.target, &sigmas);
      if (view.ids.size() >= 6) camera.views.push_back(std::move(view));
    }
  }
  if (!sigmas.empty()) {
    std::nth_element(sigmas.begin(), sigmas.begin() + sigmas.size() / 2, sigmas.end());
    report->target_sigma_px = sigmas[sigmas.size() / 2];
  }
  for (TargetViews& camera : measured) camera.pixel_sigma_px = report->target_sigma_px;
  return measured;
}

// The first camera's pose per stage pose, as the adjustment left them.
std::vector<std::optional<Eigen::Isometry3d>> AdjustedPoses(
    size_t count, const std::vector<const CameraCalibration*>& cameras,
    const Eigen::Isometry3d& second_from_first, const std::vector<TargetViews>& measured) {
  std::vector<std::optional<Eigen::Isometry3d>> poses(count);
  for (size_t c = cameras.size(); c-- > 0;)
    for (size_t v = 0; v < measured[c].views.size(); ++v) {
      const Eigen::Isometry3d pose = cameras[c]->camera_from_target[v];
      poses[measured[c].views[v].placement] = c == 0 ? pose : second_from_first.inverse() * pose;
    }
  return poses;
}

std::string List(const std::vector<int>& ids) {
  std::string text;
  for (size_t i = 0; i < ids.size() && i < 12; ++i) {
    if (i) text += ' ';
    text += std::to_string(ids[i]);
  }
  return ids.size() > 12 ? text + " ..." : text;
}

// Targets found in too few images, and surveyed points the adjustment moved too far.
void ReportTargets(const ControlField& field, const Eigen::Vector3d& centre,
                   const std::vector<TargetViews>& measured, const CameraCalibration& adjusted,
                   const FieldCalibrationOptions& o, FieldReport* report) {
  std::vector<int> images(field.targets.size(), 0);
  for (const TargetViews& camera : measured)
    for (const TargetView& v : camera.views)
      for (int id : v.ids) ++images[id];
  std::vector<int> few, moved;
  report->targets_found = 0;
  for (size_t i = 0; i < field.targets.size(); ++i) {
    report->targets_found += images[i] > 0;
    if (images[i] > 0 && images[i] < o.min_images_per_target) few.push_back(field.targets[i].id);
    const double sigma = field.targets[i].sigma_m;
    const Eigen::Vector3d shift = adjusted.target[i] - (field.targets[i].position_m - centre);
    if (sigma > 0.0 && shift.cwiseAbs().maxCoeff() > o.moved_k * sigma)
      moved.push_back(field.targets[i].id);
  }
  if (!few.empty())
    report->warnings.push_back(std::to_string(few.size()) + " targets found in fewer than " +
                               std::to_string(o.min_images_per_target) + " images: " + List(few));
  if (!moved.empty())
    report->warnings.push_back(std::to_string(moved.size()) +
                               " surveyed targets moved by the adjustment more than " +
                               std::to_string(static_cast<int>(o.moved_k)) +
                               " sigma (disturbed, or a survey error?): " + List(moved));
}

// The first camera's pose per stage pose, resected from the targets each camera found there
// (its own first).
std::vector<std::optional<Eigen::Isometry3d>> ResectedPoses(
    size_t count, const std::vector<TargetViews>& measured,
    const std::vector<CameraIntrinsics>& cameras, const Eigen::Isometry3d& second_from_first) {
  std::vector<std::optional<Eigen::Isometry3d>> poses(count);
  for (size_t c = measured.size(); c-- > 0;)
    for (const TargetView& v : measured[c].views) {
      std::vector<Eigen::Vector3d> target;
      for (int id : v.ids) target.push_back(measured[c].target[id]);
      const std::optional<Eigen::Isometry3d> pose = Resect(target, v.pixels, cameras[c]);
      if (pose) poses[v.placement] = c == 0 ? *pose : second_from_first.inverse() * *pose;
    }
  return poses;
}

// The first adjustment only predicts where the targets are for the second: a model of the
// terms every lens has, without the significance tests.
CameraCalibrationOptions PredictionModel(CameraCalibrationOptions o) {
  o.fix_k3 = o.fix_scale_x = o.fix_shear = true;
  o.keep_all_terms = true;
  return o;
}

Status CheckInputs(const FieldViews& views, const CameraCalibrationOptions& calibration,
                   const FieldCalibrationOptions& o, size_t cameras) {
  std::string why;
  if (!calibration.Check(&why) || !o.Check(&why)) return Error{why};
  if (views.images.size() != cameras || views.start.size() != cameras)
    return Error{"field calibration: images and a design camera per camera are needed"};
  for (const auto& images : views.images)
    if (images.size() != views.images[0].size())
      return Error{"field calibration: the cameras have different numbers of images"};
  return {};
}

}  // namespace

Result<std::vector<TargetViews>> MeasureFieldTargets(const ControlField& field,
                                                     const FieldViews& views,
                                                     const FieldCalibrationOptions& o,
                                                     FieldReport* report) {
  if (Status s = CheckInputs(views, {}, o, views.images.size()); !s) return Error{s.error()};
  if (views.images.empty() || views.images.size() > 2)
    return Error{"field targets: one camera's images or a stereo pair's are needed"};
  const Eigen::Vector3d centre = Centroid(field);
  auto poses = OrientPlacements(field, centre, views, o, &report->warnings);
  std::vector<TargetViews> measured =
      MeasureViews(field, centre, views, views.start, poses, views.second_from_first, nullptr,
                   o.first_search_px, o, report);
  poses = ResectedPoses(poses.size(), measured, views.start, views.second_from_first);
  measured = MeasureViews(field, centre, views, views.start, poses, views.second_from_first,
                          nullptr, o.refine_search_px, o, report);
  std::set<int> found;
  for (const TargetViews& camera : measured)
    for (const TargetView& v : camera.views) found.insert(v.ids.begin(), v.ids.end());
  report->targets_found = static_cast<int>(found.size());
  report->views = measured;
  if (found.empty()) return Error{"field targets: no target found in any view"};
  return measured;
}

Result<CameraCalibration> CalibrateCameraAtField(const ControlField& field, const FieldViews& views,
                                                 const CameraCalibrationOptions& calibration,
                                                 const FieldCalibrationOptions& o,
                                                 FieldReport* report) {
  if (Status s = CheckInputs(views, calibration, o, 1); !s) return Error{s.error()};
  const Eigen::Vector3d centre = Centroid(field);
  auto poses = OrientPlacements(field, centre, views, o, &report->warnings);
  const Eigen::Isometry3d none = Eigen::Isometry3d::Identity();
  std::vector<TargetViews> measured = MeasureViews(field, centre, views, views.start, poses, none,
                                                   nullptr, o.first_search_px, o, report);
  const Result<CameraCalibration> first =
      CalibrateCamera(measured[0], PredictionModel(calibration), &views.start[0]);
  if (!first) return first;
  poses = AdjustedPoses(poses.size(), {&*first}, none, measured);
  measured = MeasureViews(field, centre, views, {first->intrinsics}, poses, none, &first->target,
                          o.refine_search_px, o, report);
  Result<CameraCalibration> final = CalibrateCamera(measured[0], calibration, &first->intrinsics);
  if (final) ReportTargets(field, centre, measured, *final, o, report);
  report->views = measured;
  return final;
}

Result<StereoCalibration> CalibrateStereoAtField(const ControlField& field, const FieldViews& views,
                                                 const CameraCalibrationOptions& calibration,
                                                 const FieldCalibrationOptions& o,
                                                 FieldReport* report) {
  if (Status s = CheckInputs(views, calibration, o, 2); !s) return Error{s.error()};
  const Eigen::Vector3d centre = Centroid(field);
  auto poses = OrientPlacements(field, centre, views, o, &report->warnings);
  std::vector<TargetViews> measured =
      MeasureViews(field, centre, views, views.start, poses, views.second_from_first, nullptr,
                   o.first_search_px, o, report);
  const Result<StereoCalibration> first = CalibrateStereo(
      measured[0], measured[1], PredictionModel(calibration), &views.start[0], &views.start[1]);
  if (!first) return first;
  poses =
      AdjustedPoses(poses.size(), {&first->left, &first->right}, first->right_from_left, measured);
  measured =
      MeasureViews(field, centre, views, {first->left.intrinsics, first->right.intrinsics}, poses,
                   first->right_from_left, &first->left.target, o.refine_search_px, o, report);
  Result<StereoCalibration> final = CalibrateStereo(
      measured[0], measured[1], calibration, &first->left.intrinsics, &first->right.intrinsics);
  if (final) ReportTargets(field, centre, measured, final->left, o, report);
  report->views = measured;
  return final;
}

}  // namespace ts
