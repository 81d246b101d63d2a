#pragma once
// The one HDF5 layer of slipstrip (kernels' cache, events' catalogs, core's
// run file and restart points all go through io/).  This header: ownership of
// HDF5 identifiers, error reporting, files, groups and links.  Attributes:
// io/attributes.hpp; datasets (whole arrays and incremental ones):
// io/datasets.hpp.
//
// Errors.  A failed HDF5 call throws std::runtime_error
//   "HDF5 error: <operation>(<file>:<object path>) failed: <cause>"
// naming the file and the object, with the operating system's or HDF5's
// cause.  Content that does not match what the caller asks for (a missing
// attribute or dataset, an array where a scalar belongs, a string where a
// number belongs) throws std::invalid_argument naming the file and object:
// that is bad input, not a failure of the program.
#include <hdf5.h>

#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace slipstrip::io {

// The cause of the HDF5 error just raised on this thread, in one line: the
// operating system's message when HDF5 recorded one ("No space left on
// device"), else the innermost HDF5 description; "" if the stack is empty.
// Read it before any other HDF5 call: every API call clears the stack.
std::string last_error_cause();

// "HDF5 error: <what> failed[: <cause>]" with the cause of the last error.
std::string with_cause(const std::string& what);

// "<file>:<path>" of an open object, e.g. "run.h5:/slip_sampling"; with a
// member name, that of the member ("run.h5:/slip_sampling/x"; an attribute
// as "@name": "run.h5:/events@alpha").  For messages.
std::string object_path(hid_t object);
std::string member_path(hid_t parent, std::string_view member);
// The parts: the file name as the file was opened ("" if none), and the path
// inside the file ("/slip_sampling/x").
std::string file_name(hid_t object);
std::string path_in_file(hid_t parent, std::string_view member = {});

// Throws std::runtime_error for the failed `operation` on `member` of
// `object` (or on `object` itself).  The cause is captured first, before the
// calls that name the object clear HDF5's error stack.
[[noreturn]] void throw_failure(std::string_view operation, hid_t object, std::string_view member = {});

// status < 0: throw_failure(operation, object, member).
inline void check(herr_t status, std::string_view operation, hid_t object, std::string_view member = {}) {
  if (status < 0) throw_failure(operation, object, member);
}
// status < 0: std::runtime_error(with_cause(what)).  For calls with no object to name.
void check(herr_t status, const std::string& what);

// Owns one HDF5 identifier (file, group, dataset, dataspace, datatype,
// attribute or property list) and closes it with the function of its type.
class Handle {
 public:
  Handle() = default;
  // Takes ownership; id < 0 (the call that produced it failed) throws
  // std::runtime_error(with_cause(what)).
  explicit Handle(hid_t id, const std::string& what = "HDF5 call") : id_(id) {
    if (id_ < 0) throw std::runtime_error(with_cause(what));
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& other) noexcept : id_(std::exchange(other.id_, H5I_INVALID_HID)) {}
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, H5I_INVALID_HID);
    }
    return *this;
  }
  ~Handle() { reset(); }

  hid_t get() const { return id_; }
  operator hid_t() const { return id_; }
  bool valid() const { return id_ >= 0; }
  // Gives up ownership, e.g. to close explicitly and check the result.
  hid_t release() { return std::exchange(id_, H5I_INVALID_HID); }
  // Closes now (errors ignored: a destructor cannot report them; close_file
  // is the checked close of a file).
  void reset() noexcept;

 private:
  hid_t id_ = H5I_INVALID_HID;
};

// Takes ownership of `id`; id < 0 throws throw_failure(operation, object, member).
Handle adopt(hid_t id, std::string_view operation, hid_t object, std::string_view member = {});

// --- Files ------------------------------------------------------------------

enum class FileAccess { read_only, read_write };
enum class FileCreation { truncate, exclusive };

// `access_list`: an H5P_FILE_ACCESS list (file_access_list) or H5P_DEFAULT.
Handle create_file(const std::string& path, FileCreation creation = FileCreation::truncate,
                   hid_t access_list = H5P_DEFAULT);
Handle open_file(const std::string& path, FileAccess access, hid_t access_list = H5P_DEFAULT);
// As open_file, but a missing file or one that is not HDF5 is bad input:
// std::invalid_argument "path = '<path>' is invalid: file does not exist"
// (or "not an HDF5 file").
Handle open_existing_file(const std::string& path, FileAccess access);
// Closes explicitly and checks: H5Fclose writes the metadata, and its failure
// must not go unnoticed (a destructor would swallow it).
void close_file(Handle& file);

// File access list with HDF5's file locking on or off.  Locking is what keeps
// a reader consistent (h5py holds a shared lock while a file is open); on file
// systems without lock support the lock is skipped instead of failing.
Handle file_access_list(bool use_locking);

// --- Groups and links ---------------------------------------------------------

bool has_member(hid_t parent, const std::string& name);
Handle create_group(hid_t parent, const std::string& name);
// A missing group throws std::invalid_argument
// "path = '<file>' is invalid: group /<parent>/<name> is missing".
Handle open_group(hid_t parent, const std::string& name);
// A missing dataset throws std::invalid_argument
// "path = '<file>' is invalid: dataset /<parent>/<name> is missing".
Handle open_dataset(hid_t parent, const std::string& name);
void remove_member_if_present(hid_t parent, const std::string& name);
// Names of the members of a group, in name order.
std::vector<std::string> member_names(hid_t group);

// Number of identifiers HDF5 holds open on all files (H5Fget_obj_count over
// every file): what a leak check compares before and after.
long open_object_count();

}  // namespace slipstrip::io
