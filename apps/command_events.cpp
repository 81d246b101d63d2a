// slipstrip events RUN.h5: the slip-event catalog from the run's slip
// sampling (docs/events.md).
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "apps/cli.hpp"
#include "events/catalog_io.hpp"
#include "events/event_detection.hpp"
#include "io/file_lock.hpp"
#include "io/output_paths.hpp"
#include "solver/checkpoint.hpp"

namespace slipstrip::cli {
namespace {

struct EventsOptions {
  std::string run_path, out_path, csv_path;
  double alpha = 15.0;
  double min_slip_rate = 0.0;  // [v0]; 0: every nodal slip counts
  bool overwrite = false;
};

int events(const EventsOptions& o) {
  if (!(o.min_slip_rate >= 0.0) || !std::isfinite(o.min_slip_rate)) {
    char value[32];
    std::snprintf(value, sizeof value, "%g", o.min_slip_rate);
    throw std::invalid_argument(std::string("--min-slip-rate ") + value +
                                " is invalid: must be a finite number >= 0 (nodal slip rate in units of v0; 0 "
                                "keeps every nodal slip)");
  }
  // The output-path rule (io/output_paths.hpp): --out and --csv never name
  // the run file (the default --out, the run file itself, adds /events to it)
  // nor, without --overwrite, an existing file.
  const io::OutputPath outputs[] = {{"--out", o.out_path}, {"--csv", o.csv_path}};
  const std::string inputs[] = {o.run_path};
  io::check_output_paths(outputs, inputs, o.overwrite);
  // Writing into the run file: not while a run or resume writes it.
  std::optional<io::FileLock> lock;
  if (o.out_path.empty()) lock.emplace(run_lock_path(o.run_path), "run file '" + o.run_path + "'");
  events::EventDetectionOptions options;
  options.alpha = o.alpha;
  options.min_slip_rate_v0 = o.min_slip_rate;
  events::EventCatalog catalog;
  try {
    catalog = events::detect_events_in_file(o.run_path, options);
  } catch (const std::runtime_error& e) {
    // An HDF5 read failure (truncated or damaged file) is bad input, not a bug: exit 2.
    throw std::invalid_argument("run file '" + o.run_path + "' cannot be read: " + e.what());
  }
  const std::string target = o.out_path.empty() ? o.run_path : o.out_path;
  events::write_event_catalog(target, catalog);
  if (!o.csv_path.empty()) events::write_event_catalog_csv(o.csv_path, catalog);
  std::printf("%llu nodal slips", static_cast<unsigned long long>(catalog.n_nodal_slips));
  if (o.min_slip_rate > 0.0)
    std::printf(" (%llu slower than %g v0 ignored)",
                static_cast<unsigned long long>(catalog.n_nodal_slips_below_min_slip_rate), o.min_slip_rate);
  std::printf(", %llu events detected, %zu kept (alpha = %g, waiting-time threshold %.4g s); catalog in %s:/events\n",
              static_cast<unsigned long long>(catalog.n_events_detected), catalog.n_events(), o.alpha,
              catalog.waiting_time_threshold, target.c_str());
  if (catalog.n_events() == 0) {
    // The catalog (its counts) is written, but holds nothing to work with:
    // say why and what to change, and exit 1 as `analyze` does.
    std::fprintf(stderr, "events: %s\n", events::empty_catalog_reason(catalog).c_str());
    return 1;
  }
  return 0;
}

}  // namespace

Command add_events_command(CLI::App& app) {
  auto o = std::make_shared<EventsOptions>();
  auto* ev = app.add_subcommand("events", "Detect slip events from /slip_sampling (paper's slip-sampled procedure)");
  ev->add_option("run", o->run_path, "Run file (or a file holding only /slip_sampling)")->required();
  ev->add_option("--alpha", o->alpha, "Waiting-time threshold factor alpha (threshold alpha*delta_th/(v0 N))");
  ev->add_option("--min-slip-rate", o->min_slip_rate,
                 "Ignore nodal slips slower than this many v0 (rate delta_th/Delta t), e.g. creep; 0 (default) "
                 "keeps all (docs/events.md)");
  ev->add_option("--out", o->out_path, "Catalog HDF5 file (default: add /events to the run file)");
  ev->add_option("--csv", o->csv_path, "Also write the catalog as CSV");
  ev->add_flag("--overwrite", o->overwrite, "Replace an existing --out or --csv file (never the run file itself)");
  return {ev, [o] { return events(*o); }};
}

}  // namespace slipstrip::cli
