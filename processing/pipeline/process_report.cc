#include "processing/pipeline/process_report.h"

#include <sys/resource.h>

#include <cmath>

#include "core/version.h"
#include "processing/dem/variogram.h"
#include "processing/geometry/theoretical_accuracy.h"

namespace ts {
namespace {

double PeakMemoryMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // kB on Linux
}

// Every step's counts in one object (the per-pair table apart).
nlohmann::json Counts(const ProcessSummary& summary) {
  nlohmann::json counts = nlohmann::json::object();
  for (const StepSummary& s : summary.steps)
    for (const auto& [key, value] : s.counts.items())
      if (key != "per_pair") counts[key] = value;
  return counts;
}

nlohmann::json AccuracyTable(const Calibration& calibration) {
  nlohmann::json accuracy = nlohmann::json::array();
  for (const AccuracyRow& row :
       TheoreticalAccuracy(calibration.rig.baseline_m, calibration.rig.left.principal_distance_px,
                           TheoreticalAccuracyOptions{}))
    accuracy.push_back({{"range_m", row.range_m},
                        {"sigma_x_m", row.sigma_x_m},
                        {"sigma_y_m", row.sigma_y_m},
                        {"sigma_z_m", row.sigma_z_m}});
  return accuracy;
}

}  // namespace

nlohmann::json BuildProcessReport(const ProcessOptions& o, const StationWork& w,
                                  const ProcessSummary& summary, double wall_s) {
  const StationInputs& in = *w.inputs;
  nlohmann::json report;
  report["station"] = in.manifest.station_id;
  report["software"] = {{"name", "topostation"}, {"version", SoftwareVersion()}};
  // The station frame's datums, which no panorama shows: the pan zero its azimuth, the tilt
  // axis's height over L's origin the height of that origin under the taped tilt axis.
  report["calibration"] = {{"source", in.calibration_source},
                           {"sha256", in.calibration_sha256},
                           {"pan_zero_deg", in.calibration.stage.pan_zero_deg},
                           {"tilt_axis_height_m", in.calibration.stage.tilt_axis_offset_m.z()}};
  if (!w.rig_check.is_null()) report["rig"] = w.rig_check;
  report["frame"] = in.georeference ? "projected CRS (GCPs)" : "station frame L";
  report["station_mark"] = {w.mark_dem.x(), w.mark_dem.y(), w.mark_dem.z()};
  const TerrainCorrection& tc = w.terrain_correction;
  report["terrain_correction_mgal"] = tc.Usable() ? nlohmann::json(tc.total_mgal) : nullptr;
  report["terrain_correction_sigma_mgal"] = tc.Usable() ? nlohmann::json(tc.sigma_mgal) : nullptr;
  report["verdict"] = tc.Usable() ? "usable" : "unusable";
  if (!tc.Usable()) report["unusable_because"] = tc.unusable_because;
  report["timings_s"] = summary.TimingsJson();
  if (nlohmann::json capture = CaptureTimelineJson(in.manifest.pairs); !capture.is_null())
    report["capture_timeline"] = capture;
  report["wall_s"] = wall_s;
  report["peak_memory_mib"] = PeakMemoryMiB();
  report["counts"] = Counts(summary);
  if (const StepSummary* matching = summary.Find("matching"))
    report["pairs"] = matching->counts.value("per_pair", nlohmann::json::array());
  const VariogramModel& model = w.kriged.model;
  report["variogram"] = {{"model", VariogramKindName(model.kind)},
                         {"nugget_m2", model.nugget},
                         {"partial_sill_m2", model.partial_sill},
                         {"range_m", model.range_m},
                         {"median_held_out_signal_scale", w.kriged.median_signal_scale}};
  for (const KrigingResult::KindTried& k : w.kriged.cross_validation) {
    report["variogram"]["cross_validation_rms_m"][VariogramKindName(k.model.kind)] =
        k.cross_validation_rms_m;
    report["variogram"]["cross_validation_log_score"][VariogramKindName(k.model.kind)] =
        k.cross_validation_log_score;
  }
  report["dem"] = {{"cell_m", o.dem_cell_m},
                   {"cells", w.kriged.dem.cols * w.kriged.dem.rows},
                   {"coverage_30m", w.coverage_30m},
                   {"coverage_square", w.coverage_square}};
  if (in.georeference) {
    const Georeference& g = *in.georeference;
    report["georeference"] = {{"scale", g.scale},
                              {"rotation_deg", g.rotation_rad * 180.0 / M_PI},
                              {"height_offset_m", g.height_offset_m},
                              {"gcp_residuals_m", g.residuals_m}};
  }
  report["theoretical_accuracy"] = AccuracyTable(in.calibration);
  report["options"] = ProcessOptionsToJson(o);
  report["warnings"] = summary.Warnings();
  return report;
}

}  // namespace ts
