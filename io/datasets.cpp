#include "io/datasets.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "io/strings.hpp"

namespace slipstrip::io {

// --- Whole arrays ---------------------------------------------------------------

void write_array(hid_t group, const std::string& name, std::span<const hsize_t> dims, NumberTypes types,
                 const void* values, std::span<const hsize_t> chunk) {
  const int rank = static_cast<int>(dims.size());
  Handle space = adopt(H5Screate_simple(rank, dims.data(), nullptr), "H5Screate_simple", group, name);
  Handle creation(H5Pcreate(H5P_DATASET_CREATE), "H5Pcreate(dataset create)");
  if (!chunk.empty()) {
    if (chunk.size() != dims.size())
      throw std::invalid_argument("dataset '" + name + "': chunk rank " + std::to_string(chunk.size()) +
                                  " differs from the dataset's rank " + std::to_string(rank));
    check(H5Pset_chunk(creation, rank, chunk.data()), "H5Pset_chunk", group, name);
  }
  const Handle dataset =
      adopt(H5Dcreate2(group, name.c_str(), types.file, space, H5P_DEFAULT, creation, H5P_DEFAULT), "H5Dcreate2",
            group, name);
  hsize_t size = 1;
  for (const hsize_t d : dims) size *= d;
  if (size > 0)
    check(H5Dwrite(dataset, types.memory, H5S_ALL, H5S_ALL, H5P_DEFAULT, values), "H5Dwrite", group, name);
}

void write_strings(hid_t group, const std::string& name, std::span<const std::string> texts) {
  const Handle type = utf8_string_type();
  const hsize_t dims[1] = {texts.size()};
  Handle space = adopt(H5Screate_simple(1, dims, nullptr), "H5Screate_simple", group, name);
  const Handle dataset =
      adopt(H5Dcreate2(group, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "H5Dcreate2",
            group, name);
  if (texts.empty()) return;
  const std::vector<const char*> pointers = c_strings(texts);
  check(H5Dwrite(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, pointers.data()), "H5Dwrite", group, name);
}

std::vector<std::string> read_strings(hid_t group, const std::string& name) {
  const Handle dataset = open_dataset(group, name);
  const Handle type = adopt(H5Dget_type(dataset), "H5Dget_type", group, name);
  const std::vector<hsize_t> dims = extent(dataset);
  if (dims.size() != 1 || H5Tget_class(type) != H5T_STRING)
    throw std::invalid_argument(member_path(group, name) + " is invalid: expected a 1-D dataset of strings");
  std::vector<std::string> texts = read_string_values(type, dims[0], [&](hid_t memory_type, void* buffer) {
    return H5Dread(dataset, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer);
  });
  if (texts.size() != dims[0]) throw_failure("H5Dread", group, name);
  return texts;
}

void overwrite(hid_t dataset, NumberTypes types, const void* values, std::size_t count) {
  hsize_t size = 1;
  for (const hsize_t d : extent(dataset)) size *= d;
  if (size != count)
    throw std::invalid_argument(object_path(dataset) + " holds " + std::to_string(size) + " values, not the " +
                                std::to_string(count) + " given to rewrite it");
  if (count > 0) check(H5Dwrite(dataset, types.memory, H5S_ALL, H5S_ALL, H5P_DEFAULT, values), "H5Dwrite", dataset);
}

std::vector<hsize_t> extent(hid_t dataset) {
  const Handle space = adopt(H5Dget_space(dataset), "H5Dget_space", dataset);
  const int rank = H5Sget_simple_extent_ndims(space);
  if (rank < 0) throw_failure("H5Sget_simple_extent_ndims", dataset);
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  if (rank > 0) check(H5Sget_simple_extent_dims(space, dims.data(), nullptr), "H5Sget_simple_extent_dims", dataset);
  return dims;
}

OpenVector open_vector(hid_t group, const std::string& name) {
  OpenVector vector{open_dataset(group, name), 0};
  const std::vector<hsize_t> dims = extent(vector.dataset);
  if (dims.size() != 1)
    throw std::invalid_argument(object_path(group) + " dataset '" + name + "' is invalid: must be 1-D");
  const Handle type = adopt(H5Dget_type(vector.dataset), "H5Dget_type", group, name);
  const H5T_class_t kind = H5Tget_class(type);
  if (kind != H5T_FLOAT && kind != H5T_INTEGER)
    throw std::invalid_argument(object_path(group) + " dataset '" + name +
                                "' is invalid: must hold numbers (integers or floats)");
  vector.size = static_cast<std::size_t>(dims[0]);
  return vector;
}

void read_all(hid_t dataset, hid_t memory_type, void* values) {
  check(H5Dread(dataset, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values), "H5Dread", dataset);
}

// --- Incremental datasets ---------------------------------------------------------

Handle create_extendible(hid_t group, const std::string& name, const ExtendibleLayout& layout) {
  const int rank = layout.columns == 0 ? 1 : layout.planes == 0 ? 2 : 3;
  const hsize_t dims[3] = {0, rank == 3 ? layout.planes : layout.columns, layout.columns};
  const hsize_t max_dims[3] = {H5S_UNLIMITED, dims[1], dims[2]};
  const hsize_t chunk[3] = {layout.chunk_rows,
                            rank == 3 || layout.chunk_columns == 0 ? dims[1] : layout.chunk_columns, dims[2]};
  if (layout.deflate < 0 || layout.deflate > 9)
    throw std::invalid_argument("dataset '" + name + "': deflate level " + std::to_string(layout.deflate) +
                                " is invalid: allowed 0..9");
  Handle space = adopt(H5Screate_simple(rank, dims, max_dims), "H5Screate_simple", group, name);
  Handle creation(H5Pcreate(H5P_DATASET_CREATE), "H5Pcreate(dataset create)");
  check(H5Pset_chunk(creation, rank, chunk), "H5Pset_chunk", group, name);
  if (layout.deflate > 0) {
    check(H5Pset_shuffle(creation), "H5Pset_shuffle", group, name);
    check(H5Pset_deflate(creation, static_cast<unsigned>(layout.deflate)), "H5Pset_deflate", group, name);
  }
  if (layout.fill) {
    const double fill = *layout.fill;
    check(H5Pset_fill_value(creation, H5T_NATIVE_DOUBLE, &fill), "H5Pset_fill_value", group, name);
    check(H5Pset_fill_time(creation, H5D_FILL_TIME_ALLOC), "H5Pset_fill_time", group, name);
  }
  return adopt(H5Dcreate2(group, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, creation, H5P_DEFAULT),
               "H5Dcreate2", group, name);
}

hsize_t rows_of(hid_t dataset) {
  const std::vector<hsize_t> dims = extent(dataset);
  if (dims.empty())
    throw std::invalid_argument(object_path(dataset) + " is invalid: a scalar where rows are expected");
  return dims[0];
}

void set_rows(hid_t dataset, hsize_t rows) {
  std::vector<hsize_t> dims = extent(dataset);
  if (dims.empty())
    throw std::invalid_argument(object_path(dataset) + " is invalid: a scalar where rows are expected");
  dims[0] = rows;
  check(H5Dset_extent(dataset, dims.data()), "H5Dset_extent", dataset);
}

void grow_rows(hid_t dataset, hsize_t rows) {
  if (rows_of(dataset) < rows) set_rows(dataset, rows);
}

namespace {

// The file dataspace of `dataset` with rows [first_row, first_row + count)
// selected, and the row width (0 for 1-D).
struct RowSelection {
  Handle file_space;
  hsize_t columns = 0;
};

RowSelection select_rows(hid_t dataset, hsize_t first_row, hsize_t count) {
  RowSelection selection{adopt(H5Dget_space(dataset), "H5Dget_space", dataset), 0};
  const int rank = H5Sget_simple_extent_ndims(selection.file_space);
  if (rank < 1 || rank > 3)
    throw std::invalid_argument(object_path(dataset) + " is invalid: rank " + std::to_string(rank) +
                                ", rows need a 1-D, 2-D or 3-D dataset");
  hsize_t dims[3] = {0, 1, 1};
  check(H5Sget_simple_extent_dims(selection.file_space, dims, nullptr), "H5Sget_simple_extent_dims", dataset);
  if (first_row + count > dims[0])
    throw std::out_of_range(object_path(dataset) + ": rows [" + std::to_string(first_row) + ", " +
                            std::to_string(first_row + count) + ") are beyond its " + std::to_string(dims[0]) +
                            " rows");
  // A row of a 3-D dataset is written and read as one flat row of
  // planes * columns values (the memory space has the same number of elements).
  selection.columns = rank == 1 ? 0 : dims[1] * dims[2];
  const hsize_t start[3] = {first_row, 0, 0};
  const hsize_t block[3] = {count, dims[1], dims[2]};
  check(H5Sselect_hyperslab(selection.file_space, H5S_SELECT_SET, start, nullptr, block, nullptr),
        "H5Sselect_hyperslab", dataset);
  return selection;
}

}  // namespace

void write_rows(hid_t dataset, hsize_t first_row, hsize_t count, const double* values, hsize_t stride) {
  if (count == 0) return;
  const RowSelection selection = select_rows(dataset, first_row, count);
  Handle memory_space;
  if (selection.columns == 0) {
    // Every stride-th value of the buffer (one column of interleaved rows).
    const hsize_t memory_dims[1] = {(count - 1) * stride + 1};
    memory_space = Handle(H5Screate_simple(1, memory_dims, nullptr), "H5Screate_simple(memory)");
    const hsize_t start[1] = {0}, step[1] = {stride}, picked[1] = {count};
    check(H5Sselect_hyperslab(memory_space, H5S_SELECT_SET, start, step, picked, nullptr),
          "H5Sselect_hyperslab(memory)");
  } else {
    const hsize_t memory_dims[2] = {count, selection.columns};
    memory_space = Handle(H5Screate_simple(2, memory_dims, nullptr), "H5Screate_simple(memory)");
  }
  check(H5Dwrite(dataset, H5T_NATIVE_DOUBLE, memory_space, selection.file_space, H5P_DEFAULT, values), "H5Dwrite",
        dataset);
}

hsize_t append_rows(hid_t dataset, hsize_t count, const double* values, hsize_t stride) {
  const hsize_t first = rows_of(dataset);
  if (count == 0) return first;
  set_rows(dataset, first + count);
  write_rows(dataset, first, count, values, stride);
  return first + count;
}

void read_rows(hid_t dataset, hsize_t first_row, hsize_t count, double* values) {
  if (count == 0) return;
  const RowSelection selection = select_rows(dataset, first_row, count);
  const hsize_t memory_dims[2] = {count, std::max<hsize_t>(selection.columns, 1)};
  Handle memory_space(H5Screate_simple(selection.columns == 0 ? 1 : 2, memory_dims, nullptr),
                      "H5Screate_simple(memory)");
  check(H5Dread(dataset, H5T_NATIVE_DOUBLE, memory_space, selection.file_space, H5P_DEFAULT, values), "H5Dread",
        dataset);
}

void write_elements(hid_t dataset, std::span<const hsize_t> coordinates, std::span<const double> values) {
  if (values.empty()) return;
  if (coordinates.size() != 2 * values.size())
    throw std::invalid_argument(object_path(dataset) + ": " + std::to_string(coordinates.size()) +
                                " coordinates for " + std::to_string(values.size()) + " values (need 2 per value)");
  const Handle file_space = adopt(H5Dget_space(dataset), "H5Dget_space", dataset);
  check(H5Sselect_elements(file_space, H5S_SELECT_SET, values.size(), coordinates.data()), "H5Sselect_elements",
        dataset);
  const hsize_t count[1] = {values.size()};
  Handle memory_space(H5Screate_simple(1, count, nullptr), "H5Screate_simple(memory)");
  check(H5Dwrite(dataset, H5T_NATIVE_DOUBLE, memory_space, file_space, H5P_DEFAULT, values.data()), "H5Dwrite",
        dataset);
}

}  // namespace slipstrip::io
