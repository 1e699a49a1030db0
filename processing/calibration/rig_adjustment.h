#pragma once
// The rig on its stage (issue 21): the stage kinematics (stage_kinematics.h) estimated from tie
// points of a panorama, the interior and stereo calibration held, or refined with the
// covariance of their calibration when the user asks (rig_cameras.h). Each tie point is a point of
// the terrain seen from two or more stage poses (neighbouring pairs in their overlaps, a row
// pose and the pose above it); its position in L is an unknown, and each image that measured
// it is an observation through the project's camera model:
//
//   pixel = Project(camera_from_L(pan + d_pan, tilt + d_tilt) * point_L)
//
// The encoder readings are observations of the true angles (d_pan, d_tilt per pose, sigma
// encoder_sigma_deg); the inclinometer, when given, observes the levelling; every kinematic
// parameter has a prior (the previous calibration, sigmas of prior_*). The pan zero is the
// azimuth datum, which no panorama shows: it is held.
//
// Several stations of one rig join one adjustment: the stage is the rig's and shared, the
// levelling is each set-up's own (with its own inclinometer reading and prior), and tie points
// tie poses of one station only.
//
// What a panorama cannot determine is found on the information it adds to the prior: the
// stage parameters' marginal information from the data, scaled by the prior sigmas, has an
// eigenvector for every combination of them; where an eigenvalue is below 1 (the data tell less
// of that combination than the prior did), the parameter that dominates it is held at its
// prior and named. The combinations that remain (tilt zero against the rig's omega with one
// tilt, for example: only their sum turns the views) are carried by the others.
//
// A control field in view joins the same adjustment: its targets are points like the tie
// points, seen from the poses of the set-up at the field, and their surveyed coordinates are
// observations of them through the field's pose in L (six unknowns; the field's frame is its
// own). Where tie points only tell how the views turn against each other, the targets fix
// where each camera stands: the offsets of the tilt axis and of the rig come from them. That
// set-up's levelling is held, its rotation being the field pose's.
#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/options.h"
#include "core/result.h"
#include "processing/calibration/rig_cameras.h"
#include "processing/geometry/calibration.h"

namespace ts {

struct RigAdjustmentOptions {
  double pixel_sigma_px = 0.3;            // a tie point's image measurement, a priori
  double encoder_sigma_deg = 0.002;       // the stage's read-back angles
  double inclinometer_sigma_deg = 0.02;   // one reading: its index error
  double inclinometer_noise_deg = 0.002;  // a reading's noise (inclinometer.h)
  double prior_angle_sigma_deg = 1.0;     // levelling, tilt zero, skew
  // The rig's rotation on its tilt plate. A transport resets the encoder zeros and the
  // levelling; the rig stays bolted to its plate. So where one tilt cannot tell tilt zero from
  // the rig's omega, nor the skew from its kappa, the mount is what the data leave at its prior,
  // on every station alike: with equal priors the held one is whichever rounding favours.
  double prior_mount_sigma_deg = 0.1;
  double prior_offset_sigma_m = 0.02;  // tilt-axis and rig offsets
  bool refine_cameras = false;         // rig_cameras.h
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("pixel_sigma_px", self.pixel_sigma_px, {"a tie point's image sigma", "px", 1e-3, 10});
    v("encoder_sigma_deg", self.encoder_sigma_deg, {"read-back angle sigma", "deg", 1e-5, 1});
    v("inclinometer_sigma_deg", self.inclinometer_sigma_deg,
      {"sigma of the levelling from one inclinometer reading", "deg", 1e-4, 1});
    v("inclinometer_noise_deg", self.inclinometer_noise_deg,
      {"noise of an inclinometer reading (readings round the pan fit the levelling)", "deg", 1e-5,
       1});
    v("prior_angle_sigma_deg", self.prior_angle_sigma_deg,
      {"prior sigma of the stage's small angles", "deg", 1e-4, 10});
    v("prior_mount_sigma_deg", self.prior_mount_sigma_deg,
      {"prior sigma of the rig's rotation on its tilt plate", "deg", 1e-4, 10});
    v("prior_offset_sigma_m", self.prior_offset_sigma_m,
      {"prior sigma of the stage's offsets", "m", 1e-5, 1});
    v("refine_cameras", self.refine_cameras,
      {"refine the cameras and the stereo pair, weighed by their calibration's covariance"});
  }
  bool Check(std::string* why) const { return CheckDeclaredOptions(*this, why); }
};

struct RigPose {
  double pan_deg = 0.0;  // encoder read-back
  double tilt_deg = 0.0;
  int station = 0;  // index into the input's stations
};

// One set-up of the tripod: what is its own rather than the rig's.
struct RigStation {
  Eigen::Vector2d levelling_deg = Eigen::Vector2d::Zero();  // the start and the prior
  std::optional<Eigen::Vector2d> inclinometer_deg;          // its reading, when there is one
  double inclinometer_sigma_deg = 0.0;  // of that reading; 0: the options' (one reading)
};

