#pragma once
// Kriging of ground points onto a raster grid (seed 003: "a DEM is generated using Kriging
// interpolation"): for every cell centre, the nearest points in each quadrant (a local,
// balanced neighbourhood) and the kriging system in covariance form
//   [C + nugget I  F; F' 0] [lambda; mu] = [c_0; f_0],   z = lambda' z_i,
//   sigma^2 = C(0) - lambda' c_0 - mu' f_0
// with F = [1 x_i y_i] (universal kriging, a local linear drift, coordinates relative to the
// cell centre so f_0 = [1 0 0]) or F = [1] (ordinary kriging), C the covariance of the noise-free
// surface (VariogramModel::SignalCovariance). The nugget is the points' own noise: it weighs the
// data but is not predicted ("filtered" kriging), so the DEM estimates the surface, not another
// noisy point, and sigma is the standard deviation of that estimate. Without a nugget this is the
// exact interpolator. Cells farther than max_distance_m from any point are nodata: the DEM says
// where it was not seen instead of inventing terrain. Dense clouds are thinned first to the mean
// point of each thin_cell_m square (the variogram and the neighbourhood then see the terrain,
// not the sampling).
// The variogram's kind is the one whose fit best predicts ground held out of the points in
// blocks (BlockCrossValidationScores), its height and its std alike: the lowest mean of
// e^2 / v + ln v over the held-out points (e the error, v the predicted variance of the point:
// kriging's plus the point's own noise), the log score of a Gaussian forecast. The kinds' fits
// to the variogram's bins differ most in how they bridge gaps, which the bins do not show. The
// squared error alone cannot tell kinds apart where the points' noise dominates it (flat
// ground: every kind within 0.1 % of 6.8 mm), and there chose a spherical or exponential fit,
// linear at the origin, whose std of seen cells was 3-4 times their error; the score also asks
// whether the std each kind claims is the error it makes.
// Points may carry their own height variance (from the intersection's covariance): a point's
// nugget is then the larger of the fitted nugget and its own variance, so a few noisy far points
// weigh less and the sigma of the cells they alone support says so. The fitted nugget is what
// the dense, near points show; it is over-confident for the sparse, far ones.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/options.h"
#include "processing/dem/shared_noise.h"
#include "processing/dem/variogram.h"
#include "processing/io/raster.h"

namespace ts {

struct KrigingOptions {
  int neighbours = 16;            // at most, a quarter per quadrant where the points allow
  double search_radius_m = 15.0;  // no neighbour farther than this
  // Nodata where the nearest point is farther: a trade of coverage behind brows against the
  // error of cells reached from afar; the kriging std of each cell says how far it reached.
  // (`process` reaches farther in the shadows of objects:
  // HorizonLimitOptions::object_shadow_reach_m.)
  double max_distance_m = 5.5;
  double thin_cell_m = 0.25;  // 0: no thinning
  // Universal kriging with a local linear drift (x, y in the unbiasedness constraints) instead
  // of ordinary kriging: on sloping ground ordinary kriging pulls every cell to its
  // neighbours' mean, so a slope comes out terraced.
  bool linear_drift = true;
  // Neighbours for a cell beyond the edge of the data (all its neighbours on one side), where the
  // drift is extrapolated and a few metres of neighbours would decide its slope; more of them
  // steady it (the last metre before an occlusion shadow often slopes: tree bases, canopy
  // edges). No more than `neighbours` turns this off.
  int extrapolation_neighbours = 64;
  // The variogram's kind is chosen by how well each predicts the ground in blocks this wide,
  // held out of the points, from the rest (0 blocks: the best fit to the variogram's bins).
  double cross_validation_block_m = 2.0;
  int cross_validation_blocks = 60;
  // The variogram of the surface: each pair's own noise variances taken out (variogram.h).
  bool signal_variogram = true;
  // Kriging's std is rescaled by how well the model predicted the points held out within this
  // of a cell (RescaleStdByHeldOutPoints; 0: not).
  double held_out_window_m = 5.0;
  VariogramOptions variogram;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("neighbours", self.neighbours, {"kriging neighbours of a cell, at most", "", 1, 64});
    v("search_radius_m", self.search_radius_m, {"no neighbour farther than this", "m", 0.1, 200});
    v("max_distance_m", self.max_distance_m,
      {"nodata where the nearest ground point is farther", "m", 0.1, 50});
    v("thin_cell_m", self.thin_cell_m,
      {"ground thinned to one mean point per square this wide (0: none)", "m", 0, 10});
    v("linear_drift", self.linear_drift, {"universal kriging with a local linear drift", "", 0, 1});
    v("extrapolation_neighbours", self.extrapolation_neighbours,
      {"neighbours of a cell beyond the edge of the data", "", 0, 256});
    v("cross_validation_block_m", self.cross_validation_block_m,
      {"the variogram's kind is chosen by predicting held-out blocks this wide", "m", 0.25, 50});
    v("cross_validation_blocks", self.cross_validation_blocks,
      {"blocks held out to choose the variogram's kind (0: its best fit)", "", 0, 10000});
    v("signal_variogram", self.signal_variogram,
      {"the variogram less the points' own noise variances", "", 0, 1});
    v("held_out_window_m", self.held_out_window_m,
      {"kriging's std is scaled by its held-out errors within this of a cell (0: not)", "m", 0,
       100});
    v.Group("variogram", self.variogram);
  }
  bool Check(std::string* why) const;
};

