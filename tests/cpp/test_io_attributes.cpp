// io/ attributes: every supported type round-trips, strings are stored in the
// one encoding (variable-length UTF-8), files of the older fixed-length
// encoding still read, and bad content is an error naming file, object and
// attribute.
#include <doctest/doctest.h>
#include <hdf5.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/attributes.hpp"
#include "io/hdf5.hpp"
#include "io_test_support.hpp"

using namespace slipstrip;
using io_test::contains;
using io_test::error_of;
using io_test::temp_path;

namespace {

// The stored (file) type of an attribute, to check what the layer writes.
io::Handle stored_type(hid_t object, const std::string& name) {
  io::Handle attribute(H5Aopen(object, name.c_str(), H5P_DEFAULT), "H5Aopen " + name);
  return io::Handle(H5Aget_type(attribute), "H5Aget_type " + name);
}

bool stored_as(hid_t object, const std::string& name, hid_t file_type) {
  return H5Tequal(stored_type(object, name), file_type) > 0;
}

}  // namespace

TEST_CASE("numeric attributes of every supported type round-trip exactly, in little-endian file types") {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const std::string path = temp_path("numbers");
  {
    io::Handle file = io::create_file(path);
    const io::Handle group = io::create_group(file, "slip_sampling");
    io::write_attribute(group, "delta_th", 1e-8);
    io::write_attribute(group, "tiny", std::numeric_limits<double>::denorm_min());
    io::write_attribute(group, "not_a_number", std::numeric_limits<double>::quiet_NaN());
    io::write_attribute(group, "single", 0.1f);
    io::write_attribute(group, "int32", std::int32_t{-2147483647});
    io::write_attribute(group, "int64", std::int64_t{-9007199254740993});
    io::write_attribute(group, "uint64", std::uint64_t{18446744073709551615ull});
    io::write_attribute(group, "int8", std::int8_t{-7});
    io::write_attribute(group, "uint16", std::uint16_t{65535});
    io::write_attribute(group, "long_long", -5LL);
    io::close_file(file);
  }
  const io::Handle file = io::open_file(path, io::FileAccess::read_only);
  const io::Handle group = io::open_group(file, "slip_sampling");
  CHECK(io::read_attribute<double>(group, "delta_th") == 1e-8);
  CHECK(io::read_attribute<double>(group, "tiny") == std::numeric_limits<double>::denorm_min());
  CHECK(std::isnan(io::read_attribute<double>(group, "not_a_number")));
  CHECK(io::read_attribute<float>(group, "single") == 0.1f);
  CHECK(io::read_attribute<std::int32_t>(group, "int32") == -2147483647);
  CHECK(io::read_attribute<std::int64_t>(group, "int64") == -9007199254740993);
  CHECK(io::read_attribute<std::uint64_t>(group, "uint64") == 18446744073709551615ull);
  CHECK(io::read_attribute<std::int8_t>(group, "int8") == -7);
  CHECK(io::read_attribute<std::uint16_t>(group, "uint16") == 65535);
  CHECK(io::read_attribute<long long>(group, "long_long") == -5);
  // HDF5 converts on read: an integer attribute reads as a double.
  CHECK(io::read_attribute<double>(group, "int32") == -2147483647.0);

  CHECK(stored_as(group, "delta_th", H5T_IEEE_F64LE));
  CHECK(stored_as(group, "single", H5T_IEEE_F32LE));
  CHECK(stored_as(group, "int32", H5T_STD_I32LE));
  CHECK(stored_as(group, "int64", H5T_STD_I64LE));
  CHECK(stored_as(group, "long_long", H5T_STD_I64LE));
  CHECK(stored_as(group, "uint64", H5T_STD_U64LE));
  CHECK(stored_as(group, "int8", H5T_STD_I8LE));
  CHECK(stored_as(group, "uint16", H5T_STD_U16LE));
  std::filesystem::remove(path);
}

