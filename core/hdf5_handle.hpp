#pragma once
// RAII ownership of HDF5 identifiers (file, group, dataset, dataspace, type,
// property list, attribute).  One small type instead of a wrapper hierarchy:
// the closing function is chosen from the identifier's type at release time.
#include <hdf5.h>

#include <stdexcept>
#include <string>
#include <utility>

namespace slipstrip::hdf5 {

class Handle {
 public:
  Handle() = default;
  // Takes ownership; throws if the HDF5 call that produced `id` failed.
  explicit Handle(hid_t id, const std::string& what = "HDF5 call") : id_(id) {
    if (id_ < 0) throw std::runtime_error("HDF5 error: " + what + " failed");
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
  if (status < 0) throw std::runtime_error("HDF5 error: " + what + " failed");
}

}  // namespace slipstrip::hdf5
