#include "evaluation/sweep/slurm_submit.h"

#include <fmt/format.h>
#include <sys/wait.h>

#include <cstdio>
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
#include "core/text.h"
#include "evaluation/sweep/sweep_partial.h"

namespace fs = std::filesystem;

namespace mavloc {

namespace {

std::string Tool(const char* name, const char* environment_override) {
  const char* value = std::getenv(environment_override);
  return value && *value ? value : name;
}

struct CommandOutput {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

CommandOutput RunShell(const std::string& command) {
  CommandOutput result;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return result;
  char buffer[4096];
  size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof(buffer), pipe)) > 0) result.output.append(buffer, n);
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

// sbatch --parsable prints "jobid" or "jobid;cluster".
std::string Submit(const std::string& arguments) {
  const std::string command = Tool("sbatch", "MAVLOC_SBATCH") + " --parsable " + arguments;
  const CommandOutput out = RunShell(command);
  std::string text = Trim(out.output);
  const auto newline = text.rfind('\n');
  std::string last = newline == std::string::npos ? text : text.substr(newline + 1);
  last = last.substr(0, last.find(';'));
  if (out.exit_code != 0 || last.empty() ||
      last.find_first_not_of("0123456789") != std::string::npos)
    throw InputError("sbatch failed (" + command + "): " + text);
  return last;
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

nlohmann::json ReadState(const std::string& results_dir) {
  const std::string path = results_dir + "/slurm.json";
  if (!fs::exists(path))
    throw InputError(path, 0, "", "not a sweep results folder (written by `mavloc sweep --slurm`)");
  try {
    return nlohmann::json::parse(ReadText(path));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, 0, "", std::string("unreadable: ") + e.what());
  }
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
  if (options.shards < 1) throw InputError("--shards: must be at least 1");
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
  WriteFileAtomically(out + "/sweep.sbatch", array);
  WriteFileAtomically(out + "/merge.sbatch", merge);
  fs::permissions(out + "/sweep.sbatch", fs::perms::owner_exec, fs::perm_options::add, error);
  fs::permissions(out + "/merge.sbatch", fs::perms::owner_exec, fs::perm_options::add, error);
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
  nlohmann::json state = ReadState(dir);
  const int shards = state.value("shards", 0);
  std::vector<int> array_tasks = tasks;
  if (array_tasks.empty())
    for (int i = 1; i <= shards; ++i) array_tasks.push_back(i);
  // A resubmission replaces the merge job that waits on the failed array (afterok can no longer be
  // satisfied); cancelling it is best effort.
  if (!tasks.empty() && !state["submissions"].empty()) {
    const std::string old_merge = state["submissions"].back().value("merge_job", "");
    if (!old_merge.empty()) RunShell(Tool("scancel", "MAVLOC_SCANCEL") + " " + old_merge);
  }
  SlurmSubmission submission;
  const std::string array_flag =
      tasks.empty() ? std::string() : "--array=" + TaskList(array_tasks) + " ";
  submission.array_job_id = Submit(array_flag + ShellQuote(dir + "/sweep.sbatch"));
  submission.merge_job_id = Submit("--dependency=afterok:" + submission.array_job_id + " " +
                                   ShellQuote(dir + "/merge.sbatch"));
  state["submissions"].push_back({{"array_job", submission.array_job_id},
                                  {"merge_job", submission.merge_job_id},
                                  {"tasks", array_tasks}});
  WriteFileAtomically(dir + "/slurm.json", state.dump(2) + "\n");
  return submission;
}

SweepStatus ReadSweepStatus(const std::string& results_dir) {
  const std::string dir = fs::absolute(results_dir).lexically_normal().string();
  const nlohmann::json state = ReadState(dir);
  SweepStatus status;
  status.shards = state.value("shards", 0);
  const std::vector<bool> complete =
      CompleteShards(dir + "/partials", status.shards, state.value("fingerprint", ""));
  std::map<int, std::string> job_of_task;  // latest submission per shard
  std::vector<std::string> array_jobs;
  for (const auto& submission : state["submissions"]) {
    const std::string array_job = submission.value("array_job", "");
    array_jobs.push_back(array_job);
    status.merge_job_id = submission.value("merge_job", "");
    for (const int task : submission["tasks"])
      job_of_task[task] = array_job + "_" + std::to_string(task);
  }
  std::map<std::string, std::string> slurm_state;  // "A_I" -> state
  if (!array_jobs.empty()) {
    const std::string ids = fmt::format("{}", fmt::join(array_jobs, ","));
    // Finished tasks from accounting, then live ones from the queue (the queue wins).
    const auto sacct =
        RunShell(Tool("sacct", "MAVLOC_SACCT") + " -n -P -X --format=JobID,State -j " + ids);
    if (sacct.exit_code == 0) {
      std::istringstream lines(sacct.output);
      for (std::string line; std::getline(lines, line);) {
        const auto bar = line.find('|');
        if (bar != std::string::npos) slurm_state[line.substr(0, bar)] = Trim(line.substr(bar + 1));
      }
    } else {
      status.note = "sacct unavailable (" + Trim(sacct.output).substr(0, 200) +
                    "): the state of finished tasks is known only from their partials";
    }
    const auto squeue = RunShell(Tool("squeue", "MAVLOC_SQUEUE") + " -h -r -o '%i|%T' -j " + ids);
    if (squeue.exit_code == 0) {
      std::istringstream lines(squeue.output);
      for (std::string line; std::getline(lines, line);) {
        const auto bar = line.find('|');
        if (bar != std::string::npos) slurm_state[line.substr(0, bar)] = Trim(line.substr(bar + 1));
      }
    }
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