TEST_CASE("string attributes are variable-length UTF-8, any length and content, and round-trip") {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const std::string path = temp_path("strings");
  const std::string utf8 = "\xce\xbc = 9 GPa, \xce\x94\xce\xb8 = 1e-8 m, \xe2\x86\x92 \xe2\x9c\x93";  // μ, Δθ, →, ✓
  std::string config;  // longer than HDF5's 64 KiB limit for compact attributes
  while (config.size() < 100000) config += "[geometry]\nnodes = 1600  # \xce\xbc\n";
  {
    io::Handle file = io::create_file(path);
    io::write_attribute(file, "status", "running");
    io::write_attribute(file, "utf8", utf8);
    io::write_attribute(file, "empty", "");
    io::write_attribute(file, "config", config);
    io::write_attribute(file, "view", std::string_view("diverged: NaN at node 3, t = 5 s").substr(0, 8));
    io::close_file(file);
  }
  {
    io::Handle file = io::open_file(path, io::FileAccess::read_write);
    CHECK(io::read_string_attribute(file, "status") == "running");
    CHECK(io::read_string_attribute(file, "utf8") == utf8);
    CHECK(io::read_string_attribute(file, "empty").empty());
    CHECK(io::read_string_attribute(file, "config") == config);
    CHECK(io::read_string_attribute(file, "view") == "diverged");
    for (const char* name : {"status", "utf8", "empty", "config", "view"}) {
      CAPTURE(name);
      const io::Handle type = stored_type(file, name);
      CHECK(H5Tget_class(type) == H5T_STRING);
      CHECK(H5Tis_variable_str(type) > 0);
      CHECK(H5Tget_cset(type) == H5T_CSET_UTF8);
    }
    // Rewriting replaces the value, also with another type.
    io::write_attribute(file, "status", "completed");
    io::write_attribute(file, "empty", 3.5);
    CHECK(io::read_string_attribute(file, "status") == "completed");
    CHECK(io::read_attribute<double>(file, "empty") == 3.5);
    io::remove_attribute_if_present(file, "view");
    io::remove_attribute_if_present(file, "view");  // absent: nothing to do
    CHECK_FALSE(io::has_attribute(file, "view"));
    CHECK(io::attribute_names(file) == std::vector<std::string>{"config", "empty", "status", "utf8"});
    io::close_file(file);
  }
  std::filesystem::remove(path);
}

TEST_CASE("string array attributes round-trip, including empty arrays and empty or UTF-8 elements") {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const std::string path = temp_path("string_arrays");
  const std::vector<std::string> columns = {"height", "", "\xce\xbc_Pa", "wall_time_s"};
  {
    io::Handle file = io::create_file(path);
    io::write_attribute(file, "columns", columns);
    io::write_attribute(file, "none", std::vector<std::string>{});
    io::close_file(file);
  }
  const io::Handle file = io::open_file(path, io::FileAccess::read_only);
  CHECK(io::read_string_array_attribute(file, "columns") == columns);
  CHECK(io::read_string_array_attribute(file, "none").empty());
  const io::Handle type = stored_type(file, "columns");
  CHECK(H5Tis_variable_str(type) > 0);
  CHECK(H5Tget_cset(type) == H5T_CSET_UTF8);
  // An array is not a scalar string, and a scalar string is not an array.
  CHECK_THROWS_AS(io::read_string_attribute(file, "columns"), std::invalid_argument);
  std::filesystem::remove(path);
}

TEST_CASE("fixed-length and ASCII strings (files written before the encoding was unified) still read") {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const std::string path = temp_path("legacy_strings");
  {
    // Written the way events/catalog_io.cpp wrote "units" before: fixed
    // length, NUL-terminated ASCII; and a space-padded array.
    io::Handle file = io::create_file(path);
    const auto write_fixed = [&](const char* name, const std::string& text) {
      io::Handle type(H5Tcopy(H5T_C_S1), "H5Tcopy");
      io::check(H5Tset_size(type, text.size() + 1), "H5Tset_size");
      io::check(H5Tset_strpad(type, H5T_STR_NULLTERM), "H5Tset_strpad");
      io::Handle space(H5Screate(H5S_SCALAR), "H5Screate");
      io::Handle attribute(H5Acreate2(file, name, type, space, H5P_DEFAULT, H5P_DEFAULT), "H5Acreate2");
      io::check(H5Awrite(attribute, type, text.c_str()), "H5Awrite");
    };
    write_fixed("units", "N/m");
    write_fixed("empty", "");
    {
      io::Handle type(H5Tcopy(H5T_C_S1), "H5Tcopy");
      io::check(H5Tset_size(type, 6), "H5Tset_size");
      io::check(H5Tset_strpad(type, H5T_STR_SPACEPAD), "H5Tset_strpad");
      const hsize_t dims[1] = {2};
      io::Handle space(H5Screate_simple(1, dims, nullptr), "H5Screate_simple");
      io::Handle attribute(H5Acreate2(file, "padded", type, space, H5P_DEFAULT, H5P_DEFAULT), "H5Acreate2");
      io::check(H5Awrite(attribute, type, "slip  rate  "), "H5Awrite");
    }
    {  // variable-length ASCII (h5py writes bytes this way)
      io::Handle type(H5Tcopy(H5T_C_S1), "H5Tcopy");
      io::check(H5Tset_size(type, H5T_VARIABLE), "H5Tset_size");
      io::Handle space(H5Screate(H5S_SCALAR), "H5Screate");
      io::Handle attribute(H5Acreate2(file, "ascii", type, space, H5P_DEFAULT, H5P_DEFAULT), "H5Acreate2");
      const char* text = "completed";
      io::check(H5Awrite(attribute, type, &text), "H5Awrite");
    }
    io::close_file(file);
  }
  const io::Handle file = io::open_file(path, io::FileAccess::read_only);
  CHECK(io::read_string_attribute(file, "units") == "N/m");
  CHECK(io::read_string_attribute(file, "empty").empty());
  CHECK(io::read_string_attribute(file, "ascii") == "completed");
  CHECK(io::read_string_array_attribute(file, "padded") == std::vector<std::string>{"slip", "rate"});
  std::filesystem::remove(path);
}

