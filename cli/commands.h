// The mavloc subcommands. Each Register* adds one CLI11 subcommand whose callback does the work and
// stores the process exit code in *exit_code. Callbacks throw InputError for bad input; main()
// turns it into one line on stderr and exit code 2.
#pragma once

#include <CLI/CLI.hpp>

namespace mavloc::cli {

void RegisterList(CLI::App& app, int* exit_code);
void RegisterSimulate(CLI::App& app, int* exit_code);
void RegisterRun(CLI::App& app, int* exit_code);
void RegisterEval(CLI::App& app, int* exit_code);
void RegisterConvert(CLI::App& app, int* exit_code);
void RegisterCompare(CLI::App& app, int* exit_code);
void RegisterRepro(CLI::App& app, int* exit_code);
void RegisterObservability(CLI::App& app, int* exit_code);
void RegisterDetectTags(CLI::App& app, int* exit_code);
void RegisterObstacles(CLI::App& app, int* exit_code);
void RegisterImportAprilgrid(CLI::App& app, int* exit_code);
void RegisterFigures(CLI::App& app, int* exit_code);
void RegisterImportTagslam(CLI::App& app, int* exit_code);
void RegisterLog(CLI::App& app, int* exit_code);
void RegisterSweep(CLI::App& app, int* exit_code);  // sweep, sweep-merge, sweep-status
void RegisterMatrix(CLI::App& app, int* exit_code);
void RegisterImuNoise(CLI::App& app, int* exit_code);       // cli/command_imu_noise.cc
void RegisterTrackFeatures(CLI::App& app, int* exit_code);  // cli/command_track_features.cc

// Parses "key=value" items (from repeated --set / --option flags) into a map; throws InputError.
std::map<std::string, std::string> ParseKeyValues(const std::vector<std::string>& items,
                                                  const std::string& flag);

}  // namespace mavloc::cli
