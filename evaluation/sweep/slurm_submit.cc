#include "evaluation/sweep/slurm_submit.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/interrupt.h"
#include "core/subprocess.h"
#include "core/text.h"
#include "evaluation/sweep/sweep_partial.h"

namespace fs = std::filesystem;

namespace mavloc {

namespace {

// More array tasks than this is no sweep anyone submits (Slurm's own MaxArraySize defaults to
// 1001); the bound keeps a damaged slurm.json from driving a loop over billions of shards.
constexpr size_t kMaxSlurmShards = 100000;

struct SlurmState {
  struct Submission {
    std::string array_job, merge_job;
    std::vector<int> tasks;
  };
  int shards = 0;
  std::string fingerprint;
  std::vector<Submission> submissions;
};

bool IsSlurmJobId(const std::string& text) {
  return !text.empty() && text.size() <= 18 &&
         text.find_first_not_of("0123456789") == std::string::npos;
}

std::string Tool(const char* name, const char* environment_override) {
  const char* value = std::getenv(environment_override);
  return value && *value ? value : name;
}

// The shortest text of a Slurm command's output worth quoting in a message.
std::string Excerpt(const std::string& text) { return Trim(text).substr(0, 300); }

// sbatch --parsable prints "jobid" or "jobid;cluster".
std::string Submit(const std::vector<std::string>& arguments) {
  std::vector<std::string> argv = {Tool("sbatch", "MAVLOC_SBATCH"), "--parsable"};
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  const ProgramRun run = RunProgram(argv, {.merge_stderr = true});
  const std::string text = Trim(run.out);
  const auto newline = text.rfind('\n');
  std::string last = newline == std::string::npos ? text : text.substr(newline + 1);
  last = last.substr(0, last.find(';'));
  if (!run.started) throw InputError("sbatch failed: " + run.error);
  if (run.exit_code != 0 || !IsSlurmJobId(last))
    throw InputError(fmt::format("sbatch failed (exit code {}): {}", run.exit_code, Excerpt(text)));
  return last;
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The number of units of the folder's grid.json: a shard count beyond it cannot be ours.
size_t GridUnitCount(const std::string& results_dir) {
  const std::string path = results_dir + "/grid.json";
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(ReadText(path));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, 0, "", std::string("unreadable: ") + e.what());
  }
  return SweepUnitCount(SweepGridFromJson(json, path));
}

std::string RequireJobId(const nlohmann::json& value, const std::string& path,
                         const std::string& field) {
  if (!value.is_string() || !IsSlurmJobId(value.get<std::string>()))
    throw InputError(
        path, 0, field,
        "not a Slurm job id (a whole number of at most 18 digits): " + Excerpt(value.dump()));
  return value.get<std::string>();
}

// slurm.json as `mavloc sweep --slurm` writes it, every value checked before it is used: the
// folder may be shared and written by others.
SlurmState ParseState(const nlohmann::json& json, const std::string& path, size_t unit_count) {
  if (!json.is_object()) throw InputError(path, 0, "", "not a JSON object");
  SlurmState state;
  const auto& shards = json.contains("shards") ? json["shards"] : nlohmann::json();
  if (!shards.is_number_integer() || shards.get<int64_t>() < 1 ||
      shards.get<int64_t>() > static_cast<int64_t>(std::min(unit_count, kMaxSlurmShards)))
    throw InputError(path, 0, "shards",
                     fmt::format("must be a whole number from 1 to {} (the grid's units, at most "
                                 "{}), not {}",
                                 std::min(unit_count, kMaxSlurmShards), kMaxSlurmShards,
                                 Excerpt(shards.dump())));
  state.shards = static_cast<int>(shards.get<int64_t>());
  if (!json.contains("fingerprint") || !json["fingerprint"].is_string())
    throw InputError(path, 0, "fingerprint", "must be a string");
  state.fingerprint = json["fingerprint"].get<std::string>();
  if (!json.contains("submissions") || !json["submissions"].is_array())
    throw InputError(path, 0, "submissions", "must be a list");
  for (size_t k = 0; k < json["submissions"].size(); ++k) {
    const auto& item = json["submissions"][k];
    const std::string field = fmt::format("submissions[{}]", k);
    if (!item.is_object() || !item.contains("array_job") || !item.contains("merge_job") ||
        !item.contains("tasks") || !item["tasks"].is_array())
      throw InputError(path, 0, field, "must hold array_job, merge_job and a list of tasks");
    SlurmState::Submission submission;
    submission.array_job = RequireJobId(item["array_job"], path, field + ".array_job");
    submission.merge_job = RequireJobId(item["merge_job"], path, field + ".merge_job");
    for (const auto& task : item["tasks"]) {
      if (!task.is_number_integer() || task.get<int64_t>() < 1 ||
          task.get<int64_t>() > state.shards)
        throw InputError(path, 0, field + ".tasks",
                         fmt::format("a task must be a shard number from 1 to {}, not {}",
                                     state.shards, Excerpt(task.dump())));
      submission.tasks.push_back(static_cast<int>(task.get<int64_t>()));
    }
    state.submissions.push_back(std::move(submission));
  }
  return state;
}

SlurmState ReadState(const std::string& results_dir) {
  const std::string path = results_dir + "/slurm.json";
  if (!fs::exists(path))
    throw InputError(path, 0, "", "not a sweep results folder (written by `mavloc sweep --slurm`)");
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(ReadText(path));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, 0, "", std::string("unreadable: ") + e.what());
  }
  return ParseState(json, path, GridUnitCount(results_dir));
}

