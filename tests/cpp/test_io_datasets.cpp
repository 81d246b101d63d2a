// io/ datasets and handles: whole arrays and string datasets round-trip;
// incremental (extendible) datasets appended in chunks, across file openings,
// read back exactly; handles close (HDF5's open-object count returns to its
// baseline, also after errors); failures name the file and the object.
#include <doctest/doctest.h>
#include <hdf5.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/attributes.hpp"
#include "io/datasets.hpp"
#include "io/hdf5.hpp"
#include "io_test_support.hpp"

using namespace slipstrip;
using io_test::contains;
using io_test::error_of;
using io_test::temp_path;

namespace {

std::vector<double> read_all_rows(hid_t dataset) {
  const std::vector<hsize_t> dims = io::extent(dataset);
  hsize_t size = 1;
  for (const hsize_t d : dims) size *= d;
  std::vector<double> values(size);
  io::read_rows(dataset, 0, dims[0], values.data());
  return values;
}

const double nan_value = std::numeric_limits<double>::quiet_NaN();

}  // namespace

TEST_CASE("whole arrays and vectors round-trip for every number type; string datasets too") {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const std::string path = temp_path("arrays");
  const std::vector<double> x = {0.0, 0.5e-3, 1e-3, -0.0, std::numeric_limits<double>::max()};
  const std::vector<int> clusters = {1, -2, 2147483647};
  const std::vector<std::uint64_t> levels = {0, 7, 18446744073709551615ull};
  const std::vector<double> matrix = {1, 2, 3, 4, 5, 6};  // [2, 3]
  const std::vector<std::string> names = {"slip", "", "\xce\x94\xce\xb8"};
  {
    io::Handle file = io::create_file(path);
    const io::Handle group = io::create_group(file, "record");
    io::write_vector(group, "x", x);
    io::write_vector(group, "n_clusters", clusters);
    io::write_vector(group, "levels", levels);
    io::write_vector(group, "empty", std::vector<double>{});
    const hsize_t dims[2] = {2, 3}, chunk[2] = {1, 3};
    io::write_array(group, "matrix", dims, std::span<const double>(matrix), chunk);
    io::write_strings(group, "names", names);
    CHECK_THROWS_AS(io::write_array(group, "short", dims, std::span<const double>(x)), std::invalid_argument);
    io::close_file(file);
  }
  const io::Handle file = io::open_file(path, io::FileAccess::read_only);
  const io::Handle group = io::open_group(file, "record");
  CHECK(io::read_vector<double>(group, "x") == x);
  CHECK(std::signbit(io::read_vector<double>(group, "x")[3]));
  CHECK(io::read_vector<int>(group, "n_clusters") == clusters);
  CHECK(io::read_vector<std::uint64_t>(group, "levels") == levels);
  CHECK(io::read_vector<double>(group, "empty").empty());
  CHECK(io::read_strings(group, "names") == names);
  const io::Handle dataset = io::open_dataset(group, "matrix");
  CHECK(io::extent(dataset) == std::vector<hsize_t>{2, 3});
  CHECK(read_all_rows(dataset) == matrix);
  {
    const io::Handle type(H5Dget_type(io::open_dataset(group, "n_clusters")), "type");
    CHECK(H5Tequal(type, H5T_STD_I32LE) > 0);
    const io::Handle names_type(H5Dget_type(io::open_dataset(group, "names")), "type");
    CHECK(H5Tis_variable_str(names_type) > 0);
    CHECK(H5Tget_cset(names_type) == H5T_CSET_UTF8);
  }
  CHECK(io::member_names(group) == std::vector<std::string>{"empty", "levels", "matrix", "n_clusters", "names", "x"});
  // A 2-D dataset is not a vector; strings are not numbers; absent is absent.
  CHECK(error_of([&] { io::read_vector<double>(group, "matrix"); }) ==
        path + ":/record dataset 'matrix' is invalid: must be 1-D");
  CHECK(contains(error_of([&] { io::read_vector<double>(group, "names"); }), "must hold numbers"));
  CHECK(error_of([&] { io::read_vector<double>(group, "slip"); }) ==
        "path = '" + path + "' is invalid: dataset /record/slip is missing");
  CHECK(error_of([&] { io::open_group(file, "events"); }) == "path = '" + path + "' is invalid: group /events is missing");
  CHECK_THROWS_AS(io::read_vector<double>(group, "slip"), std::invalid_argument);
  std::filesystem::remove(path);
}

