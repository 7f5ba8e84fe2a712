// Slurm job arrays for sweeps (docs/commands/sweep.md, "Slurm"). `mavloc sweep ... --slurm --out
// DIR` writes into DIR (a folder on the file system the cluster's nodes share):
//   grid.json      the canonical grid (evaluation/sweep/sweep_grid.h)
//   sweep.sbatch   a job array, one task per shard: task I runs
//                  `mavloc sweep --grid-file DIR/grid.json --shard I/N --jobs $SLURM_CPUS_PER_TASK
//                  --out DIR/partials`; resources (--time, --mem, --cpus-per-task, --partition,
//                  --account) from the options; setup lines (`module load ...`) before it
//   merge.sbatch   `mavloc sweep-merge DIR/partials --out DIR/report`
//   logs/          one log per task (shard-I-jobJ.out) and per merge job
//   slurm.json     the submitted job ids (array, merge, and every resubmission)
// and submits both with sbatch (sbatch(1) --parsable prints "jobid[;cluster]"): the array first,
// then the merge with --dependency=afterok:<array job id>. `mavloc sweep-status DIR` lists each
// shard's state (complete partial, or its Slurm state from squeue/sacct when those know it) and
// with
// --resubmit submits only the shards without a complete partial (sbatch --array=3,7 sweep.sbatch)
// plus a new merge job after them (the old one, waiting on a failed array, is cancelled).
// The sbatch/squeue/sacct/scancel commands can be overridden by MAVLOC_SBATCH etc. (tests).
#pragma once

#include <string>
#include <vector>

#include "evaluation/sweep/sweep_grid.h"

namespace mavloc {

struct SlurmOptions {
  std::string results_dir;        // made absolute
  int shards = 1;                 // array tasks
  std::string time = "01:00:00";  // per task, sbatch --time
  std::string mem;                // per task, sbatch --mem (e.g. 4G); empty: the cluster default
  int cpus_per_task = 1;          // also the --jobs of each task
  std::string partition, account;
  std::vector<std::string> setup_lines;  // shell lines before mavloc runs (module load ...)
  std::string mavloc_path;               // absolute; default: this executable
  // Where the files are written when not results_dir itself: the staging folder the CLI puts in
  // results_dir's place afterwards (cli/output_folder.h). The scripts name results_dir.
  std::string write_dir;
};

// Throws InputError naming the option (--time, --mem, --partition, --account, --setup, --out)
// whose value would not be one #SBATCH or shell line of the scripts: a newline or another control
// character (which would inject lines), or a value that is not in Slurm's format (--time
// MINUTES, MM:SS, HH:MM:SS, D-HH, D-HH:MM, D-HH:MM:SS or UNLIMITED; --mem a whole number with an
// optional K, M, G or T; --partition and --account names of letters, digits, '_', '-', '.').
void CheckSlurmOptions(const SlurmOptions& options);

struct SlurmFiles {
  std::string array_script, merge_script;
};

// Writes grid.json, sweep.sbatch, merge.sbatch, slurm.json (slurm.json and sweep.sbatch mark the
// folder as a Slurm results folder, which a later `--slurm --out` into it may replace, a report
// command not: cli/output_folder.h), README.md (what the folder is and where the merged report will
// be) and the partials/ and logs/ folders. Checks the options
// first (CheckSlurmOptions).
SlurmFiles WriteSlurmFiles(const SweepGrid& grid, const SlurmOptions& options);

struct SlurmSubmission {
  std::string array_job_id, merge_job_id;
};

// Submits the array (all tasks, or only `tasks` when not empty) and the merge job after it;
// records the ids in results_dir/slurm.json. Throws InputError when sbatch fails (its message).
SlurmSubmission SubmitSlurm(const std::string& results_dir, const std::vector<int>& tasks);

struct ShardStatus {
  int shard = 0;
  bool complete = false;    // a complete partial exists
  std::string job_id;       // array task id "A_I" of the latest submission that ran it
  std::string slurm_state;  // from squeue/sacct; empty when unknown
};

struct SweepStatus {
  int shards = 0;
  std::vector<ShardStatus> shard_states;
  std::string merge_job_id;
  std::string note;  // e.g. "sacct unavailable (no accounting storage)"
};

SweepStatus ReadSweepStatus(const std::string& results_dir);

}  // namespace mavloc