// "JOBID_TASK|STATE" lines of squeue -o '%i|%T' and sacct -P --format=JobID,State.
void ReadJobStates(const std::string& output, std::map<std::string, std::string>* states) {
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);) {
    const auto bar = line.find('|');
    if (bar != std::string::npos) (*states)[line.substr(0, bar)] = Trim(line.substr(bar + 1));
  }
}

nlohmann::json StateToJson(const SlurmState& state) {
  nlohmann::json submissions = nlohmann::json::array();
  for (const auto& s : state.submissions)
    submissions.push_back(
        {{"array_job", s.array_job}, {"merge_job", s.merge_job}, {"tasks", s.tasks}});
  return {
      {"shards", state.shards}, {"fingerprint", state.fingerprint}, {"submissions", submissions}};
}

std::string TaskList(const std::vector<int>& tasks) {
  return fmt::format("{}", fmt::join(tasks, ","));
}

bool HasControlCharacter(const std::string& text) {
  for (const unsigned char c : text)
    if (c < 0x20 || c == 0x7f) return true;
  return false;
}

void RequireFormat(const std::string& option, const std::string& value, const std::regex& format,
                   const std::string& expected) {
  if (HasControlCharacter(value) || !std::regex_match(value, format))
    throw InputError(option + ": '" + value + "' is not " + expected +
                     " (it goes into an #SBATCH line of the job scripts)");
}

}  // namespace

void CheckSlurmOptions(const SlurmOptions& options) {
  static const std::regex kTime(
      R"((\d+-\d+(:\d+){0,2})|(\d+(:\d+){0,2})|UNLIMITED|unlimited|INFINITE|infinite)");
  static const std::regex kMem(R"(\d+[KMGTkmgt]?)");
  static const std::regex kName(R"([A-Za-z0-9_.\-]+)");
  static const std::regex kNames(R"([A-Za-z0-9_.\-]+(,[A-Za-z0-9_.\-]+)*)");
  RequireFormat("--time", options.time, kTime,
                "a Slurm time limit (MINUTES, MM:SS, HH:MM:SS, D-HH, D-HH:MM, D-HH:MM:SS or "
                "UNLIMITED)");
  if (!options.mem.empty())
    RequireFormat("--mem", options.mem, kMem,
                  "a Slurm memory size (a whole number with an optional K, M, G or T, e.g. 4G)");
  if (!options.partition.empty())
    RequireFormat("--partition", options.partition, kNames,
                  "a Slurm partition name (letters, digits, '_', '-', '.'; a comma between names)");
  if (!options.account.empty())
    RequireFormat("--account", options.account, kName,
                  "a Slurm account name (letters, digits, '_', '-', '.')");
  for (const auto& line : options.setup_lines)
    if (HasControlCharacter(line))
      throw InputError("--setup: '" + line +
                       "' holds a newline or another control character: give one shell line per "
                       "--setup");
  const std::string dir = fs::absolute(options.results_dir).lexically_normal().string();
  if (HasControlCharacter(dir) || dir.find_first_of(" \t%") != std::string::npos)
    throw InputError("--out: '" + options.results_dir +
                     "' holds a space, '%' or a control character, which an #SBATCH --output line "
                     "cannot hold; choose another results folder");
}

