// mavloc convert: a trajectory file in any format mavloc reads (trajectory_formats/
// trajectory_format.h) written as TUM or KITTI, e.g. for evo or the KITTI devkit.
//   TUM:   "timestamp tx ty tz qx qy qz qw", nanosecond precision;
//   KITTI: 12 numbers per line (T_W_B 3x4 row-major, 17 significant digits), and with
//          --out-times a times file (one stamp [s] per line, KITTI's times.txt) so that a
//          KITTI -> TUM conversion gets the stamps back (--in-times).
#include <fmt/format.h>

#include <cstdio>

#include "cli/commands.h"
#include "cli/option_checks.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "datasets/io/trajectory_formats/kitti_poses.h"
#include "datasets/io/trajectory_formats/trajectory_format.h"
#include "datasets/io/tum_io.h"

namespace mavloc::cli {

void RegisterConvert(CLI::App& app, int* exit_code) {
  auto* command = app.add_subcommand(
      "convert", "Convert a trajectory file (TUM, EuRoC/ASL CSV, KITTI) to TUM or KITTI");
  struct Args {
    std::string in, out, format, in_format = "auto", in_times, out_times;
    bool sort = false;
  };
  auto args = std::make_shared<Args>();
  command->add_option("--in", args->in, "Input trajectory file")->required();
  command->add_option("--out", args->out, "Output file")->check(OutputFile())->required();
  command->add_option("--format", args->format, "Output format: tum or kitti")
      ->required()
      ->check(CLI::IsMember({"tum", "kitti"}));
  command
      ->add_option("--in-format", args->in_format,
                   "Input format: auto (from the content), tum, euroc, asl or kitti")
      ->check(CLI::IsMember({"auto", "tum", "euroc", "asl", "kitti"}))
      ->capture_default_str();
  command->add_option("--in-times", args->in_times,
                      "KITTI input: times file (one stamp [s] per line)");
  command->add_option("--out-times", args->out_times,
                      "KITTI output: also write the stamps to this times file");
  command->add_flag("--sort", args->sort,
                    "Sort rows by time instead of refusing rows out of order");
  command->callback([args, exit_code] {
    TrajectoryReadOptions options;
    options.format = *ParseTrajectoryFormat(args->in_format);
    options.sort = args->sort;
    options.times_path = args->in_times;
    if (args->format == "tum" && !args->out_times.empty())
      throw InputError("--out-times", 0, "", "only for --format kitti (TUM files carry stamps)");
    const LoadedTrajectory loaded = ReadTrajectory(args->in, options);
    const std::string fixes = DescribeRowFixes(loaded.report);
    if (!fixes.empty()) std::fprintf(stderr, "mavloc: note: %s\n", fixes.c_str());
    const std::vector<StampedPose>& poses = loaded.poses;
    if (args->format == "tum") {
      if (!loaded.report.has_stamps)
        std::fprintf(stderr,
                     "mavloc: note: %s has no stamps (KITTI without --in-times): pose i is "
                     "written at i s\n",
                     args->in.c_str());
      WriteTumTrajectory(poses, args->out);
    } else {
      // Times first: if it cannot be written, no pose file is left without its stamps.
      if (!args->out_times.empty()) WriteFileAtomically(args->out_times, KittiTimesText(poses));
      WriteFileAtomically(args->out, KittiPosesText(poses));
    }
    // Fewer poses than rows (repeated stamps): said with the count, never silently.
    const std::string kept = DescribeRowsKept(loaded.report, poses.size());
    if (!kept.empty())
      std::fprintf(stderr, "mavloc: note: %s: wrote %s\n", args->in.c_str(), kept.c_str());
    std::printf(
        "%zu poses: %s (%s) -> %s (%s)%s\n", poses.size(), args->in.c_str(),
        loaded.report.layout.c_str(), args->out.c_str(), args->format.c_str(),
        args->out_times.empty() ? "" : fmt::format(", stamps -> {}", args->out_times).c_str());
    *exit_code = 0;
  });
}

}  // namespace mavloc::cli
