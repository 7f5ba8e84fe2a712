// `mavloc repro pixhawk`: PIXHAWK's marker localization (Meier et al., Autonomous Robots 2012,
// sections 3.2, 3.3, 5.1, 7.1-7.2, fig. 15) on the scenario marker-board-flight, N Monte-Carlo
// seeds per configuration (default 5).
//
// Tables (each in report.md, report.json "tables" and details "tables", and <table>.csv):
//   fig15      pnp (vision-only, 4-point baseline) vs upright-2p (IMU roll/pitch + known-vertical
//              2-point RANSAC + least squares) on the same corners at the scenario's defaults, the
//              roll/pitch coming from the gravity EKF of the three-point paper on the simulated
//              IMU.
//   sweep      the same comparison while one factor changes: the IMU attitude error (ground-truth
//              roll/pitch + a Gauss-Markov error of 0.05..2 deg, tau 1 s; with all markers and with
//              one marker in view), the pixel noise (0.5..3 px), the markers in view (1, 2, 4,
//              all) and gross outliers (0..20 % of corners displaced 20-60 px; upright-2p also
//              without RANSAC).
//   kf         the 4 x 1-D Kalman filters (pixhawk-kf) fed by upright-2p or pnp (with and without
//              the roll/pitch outlier check), at the defaults, with one marker in view, and with
//              20 % of frames dropped (measured vs nominal dt).
//   timestamps exposure (hardware trigger) vs arrival stamps (exposure + 16-19 ms) without and
//              with compensation of the mean delay, at 0.5 and 1.5 m/s.
//
// Metrics, pooled over every frame with an output of every run: position error e = |p_est -
// p_true| (truth interpolated at the estimate's stamp, no alignment): RMSE and max; jumps:
// consecutive outputs (<= 0.1 s apart) whose position error changes by more than 10 cm, per run;
// yaw and roll/pitch RMSE; velocity RMSE (kf); outputs: % of camera frames with an estimate.
//
// Settings (`--set key=value`): tables (comma list, default "fig15,sweep,kf,timestamps");
// duration_s (cut the flight, for quick runs); any other key goes to the scenario.
//
// A unit is one configuration of a table (its scenario settings and variants, e.g.
// "sweep-pixel-noise-2" or "kf-frames-dropped") and one seed, and returns the sums behind each
// variant's metrics as JSON; the summary adds them in seed order, so `--jobs N` gives the numbers
// of `--jobs 1` (only the time per frame, a wall time, differs).
#pragma once

#include "evaluation/repro/repro.h"

namespace mavloc {

ReproDefinition PixhawkRepro();

}  // namespace mavloc
