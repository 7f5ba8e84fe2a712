// `mavloc repro apriltag`: the simulations of de Almeida Barbosa, Dias, dos Santos (AprilTag
// visual-inertial EKF, section V), end to end from images: the arena is rendered at every camera
// frame (datasets/rendering), the tags are detected by libapriltag (frontends/apriltag,
// RectifiedTagDetector), each detection becomes a per-tag PnP pose, and tag-ekf filters them with
// the IMU. Tables:
// - images:  how the detector did on the rendered frames (recall, corner error against the true
//            projection, per-tag pose error), and the time per frame of rendering and detection;
// - hover:   V-B, Monte-Carlo over the filter's initial state (N runs, default 100; each run also
//            draws its own IMU noise): time for the position, velocity and attitude errors to
//            converge below stated thresholds (the paper: about 2 s) and their final values;
// - dynamic: V-C, the fast-turn flight from x0 = [0 0 0.08 0...] with the filter started at zero:
//            peak errors after convergence, with tags (delay compensated, and the naive filter that
//            ignores the delay), without tags (prediction only: it drifts), and tag-pnp; against
//            the paper's peaks (position < 0.05 m, velocity < 0.06 m/s, roll < 0.009 rad, pitch <
//            0.014 rad);
// - nees:    the hover runs' average NEES of position, velocity and attitude against the 95 %
//            chi-square band for N runs.
// Settings (`--set key=value`): hover_duration_s (10), dynamic_duration_s (40), images (1; 0 uses
// the projected corners with corner_noise_px instead), supersampling (4), exposure_s (0: no motion
// blur), image_noise_grey (2), processing_delay_s (0.05), refine_edges (1), decimate (1),
// hover_images_seed (the seed of the hover's image noise; default: the first seed).
// Default runtime: about a minute on 2 cores (500 rendered and detected frames, 100 EKF runs).
//
// The units are (dynamic, first seed) — the flight rendered, detected and filtered by every
// variant — and (hover, seed) for every seed — both P0 variants of one Monte-Carlo run, on the
// hover images (rendered once per process: the hover flight does not change with the seed). Each
// returns JSON, so `--jobs N` gives the numbers of `--jobs 1` (only wall times differ).
#pragma once

#include "evaluation/repro/repro.h"

namespace mavloc {

ReproDefinition AprilTagRepro();

}  // namespace mavloc