SlurmFiles WriteSlurmFiles(const SweepGrid& grid, const SlurmOptions& options) {
  CheckSlurmOptions(options);
  const std::string dir = fs::absolute(options.results_dir).lexically_normal().string();
  const std::string out =
      options.write_dir.empty() ? dir : fs::absolute(options.write_dir).lexically_normal().string();
  std::string mavloc = options.mavloc_path;
  if (mavloc.empty()) mavloc = fs::read_symlink("/proc/self/exe").string();
  if (options.shards < 1 || static_cast<size_t>(options.shards) > kMaxSlurmShards)
    throw InputError(fmt::format("--shards: must be from 1 to {}", kMaxSlurmShards));
  std::error_code error;
  for (const char* sub : {"", "/partials", "/logs"}) {
    CreateOutputDirectories(out + sub, error);
    if (error) throw InputError(out + sub, 0, "", "cannot create folder: " + error.message());
  }
  WriteFileAtomically(out + "/grid.json", SweepGridToJson(grid).dump(2) + "\n");

  auto header = [&](const std::string& name) {
    std::string text = "#!/bin/bash\n#SBATCH --job-name=" + name + "\n";
    text += "#SBATCH --time=" + options.time + "\n";
    if (!options.mem.empty()) text += "#SBATCH --mem=" + options.mem + "\n";
    if (!options.partition.empty()) text += "#SBATCH --partition=" + options.partition + "\n";
    if (!options.account.empty()) text += "#SBATCH --account=" + options.account + "\n";
    return text;
  };
  const std::string setup = [&] {
    std::string text;
    for (const auto& line : options.setup_lines) text += line + "\n";
    return text;
  }();
  std::string array = header("mavloc-sweep");
  array += fmt::format("#SBATCH --array=1-{}\n#SBATCH --cpus-per-task={}\n", options.shards,
                       options.cpus_per_task);
  array += "#SBATCH --output=" + dir + "/logs/shard-%a-job%A.out\n";
  array += fmt::format(
      "# Generated by `mavloc sweep --slurm`: grid fingerprint {}, {} units in {} shards.\n"
      "# Resubmit failed shards only: `mavloc sweep-status {} --resubmit`.\n",
      SweepFingerprint(grid), SweepUnitCount(grid), options.shards, dir);
  array += "set -eu\n" + setup;
  array += "export MAVLOC_QUIET=1\n";
  array += fmt::format(
      "exec {} sweep --grid-file {} --shard \"${{SLURM_ARRAY_TASK_ID}}/{}\" "
      "--jobs \"${{SLURM_CPUS_PER_TASK:-1}}\" --out {}\n",
      ShellQuote(mavloc), ShellQuote(dir + "/grid.json"), options.shards,
      ShellQuote(dir + "/partials"));
  std::string merge = header("mavloc-sweep-merge");
  merge += "#SBATCH --cpus-per-task=1\n#SBATCH --output=" + dir + "/logs/merge-job%j.out\n";
  merge += "set -eu\n" + setup;
  merge += fmt::format("exec {} sweep-merge {} --out {}\n", ShellQuote(mavloc),
                       ShellQuote(dir + "/partials"), ShellQuote(dir + "/report"));

  SlurmFiles files{dir + "/sweep.sbatch", dir + "/merge.sbatch"};
  // Executable from creation: no chmod afterwards through a name someone else could replace.
  WriteFileAtomically(out + "/sweep.sbatch", array, {.executable = true});
  WriteFileAtomically(out + "/merge.sbatch", merge, {.executable = true});
  nlohmann::json state = {{"shards", options.shards},
                          {"fingerprint", SweepFingerprint(grid)},
                          {"submissions", nlohmann::json::array()}};
  WriteFileAtomically(out + "/slurm.json", state.dump(2) + "\n");
  WriteFileAtomically(
      out + "/README.md",
      fmt::format("# Sweep on Slurm (mavloc sweep --slurm)\n\n"
                  "Grid fingerprint {}: {} units in {} shards (grid.json). The job array "
                  "(sweep.sbatch) writes partials/, the merge job (merge.sbatch) the report to "
                  "report/ when every shard is complete.\n\n"
                  "Status: `mavloc sweep-status {}`; failed shards only: `mavloc sweep-status {} "
                  "--resubmit`.\n",
                  SweepFingerprint(grid), SweepUnitCount(grid), options.shards, dir, dir));
  return files;
}

