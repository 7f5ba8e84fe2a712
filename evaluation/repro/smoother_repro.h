// `mavloc repro smoother`: is the smoother more accurate than its seed and the papers' filters?
// On every scenario with visual residuals, over N seeds (default 20), the Ceres batch smoother
// (solver/estimators/smoother_estimator.h) against its seed estimator(s) and the paper's filter,
// all run on the SAME simulated dataset per seed with RunAndEvaluate (evaluation/comparison.h).
//
// Scenarios and rows (the smoother first):
//   tag-arena-dynamic, tag-arena-hover: tag-pnp (seed), tag-ekf (AprilTag paper's EKF)
//   marker-board-flight: tag-pnp (seed), pnp and upright-2p (PIXHAWK closed form), pixhawk-kf
//   three-point-hover: three-point (seed), two-point, gravity-ekf (the paper's filter: roll and
//     pitch only), and the smoother with the generic bias prior instead of the one imu0 states
//     (a variant, not judged)
//   mav-figure-eight: the smoother's built-in landmark-pnp seed; no paper filter applies
//   laser-plane, euroc-laser (only when the shared EuRoC data exist): laser-ekf (seed and filter)
//
// Metrics per run: position RMSE and attitude RMSE (rotation angle) of the ATE with alignment
// none, over each estimator's own poses; roll and pitch RMSE from the quantity errors; for the
// laser scenarios the RMSE of d, v_o, roll, pitch, alpha (the observable modes, RR-7906 sect. 4).
// Aggregates: the mean over runs; the smoother "wins" a run against a competitor when it is more
// accurate on position AND attitude (gravity-ekf: roll AND pitch; laser: all five quantities).
// The smoother's position RMSE is also split into the frames its seed solved and the frames it
// bridged by the IMU alone (where the seed, and the closed-form competitors, give no pose).
// Where the smoother is not more accurate, the verdict line says why from the measured numbers.
//
// Settings (`--set key=value`): scenarios (comma list, default all of the above), duration_s
// (every scenario; default: the scenario's own), duration_s.SCENARIO (one scenario), euroc_data
// (EuRoC V1_01_easy folder; default: the scenario's own look-up), euroc_imu_noise_model (a Kalibr
// imu.yaml or EuRoC sensor.yaml whose densities euroc-laser's estimators and bound take),
// euroc_imu_noise_scale (every density times it), smoother.KEY=VALUE (a smoother option for every
// scenario).
//
// Runs on the sweep machinery (evaluation/sweep/): every (scenario, seed) is one unit whose result
// is JSON (the per-estimator metrics, NEES and Cramér–Rao sums of that run),
// and the report is made from those results, in this process (--jobs 1) or from sweep workers
// (`repro smoother --jobs N`), with the same numbers either way. Estimators with their own thread
// pool (the smoother's Ceres solve) run on one thread unless `smoother.threads` says otherwise, so
// that the numbers do not depend on --jobs.
#pragma once

#include "evaluation/repro/repro.h"

namespace mavloc {

ReproDefinition SmootherRepro();

}  // namespace mavloc