TEST_CASE("attribute errors are std::invalid_argument naming the file, the object and the attribute") {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const std::string path = temp_path("attribute_errors");
  {
    io::Handle file = io::create_file(path);
    const io::Handle group = io::create_group(file, "events");
    io::write_attribute(group, "alpha", "fifteen");
    io::write_attribute(group, "thresholds", std::vector<std::string>{"a", "b"});
    io::write_attribute(group, "n_events", std::uint64_t{12});
    {  // a boolean as h5py writes it: an enum
      io::Handle type(H5Tenum_create(H5T_NATIVE_INT8), "H5Tenum_create");
      const std::int8_t no = 0, yes = 1;
      io::check(H5Tenum_insert(type, "FALSE", &no), "H5Tenum_insert");
      io::check(H5Tenum_insert(type, "TRUE", &yes), "H5Tenum_insert");
      io::Handle space(H5Screate(H5S_SCALAR), "H5Screate");
      io::Handle attribute(H5Acreate2(group, "flag", type, space, H5P_DEFAULT, H5P_DEFAULT), "H5Acreate2");
      io::check(H5Awrite(attribute, type, &yes), "H5Awrite");
    }
    {  // an array where a scalar belongs
      const double values[3] = {1, 2, 3};
      const hsize_t dims[1] = {3};
      io::Handle space(H5Screate_simple(1, dims, nullptr), "H5Screate_simple");
      io::Handle attribute(H5Acreate2(group, "dx", H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT), "H5Acreate2");
      io::check(H5Awrite(attribute, H5T_NATIVE_DOUBLE, values), "H5Awrite");
    }
    io::close_file(file);
  }
  const io::Handle file = io::open_file(path, io::FileAccess::read_only);
  const io::Handle group = io::open_group(file, "events");
  const std::string where = path + ":/events";

  std::string message = error_of([&] { io::read_attribute<double>(group, "mu"); });
  CHECK(message == where + " attribute 'mu' is missing");
  message = error_of([&] { io::read_string_attribute(group, "status"); });
  CHECK(message == where + " attribute 'status' is missing");
  message = error_of([&] { io::read_attribute<double>(group, "alpha"); });
  CHECK(contains(message, where + " attribute 'alpha' is invalid"));
  CHECK(contains(message, "a string"));
  message = error_of([&] { io::read_attribute<double>(group, "flag"); });
  CHECK(contains(message, "boolean/enum"));
  message = error_of([&] { io::read_attribute<double>(group, "dx"); });
  CHECK(contains(message, where + " attribute 'dx' is invalid: it is an array of 3 values"));
  message = error_of([&] { io::read_string_attribute(group, "n_events"); });
  CHECK(contains(message, where + " attribute 'n_events' is invalid"));
  CHECK(contains(message, "expected a scalar string"));
  message = error_of([&] { io::read_string_array_attribute(group, "alpha"); });
  CHECK(contains(message, "expected a 1-D array of strings"));
  for (const auto& read : {+[](hid_t g) { io::read_attribute<double>(g, "mu"); },
                           +[](hid_t g) { io::read_attribute<double>(g, "alpha"); },
                           +[](hid_t g) { io::read_string_attribute(g, "n_events"); }})
    CHECK_THROWS_AS(read(group), std::invalid_argument);
  std::filesystem::remove(path);
}
