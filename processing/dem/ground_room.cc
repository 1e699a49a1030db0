#include "processing/dem/ground_room.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

#include "processing/common/angles.h"
#include "processing/common/median.h"

namespace ts {

bool GroundRoomOptions::Check(std::string* why) const { return CheckDeclaredOptions(*this, why); }

namespace {

// The DEM's gradient (rise over run, east and north) at a cell with data, from its neighbours
// with data.
Eigen::Vector2d GradientAt(const Raster& dem, int r, int c) {
  auto value = [&](int rr, int cc) {
    if (rr < 0 || cc < 0 || rr >= dem.rows || cc >= dem.cols) return std::nan("");
    const float v = dem.at(rr, cc);
    return Raster::IsNoData(v) ? std::nan("") : static_cast<double>(v);
  };
  auto derivative = [&](double before, double here, double after) {
    if (std::isfinite(before) && std::isfinite(after)) return 0.5 * (after - before);
    if (std::isfinite(after)) return after - here;
    if (std::isfinite(before)) return here - before;
    return 0.0;
  };
  const double z = value(r, c);
  // Rows run south: north is the row before.
  return Eigen::Vector2d(derivative(value(r, c - 1), z, value(r, c + 1)),
                         derivative(value(r + 1, c), z, value(r - 1, c))) /
         dem.cell_m;
}

// The ground points on a grid a quarter cell fine that reaches margin_m beyond the DEM (points
// there count), and how near they come to each cell centre.
class FinePoints {
 public:
  FinePoints(const KrigingPoints& ground, const Raster& dem, double margin_m)
      : fine_(dem.cell_m / kRatio), margin_(static_cast<int>(std::ceil(margin_m / fine_))) {
    free_ = cv::Mat(dem.rows * kRatio + 2 * margin_, dem.cols * kRatio + 2 * margin_, CV_8U,
                    cv::Scalar(255));
    for (const Eigen::Vector3d& p : ground.All()) {
      const int c = static_cast<int>(std::floor((p.x() - dem.min_x_m) / fine_)) + margin_;
      const int r = static_cast<int>(std::floor((dem.max_y_m - p.y()) / fine_)) + margin_;
      if (c >= 0 && r >= 0 && c < free_.cols && r < free_.rows) free_.at<uint8_t>(r, c) = 0;
    }
    cv::distanceTransform(free_, distance_, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  }
  // Distance (m) from the centre of DEM cell (r, c) to the nearest point.
  double DistanceToCentre(int r, int c) const {
    return fine_ * distance_.at<float>(FineRow(r), FineCol(c));
  }
  // Whether the points within cell_m of the nearest one lie all around the centre (no gap
  // over 180 degrees among them).
  bool CentreSurrounded(int r, int c, double cell_m) const {
    const int fr = FineRow(r), fc = FineCol(c);
    const double within = (DistanceToCentre(r, c) + cell_m) / fine_;  // fine cells
    const int reach = static_cast<int>(std::ceil(within));
    std::vector<double> angles;
    for (int rr = std::max(0, fr - reach); rr <= std::min(free_.rows - 1, fr + reach); ++rr)
      for (int cc = std::max(0, fc - reach); cc <= std::min(free_.cols - 1, fc + reach); ++cc) {
        // The fine cell (fr, fc)'s centre is half a fine cell off the DEM cell's (kRatio is even).
        const double up = fr - rr - 0.5, east = cc - fc + 0.5;
        // Within the circle: the square's corners would reach the far tread past a riser
        // (beside a cell centre past the lip, 2 m off) and close the gap the lip leaves.
        if (!free_.at<uint8_t>(rr, cc) && std::hypot(up, east) <= within)
          angles.push_back(std::atan2(up, east));
      }
    return LargestAngularGap(std::move(angles)) <= M_PI;
  }

 private:
  static constexpr int kRatio = 4;
  int FineRow(int r) const { return r * kRatio + kRatio / 2 + margin_; }
  int FineCol(int c) const { return c * kRatio + kRatio / 2 + margin_; }
  double fine_;
  int margin_;
  cv::Mat free_;      // 0 where a point lies
  cv::Mat distance_;  // fine cells to the nearest point
};

// Ground points per DEM cell.
std::vector<int> PointsPerCell(const KrigingPoints& ground, const Raster& dem) {
  std::vector<int> count(dem.values.size(), 0);
  int r = 0, c = 0;
  for (const Eigen::Vector3d& p : ground.All())
    if (dem.CellOf(p.x(), p.y(), &r, &c)) ++count[static_cast<size_t>(r) * dem.cols + c];
  return count;
}

// How much the slope of the seen cells within a window changes: the range of their gradients,
// east and north, combined. Kriging's linear drift carries a cell's slope on into ground nobody
// saw; the hidden ground can turn by as much as the seen ground turns. A cell d metres from
// the nearest point is carried on over d, so the window is d wide where d exceeds window_m:
// over a longer reach the ground turns more, and the seen ground within window_m of a cell far
// out is none (its room would be nothing). One map per window size, made as asked for.
class SeenTurns {
 public:
  SeenTurns(const Raster& dem, const std::vector<int>& count, double window_m)
      : cell_m_(dem.cell_m), window_m_(window_m) {
    constexpr float kNone = std::numeric_limits<float>::infinity();
    east_hi_ = cv::Mat(dem.rows, dem.cols, CV_32F, cv::Scalar(-kNone));
    east_lo_ = cv::Mat(east_hi_.size(), CV_32F, cv::Scalar(kNone));
    north_hi_ = east_hi_.clone(), north_lo_ = east_lo_.clone();
    for (int r = 0; r < dem.rows; ++r)
      for (int c = 0; c < dem.cols; ++c) {
        if (count[static_cast<size_t>(r) * dem.cols + c] == 0 || Raster::IsNoData(dem.at(r, c)))
          continue;
        const Eigen::Vector2d g = GradientAt(dem, r, c);
        east_hi_.at<float>(r, c) = east_lo_.at<float>(r, c) = static_cast<float>(g.x());
        north_hi_.at<float>(r, c) = north_lo_.at<float>(r, c) = static_cast<float>(g.y());
      }
  }
  // The turn around cell (r, c) for ground carried on over distance_m.
  double At(int r, int c, double distance_m) {
    const int half = static_cast<int>(std::lround(std::max(window_m_, distance_m) / cell_m_));
    auto [it, made] = maps_.try_emplace(half);
    if (made) it->second = Within(half);
    return it->second.at<float>(r, c);
  }

