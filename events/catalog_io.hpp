#pragma once
// HDF5 and CSV input/output of slip-sampled data and event catalogs.
//   /slip_sampling : written by the solver (or write_slip_sampling for
//                    synthetic input); attributes delta_th, dx, v0, mu, D, L;
//                    datasets x [N], crossing_time [n_levels, N].
//   /events        : the catalog, 1-D datasets with a "units" attribute each.
#include <span>
#include <string>

#include "io/hdf5.hpp"
#include "events/event_detection.hpp"

namespace slipstrip::events {

// Streams /slip_sampling/crossing_time from an open file in row blocks
// (io::read_rows), so the matrix is never loaded whole.
class Hdf5CrossingTimes final : public CrossingTimeSource {
 public:
  explicit Hdf5CrossingTimes(const std::string& path);
  std::size_t n_levels() const override { return n_levels_; }
  std::size_t n_nodes() const override { return n_nodes_; }
  void read_rows(std::size_t j0, std::size_t j1, std::span<double> block) const override;

 private:
  io::Handle file_;
  io::Handle dataset_;
  std::size_t n_levels_ = 0;
  std::size_t n_nodes_ = 0;
};

// Attributes and x of /slip_sampling (x defaults to i * dx if absent).
SlipSamplingInfo read_slip_sampling_info(const std::string& path);

// Reads /slip_sampling of `path` (streaming) and detects events.
EventCatalog detect_events_in_file(const std::string& path, const EventDetectionOptions& options = {});

// The attributes of a /slip_sampling group (delta_th, dx, v0, mu, D, L): one
// definition for the solver's run file (solver/run_output.cpp) and for
// write_slip_sampling.
void write_slip_sampling_attributes(hid_t group, const SlipSamplingInfo& info);

// Creates (truncates) `path` holding only /slip_sampling; crossing_time is
// row-major [n_levels, info.x.size()].  For tests and synthetic input.
void write_slip_sampling(const std::string& path, const SlipSamplingInfo& info,
                         std::span<const double> crossing_time, std::size_t n_levels);

// Writes group /events into `path`: appends to an existing HDF5 file
// (replacing an existing /events group) or creates a new file.
void write_event_catalog(const std::string& path, const EventCatalog& catalog);

// Reads /events back (datasets, thresholds and counts).
EventCatalog read_event_catalog(const std::string& path);

// One header line, then one line per event; columns as in /events.
void write_event_catalog_csv(const std::string& path, const EventCatalog& catalog);

}  // namespace slipstrip::events
