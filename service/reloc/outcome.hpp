// The outcome of one task of `polyloc relocalize` (a recording, or one time segment of it) and
// its byte form, in which MPI ranks send their outcomes to rank 0 (CBOR: doubles exact).
#pragma once

#include "reloc/recording_job.hpp"

#include <string>
#include <vector>

namespace polyloc::reloc {

struct TaskOutcome {
  size_t task = 0;     // index into the plan (the same on every rank)
  int rank = 0;        // which process ran it
  bool ok = false;
  std::string error;   // when !ok: what went wrong
  std::vector<std::string> log;  // the job's notes and warnings
  JobResult result;    // when ok
};

std::string encodeOutcomes(const std::vector<TaskOutcome>& outcomes);
// Throws std::runtime_error when the bytes are not what encodeOutcomes wrote.
std::vector<TaskOutcome> decodeOutcomes(const std::string& bytes);

}  // namespace polyloc::reloc