 private:
  cv::Mat Within(int half) const {
    const cv::Mat window =
        cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * half + 1, 2 * half + 1));
    cv::Mat east_hi, east_lo, north_hi, north_lo;
    cv::dilate(east_hi_, east_hi, window), cv::dilate(north_hi_, north_hi, window);
    cv::erode(east_lo_, east_lo, window), cv::erode(north_lo_, north_lo, window);
    cv::Mat change(east_hi.size(), CV_32F, cv::Scalar(0));
    for (int r = 0; r < change.rows; ++r)
      for (int c = 0; c < change.cols; ++c) {
        const float de = east_hi.at<float>(r, c) - east_lo.at<float>(r, c);
        const float dn = north_hi.at<float>(r, c) - north_lo.at<float>(r, c);
        if (std::isfinite(de) && std::isfinite(dn)) change.at<float>(r, c) = std::hypot(de, dn);
      }
    return change;
  }
  double cell_m_, window_m_;
  cv::Mat east_hi_, east_lo_, north_hi_, north_lo_;  // the seen cells' gradients
  std::map<int, cv::Mat> maps_;                      // by the window's half size in cells
};

// The std of ground nobody saw under the lines of sight. Behind a brow, the lowest line over
// it grazes the brow and lands on the first ground seen past the hidden stretch (a terrace's
// lower tread, a gully's far wall): the ground there plausibly lies no lower than that
// landing, and kriging has bridged it from the brow. The std is the RMS distance from the DEM
// to ground anywhere in the room below it down to the landing ((v - landing) / sqrt(3)); the
// room above is the seen slopes' turn.
double ShadowStd(double value, const SightLineCeilings* sight, int r, int c) {
  if (!sight || sight->landing_per_cell.values.empty()) return 0.0;
  const float landing = sight->landing_per_cell.at(r, c);
  if (Raster::IsNoData(landing)) return 0.0;
  return std::max(0.0, value - landing) / std::sqrt(3.0);
}

// How steeply the ground this station saw falls: the seen cells' slope at the quantile.
double SteepSeenSlope(const Raster& dem, const std::vector<int>& count, double quantile) {
  std::vector<double> slopes;
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c)
      if (count[static_cast<size_t>(r) * dem.cols + c] > 0 && !Raster::IsNoData(dem.at(r, c)))
        slopes.push_back(GradientAt(dem, r, c).norm());
  return QuantileInPlace(&slopes, quantile);
}

