#pragma once
// Datasets: whole arrays written once, and incremental ("extendible") datasets
// that grow by rows as a run appends to them (io/hdf5.hpp for errors,
// io/attributes.hpp for the number types and the string encoding).
#include <optional>
#include <stdexcept>
#include <span>
#include <string>
#include <vector>

#include "io/attributes.hpp"
#include "io/hdf5.hpp"

namespace slipstrip::io {

// --- Whole arrays ---------------------------------------------------------------

// Creates dataset `name` of shape `dims` (row-major `values`, whose size must
// be the product of dims) in `group`.  `chunk` empty: contiguous storage.
void write_array(hid_t group, const std::string& name, std::span<const hsize_t> dims, NumberTypes types,
                 const void* values, std::span<const hsize_t> chunk = {});
template <Number T>
void write_array(hid_t group, const std::string& name, std::span<const hsize_t> dims, std::span<const T> values,
                 std::span<const hsize_t> chunk = {});
template <Number T>
void write_vector(hid_t group, const std::string& name, std::span<const T> values) {
  const hsize_t dims[1] = {values.size()};
  write_array<T>(group, name, dims, values);
}
template <Number T>
void write_vector(hid_t group, const std::string& name, const std::vector<T>& values) {
  write_vector(group, name, std::span<const T>(values));
}

// A 1-D dataset of strings (variable-length UTF-8, io/attributes.hpp).
void write_strings(hid_t group, const std::string& name, std::span<const std::string> texts);
std::vector<std::string> read_strings(hid_t group, const std::string& name);

// Rewrites every value of an existing dataset; `count` must equal its number
// of elements (values row-major).
void overwrite(hid_t dataset, NumberTypes types, const void* values, std::size_t count);
template <Number T>
void overwrite(hid_t dataset, std::span<const T> values) {
  overwrite(dataset, number_types<T>(), values.data(), values.size());
}

// Shape of a dataset ({} for a scalar).
std::vector<hsize_t> extent(hid_t dataset);

// Opens a 1-D numeric dataset for read_vector (checks as read_vector says).
struct OpenVector {
  Handle dataset;
  std::size_t size = 0;
};
OpenVector open_vector(hid_t group, const std::string& name);
// Reads a whole dataset into `values`, converted to `memory_type`.
void read_all(hid_t dataset, hid_t memory_type, void* values);

// A 1-D numeric dataset read whole.  Missing, not 1-D, or not numbers:
// std::invalid_argument naming the file and dataset.
template <Number T>
std::vector<T> read_vector(hid_t group, const std::string& name);

// --- Incremental datasets ---------------------------------------------------------

// An extendible float64 dataset: [rows] (columns == 0) or [rows, columns],
// starting with 0 rows; rows are unlimited.
struct ExtendibleLayout {
  hsize_t columns = 0;        // 0 = 1-D
  // > 0: a 3-D dataset [rows, planes, columns] (e.g. one [nodes_z, nodes_x]
  // field per row); each row is planes * columns values, chunk [chunk_rows,
  // planes, columns].
  hsize_t planes = 0;
  hsize_t chunk_rows = 1024;  // chunk shape [chunk_rows] or [chunk_rows, chunk_columns]
  hsize_t chunk_columns = 0;  // 2-D only; 0 = all columns
  // Deflate level 0..9 (with shuffle); 0 = uncompressed.  Uncompressed chunks
  // are rewritten in place when a later append fills a partial chunk; a
  // compressed chunk is reallocated and its old space is lost in the file.
  int deflate = 0;
  // Value of elements never written, allocated with the chunk (e.g. NaN =
  // "not reached yet"); none = HDF5's default 0.
  std::optional<double> fill = std::nullopt;
};
Handle create_extendible(hid_t group, const std::string& name, const ExtendibleLayout& layout);

// Number of rows (dims[0]).
hsize_t rows_of(hid_t dataset);
// Sets the number of rows: grows (new rows hold the fill value) or cuts.
void set_rows(hid_t dataset, hsize_t rows);
// Grows to at least `rows` (never cuts).
void grow_rows(hid_t dataset, hsize_t rows);

// Writes `count` rows starting at `first_row` (the dataset must already hold
// them: grow_rows).  1-D: `count` values spaced by `stride` in memory
// (stride > 1 picks one column of an interleaved row buffer); 2-D and 3-D:
// `count` contiguous rows of all the values of a row (stride ignored).
void write_rows(hid_t dataset, hsize_t first_row, hsize_t count, const double* values, hsize_t stride = 1);
// Grows by `count` rows and writes them at the end; returns the new row count.
hsize_t append_rows(hid_t dataset, hsize_t count, const double* values, hsize_t stride = 1);
// Reads rows [first_row, first_row + count) into `values` (count x columns, row-major).
void read_rows(hid_t dataset, hsize_t first_row, hsize_t count, double* values);
// Writes single elements: coordinates[2k], coordinates[2k+1] = (row, column)
// of values[k] (2-D datasets).
void write_elements(hid_t dataset, std::span<const hsize_t> coordinates, std::span<const double> values);

}  // namespace slipstrip::io

// --- templates --------------------------------------------------------------------

namespace slipstrip::io {

template <Number T>
void write_array(hid_t group, const std::string& name, std::span<const hsize_t> dims, std::span<const T> values,
                 std::span<const hsize_t> chunk) {
  hsize_t size = 1;
  for (const hsize_t d : dims) size *= d;
  if (size != values.size())
    throw std::invalid_argument("dataset '" + name + "': " + std::to_string(values.size()) +
                                " values do not fill its shape of " + std::to_string(size));
  write_array(group, name, dims, number_types<T>(), values.data(), chunk);
}

template <Number T>
std::vector<T> read_vector(hid_t group, const std::string& name) {
  const OpenVector vector = open_vector(group, name);
  std::vector<T> values(vector.size);
  if (!values.empty()) read_all(vector.dataset, number_types<T>().memory, values.data());
  return values;
}

}  // namespace slipstrip::io