TEST_CASE("extendible datasets appended in chunks of any size read back exactly, also after reopening") {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const std::string path = temp_path("extendible");
  const hsize_t columns = 5;
  std::vector<double> series_expected, field_expected;
  {
    io::Handle file = io::create_file(path);
    const io::Handle group = io::create_group(file, "timeseries");
    const io::Handle series = io::create_extendible(group, "time", {.chunk_rows = 4});
    const io::Handle field =
        io::create_extendible(group, "slip", {.columns = columns, .chunk_rows = 3, .deflate = 4});
    CHECK(io::rows_of(series) == 0);
    CHECK(io::extent(field) == std::vector<hsize_t>{0, columns});
    // Appends of 1, 3, 4, 7 rows: inside a chunk, filling it, across chunk boundaries.
    double t = 0.0;
    for (const hsize_t count : {1, 3, 4, 7}) {
      // Interleaved buffer (time, other) per row: the stride picks the time column.
      std::vector<double> interleaved;
      std::vector<double> rows;
      for (hsize_t r = 0; r < count; ++r, t += 0.25) {
        interleaved.push_back(t);
        interleaved.push_back(-1.0);
        series_expected.push_back(t);
        for (hsize_t c = 0; c < columns; ++c) rows.push_back(t * 10 + static_cast<double>(c));
      }
      field_expected.insert(field_expected.end(), rows.begin(), rows.end());
      const hsize_t before = io::rows_of(series);
      CHECK(io::append_rows(series, count, interleaved.data(), 2) == before + count);
      io::append_rows(field, count, rows.data());
    }
    CHECK(io::rows_of(series) == 15);
    io::close_file(file);
  }
  {  // A second opening appends more rows, as the run file's write-outs do.
    io::Handle file = io::open_file(path, io::FileAccess::read_write);
    const io::Handle group = io::open_group(file, "timeseries");
    const io::Handle series = io::open_dataset(group, "time");
    const std::vector<double> more = {100.0, 101.0};
    io::grow_rows(series, 17);
    io::grow_rows(series, 3);  // never cuts
    io::write_rows(series, 15, 2, more.data());
    series_expected.insert(series_expected.end(), more.begin(), more.end());
    io::close_file(file);
  }
  {
    const io::Handle file = io::open_file(path, io::FileAccess::read_only);
    const io::Handle group = io::open_group(file, "timeseries");
    const io::Handle series = io::open_dataset(group, "time");
    const io::Handle field = io::open_dataset(group, "slip");
    CHECK(read_all_rows(series) == series_expected);
    CHECK(read_all_rows(field) == field_expected);
    // A block of rows from the middle.
    std::vector<double> block(4 * columns);
    io::read_rows(field, 6, 4, block.data());
    CHECK(std::vector<double>(block.begin(), block.end()) ==
          std::vector<double>(field_expected.begin() + 6 * columns, field_expected.begin() + 10 * columns));
    // Layout: unlimited rows, the chunk shape asked for, deflate on the field.
    const io::Handle space(H5Dget_space(field), "space");
    hsize_t dims[2], max_dims[2];
    H5Sget_simple_extent_dims(space, dims, max_dims);
    CHECK(max_dims[0] == H5S_UNLIMITED);
    CHECK(max_dims[1] == columns);
    const io::Handle creation(H5Dget_create_plist(field), "plist");
    hsize_t chunk[2] = {0, 0};
    CHECK(H5Pget_chunk(creation, 2, chunk) == 2);
    CHECK(chunk[0] == 3);
    CHECK(chunk[1] == columns);
    CHECK(H5Pget_nfilters(creation) == 2);  // shuffle + deflate
    CHECK_THROWS_AS(io::read_rows(field, 14, 2, block.data()), std::out_of_range);
  }
  std::filesystem::remove(path);
}

