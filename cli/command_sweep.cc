// mavloc sweep, sweep-merge, sweep-status: Monte-Carlo grids of scenarios x settings x
// seeds x estimators, run on all local cores, in shards merged exactly, or as a Slurm job array.
// The engine is evaluation/sweep/ (grid, unit, runner, partials, report, Slurm files); this file
// only parses options. `sweep-worker` (hidden) serves units to the parallel runner.
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <stdexcept>

#include "cli/commands.h"
#include "cli/common.h"
#include "cli/option_checks.h"
#include "cli/output_folder.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/key_values.h"
#include "core/number_text.h"
#include "evaluation/report_figures.h"
#include "evaluation/sweep/slurm_submit.h"
#include "evaluation/sweep/sweep_grid.h"
#include "evaluation/sweep/sweep_partial.h"
#include "evaluation/sweep/sweep_report.h"
#include "evaluation/sweep/sweep_runner.h"
#include "evaluation/sweep/sweep_unit.h"

namespace fs = std::filesystem;

namespace mavloc::cli {

namespace {

SweepGrid ReadGridFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot read the grid file");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, 0, "", std::string("not JSON: ") + e.what());
  }
  return SweepGridFromJson(json, path);
}

SweepRunOptions RunOptions(int jobs) {
  SweepRunOptions options;
  options.jobs = jobs > 0 ? jobs : AvailableCores();
  options.worker_argv = {SelfPath(), "sweep-worker", "--grid", "{grid}"};
  return options;
}

void PrintStatus(const SweepStatus& status) {
  int complete = 0;
  std::vector<int> failed;
  for (const auto& s : status.shard_states) {
    complete += s.complete;
    std::printf("shard %d/%d: %s", s.shard, status.shards,
                s.complete ? "complete" : "no complete partial");
    if (!s.job_id.empty())
      std::printf(" (slurm job %s%s%s)", s.job_id.c_str(), s.slurm_state.empty() ? "" : ": ",
                  s.slurm_state.c_str());
    std::printf("\n");
    const bool live = s.slurm_state == "PENDING" || s.slurm_state == "RUNNING" ||
                      s.slurm_state == "CONFIGURING" || s.slurm_state == "COMPLETING";
    if (!s.complete && !live) failed.push_back(s.shard);
  }
  std::printf("%d of %d shards complete; merge job %s\n", complete, status.shards,
              status.merge_job_id.empty() ? "(none submitted)" : status.merge_job_id.c_str());
  if (!failed.empty()) {
    std::string list;
    for (const int f : failed) list += (list.empty() ? "" : ",") + std::to_string(f);
    std::printf("failed or never run: shards %s (resubmit with --resubmit: sbatch --array=%s)\n",
                list.c_str(), list.c_str());
  }
  if (!status.note.empty()) std::printf("note: %s\n", status.note.c_str());
}

}  // namespace

