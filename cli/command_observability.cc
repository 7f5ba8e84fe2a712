// mavloc observability laser: the rank of the laser-spot system's observability matrix from Lie
// derivatives (Martinelli & Troiani, INRIA RR-7906, 2012, section 3 and appendix B), computed at
// random states, with its singular values.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include "cli/commands.h"
#include "cli/option_checks.h"
#include "core/errors.h"
#include "core/random.h"
#include "solver/laser/observability.h"

namespace mavloc::cli {

void RegisterObservability(CLI::App& app, int* exit_code) {
  auto* command = app.add_subcommand(
      "observability", "Observability rank of a system from Lie derivatives (system: laser)");
  auto system = std::make_shared<std::string>();
  auto states = std::make_shared<int>(3);
  auto seed = std::make_shared<unsigned>(1);
  auto order = std::make_shared<int>(2);
  auto L = std::make_shared<double>(0.3);
  command->add_option("system", *system, "System to analyse: laser")->required();
  command->add_option("--states", *states, "Number of random states")->check(WholeNumber(1, 1000));
  command->add_option("--seed", *seed, "Seed of the random states")
      ->check(WholeNumber(0, 4294967295LL));
  command->add_option("--order", *order, "Highest Lie-derivative order (0..2)")
      ->check(WholeNumber(0, 2));
  command->add_option("--L", *L, "Laser offset L in metres")->check(PositiveAtMost(100.0, "m"));
  command->callback([=] {
    if (*system != "laser")
      throw InputError("observability: unknown system '" + *system + "' (known: laser)");
    std::printf(
        "Laser-spot system (Martinelli & Troiani, RR-7906, sect. 3, app. B): state [r, v, q, k] "
        "(dimension 11),\noutputs h_cam (eq. 3) and q*q (eq. 4), inputs A, Omega; gradients of "
        "the Lie derivatives up to order %d.\n",
        *order);
    Rng rng(*seed);
    ObservabilityOptions options;
    options.L_m = *L;
    options.max_order = *order;
    int rank_min = 11, rank_max = 0;
    for (int s = 0; s < *states; ++s) {
      const LaserSystemState S = RandomLaserSystemState(rng, *L);
      const ObservabilityResult result = LaserObservability(S, options);
      rank_min = std::min(rank_min, result.rank);
      rank_max = std::max(rank_max, result.rank);
      std::printf("\nstate %d: rank %d of %d (%d Lie derivatives)\n  singular values:", s + 1,
                  result.rank, 11, result.rows);
      for (int i = 0; i < result.singular_values.size(); ++i)
        std::printf(" %.3e", result.singular_values[i]);
      std::printf("\n");
    }
    const std::string rank = rank_min == rank_max
                                 ? std::to_string(rank_min)
                                 : std::to_string(rank_min) + ".." + std::to_string(rank_max);
    std::printf(
        "\nrank %s: %d observable modes (the paper: 6, m1..m6 of eq. 7), %d continuous symmetries "
        "(appendix B: 5)\n",
        rank.c_str(), rank_max, 11 - rank_max);
    *exit_code = 0;
  });
}

}  // namespace mavloc::cli
