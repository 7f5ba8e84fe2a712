// mavloc import-aprilgrid: an ASL dataset from a Kalibr-style aprilgrid calibration log (IMU CSV,
// per-image corner files, calibration files) -> imu0, camN, tags0/tags1, map.yaml (frame: board)
// (datasets/io/aprilgrid_log_import.h).
#include <chrono>
#include <cstdio>

#include "cli/commands.h"
#include "cli/option_checks.h"
#include "cli/output_folder.h"
#include "core/interrupt.h"
#include "core/progress.h"
#include "datasets/io/aprilgrid_log_import.h"
#include "datasets/io/euroc_io.h"

namespace mavloc::cli {

void RegisterImportAprilgrid(CLI::App& app, int* exit_code) {
  auto* command = app.add_subcommand(
      "import-aprilgrid",
      "Assemble an ASL dataset from an aprilgrid calibration log: IMU CSV + per-image corner "
      "files (yac/Kalibr layout) + calibration files -> imu0, cam0/cam1, tags0/tags1, map.yaml "
      "(frame: board)");
  struct Args {
    AprilgridLogInputs inputs;
    std::string out;
    bool force = false;
  };
  auto args = std::make_shared<Args>();
  command
      ->add_option("--imu", args->inputs.imu_csv,
                   "IMU CSV with EuRoC imu0 columns (#ts,wx,wy,wz,ax,ay,az; ns, rad/s, m/s^2)")
      ->required();
  command
      ->add_option("--corners", args->inputs.corners,
                   "camN=FOLDER of <timestamp>.csv corner files (repeatable; cam0, cam1)")
      ->required();
  command->add_option("--config", args->inputs.configs,
                      "[camN=]FILE_OR_DIR: a calibration whose every item is used (target, "
                      "intrinsics, extrinsics, IMU noise): yac config.yaml, Kalibr "
                      "camchain/imu/target.yaml, EuRoC dataset, mav0/, camN/ or sensor.yaml "
                      "(repeatable; the first holding an item wins)");
  command->add_option("--target", args->inputs.target,
                      "Aprilgrid description only: Kalibr target.yaml or yac calib_target");
  command->add_option("--intrinsics", args->inputs.intrinsics,
                      "[camN=]FILE_OR_DIR: camera models only (repeatable; before --config)");
  command->add_option("--extrinsics", args->inputs.extrinsics,
                      "[camN=]FILE_OR_DIR: T_B_C only, e.g. an EuRoC mav0/ folder (T_BS) or a "
                      "Kalibr camchain (T_cam_imu); none known: identity, said so (repeatable; "
                      "before --config)");
  command->add_option("--imu-noise", args->inputs.imu_noise,
                      "IMU noise densities only: Kalibr imu.yaml, EuRoC imu0/sensor.yaml or yac "
                      "config.yaml (before --config)");
  command->add_option("--out", args->out, "Output dataset folder (must not exist or be empty)")
      ->check(OutputFolder())
      ->required();
  command->add_flag("--force", args->force, "Replace a non-empty --out folder");
  command->callback([args, exit_code] {
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    ReportProgress("import-aprilgrid", "reading the log");
    const AprilgridLogImport result = ImportAprilgridLog(args->inputs);
    const double read_s = std::chrono::duration<double>(Clock::now() - start).count();
    ReportProgress("import-aprilgrid", "writing " + args->out);
    // Its staging folder is removed if the command is interrupted (core/interrupt.h).
    const TemporaryPathGuard staging(StagingPathFor(args->out));
    WriteEurocDatasetAtomically(result.dataset, args->out, {{"import.yaml", result.ImportYaml()}},
                                args->force);
    const double total_s = std::chrono::duration<double>(Clock::now() - start).count();
    for (const std::string& note : result.notes) std::printf("%s\n", note.c_str());
    for (const AprilgridLogCamera& camera : result.cameras) {
      if (camera.corners_folder.empty()) continue;
      const AprilgridCornerStats& s = camera.stats;
      std::printf(
          "%s: %d frames (%d without detections), %ld tags, %ld corners read; %ld incomplete "
          "tags skipped (%ld corners)\n",
          camera.name.c_str(), s.frames, s.empty_frames, s.tags, s.corners, s.incomplete_tags,
          s.incomplete_corners);
    }
    std::printf("wrote %s (read and checked in %.2f s, %.2f s in all)\n", args->out.c_str(), read_s,
                total_s);
    *exit_code = 0;
  });
}

}  // namespace mavloc::cli
