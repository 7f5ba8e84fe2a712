// What the smoother estimator's runs share (smoother_estimator.cc, smoother_tracks.cc).
#pragma once

#include <Eigen/Geometry>

#include "core/dataset.h"
#include "core/estimate.h"
#include "solver/smoother/smoother_problem.h"

namespace mavloc {

// d(roll, pitch, yaw) / d(dtheta) for R Exp(dtheta), by central differences.
Eigen::Matrix3d EulerJacobian(const Eigen::Quaterniond& q);

// fit_imu_noise=1: the IMU noise densities scaled until the IMU residuals' chi2 matches their
// redundancy; the scale and the rounds are said in the estimate.
void RefitImuNoise(const Dataset& dataset, const SmootherProblemOptions& options,
                   SmootherResult* result, Estimate* estimate);

// An unusable solution counts all `frames` as failures under "smoother: <why>" and returns true.
bool CountUnusableSolve(const SmootherResult& result, int frames, Estimate* estimate);

// An estimate whose last solve stopped at max_iterations says so in its events.
void NoteUnconverged(const SmootherResult& result, int max_iterations, Estimate* estimate);

// Feature tracks of unknown landmarks (no map landmarks, not the three-point world).
bool HasFeatureTracks(const Dataset& dataset);

}  // namespace mavloc