struct RigTieObservation {
  int pose = 0;  // index into the poses
  Side side = Side::kLeft;
  int point = 0;  // index into the points
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  // The pixel carries one coordinate of information, not two: the partner image of a rectified
  // stereo match, whose position across the epipolar line the matching imposed.
  bool along_epipolar_only = false;
  // The matching's own a-posteriori sigma of this measurement (px, per coordinate; 0: none).
  // A tie point found in a neighbour by least-squares matching is as precise as its fit, which
  // varies several-fold with the texture; its weight follows it (RigAdjustment::
  // observation_sigma_px), as one image sigma for all would not.
  double measured_sigma_px = 0.0;
};

// Targets surveyed in a frame of their own, seen from the poses of one station (the set-up at
// the field).
struct RigControlField {
  int station = 0;
  std::vector<int> points;                // the input's points that are its targets
  std::vector<Eigen::Vector3d> surveyed;  // their coordinates in the field's frame (m)
  std::vector<double> sigma_m;            // of each coordinate; 0: taken as 0.1 mm
  Eigen::Isometry3d l_from_field = Eigen::Isometry3d::Identity();  // the start
};

struct RigAdjustmentInput {
  // The cameras held; its stage is the prior and the start of what the stations share.
  Calibration calibration;
  // Empty: one station, levelled as calibration.stage, without an inclinometer.
  std::vector<RigStation> stations;
  std::vector<RigPose> poses;
  std::vector<RigTieObservation> observations;
  std::vector<Eigen::Vector3d> points;  // each tie point's start in L
  // Its covariance from its pair's intersection (m^2, in L), for the seams' predicted sigma.
  std::vector<Eigen::Matrix3d> point_covariance_m2;
  std::vector<RigControlField> control_fields;
  // Per point: one of a control field's targets (not a tie point of a panorama's seams).
  std::vector<char> ControlPoints() const;
  // The stations as given, or the one station an empty list stands for.
  std::vector<RigStation> Stations() const;
  // calibration with the levelling of a station (that with which its points were intersected).
  Calibration CalibrationOf(int station) const;
};

struct RigAdjustment {
  StageKinematics stage;  // levelled as the first station
  // A posteriori; 0 for a held parameter. Held cameras are not exact: their calibration's
  // covariance, carried through the adjustment, is in it; sigma_from_held_cameras is that share
  // (sigma^2 = the data's^2 + the share's^2; 0 when the cameras are refined, whose errors are
  // then unknowns, or their calibration states no precision).
  StageVector sigma{};
  StageVector sigma_from_held_cameras{};
  // What the data alone leave: sqrt(sigma^2 - sigma_from_held_cameras^2).
  StageVector SigmaOfTheData() const;
  // Each station's levelling and its sigma (deg, about L's X and Y).
  std::vector<Eigen::Vector2d> levelling_deg, levelling_sigma_deg;
  // The parameters held at their prior because the panorama does not determine them, with why.
  std::vector<std::string> undetermined;
  // Of a tie point's image coordinate, a posteriori (a variance component: the sigmas above
  // are weighed with it; a control field's targets have their own); of one whose measurement
  // has a sigma of its own, this for the median one (observation_sigma_px).
  double image_sigma_px = 0.0;
  double rms_px = 0.0;                     // over the image observations kept
  int observations = 0;                    // image observations kept
  int rejected = 0;                        // off by more than 4 sigma: mismatched tie points
  std::vector<char> rejected_observation;  // per input observation
  // Per input observation, its sigma a posteriori (px, per coordinate): its kind's image sigma,
  // scaled for a measurement with a sigma of its own by that over the median of its kind's.
  std::vector<double> observation_sigma_px;
  double encoder_sigma_deg = 0.0;       // of the read-back angles (the options')
  std::vector<Eigen::Vector3d> points;  // adjusted, in L
  // Per control field: its pose in L, and how its targets fit (RMS of their image residuals;
  // the largest move of a surveyed point, in its sigmas).
  struct ControlFit {
    Eigen::Isometry3d l_from_field = Eigen::Isometry3d::Identity();
    int targets = 0;
    double rms_px = 0.0;
    double image_sigma_px = 0.0;  // of a target's image coordinate, its variance component
    double largest_move_sigma = 0.0;
  };
  std::vector<ControlFit> control;
  RigCameras cameras;  // as given, or refined (options.refine_cameras)
  // `given` with this stage, and these cameras with their precision.
  Calibration Adjusted(const Calibration& given) const;
};

// The tie points of several stations of one rig as one input: poses, points and observations
// renumbered, each pose knowing its station, control fields with them; the first station's
// calibration is the start.
RigAdjustmentInput JoinStations(const std::vector<RigAdjustmentInput>& stations);

// Needs observations of at least one point from two poses.
Result<RigAdjustment> AdjustRig(const RigAdjustmentInput& input,
                                const RigAdjustmentOptions& options);

}  // namespace ts