SlurmSubmission SubmitSlurm(const std::string& results_dir, const std::vector<int>& tasks) {
  const std::string dir = fs::absolute(results_dir).lexically_normal().string();
  SlurmState state = ReadState(dir);
  std::vector<int> array_tasks = tasks;
  if (array_tasks.empty())
    for (int i = 1; i <= state.shards; ++i) array_tasks.push_back(i);
  // A resubmission replaces the merge job that waits on the failed array (afterok can no longer be
  // satisfied); cancelling it is best effort.
  if (!tasks.empty() && !state.submissions.empty())
    RunProgram({Tool("scancel", "MAVLOC_SCANCEL"), state.submissions.back().merge_job},
               {.merge_stderr = true});
  SlurmSubmission submission;
  std::vector<std::string> array_arguments;
  if (!tasks.empty()) array_arguments.push_back("--array=" + TaskList(array_tasks));
  array_arguments.push_back(dir + "/sweep.sbatch");
  submission.array_job_id = Submit(array_arguments);
  submission.merge_job_id =
      Submit({"--dependency=afterok:" + submission.array_job_id, dir + "/merge.sbatch"});
  state.submissions.push_back(
      {submission.array_job_id, submission.merge_job_id, std::move(array_tasks)});
  WriteFileAtomically(dir + "/slurm.json", StateToJson(state).dump(2) + "\n");
  return submission;
}

SweepStatus ReadSweepStatus(const std::string& results_dir) {
  const std::string dir = fs::absolute(results_dir).lexically_normal().string();
  const SlurmState state = ReadState(dir);
  SweepStatus status;
  status.shards = state.shards;
  const std::vector<bool> complete =
      CompleteShards(dir + "/partials", status.shards, state.fingerprint);
  std::map<int, std::string> job_of_task;  // latest submission per shard
  std::vector<std::string> array_jobs;
  for (const auto& submission : state.submissions) {
    array_jobs.push_back(submission.array_job);
    status.merge_job_id = submission.merge_job;
    for (const int task : submission.tasks)
      job_of_task[task] = submission.array_job + "_" + std::to_string(task);
  }
  std::map<std::string, std::string> slurm_state;  // "A_I" -> state
  if (!array_jobs.empty()) {
    const std::string ids = fmt::format("{}", fmt::join(array_jobs, ","));
    // Finished tasks from accounting, then live ones from the queue (the queue wins).
    const ProgramRun sacct = RunProgram(
        {Tool("sacct", "MAVLOC_SACCT"), "-n", "-P", "-X", "--format=JobID,State", "-j", ids},
        {.merge_stderr = true});
    if (sacct.started && sacct.exit_code == 0) {
      ReadJobStates(sacct.out, &slurm_state);
    } else {
      status.note = "sacct unavailable (" + Excerpt(sacct.started ? sacct.out : sacct.error) +
                    "): the state of finished tasks is known only from their partials";
    }
    const ProgramRun squeue =
        RunProgram({Tool("squeue", "MAVLOC_SQUEUE"), "-h", "-r", "-o", "%i|%T", "-j", ids});
    if (squeue.started && squeue.exit_code == 0) ReadJobStates(squeue.out, &slurm_state);
  }
  for (int i = 1; i <= status.shards; ++i) {
    ShardStatus shard;
    shard.shard = i;
    shard.complete = complete[static_cast<size_t>(i)];
    if (const auto it = job_of_task.find(i); it != job_of_task.end()) {
      shard.job_id = it->second;
      if (const auto s = slurm_state.find(it->second); s != slurm_state.end())
        shard.slurm_state = s->second;
    }
    status.shard_states.push_back(shard);
  }
  return status;
}

}  // namespace mavloc