// The std of ground no line of sight passed over (none where one did, or where the lines are
// not known): anywhere from the DEM down the steep slope over the distance, whose RMS distance
// from the DEM is the slope times the distance over sqrt(3).
double UnboundedStd(double steep_slope, double distance_m, const SightLineCeilings* sight, int r,
                    int c) {
  if (!sight || sight->per_cell.values.empty() || !Raster::IsNoData(sight->per_cell.at(r, c)))
    return 0.0;
  return steep_slope * distance_m / std::sqrt(3.0);
}

}  // namespace

GroundEstimate EstimateEveryCell(const KrigingPoints& ground, const Raster& dem,
                                 const Raster& std_dev, const SightLineCeilings* sight,
                                 const Raster* horizon, const GroundRoomOptions& o) {
  GroundEstimate out{dem, std_dev, std::vector<CellGround>(dem.values.size(), CellGround::kSeen)};
  const std::vector<int> count = PointsPerCell(ground, dem);
  // The nearest cell with data, and how far it is.
  cv::Mat no_data(dem.rows, dem.cols, CV_8U);
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c)
      no_data.at<uint8_t>(r, c) = Raster::IsNoData(dem.at(r, c)) ? 255 : 0;
  if (static_cast<size_t>(cv::countNonZero(no_data)) == no_data.total())
    return out;  // nothing to start from
  cv::Mat distance, label;
  cv::distanceTransform(no_data, distance, label, cv::DIST_L2, cv::DIST_MASK_5,
                        cv::DIST_LABEL_PIXEL);
  std::vector<cv::Point> cell_of_label(dem.values.size() + 1);
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c)
      if (!no_data.at<uint8_t>(r, c)) cell_of_label[label.at<int>(r, c)] = {c, r};
  SeenTurns turns(dem, count, o.slope_window_m);
  const FinePoints fine_points(ground, dem, o.slope_window_m);
  const double steep = SteepSeenSlope(dem, count, o.steep_slope_quantile);
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c) {
      const size_t cell = static_cast<size_t>(r) * dem.cols + c;
      if (!no_data.at<uint8_t>(r, c)) {
        out.kind[cell] = count[cell] > 0 ? CellGround::kSeen : CellGround::kUnseen;
        continue;
      }
      out.kind[cell] = CellGround::kEstimated;
      // The nearest cell's slope carried on, as kriging's drift carries it into the cells it
      // reaches; the room is for the turn it may take.
      const cv::Point from = cell_of_label[label.at<int>(r, c)];
      const Eigen::Vector2d slope = GradientAt(dem, from.y, from.x);
      double z =
          dem.at(from.y, from.x) + slope.dot(Eigen::Vector2d(c - from.x, from.y - r)) * dem.cell_m;
      if (sight && !Raster::IsNoData(sight->per_cell.at(r, c)))
        z = std::min(z, double(sight->per_cell.at(r, c)));
      else if (horizon && !Raster::IsNoData(horizon->at(r, c)))
        z = std::min(z, double(horizon->at(r, c)));
      // The std of the nearest cell has its own room; this adds the turn over the step from it,
      // where the ground has turned as the seen ground does over the whole reach from the points.
      const float s0 = std_dev.at(from.y, from.x);
      const double step_m = distance.at<float>(r, c) * dem.cell_m;
      const double reach_m = step_m + fine_points.DistanceToCentre(from.y, from.x);
      const double room =
          std::max({0.5 * turns.At(from.y, from.x, reach_m) * step_m, ShadowStd(z, sight, r, c),
                    UnboundedStd(steep, step_m, sight, r, c)});
      out.height.at(r, c) = static_cast<float>(z);
      out.std.at(r, c) = static_cast<float>(std::hypot(Raster::IsNoData(s0) ? 0.0 : s0, room));
    }
  return out;
}