void RegisterSweep(CLI::App& app, int* exit_code) {
  // ---- sweep ----
  auto* command = app.add_subcommand(
      "sweep",
      "Monte-Carlo sweep: scenarios x --set values x seeds x estimators, on all cores (--jobs), "
      "as shard I/N (--shard, merged by sweep-merge) or as a Slurm job array (--slurm)");
  struct Args {
    std::string scenarios, seeds = "1", estimators, align = "none", grid_file, shard, out;
    std::vector<std::string> settings, options, setup;
    double duration_s = 0.0, max_dt_s = 0.02;
    int jobs = 0, shards = 0, cpus_per_task = 1;
    bool slurm = false, dry_run = false, force = false;
    std::string time = "01:00:00", mem, partition, account;
  };
  auto args = std::make_shared<Args>();
  command->add_option("--scenario,--scenarios", args->scenarios, "Scenario names, comma-separated");
  command->add_option("--seeds", args->seeds, "Seeds: 1..100, 1,5,9 or a mix")
      ->capture_default_str();
  command->add_option("--set", args->settings,
                      "Scenario setting axis key=a,b,c or key=LO..HI[:STEP] (repeatable)");
  command->add_option("--estimators", args->estimators, "Estimator names, comma-separated");
  command->add_option("--option", args->options,
                      "Estimator option estimator:key=value or key=value for all (repeatable)");
  command->add_option("--duration", args->duration_s, "Scenario duration in seconds")
      ->check(CLI::PositiveNumber);
  command->add_option("--align", args->align, "ATE alignment: none, se3, sim3 or posyaw")
      ->capture_default_str();
  command->add_option("--max-dt", args->max_dt_s, "Association tolerance in seconds")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command->add_option("--grid-file", args->grid_file,
                      "Read the grid from this JSON file (grid.json of a --slurm folder) instead "
                      "of the grid options");
  command->add_option("--jobs,-j", args->jobs, "Parallel runs (default: the number of cores)")
      ->check(CLI::PositiveNumber);
  command->add_option("--shard", args->shard,
                      "Run only shard I of N (units with index % N == I-1) and write "
                      "OUT/partial-I-of-N.json");
  command
      ->add_option("--out", args->out,
                   "Report folder; the partial folder with --shard; the results folder on the "
                   "shared file system with --slurm")
      ->check(OutputFolder())
      ->required();
  command->add_flag("--force", args->force,
                    "Replace an existing --out folder (a mavloc report, or with --slurm the "
                    "results folder of an earlier --slurm)");
  command->add_flag("--slurm", args->slurm, "Write and submit a Slurm job array + merge job");
  command->add_flag("--dry-run", args->dry_run, "With --slurm: write the scripts, submit nothing");
  command->add_option("--shards", args->shards, "With --slurm: array tasks (default: units/10)")
      ->check(CLI::PositiveNumber);
  command->add_option("--time", args->time, "With --slurm: time limit per task")
      ->capture_default_str();
  command->add_option("--mem", args->mem, "With --slurm: memory per task (e.g. 4G)");
  command
      ->add_option("--cpus-per-task", args->cpus_per_task,
                   "With --slurm: cores per task (its --jobs)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command->add_option("--partition", args->partition, "With --slurm: partition");
  command->add_option("--account", args->account, "With --slurm: account");
  command->add_option("--setup", args->setup,
                      "With --slurm: a shell line run before mavloc in each job, e.g. "
                      "'module load gcc' (repeatable)");
  command->callback([args, exit_code] {
    SweepGrid grid;
    if (!args->grid_file.empty()) {
      grid = ReadGridFile(args->grid_file);
    } else {
      grid.scenarios = SplitList(args->scenarios);
      grid.seeds = ParseSeedList(args->seeds, "--seeds");
      for (const auto& item : args->settings) {
        auto [key, values] = ParseSettingAxis(item);
        if (grid.settings.count(key)) throw InputError("--set " + key + ": given twice");
        grid.settings[key] = values;
      }
      grid.estimators = SplitList(args->estimators);
      grid.options = args->options;
      if (args->duration_s > 0) grid.duration_s = args->duration_s;
      grid.align = args->align;
      grid.max_dt_s = args->max_dt_s;
      ValidateSweepGrid(grid);
    }
    const size_t units = SweepUnitCount(grid);
    if (args->slurm) {
      if (!args->shard.empty()) throw InputError("--slurm and --shard: choose one");
      SlurmOptions options;
      options.results_dir = args->out;
      options.shards =
          args->shards > 0 ? args->shards : static_cast<int>(std::max<size_t>(1, (units + 9) / 10));
      if (static_cast<size_t>(options.shards) > units)
        throw InputError("--shards " + std::to_string(options.shards) + ": more shards than the " +
                         std::to_string(units) + " units");
      options.time = args->time;
      options.mem = args->mem;
      options.cpus_per_task = args->cpus_per_task;
      options.partition = args->partition;
      options.account = args->account;
      options.setup_lines = args->setup;
      CheckSlurmOptions(options);  // before the folder is touched
      // The results folder is written whole (cli/output_folder.h): a new or empty folder, or the
      // results folder of an earlier --slurm (slurm.json, sweep.sbatch), never another folder.
      StagedFolder results(args->out, FolderKind::kSlurmResults, args->force);
      options.write_dir = results.path();
      const SlurmFiles files = WriteSlurmFiles(grid, options);
      results.Commit();
      std::printf("sweep: %zu units in %d shards; wrote %s and %s\n", units, options.shards,
                  files.array_script.c_str(), files.merge_script.c_str());
      if (args->dry_run) {
        std::printf(
            "dry run: nothing submitted (submit with: sbatch %s; then sbatch "
            "--dependency=afterok:<array job id> %s)\n",
            files.array_script.c_str(), files.merge_script.c_str());
      } else {
        const SlurmSubmission submission = SubmitSlurm(options.results_dir, {});
        std::printf("submitted array job %s (%d tasks) and merge job %s (afterok:%s)\n",
                    submission.array_job_id.c_str(), options.shards,
                    submission.merge_job_id.c_str(), submission.array_job_id.c_str());
        std::printf("report when done: %s/report/; status: mavloc sweep-status %s\n",
                    fs::absolute(args->out).lexically_normal().c_str(),
                    fs::absolute(args->out).lexically_normal().c_str());
      }
      *exit_code = 0;
      return;
    }
    std::vector<size_t> indices;
    ShardSpec spec;
    if (!args->shard.empty()) {
      spec = ParseShardSpec(args->shard);
      indices = ShardUnitIndices(units, spec);
    } else {
      for (size_t k = 0; k < units; ++k) indices.push_back(k);
    }
    // The report folder is checked before any unit runs and written whole (cli/output_folder.h).
    std::optional<StagedFolder> report;
    if (args->shard.empty()) report.emplace(args->out, FolderKind::kReport, args->force);
    const std::vector<nlohmann::json> results =
        RunSweepUnits(grid, indices, RunOptions(args->jobs));
    if (!args->shard.empty()) {
      const std::string path = WritePartial(args->out, grid, spec, results);
      std::printf("sweep: shard %d/%d (%zu of %zu units) written to %s\n", spec.shard, spec.shards,
                  indices.size(), units, path.c_str());
    } else {
      std::vector<std::string> warnings;
      WriteSweepReport(report->path(),
                       BuildSweepReport(grid, SweepFingerprint(grid), results, &warnings));
      for (const std::string& warning : warnings)
        std::fprintf(stderr, "mavloc: warning: %s\n", PrintableMessage(warning).c_str());
      const FigureOutcome figures =
          WriteReportFigures(report->path(), report->ForUser(report->path()));
      report->Commit();
      std::printf(
          "sweep: %zu units; report written to %s/ (report.md, report.json, runs.csv)\n%s\n", units,
          args->out.c_str(), report->ForUser(DescribeFigureOutcome(figures)).c_str());
    }
    *exit_code = 0;
  });

  // ---- sweep-merge ----
  auto* merge = app.add_subcommand(
      "sweep-merge", "Merge the partials of `mavloc sweep --shard I/N` into the sweep report");
  auto merge_inputs = std::make_shared<std::vector<std::string>>();
  auto merge_out = std::make_shared<std::string>();
  merge->add_option("inputs", *merge_inputs, "Partial files and/or folders holding them")
      ->required();
  merge->add_option("--out", *merge_out, "Report folder (created)")
      ->check(OutputFolder())
      ->required();
  auto merge_force = std::make_shared<bool>(false);
  merge->add_flag("--force", *merge_force, "Replace an existing --out folder (a mavloc report)");
  merge->callback([merge_inputs, merge_out, merge_force, exit_code] {
    StagedFolder report(*merge_out, FolderKind::kReport,
                        *merge_force);  // checked first, written whole
    const MergedSweep merged = MergePartials(*merge_inputs);
    std::vector<std::string> warnings;
    WriteSweepReport(report.path(),
                     BuildSweepReport(merged.grid, merged.fingerprint, merged.units, &warnings));
    for (const std::string& warning : warnings)
      std::fprintf(stderr, "mavloc: warning: %s\n", PrintableMessage(warning).c_str());
    for (const SkippedFile& file : merged.skipped)
      std::fprintf(stderr, "mavloc: note: %s: not used: %s\n", PrintableMessage(file.path).c_str(),
                   file.reason.c_str());
    const FigureOutcome figures = WriteReportFigures(report.path(), report.ForUser(report.path()));
    report.Commit();
    std::printf(
        "sweep-merge: %zu units; report written to %s/ (report.md, report.json, runs.csv)\n%s\n",
        merged.units.size(), merge_out->c_str(),
        report.ForUser(DescribeFigureOutcome(figures)).c_str());
    *exit_code = 0;
  });

  // ---- sweep-status ----
  auto* status = app.add_subcommand(
      "sweep-status",
      "State of a --slurm sweep folder: shards complete, failed (with Slurm job ids); "
      "--resubmit submits only the failed shards and a new merge job");
  auto status_dir = std::make_shared<std::string>();
  auto resubmit = std::make_shared<bool>(false);
  status->add_option("folder", *status_dir, "Results folder of `mavloc sweep --slurm`")->required();
  status->add_flag("--resubmit", *resubmit, "Resubmit the shards without a complete partial");
  status->callback([status_dir, resubmit, exit_code] {
    const SweepStatus state = ReadSweepStatus(*status_dir);
    PrintStatus(state);
    if (*resubmit) {
      std::vector<int> tasks;
      for (const auto& s : state.shard_states) {
        const bool live = s.slurm_state == "PENDING" || s.slurm_state == "RUNNING" ||
                          s.slurm_state == "CONFIGURING" || s.slurm_state == "COMPLETING";
        if (!s.complete && !live) tasks.push_back(s.shard);
      }
      if (tasks.empty()) {
        std::printf("nothing to resubmit\n");
      } else {
        const SlurmSubmission submission = SubmitSlurm(*status_dir, tasks);
        std::printf("resubmitted %zu shard(s) as array job %s; merge job %s (afterok:%s)\n",
                    tasks.size(), submission.array_job_id.c_str(), submission.merge_job_id.c_str(),
                    submission.array_job_id.c_str());
      }
    }
    *exit_code = 0;
  });

  // ---- sweep-worker (hidden: serves units to the parallel runner,
  // evaluation/sweep/sweep_runner.h)
  auto* worker = app.add_subcommand("sweep-worker", "");
  worker->group("");
  auto worker_grid = std::make_shared<std::string>();
  auto worker_folder = std::make_shared<std::string>();
  worker->add_option("--grid", *worker_grid)->required();
  worker->add_option("--serve", *worker_folder)->required();
  worker->callback([worker_grid, worker_folder, exit_code] {
    const SweepGrid grid = ReadGridFile(*worker_grid);
    const size_t unit_count = SweepUnitCount(grid);
    std::string pending;
    char buffer[256];
    for (;;) {
      const ssize_t n = ::read(kSweepWorkerChannelFd, buffer, sizeof(buffer));
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) throw std::runtime_error("sweep-worker: cannot read its channel (fd 3)");
      if (n == 0) break;  // no unit left
      pending.append(buffer, static_cast<size_t>(n));
      size_t newline;
      while ((newline = pending.find('\n')) != std::string::npos) {
        const std::string line = pending.substr(0, newline);
        pending.erase(0, newline + 1);
        const ParsedNumber<unsigned long long> parsed = ParseUnsignedText(line);
        if (!parsed.ok() || parsed.value >= unit_count)
          throw InputError("sweep-worker: not a unit of the grid: '" + line + "'");
        const size_t unit = parsed.value;
        WriteFileAtomically(fmt::format("{}/unit-{}.json", *worker_folder, unit),
                            RunSweepUnit(grid, unit).dump());
        const std::string reply = line + "\n";
        if (::write(kSweepWorkerChannelFd, reply.data(), reply.size()) !=
            static_cast<ssize_t>(reply.size()))
          throw std::runtime_error("sweep-worker: cannot answer on its channel (fd 3)");
      }
    }
    *exit_code = 0;
  });
}

}  // namespace mavloc::cli
