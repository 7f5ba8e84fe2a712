// Seeded randomness (DESIGN.md): every generator takes an explicit seed and the same seed gives
// the same bytes on every platform. std::normal_distribution is implementation-defined, so the
// Gaussian draws here are mavloc's own (Marsaglia polar method on a 64-bit Mersenne twister).
//
// Same bytes with every compiler: two draws must never be unsequenced operands of one expression.
// The arguments of a function call, of a constructor in parentheses and of + or * are evaluated in
// an order the compiler chooses (gcc and clang differ), so `Vector2d(rng.Gaussian(),
// rng.Gaussian())` swaps the components between the two builds. Draw vectors with
// GaussianVector<N>(), put several draws in a braced list (`Vector3d{rng.Uniform(a, b),
// rng.Uniform(c, d), 0.0}`: evaluated left to right) or in separate statements.
// tests/datasets/simulation_determinism_test.cc holds every scenario's data to one fingerprint.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <random>

namespace mavloc {

class Rng {
 public:
  explicit Rng(uint64_t seed) : engine_(seed) {}

  // Uniform in [0, 1).
  double Uniform();
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  // Uniform integer in [lo, hi].
  int UniformInt(int lo, int hi);
  double Gaussian();  // standard normal
  double Gaussian(double mean, double sigma) { return mean + sigma * Gaussian(); }
  Eigen::Vector3d Gaussian3(double sigma) { return sigma * GaussianVector<3>(); }
  // N standard normal draws, component 0 first.
  template <int N>
  Eigen::Matrix<double, N, 1> GaussianVector() {
    Eigen::Matrix<double, N, 1> v;
    for (int i = 0; i < N; ++i) v[i] = Gaussian();
    return v;
  }

 private:
  std::mt19937_64 engine_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

// Independent seeds for the streams of one simulation, derived from a master seed (SplitMix64).
struct SimulationSeeds {
  uint64_t motion = 0;
  uint64_t imu = 0;
  uint64_t camera = 0;
  uint64_t other = 0;  // anything else a scenario draws (outliers, initial filter errors, ...)
  static SimulationSeeds FromMaster(uint64_t master_seed);
};

uint64_t SplitMix64(uint64_t x);

}  // namespace mavloc
