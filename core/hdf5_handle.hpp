#pragma once
// RAII ownership of HDF5 identifiers (file, group, dataset, dataspace, type,
// property list, attribute).  One small type instead of a wrapper hierarchy:
// the closing function is chosen from the identifier's type at release time.
#include <hdf5.h>

#include <stdexcept>
#include <string>
#include <utility>

namespace slipstrip::hdf5 {

// The cause of the HDF5 error just raised on this thread, in one line: the
// operating system's message when HDF5 recorded one ("No space left on
// device"), else the innermost HDF5 description; "" if the stack is empty.
inline std::string last_error_cause() {
  struct Walk {
    std::string innermost, system;
  } walk;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_UPWARD,
      [](unsigned n, const H5E_error2_t* e, void* data) -> herr_t {
        auto* w = static_cast<Walk*>(data);
        const std::string desc = e->desc ? e->desc : "";
        if (n == 0) w->innermost = desc;
        const auto at = desc.find("error message = '");
        if (w->system.empty() && at != std::string::npos) {
          const auto begin = at + 17;
          w->system = desc.substr(begin, desc.find('\'', begin) - begin);
        }
        return 0;
      },
      &walk);
  std::string cause = walk.system.empty() ? walk.innermost : walk.system;
  if (cause.size() > 200) cause = cause.substr(0, 200) + "...";
  return cause;
}

inline std::string with_cause(const std::string& what) {
  const std::string cause = last_error_cause();
  return "HDF5 error: " + what + " failed" + (cause.empty() ? "" : ": " + cause);
}

class Handle {
 public:
  Handle() = default;
  // Takes ownership; throws if the HDF5 call that produced `id` failed.
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

  void reset() {
    if (id_ < 0) return;
    switch (H5Iget_type(id_)) {
      case H5I_FILE: H5Fclose(id_); break;
      case H5I_GROUP: H5Gclose(id_); break;
      case H5I_DATASET: H5Dclose(id_); break;
      case H5I_DATASPACE: H5Sclose(id_); break;
      case H5I_DATATYPE: H5Tclose(id_); break;
      case H5I_ATTR: H5Aclose(id_); break;
      case H5I_GENPROP_LST: H5Pclose(id_); break;
      default: break;
    }
    id_ = H5I_INVALID_HID;
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
};

inline void check(herr_t status, const std::string& what) {
  if (status < 0) throw std::runtime_error(with_cause(what));
}

// Scalar attributes on a file, group or dataset; an existing attribute of the
// same name is replaced.  Strings are variable-length UTF-8 so h5py returns a
// plain str and there is no 64 KiB compact-attribute limit on long texts.
inline void remove_attribute_if_present(hid_t object, const std::string& name) {
  const htri_t exists = H5Aexists(object, name.c_str());
  check(exists, "H5Aexists(" + name + ")");
  if (exists > 0) check(H5Adelete(object, name.c_str()), "H5Adelete(" + name + ")");
}

inline void write_attribute(hid_t object, const std::string& name, const std::string& value) {
  remove_attribute_if_present(object, name);
  Handle type(H5Tcopy(H5T_C_S1), "H5Tcopy");
  check(H5Tset_size(type, H5T_VARIABLE), "H5Tset_size");
  check(H5Tset_cset(type, H5T_CSET_UTF8), "H5Tset_cset");
  Handle space(H5Screate(H5S_SCALAR), "H5Screate");
  Handle attr(H5Acreate2(object, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT),
              "H5Acreate2(" + name + ")");
  const char* text = value.c_str();
  check(H5Awrite(attr, type, &text), "H5Awrite(" + name + ")");
}

inline void write_attribute(hid_t object, const std::string& name, double value) {
  remove_attribute_if_present(object, name);
  Handle space(H5Screate(H5S_SCALAR), "H5Screate");
  Handle attr(H5Acreate2(object, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT),
              "H5Acreate2(" + name + ")");
  check(H5Awrite(attr, H5T_NATIVE_DOUBLE, &value), "H5Awrite(" + name + ")");
}

// A scalar string attribute, fixed- or variable-length.
inline std::string read_string_attribute(hid_t object, const std::string& name) {
  Handle attr(H5Aopen(object, name.c_str(), H5P_DEFAULT), "H5Aopen(" + name + ")");
  Handle type(H5Aget_type(attr), "H5Aget_type(" + name + ")");
  std::string value;
  if (H5Tis_variable_str(type) > 0) {
    char* text = nullptr;
    Handle memory(H5Tcopy(H5T_C_S1), "H5Tcopy");
    check(H5Tset_size(memory, H5T_VARIABLE), "H5Tset_size");
    // HDF5 does not convert between ASCII and UTF-8: read in the stored set.
    check(H5Tset_cset(memory, H5Tget_cset(type)), "H5Tset_cset");
    check(H5Aread(attr, memory, &text), "H5Aread(" + name + ")");
    value = text ? text : "";
    H5free_memory(text);
  } else {
    value.resize(H5Tget_size(type));
    check(H5Aread(attr, type, value.data()), "H5Aread(" + name + ")");
    while (!value.empty() && value.back() == '\0') value.pop_back();
  }
  return value;
}

}  // namespace slipstrip::hdf5