TEST_CASE("extendible datasets: fill value for unwritten elements, element writes, cutting rows back") {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const std::string path = temp_path("crossings");
  io::Handle file = io::create_file(path);
  const io::Handle dataset =
      io::create_extendible(file, "crossing_time", {.columns = 4, .chunk_rows = 2, .chunk_columns = 3, .fill = nan_value});
  io::grow_rows(dataset, 3);
  // (level, node) -> time, like the slip-sampling record.
  const std::vector<hsize_t> coordinates = {0, 0, 0, 3, 2, 1};
  const std::vector<double> times = {0.5, 0.75, 2.0};
  io::write_elements(dataset, coordinates, times);
  std::vector<double> values = read_all_rows(dataset);
  REQUIRE(values.size() == 12);
  for (std::size_t k = 0; k < values.size(); ++k) {
    CAPTURE(k);
    if (k == 0) CHECK(values[k] == 0.5);
    else if (k == 3) CHECK(values[k] == 0.75);
    else if (k == 9) CHECK(values[k] == 2.0);
    else CHECK(std::isnan(values[k]));
  }
  CHECK_THROWS_AS(io::write_elements(dataset, std::span<const hsize_t>(coordinates).first(4), times),
                  std::invalid_argument);
  // Cut back to one row, grow again: the regrown rows hold the fill value.
  io::set_rows(dataset, 1);
  CHECK(io::extent(dataset) == std::vector<hsize_t>{1, 4});
  io::set_rows(dataset, 3);
  values = read_all_rows(dataset);
  CHECK(values[0] == 0.5);
  CHECK(values[3] == 0.75);
  CHECK(std::isnan(values[9]));
  // Rewriting a whole dataset.
  std::vector<double> front(12, 1.25);
  io::overwrite(dataset, std::span<const double>(front));
  CHECK(read_all_rows(dataset) == front);
  CHECK_THROWS_AS(io::overwrite(dataset, std::span<const double>(front).first(5)), std::invalid_argument);
  io::close_file(file);
  std::filesystem::remove(path);
}

TEST_CASE("handles close what they own: HDF5's open-object count returns to its baseline, also after errors") {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const std::string path = temp_path("raii");
  const long baseline = io::open_object_count();
  {
    io::Handle file = io::create_file(path);
    {
      const io::Handle group = io::create_group(file, "snapshots");
      io::write_attribute(group, "trigger", "time");
      io::write_vector(group, "x", std::vector<double>{0, 1, 2});
      const io::Handle dataset = io::create_extendible(group, "slip", {.columns = 3, .chunk_rows = 1});
      const std::vector<double> row = {1, 2, 3};
      io::append_rows(dataset, 1, row.data());
      CHECK(io::open_object_count() == baseline + 3);  // file, group, dataset
    }
    CHECK(io::open_object_count() == baseline + 1);
    // Moving transfers ownership; the moved-from handle owns nothing.
    io::Handle moved = std::move(file);
    CHECK_FALSE(file.valid());
    CHECK(moved.valid());
    CHECK(io::open_object_count() == baseline + 1);
    moved = io::open_group(moved, "snapshots");  // move-assignment closes the file identifier it held
    CHECK(H5Iget_type(moved) == H5I_GROUP);
    moved.reset();
    CHECK_FALSE(moved.valid());
  }
  CHECK(io::open_object_count() == baseline);
  // Every reader and error path: identifiers opened before the throw are closed.
  {
    const io::Handle file = io::open_file(path, io::FileAccess::read_only);
    const io::Handle group = io::open_group(file, "snapshots");
    CHECK(io::read_string_attribute(group, "trigger") == "time");
    CHECK(io::read_vector<double>(group, "x").size() == 3);
    CHECK_THROWS(io::read_attribute<double>(group, "trigger"));           // a string, not a number
    CHECK_THROWS(io::read_vector<double>(group, "slip"));                 // 2-D
    CHECK_THROWS(io::read_string_array_attribute(group, "trigger"));      // scalar
    CHECK_THROWS(io::write_attribute(group, "status", "running"));        // read-only file
    CHECK_THROWS(io::create_extendible(group, "state", {.chunk_rows = 0}));  // invalid chunk
    CHECK(io::open_object_count() == baseline + 2);
  }
  CHECK(io::open_object_count() == baseline);
  std::filesystem::remove(path);
}

