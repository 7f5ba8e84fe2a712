// Consistency of an estimator's own covariances over Monte-Carlo runs (Bar-Shalom, Li,
// Kirubarajan, "Estimation with Applications to Tracking and Navigation", 2001, sec. 5.4.2): the
// normalised estimation error squared NEES_k = e_k^T P_k^-1 e_k per time step (position x y z and
// attitude roll pitch yaw, 3 dof each), averaged over the N runs (ANEES, not divided by the dof:
// its expectation is 3 for a consistent estimator), with the two-sided 95 % band of chi^2(3N) / N
// and the fraction of time steps inside it. Judged on simulations only (the only place with a
// truth whose noise is known).
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/estimate.h"

namespace mavloc {

// The p-quantile of chi^2 with k degrees of freedom (Wilson–Hilferty approximation, relative
// error below 1e-3 for k >= 3 in the 2.5 % and 97.5 % tails).
double ChiSquareQuantileWh(double k, double p);

struct NeesAccumulator {
  // Per time step (stamp rounded to 1 ms): sum of NEES over runs and the number of runs.
  std::map<TimeNs, std::pair<double, int>> position, attitude;
  int runs = 0;
};

// Adds one run: NEES at every stamp of estimate.covariances that has a pose (Estimate::poses, or
// the quantities x y z roll pitch yaw) and a ground-truth state (interpolated between rows at most
// 8 ms apart, else the nearest row within 2 ms), and whose covariance names x y z (position) or
// roll pitch yaw (attitude). Returns false when the estimate has no such covariance.
bool AccumulateNees(const Dataset& dataset, const Estimate& estimate, NeesAccumulator* nees);

// Adds the sums of `other` (runs computed elsewhere, e.g. in a sweep worker) to `nees`.
void MergeNees(const NeesAccumulator& other, NeesAccumulator* nees);
// Every field as JSON and back, exactly ({"runs": n, "position": [[t_ns, sum, count], ...],
// "attitude": [...]}); throws nlohmann's exceptions for a malformed object.
nlohmann::json NeesToJson(const NeesAccumulator& nees);
NeesAccumulator NeesFromJson(const nlohmann::json& json);

struct AneesSummary {
  bool available = false;
  int runs = 0;
  int steps = 0;          // time steps with every run
  double mean_anees = 0;  // mean over those steps
  double band_low = 0, band_high = 0;
  double fraction_inside = 0;  // of those steps
};
// Over the time steps every run reached (steps with fewer runs are left out).
AneesSummary SummarizeAnees(const std::map<TimeNs, std::pair<double, int>>& series, int runs);

}  // namespace mavloc
