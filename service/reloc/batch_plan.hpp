// The plan of `polyloc relocalize` (docs/relocalize.md): recordings, each whole or split into
// time segments of `segment_s` with a warm-up of `warmup_s` before each segment but the first.
// Every process plans alike from the same options, so MPI ranks agree on task numbers without
// talking; which rank runs which task is `assignTasks`.
#pragma once

#include "reloc/recording_job.hpp"
#include "reloc/report.hpp"

#include <string>
#include <vector>

namespace polyloc::reloc {

struct BatchOptions {
  std::vector<std::string> inputs;
  std::string out_dir;
  bool global = false;       // global localisation in every task; else the start rules of localize
  int jobs = 1;              // recordings (tasks) run side by side in this process
  int threads = 0;           // TBB arena of this process; 0 = jobs
  double segment_s = 0;      // > 0: split recordings longer than this into segments of this length
  double warmup_s = 5;       // a segment's filter starts this long before its own span
  CsvCovariance covariance = CsvCovariance::Diagonal;
  JobOptions base;           // sensors, init sigma, plot particles: copied into every task
};

struct Task {
  size_t input = 0;          // index into BatchOptions::inputs
  size_t segment = 0, segments = 1;
  double weight = 0;         // the order of work: seconds read (segments) or file bytes
  JobOptions job;
};

struct Plan {
  std::vector<Task> tasks;
  std::vector<std::string> names;         // per input: the folder under out_dir
  std::vector<std::string> input_errors;  // per input: why it could not be planned ("" = fine)
};

// Opens the inputs only to split them (segment_s > 0); an input that cannot be opened then
// gets an input_error and no task; otherwise a bad input fails in its task.
Plan planBatch(const BatchOptions& options);

// The tasks of `rank` out of `ranks`: longest first, dealt round robin.
std::vector<size_t> assignTasks(const Plan& plan, int rank, int ranks);

}  // namespace polyloc::reloc