GroundRoomResult WidenStdByGroundRoom(const KrigingPoints& ground, const Raster& dem,
                                      const SightLineCeilings* sight, const GroundRoomOptions& o,
                                      Raster* std_dev) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("GroundRoomOptions: " + why);
  if (std_dev->rows != dem.rows || std_dev->cols != dem.cols)
    throw std::invalid_argument("WidenStdByGroundRoom: the std grid differs from the DEM's");
  if (!ground.height_variances_m2.empty() &&
      ground.height_variances_m2.size() != ground.positions.size())
    throw std::invalid_argument("WidenStdByGroundRoom: one height variance per point or none");
  GroundRoomResult result;
  if (!o.enabled) return result;
  // The ground's departure from the DEM's surface in each cell, less the points' own noise. The
  // surface is the cubic one through the cell centres: on curved ground the bilinear one cuts
  // chords below the crests and above the hollows, and the points' departure from those chords
  // says nothing about the centres' heights.
  std::vector<double> departure2(dem.values.size(), 0.0), noise2(dem.values.size(), 0.0);
  const std::vector<int> count = PointsPerCell(ground, dem);
  for (size_t i = 0; i < ground.positions.size(); ++i) {
    const Eigen::Vector3d& p = ground.positions[i];
    int r = 0, c = 0;
    if (!dem.CellOf(p.x(), p.y(), &r, &c)) continue;
    const size_t cell = static_cast<size_t>(r) * dem.cols + c;
    const double surface = dem.InterpolateCubic(p.x(), p.y());
    if (!std::isfinite(surface)) continue;
    departure2[cell] += (p.z() - surface) * (p.z() - surface);
    if (!ground.height_variances_m2.empty()) noise2[cell] += ground.height_variances_m2[i];
  }
  SeenTurns turns(dem, count, o.slope_window_m);
  const FinePoints fine_points(ground, dem, o.slope_window_m);
  const double steep = SteepSeenSlope(dem, count, o.steep_slope_quantile);
  std::vector<double> widening, departures;
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c) {
      float& s = std_dev->at(r, c);
      if (Raster::IsNoData(dem.at(r, c)) || Raster::IsNoData(s)) continue;
      const size_t cell = static_cast<size_t>(r) * dem.cols + c;
      // The centre of a cell seen at one corner is as unseen as ground that far from a point:
      // it gets the turn's room and, behind a brow, the room below (a terrace's lip seen in the
      // cell, its lower tread at the centre). Ground with points all around the centre shows
      // its own turns: in the points' departure from the DEM here, and in kriging's sigma.
      double room = 0.0;
      if (count[cell] == 0 || !fine_points.CentreSurrounded(r, c, dem.cell_m)) {
        const double reach_m = fine_points.DistanceToCentre(r, c);
        room =
            std::max({0.5 * turns.At(r, c, reach_m) * reach_m, ShadowStd(dem.at(r, c), sight, r, c),
                      UnboundedStd(steep, reach_m, sight, r, c)});
      }
      double departure = 0.0;
      if (count[cell] > 0) {
        ++result.seen_cells;
        departure = std::sqrt(std::max(0.0, (departure2[cell] - noise2[cell]) / count[cell]));
        departures.push_back(departure);
      } else {
        ++result.unseen_cells;
        widening.push_back(room);
      }
      s = static_cast<float>(std::sqrt(double(s) * s + departure * departure + room * room));
    }
  result.median_unseen_widening_m = Median(widening);
  result.median_seen_departure_m = Median(departures);
  return result;
}

}  // namespace ts