struct KrigingResult {
  Raster dem;  // the grid given, filled
  Raster std;  // kriging standard deviation (m), same grid
  VariogramModel model;
  ExperimentalVariogram experimental;
  size_t points_used = 0;  // after thinning
  // The median over the cells of the factor on the surface's variance that held-out points
  // near them asked for (RescaleStdByHeldOutPoints); 1 where none was applied.
  double median_signal_scale = 1.0;
  struct KindTried {
    VariogramModel model;
    double cross_validation_rms_m = 0.0;
    double cross_validation_log_score = 0.0;
  };
  // Each kind fitted, and how well it predicted held-out blocks; empty where too few points
  // could be held out (the best fit to the bins is the model).
  std::vector<KindTried> cross_validation;
};

// Points to krige; height_variances_m2 is empty (all alike: the fitted nugget) or one per point.
// Surveyed points (the station mark: its height is the instrument height, taped) are known
// exactly: kriged without a nugget, never thinned, and not in the variogram, which is the
// matched ground's.
struct KrigingPoints {
  std::vector<Eigen::Vector3d> positions;
  std::vector<double> height_variances_m2;
  std::vector<Eigen::Vector3d> surveyed;
  // Empty (errors independent) or one per position: kriging's std adds what the weights of
  // points whose errors correlate (SharedNoiseCorrelation) do not average away.
  std::vector<PointMatch> matches = {};
  // The matched and the surveyed points in one list.
  std::vector<Eigen::Vector3d> All() const;
};

// Thins the points to one mean point per thin_cell_m square. The mean's variance is that of
// the members' mean with their shared noise (SharedNoiseCorrelation): a far square's points
// were matched in windows that overlap (a far window's footprint runs a metre or more along the
// ground), so their errors are nearly one error, which averaging does not shrink; a near
// square holds windows of their own. Without matches, all are taken as one error (the members'
// mean variance). The mean's match is the mean window of the members of the pair most of them
// came from.
KrigingPoints ThinPoints(const KrigingPoints& points, double cell_m);

// Fits the variogram to the (thinned) points and krige onto `grid` (its geometry is used;
// its values are overwritten).
KrigingResult KrigeDem(const KrigingPoints& points, const Raster& grid,
                       const KrigingOptions& options);

// For each model, how well it predicts the points in a seeded random choice of blocks (squares
// cross_validation_block_m wide) from the points outside them: how well it bridges gaps of that
// size. The same points for every model; NaN when fewer than four blocks have points.
struct CrossValidationScore {
  double rms_m = 0.0;                // RMS error
  double log_score = 0.0;            // mean of e^2 / v + ln v (v in m^2): lower is better
  std::vector<double> point_scores;  // e^2 / v + ln v of each predicted point, alike for all
};
std::vector<CrossValidationScore> BlockCrossValidationScores(
    const KrigingPoints& points, const std::vector<VariogramModel>& models,
    const KrigingOptions& options);

// The kind to krige with: the best fit to the variogram's bins (`fallback`), unless another
// kind's held-out log score is lower by more than twice the standard error of the paired
// difference over the predicted points. The scores of a few hundred points are noisy; a kind
// chosen on noise flips between two surveys of one site.
size_t ChooseKind(const std::vector<CrossValidationScore>& scores, size_t fallback);

// One variogram serves the whole square, and its sill is set by the square's roughest ground:
// a road's batters, a riser, a gully. Over the smooth fields beside them kriging's std was two
// to seven times the error it made (the simulated embankment: 1.0 mm against 7.2 mm). The
// points say how rough the ground is near each place: in each cell with data, the matched
// point nearest its centre is held out and predicted from the rest. Within held_out_window_m
// of a cell, the factor f on the surface's part of the variance is the one that makes those
// errors Gaussian with the variance claimed (the median of e^2 / (f s + n) is a chi-square's
// with one degree of freedom; s the surface's part, n the noise's, which is measured and stays).
// Measured is the points' own variance: where the fitted nugget floors it, the floor's excess
// is scatter the model assumes, as it assumes the surface's, and f scales it with s (embankment
// seed 5: a nugget of (14 mm)^2 held the std of the fields within 20 m at a median
// 8.7 mm over errors of 0.7 mm; 4.9 mm now). What neighbours' windows share stays at the floor:
// the test cannot see it (below), and without it rough seed 1's std falls short (RMS err/std 1.6).
// The DEM does not change, only its std, and only in cells holding a point: a held-out point
// tests kriging between points, not across a gap (ground nobody saw: ground_room.h). What the
// test cannot see are errors the neighbours share: a patch of points all matched wrong agrees
// with itself. `dem`: kriged on the points, with each cell's noise_variance. Returns the median
// factor over the cells scaled (1: none).
double RescaleStdByHeldOutPoints(const KrigingPoints& points, const VariogramModel& model,
                                 const KrigingOptions& options, const Raster& dem,
                                 const std::vector<double>& noise_variance, Raster* std);

// Kriging with a given model at given points (no thinning); nodata beyond max_distance_m.
// The two rasters are filled on `grid`'s geometry.
void KrigeOnto(const KrigingPoints& points, const VariogramModel& model,
               const KrigingOptions& options, Raster* dem, Raster* std);

}  // namespace ts
