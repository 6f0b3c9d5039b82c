// How a localisation run is reported (`polyloc localize`, `polyloc relocalize`;
// docs/localization.md, docs/relocalize.md): trajectory metrics as JSON (NaN -> null), the
// summary object of one recording, the per-frame CSV, the TUM trajectory and the PNG.
#pragma once

#include "reloc/recording_job.hpp"

#include <polyloc/eval/trajectory_metrics.hpp>

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace polyloc::reloc {

nlohmann::json num(double x);  // null when not finite
nlohmann::json summaryJson(const ErrorSummary& s);

// Which covariance entries the CSV carries: none, the diagonal (var_x ... var_yaw) or the upper
// triangle of the 6x6 (cov_00 ... cov_55; x y z roll pitch yaw, m and rad).
enum class CsvCovariance { None, Diagonal, Full };

// One line per kept frame: stamp, pose, status, then (with metrics, per evaluated frame) ground
// truth and errors, then covariance, ESS and particle count. Throws std::runtime_error naming
// the file when it cannot be written.
void writeCsv(const std::string& path, const TrajectoryMetrics* metrics, const std::vector<FrameRecord>& frames,
              CsvCovariance cov = CsvCovariance::Diagonal);
void writeTum(const std::string& path, const std::vector<FrameRecord>& frames);  // throws IoError

// Accuracy against the result's ground truth (nullopt without any), from the filter's start.
std::optional<TrajectoryMetrics> evaluate(const JobResult& r);

// The JSON summary of one run: the keys of `polyloc localize --json` that come from the run
// (input, format, init, frames, updates, updates_per_s, wall_s, filter_s, particles, status,
// counters and, with metrics, ground_truth and the accuracy keys).
nlohmann::json resultJson(const JobResult& r, const TrajectoryMetrics* metrics);

// Map, ground truth, estimate and clouds as PNG; the title names the command, the input and the start.
void drawPlot(const Mesh& mesh, const JobResult& r, const TrajectoryMetrics* metrics, const std::string& png_path,
              const std::string& command = "polyloc localize");

}  // namespace polyloc::reloc
