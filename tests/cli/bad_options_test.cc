// Bad command-line values, table-driven: every case must end with exit code
// 2, one line on stderr naming the option (and the offending key or value), and nothing written
// in the working folder (no output, no staging folder "*.tmp-<pid>" left behind).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/test_support.h"

namespace mavloc {
namespace {

namespace fs = std::filesystem;

struct Case {
  std::string args;                   // after `mavloc`, run in an empty folder
  std::vector<std::string> expected;  // substrings of the one-line message
};

// Every command with a few bad values of each of its options; unknown keys of every scenario.
std::vector<Case> Cases() {
  std::vector<Case> cases = {
      // simulate: seed, duration, settings.
      {"simulate --scenario mav-figure-eight --out out --seed -1", {"--seed", "'-1'"}},
      {"simulate --scenario mav-figure-eight --out out --seed 1.5", {"--seed", "1.5"}},
      {"simulate --scenario mav-figure-eight --out out --seed 18446744073709551616",
       {"--seed", "18446744073709551616"}},
      {"simulate --scenario mav-figure-eight --out out --seed 1e3", {"--seed", "1e3"}},
      {"simulate --scenario mav-figure-eight --out out --duration nan", {"--duration", "nan"}},
      {"simulate --scenario mav-figure-eight --out out --duration inf", {"--duration", "inf"}},
      {"simulate --scenario mav-figure-eight --out out --duration -1", {"--duration", "-1"}},
      {"simulate --scenario mav-figure-eight --out out --duration 0", {"--duration", "'0'"}},
      {"simulate --scenario mav-figure-eight --out out --duration 1e9",
       {"--duration", "1e9", "3600"}},
      {"simulate --scenario mav-figure-eight --out out --duration 3600.5", {"--duration", "3600"}},
      {"simulate --scenario mav-figure-eight --out out --set imu_rat_hz=100",
       {"--set imu_rat_hz=100", "mav-figure-eight", "known:", "imu_rate_hz"}},
      {"simulate --scenario mav-figure-eight --out out --set imu_rate_hz=1e6",
       {"--set imu_rate_hz=1e6", "1000"}},
      {"simulate --scenario mav-figure-eight --out out --set imu_rate_hz=nan",
       {"imu_rate_hz", "nan"}},
      {"simulate --scenario mav-figure-eight --out out --set landmarks=1.5", {"landmarks", "1.5"}},
      {"simulate --scenario mav-figure-eight --out out --set novalue", {"--set", "novalue"}},
      {"simulate --scenario no-such-scenario --out out", {"no-such-scenario", "known"}},
      // compare: seed, duration, association tolerance, scenario settings, estimator options.
      {"compare --seed -5", {"--seed", "-5"}},
      {"compare --duration nan", {"--duration", "nan"}},
      {"compare --duration 1e9", {"--duration", "3600"}},
      {"compare --max-dt 0", {"--max-dt", "'0'"}},
      {"compare --max-dt nan", {"--max-dt", "nan"}},
      {"compare --set bogus=1", {"--set bogus=1", "known:"}},
      {"compare --option bogus_option=1", {"--option bogus_option=1", "bogus_option"}},
      {"compare --option no-such-estimator:rate_hz=5",
       {"--option", "no-such-estimator", "imu-dead-reckoning"}},
      {"compare --estimators pnp --option tag-ekf:init=zero",
       {"--option", "tag-ekf", "not part of this run"}},
      {"compare --estimators imu-dead-reckoning --option imu-dead-reckoning:rat_hz=5",
       {"--option rat_hz=5", "imu-dead-reckoning", "rate_hz"}},
      {"compare --estimators imu-dead-reckoning --option D=0.1", {"--option D=0.1", "rate_hz"}},
      {"compare --estimators imu-dead-reckoning --option imu-dead-reckoning:rate_hz",
       {"--option", "key=value"}},
      {"compare --estimators no-such-estimator", {"no-such-estimator"}},
      {"compare --dataset nowhere --set D=0.1", {"--set D=0.1", "--dataset"}},
      // run: estimator options are checked before the dataset is read.
      {"run --dataset nowhere --estimator imu-dead-reckoning --out o.txt --option rat_hz=5",
       {"--option rat_hz=5", "imu-dead-reckoning", "rate_hz"}},
      {"run --dataset nowhere --estimator tag-ekf --out o.txt --option init_sigma=1",
       {"init_sigma", "init_pos_sigma"}},
      {"run --dataset nowhere --estimator smoother --out o.txt --option los=cauchy",
       {"--option los=cauchy", "loss"}},
      {"run --dataset nowhere --estimator no-such --out o.txt", {"no-such"}},
      {"run --dataset nowhere --estimator tag-ekf --out o.txt --option reacquire=maybe",
       {"reacquire", "maybe"}},
      {"run --dataset nowhere --estimator tag-ekf --out o.txt --option reacquire_frames=1",
       {"--option reacquire_frames=1", "[2, inf)"}},
      {"run --dataset nowhere --estimator tag-ekf --out o.txt --option reacquire_pos_sigma=0",
       {"--option reacquire_pos_sigma=0", "(0, inf) m"}},
      {"run --dataset nowhere --estimator tag-ekf --out o.txt --option reacquire_att_sigma=nan",
       {"reacquire_att_sigma", "nan"}},
      {"run --dataset nowhere --estimator tag-pnp --out o.txt --option ransac_threshold_px=0",
       {"--option ransac_threshold_px=0", "px"}},
      {"run --dataset nowhere --estimator tag-pnp --out o.txt --option ransac_min_tags=0",
       {"--option ransac_min_tags=0", "[1, inf)"}},
      {"run --dataset nowhere --estimator tag-pnp --out o.txt --option single_tag=2",
       {"single_tag", "2"}},
      {"run --dataset nowhere --estimator pnp --out o.txt --option min_ambiguity_ratio=-1",
       {"--option min_ambiguity_ratio=-1", "[0, inf)"}},
      {"run --dataset nowhere --estimator pnp --out o.txt --option ransac=1 --option bogus=1",
       {"bogus"}},
      {"run --dataset nowhere --estimator tag-pnp --out o.txt --option map_check=2",
       {"map_check", "2"}},
      {"run --dataset nowhere --estimator tag-pnp --out o.txt --option refine_map=2",
       {"--option refine_map=2", "0, 1 or auto"}},
      {"run --dataset nowhere --estimator tag-pnp --out o.txt --option refine_sigma_m=0",
       {"--option refine_sigma_m=0", "(0, inf) m"}},
      {"run --dataset nowhere --estimator tag-pnp --out o.txt --option neighbour_window_s=-1",
       {"--option neighbour_window_s=-1", "[0, inf) s"}},
      {"run --dataset nowhere --estimator tag-pnp --out o.txt --option neighbour_gate_m=-0.3",
       {"--option neighbour_gate_m=-0.3", "[0, inf) m"}},
      {"run --dataset nowhere --estimator tag-pnp --out o.txt --option neighbour_frames=1",
       {"--option neighbour_frames=1", "[2, inf)"}},
      {"run --dataset nowhere --estimator smoother --out o.txt --option autodiff_jacobians=maybe",
       {"autodiff_jacobians=maybe", "true or false"}},
      {"run --dataset nowhere --estimator smoother --out o.txt --option fit_imu_noise=2",
       {"fit_imu_noise=2", "true or false"}},
      {"run --dataset nowhere --estimator smoother --out o.txt --option window_s=8",
       {"window_s", "twice window_overlap_s"}},
      {"run --dataset nowhere --estimator smoother --out o.txt --option window_overlap_s=0",
       {"--option window_overlap_s=0", "outside (0, 1e+06] s"}},
      {"run --dataset nowhere --estimator smoother --out o.txt --option memory_budget_mib=-5",
       {"--option memory_budget_mib=-5", "outside (0, 1e+06] MiB"}},
      {"run --dataset nowhere --estimator tag-pnp --out o.txt --option refine_sigma_rad=-1",
       {"--option refine_sigma_rad=-1", "(0, inf) rad"}},
      {"run --dataset nowhere --estimator tag-pnp --out o.txt --option refine_loss_px=nan",
       {"refine_loss_px", "nan"}},
      {"run --dataset nowhere --estimator tag-pnp --out o.txt --option refine_gate_px=0",
       {"--option refine_gate_px=0", "px"}},
      {"run --dataset nowhere --estimator tag-pnp --out o.txt --option refine_loss=l2",
       {"refine_loss", "l2"}},
      {"run --dataset nowhere --estimator pnp --out o.txt --option refine_map=1", {"refine_map"}},
      // Option values at the edges, checked before the dataset is read (a window of 1e18 s became
      // a window of no states, a delay of 1e9 s put every tag after the log's end, a negative
      // delay was "error: : field 'delay_s'").
      {"run --dataset nowhere --estimator smoother --out o.txt --option window_s=1e18",
       {"--option window_s=1e18", "outside [0, 1e+06] s", "smoother"}},
      {"run --dataset nowhere --estimator smoother --out o.txt --option window_overlap_s=inf",
       {"--option window_overlap_s=inf", "finite"}},
      {"run --dataset nowhere --estimator tag-ekf --out o.txt --option delay_s=1e9",
       {"--option delay_s=1e9", "outside [0, 60] s", "tag-ekf"}},
      {"run --dataset nowhere --estimator tag-ekf --out o.txt --option delay_s=-1e9",
       {"--option delay_s=-1e9", "outside [0, 60] s"}},
      {"run --dataset nowhere --estimator tag-ekf --out o.txt --option init_pos_sigma=1e300",
       {"--option init_pos_sigma=1e300", "m (estimator tag-ekf)"}},
      {"run --dataset nowhere --estimator pnp --out o.txt --option image_delay_ms=1e18",
       {"--option image_delay_ms=1e18", "ms"}},
      {"compare --estimators tag-ekf --option tag-ekf:delay_s=1e9",
       {"--option delay_s=1e9", "tag-ekf", "[0, 60] s"}},
      {"compare --estimators smoother --option window_s=1e18", {"--option window_s=1e18"}},
      {"sweep --scenario tag-arena-hover --seeds 1 --estimators smoother --option window_s=1e18 "
       "--out s",
       {"--option window_s=1e18", "smoother"}},
      {"sweep --scenario tag-arena-hover --seeds 1 --estimators tag-pnp,smoother --option "
       "smoother:window_s=8 --out s",
       {"window_s", "twice window_overlap_s"}},
      {"obstacles --dataset d --report r --pose-source tag-ekf --option delay_s=1e9",
       {"--option delay_s=1e9", "tag-ekf"}},
      // Output names, checked before any work (run --out '' ran the estimator, then failed on an
      // empty name).
      {"run --dataset nowhere --estimator tag-ekf --out \"\"", {"--out", "an empty file name"}},
      {"run --dataset nowhere --estimator tag-ekf --out nodir/o.txt",
       {"--out", "nodir", "does not exist"}},
      {"run --dataset nowhere --estimator tag-ekf --out .", {"--out", "is a folder"}},
      {"convert --in t.txt --format tum --out \"\"", {"--out", "an empty file name"}},
      {"log export x.ulg:vehicle_attitude --out \"\"", {"--out", "an empty file name"}},
      {"simulate --scenario mav-figure-eight --out \"\"", {"--out", "an empty folder name"}},
      {"compare --report \"\"", {"--report", "an empty folder name"}},
      {"matrix root --out \"\"", {"--out", "an empty folder name"}},
      {"sweep-merge partials --out \"\"", {"--out", "an empty folder name"}},
      // eval: every numeric option.
      {"eval --gt gt.txt --est est.txt --rpe-distance -1", {"--rpe-distance", "-1"}},
      {"eval --gt gt.txt --est est.txt --rpe-distance inf", {"--rpe-distance", "inf"}},
      {"eval --gt gt.txt --est est.txt --rpe-time 0", {"--rpe-time", "'0'"}},
      {"eval --gt gt.txt --est est.txt --rpe-time nan", {"--rpe-time", "nan"}},
      {"eval --gt gt.txt --est est.txt --delta nan", {"--delta", "nan"}},
      {"eval --gt gt.txt --est est.txt --delta -2", {"--delta", "-2"}},
      {"eval --gt gt.txt --est est.txt --t-max-diff 0", {"--t-max-diff", "0 s", "> 0"}},
      {"eval --gt gt.txt --est est.txt --t-max-diff inf", {"--t-max-diff", "inf"}},
      {"eval --gt gt.txt --est est.txt --t-offset nan", {"--t-offset", "finite"}},
      {"eval --gt gt.txt --est est.txt --rel-lengths 0", {"--rel-lengths", "0 m"}},
      {"eval --gt gt.txt --est est.txt --max-dt nan", {"--max-dt", "nan"}},
      {"eval --gt gt.txt --est est.txt --n-to-align 1.5", {"--n-to-align", "1.5"}},
      {"eval --gt gt.txt --est est.txt --n-to-align -2", {"--n-to-align", "-2"}},
      // repro: runs, seed, unknown settings of every reproduction.
      {"repro three-point --report r --seed -1", {"--seed", "-1"}},
      {"repro three-point --report r --runs 0", {"--runs", "'0'"}},
      {"repro three-point --report r --runs 1.5", {"--runs", "1.5"}},
      {"repro three-point --report r --runs -3", {"--runs", "-3"}},
      {"repro three-point --report r --set bogus_key=1", {"bogus_key"}},
      {"repro pixhawk --report r --set bogus_key=1", {"bogus_key", "known:"}},
      {"repro laser --report r --set bogus_key=1", {"bogus_key", "known:"}},
      {"repro apriltag --report r --set bogus_key=1", {"--set bogus_key=1", "hover_duration_s"}},
      {"repro smoother --report r --set bogus_key=1", {"bogus_key", "known:"}},
      {"repro euroc-imu-april --report r --set bogus_key=1", {"bogus_key"}},
      {"repro laser --report r --set duration_s=1e9", {"duration_s", "3600"}},
      {"repro laser --report r --set ekf.bogus_key=1", {"bogus_key", "laser-ekf"}},
      {"repro laser --report r --set ekf.init_error_max=1e9",
       {"--option init_error_max=1e9", "laser-ekf"}},
      {"repro smoother --report r --set smoother.window_s=1e18",
       {"--option window_s=1e18", "smoother"}},
      {"repro no-such --report r", {"no-such", "known"}},
      // imu-noise: the window is checked before the log is read.
      {"imu-noise nowhere --out o --from nan", {"--from", "nan"}},
      {"imu-noise nowhere --out o --to inf", {"--to", "inf"}},
      {"imu-noise nowhere --out o --from -1", {"--from -1", ">= 0"}},
      {"imu-noise nowhere --out o --from 5 --to 2", {"--from 5", "--to 2"}},
      {"imu-noise nowhere --out o --max-tau 0", {"--max-tau 0", "> 0"}},
      {"imu-noise nowhere --out o --max-tau -3", {"--max-tau -3", "> 0"}},
      {"imu-noise nowhere --out o --max-tau nan", {"--max-tau", "nan"}},
      {"imu-noise nowhere --out o --max-tau inf", {"--max-tau", "inf"}},
      // observability.
      {"observability laser --states 0", {"--states", "'0'"}},
      {"observability laser --order 3", {"--order", "'3'"}},
      {"observability laser --L nan", {"--L", "nan"}},
      {"observability laser --seed -1", {"--seed", "-1"}},
      // detect-tags.
      {"detect-tags --images img --out o.csv --decimate nan", {"--decimate", "nan"}},
      {"detect-tags --images img --out o.csv --decimate 0.5", {"--decimate", "0.5"}},
      {"detect-tags --images img --out o.csv --threads 0", {"--threads", "'0'"}},
      {"detect-tags --images img --out o.csv --sigma -1", {"--sigma", "-1"}},
      {"detect-tags --images img --out o.csv --sharpening inf", {"--sharpening", "inf"}},
      {"detect-tags --images img --out o.csv --target t.yaml",
       {"--target t.yaml", "--family aprilgrid"}},
      {"detect-tags --family aprilgrid --images img --out o.csv --target missing.yaml",
       {"missing.yaml"}},
      // obstacles.
      {"obstacles --dataset d --report r --set bogus_key=1", {"--set bogus_key=1", "matcher"}},
      {"obstacles --dataset d --report r --option rate_hz=1",
       {"--option rate_hz=1", "--pose-source"}},
      {"obstacles --dataset d --report r --pose-source pnp --option bogus_key=1",
       {"--option bogus_key=1", "pnp", "image_delay_ms"}},
      // Unknown options and commands.
      {"list --bogus", {"--bogus"}},
      {"simulate --scenario mav-figure-eight --out out --bogus 1", {"--bogus"}},
  };
  // Every scenario rejects a key it does not have, naming its known keys.
  for (const char* scenario : {"mav-figure-eight", "tag-arena-hover", "tag-arena-dynamic",
                               "three-point-hover", "stereo-obstacles", "marker-board-flight",
                               "laser-plane", "euroc-laser", "aprilgrid-calibration"}) {
    cases.push_back({std::string("simulate --scenario ") + scenario + " --out out --set typo_key=1",
                     {"typo_key", scenario, "known:"}});
  }
  // compare goes through the same check (a few scenarios: each case starts mavloc once).
  for (const char* scenario : {"tag-arena-dynamic", "laser-plane", "euroc-laser"})
    cases.push_back({std::string("compare --scenario ") + scenario + " --set typo_key=1",
                     {"typo_key", scenario}});
  // euroc-laser's IMU noise model, on the real EuRoC folder: a bad scale, a file without IMU
  // densities (cam0's sensor.yaml), and the same through repro smoother's settings.
  if (testing::HasSharedData()) {
    const std::string euroc = testing::SharedDataDir() + "/euroc_v1_01_easy";
    const std::string simulate = "simulate --scenario euroc-laser --out out --set data=" + euroc;
    cases.push_back({simulate + " --set imu_noise_scale=0", {"imu_noise_scale", "(0, 1000]"}});
    cases.push_back({simulate + " --set imu_noise_scale=1e6", {"imu_noise_scale"}});
    cases.push_back({simulate + " --set imu_noise_model=" + euroc + "/mav0/cam0/sensor.yaml",
                     {"cam0/sensor.yaml", "imu_noise_model", "no IMU noise densities"}});
    cases.push_back(
        {simulate + " --set imu_noise_model=" + euroc + "/missing.yaml", {"missing.yaml"}});
    cases.push_back({"repro smoother --runs 1 --set scenarios=euroc-laser --set euroc_data=" +
                         euroc + " --set euroc_imu_noise_scale=-2 --report r",
                     {"imu_noise_scale"}});
    // euroc-vision's settings: refused before anything is rendered or written.
    const std::string vision =
        "simulate --scenario euroc-vision --render --out out --set data=" + euroc;
    cases.push_back({vision + " --set cameras=three", {"cameras", "stereo or mono"}});
    cases.push_back({vision + " --set imu=simulated", {"imu", "from_ground_truth"}});
    cases.push_back({vision + " --set image_scale=5", {"image_scale", "[0.1, 1]"}});
    cases.push_back({vision + " --set texel_m=1", {"texel_m"}});
    cases.push_back({vision + " --set camera_rate_hz=0", {"camera_rate_hz"}});
    cases.push_back(
        {vision + " --set textures=" + euroc + "/no_such_folder", {"no_such_folder", "textures"}});
    cases.push_back(
        {"compare --scenario euroc-vision --set data=" + euroc + " --set cameras=three --report r",
         {"cameras", "stereo or mono"}});
    cases.push_back({"compare --scenario euroc-vision --set data=" + euroc +
                         " --option smoother:track_window_s=-1 --report r",
                     {"track_window_s"}});
  }
  return cases;
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(BadOptions, EveryCaseExitsTwoWithOneLineAndWritesNothing) {
  const std::vector<Case> cases = Cases();
  ASSERT_GE(cases.size(), 85u);
  const std::string root = testing::MakeTempDir();
  int index = 0;
  for (const Case& c : cases) {
    SCOPED_TRACE("mavloc " + c.args);
    const std::string work = root + "/case" + std::to_string(index);
    const std::string err = root + "/stderr" + std::to_string(index) + ".txt";
    ++index;
    fs::create_directories(work);
    // MAVLOC_FIGURES=0: no figure drawing should be reached anyway.
    const testing::CommandResult r =
        testing::RunCommand("sh -c 'cd " + work + " && MAVLOC_FIGURES=0 " + testing::CliPath() +
                            " " + c.args + " >/dev/null 2>" + err + "'");
    const std::string message = ReadFile(err);
    EXPECT_EQ(r.exit_code, 2) << message;
    ASSERT_FALSE(message.empty());
    EXPECT_EQ(message.find('\n'), message.size() - 1) << "not one line: " << message;
    for (const auto& expected : c.expected)
      EXPECT_NE(message.find(expected), std::string::npos)
          << "'" << expected << "' not in: " << message;
    std::vector<std::string> left;
    for (const auto& entry : fs::directory_iterator(work))
      left.push_back(entry.path().filename().string());
    EXPECT_TRUE(left.empty()) << "left behind: " << (left.empty() ? "" : left.front());
  }
}

}  // namespace
}  // namespace mavloc