TEST_CASE("failures name the file and the object; missing or foreign files are input errors") {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const std::string path = temp_path("names");
  {
    io::Handle file = io::create_file(path);
    io::create_group(file, "stations");
    io::close_file(file);
  }
  const io::Handle file = io::open_file(path, io::FileAccess::read_only);
  const io::Handle group = io::open_group(file, "stations");
  CHECK(io::object_path(group) == path + ":/stations");
  CHECK(io::member_path(group, "slip") == path + ":/stations/slip");
  CHECK(io::member_path(group, "@units") == path + ":/stations@units");
  CHECK(io::file_name(group) == path);
  CHECK(io::path_in_file(group) == "/stations");
  CHECK(io::path_in_file(file, "stations") == "/stations");

  // A write into a read-only file fails inside HDF5: the message names the
  // call, the file and the object, and HDF5's cause.
  std::string message = error_of([&] { io::write_vector(group, "slip", std::vector<double>{1.0}); });
  CHECK(contains(message, "HDF5 error: H5Dcreate2(" + path + ":/stations/slip) failed"));
  message = error_of([&] { io::write_attribute(group, "units", "m"); });
  CHECK(contains(message, "HDF5 error: H5Acreate2(" + path + ":/stations@units) failed"));
  CHECK_THROWS_AS(io::write_attribute(group, "units", "m"), std::runtime_error);
  // Creating an existing file exclusively.
  message = error_of([&] { io::create_file(path, io::FileCreation::exclusive); });
  CHECK(contains(message, "HDF5 error: H5Fcreate(" + path + ") failed"));

  const std::string missing = temp_path("missing");
  std::filesystem::remove(missing);
  CHECK(error_of([&] { io::open_existing_file(missing, io::FileAccess::read_only); }) ==
        "path = '" + missing + "' is invalid: file does not exist");
  CHECK_THROWS_AS(io::open_existing_file(missing, io::FileAccess::read_only), std::invalid_argument);
  const std::string text = temp_path("text");
  std::ofstream(text) << "this is not an HDF5 file\n";
  CHECK(error_of([&] { io::open_existing_file(text, io::FileAccess::read_only); }) ==
        "path = '" + text + "' is invalid: not an HDF5 file");
  // A directory is named as one (HDF5 would report a failed read of -1 bytes).
  const std::string directory = temp_path("directory");
  std::filesystem::create_directories(directory);
  CHECK(contains(error_of([&] { io::open_existing_file(directory, io::FileAccess::read_only); }),
                 "path = '" + directory + "' is a directory: expected an HDF5 file"));
  std::filesystem::remove(directory);
  // open_file does not check first: HDF5's own failure, naming the file.
  message = error_of([&] { io::open_file(text, io::FileAccess::read_only); });
  CHECK(contains(message, "HDF5 error: H5Fopen(" + text + ") failed"));
  std::filesystem::remove(text);
  std::filesystem::remove(path);
}
