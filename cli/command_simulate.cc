// mavloc simulate: generate a synthetic dataset (EuRoC/ASL layout + mavloc extension streams).
#include <cstdio>
#include <filesystem>

#include "cli/commands.h"
#include "cli/common.h"
#include "cli/option_checks.h"
#include "cli/output_folder.h"
#include "core/errors.h"
#include "core/progress.h"
#include "datasets/io/euroc_io.h"

namespace mavloc::cli {

void RegisterSimulate(CLI::App& app, int* exit_code) {
  auto* command = app.add_subcommand(
      "simulate", "Generate a synthetic dataset from a scenario (see `mavloc list`) into a folder");
  struct Args {
    std::string scenario;
    std::string out;
    uint64_t seed = 1;
    double duration_s = 0.0;
    std::vector<std::string> settings;
    bool render = false;
    bool force = false;
  };
  auto args = std::make_shared<Args>();
  command->add_option("--scenario", args->scenario, "Scenario name")->required();
  command
      ->add_option("--out", args->out,
                   "Output dataset folder: created (an existing one only with --force; written "
                   "whole into a fresh folder, then renamed into place)")
      ->check(OutputFolder())
      ->required();
  command->add_flag("--force", args->force, "Replace an existing --out folder (a mavloc dataset)");
  AddSeedOption(command, &args->seed, "Master seed (motion, IMU and camera seeds derive from it)");
  AddScenarioDurationOption(command, &args->duration_s,
                            "Duration in seconds (scenario default if unset)");
  command->add_option("--set", args->settings, "Scenario setting key=value (repeatable)");
  command->add_flag("--render", args->render,
                    "Render camera images where the scenario supports it");
  command->callback([args, exit_code] {
    ScenarioOptions options;
    options.seed = args->seed;
    if (args->duration_s > 0) options.duration_s = args->duration_s;
    options.settings = ParseKeyValues(args->settings, "--set");
    options.render_images = args->render;
    // The dataset is written into a fresh folder beside --out and renamed into place: no stream of
    // an earlier dataset survives in the new one, and an error or an interrupt leaves nothing.
    StagedFolder out(args->out, FolderKind::kDataset, args->force);
    // Rendered images go to a scratch folder inside the output, removed once copied into cam*/data.
    const std::filesystem::path scratch = std::filesystem::path(out.path()) / ".render-scratch";
    if (args->render) options.image_dir = scratch.string();
    const Dataset dataset = SimulateScenario(args->scenario, options);
    ReportProgress("simulate", "writing " + args->out);
    WriteEurocDataset(dataset, out.path());
    std::filesystem::remove_all(scratch);
    out.Commit();
    std::printf(
        "wrote %s: %zu IMU samples, %zu ground-truth rows, %zu features, %zu laser, %zu tag rows\n",
        args->out.c_str(), dataset.imu.samples.size(), dataset.ground_truth.size(),
        dataset.features.size(), dataset.laser.size(), dataset.tags.size());
    *exit_code = 0;
  });
}

}  // namespace mavloc::cli
