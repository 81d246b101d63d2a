// slipstrip bench: time per step and memory (the measurement is apps/bench.cpp).
#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "apps/bench.hpp"
#include "apps/cli.hpp"

namespace slipstrip::cli {
namespace {

// The config's spelling of the history algorithms (config/simulation_config.hpp).
std::map<std::string, HistoryAlgorithm> history_algorithms_by_name() {
  std::map<std::string, HistoryAlgorithm> out;
  for (std::size_t i = 0; i < std::size(kHistoryAlgorithmNames); ++i)
    out.emplace(kHistoryAlgorithmNames[i], static_cast<HistoryAlgorithm>(i));
  return out;
}

}  // namespace

Command add_bench_command(CLI::App& app) {
  auto o = std::make_shared<BenchOptions>();
  auto* bench = app.add_subcommand("bench", "Time per step and memory for N = 256..16384, H/L = 0.025, 0.25 and half-space");
  bench->add_flag("--json", o->json, "One JSON object per line");
  bench->add_option("--nodes", o->nodes, "Node counts to time (comma-separated)")->delimiter(',');
  bench->add_option("--steps", o->steps, "Time steps per measurement");
  bench->add_option("--threads", o->threads, "OpenMP threads (default 1)");
  bench->add_option("--nodes-z", o->nodes_z,
                    "> 1: time 2D interfaces of N x nodes-z nodes (dz = dx, L_x = 4 m; docs/3d.md)")
      ->check(CLI::PositiveNumber);
  bench->add_option_function<std::vector<std::string>>(
          "--heights",
          [o](const std::vector<std::string>& values) {
            o->heights.clear();
            for (const auto& v : values) {
              const double h = v == "inf" ? std::numeric_limits<double>::infinity() : std::stod(v);
              if (!(h > 0)) throw CLI::ValidationError("--heights", "each height must be > 0 or inf, got " + v);
              o->heights.push_back(h);
            }
          },
          "Strip heights H [m] to time, comma-separated; inf = half-space (default 0.1,1,inf)")
      ->delimiter(',');
  bench->add_option_function<std::vector<std::string>>(
          "--planes",
          [o](const std::vector<std::string>& values) {
            o->planes.clear();
            for (const auto& v : values) {
              const auto* at = std::find(std::begin(kPlaneConditionNames), std::end(kPlaneConditionNames), v);
              if (at == std::end(kPlaneConditionNames))
                throw CLI::ValidationError("--planes", "each plane must be strain, stress or antiplane, got " + v);
              o->planes.push_back(static_cast<PlaneCondition>(at - std::begin(kPlaneConditionNames)));
            }
          },
          "Plane conditions to time, comma-separated (default strain; strain,antiplane adds the antiplane "
          "rows and their time ratio to in-plane)")
      ->delimiter(',');
  bench->add_flag("--pairs", o->dissimilar,
                  "Also time a pair of different bodies (bottom body: same height and wave speeds, twice mu "
                  "and rho; at inf a pair of half-spaces with four times mu and the same rho) at each "
                  "height and plane, its ratio to the identical "
                  "in-plane pair and, with antiplane, the antiplane pair's ratio to the in-plane one");
  bench->add_option("--half-space-pair", o->half_space_pair,
                    "The pair of different half-spaces (--pairs at inf): combined (one operator of the interface, "
                    "the default) or bodies (each body's own), as time.half_space_pair")
      ->transform(CLI::CheckedTransformer(std::map<std::string, HalfSpacePairOperator>{
                                              {"combined", HalfSpacePairOperator::combined},
                                              {"bodies", HalfSpacePairOperator::bodies}},
                                          CLI::ignore_case));
  bench->add_option("--antiplane-pair", o->antiplane_pair,
                    "The antiplane pair of different bodies (--pairs, antiplane; finite strips, or half-spaces "
                    "at inf): combined (one operator of the pair, the default) or bodies (each body's own), as "
                    "time.antiplane_pair")
      ->transform(CLI::CheckedTransformer(std::map<std::string, AntiplanePairOperator>{
                                              {"combined", AntiplanePairOperator::combined},
                                              {"bodies", AntiplanePairOperator::bodies}},
                                          CLI::ignore_case));
  bench->add_option("--history", o->history, "Strip history algorithm: auto, modal or block (same operator)")
      ->transform(CLI::CheckedTransformer(history_algorithms_by_name(), CLI::ignore_case));
  bench->add_option("--max-gib", o->max_operator_gib,
                    "Skip cases whose estimated history-operator memory exceeds this [GiB]");
  return {bench, [o] { return run_bench(*o); }};
}

}  // namespace slipstrip::cli
