#include "io/hdf5.hpp"

#include <filesystem>
#include <stdexcept>

#include "io/strings.hpp"

namespace slipstrip::io {

std::string last_error_cause() {
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

namespace {

std::string failure_text(std::string_view what, const std::string& cause) {
  return "HDF5 error: " + std::string(what) + " failed" + (cause.empty() ? "" : ": " + cause);
}

// H5Fget_name / H5Iget_name into a string ("" if the object has none).
template <class Get>
std::string name_of(hid_t object, Get get) {
  const ssize_t size = get(object, nullptr, 0);
  if (size <= 0) return "";
  std::string name(static_cast<std::size_t>(size) + 1, '\0');
  get(object, name.data(), name.size());
  name.resize(static_cast<std::size_t>(size));
  return name;
}

}  // namespace

std::string with_cause(const std::string& what) { return failure_text(what, last_error_cause()); }

std::string file_name(hid_t object) {
  std::string file;
  // Naming must not print HDF5's own stack for an identifier that has no name.
  H5E_BEGIN_TRY { file = name_of(object, H5Fget_name); }
  H5E_END_TRY;
  return file;
}

std::string path_in_file(hid_t parent, std::string_view member) {
  std::string path;
  H5E_BEGIN_TRY { path = name_of(parent, H5Iget_name); }
  H5E_END_TRY;
  if (path.empty()) path.push_back('/');  // the root (or an object without a name)
  if (member.empty()) return path;
  // "@name" is an attribute of the object itself: "/events@alpha".
  if (member.front() != '@' && path.back() != '/') path += '/';
  return path + std::string(member);
}

std::string object_path(hid_t object) { return member_path(object, {}); }

std::string member_path(hid_t parent, std::string_view member) {
  const std::string file = file_name(parent);
  return (file.empty() ? "<unnamed HDF5 file>" : file) + ":" + path_in_file(parent, member);
}

void throw_failure(std::string_view operation, hid_t object, std::string_view member) {
  const std::string cause = last_error_cause();
  throw std::runtime_error(failure_text(std::string(operation) + "(" + member_path(object, member) + ")", cause));
}

void check(herr_t status, const std::string& what) {
  if (status < 0) throw std::runtime_error(with_cause(what));
}

void Handle::reset() noexcept {
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

Handle adopt(hid_t id, std::string_view operation, hid_t object, std::string_view member) {
  if (id < 0) throw_failure(operation, object, member);
  return Handle(id);
}

// --- Files ------------------------------------------------------------------

namespace {
std::string call_on_path(const char* operation, const std::string& path) {
  return std::string(operation) + "(" + path + ")";
}
}  // namespace

Handle create_file(const std::string& path, FileCreation creation, hid_t access_list) {
  const unsigned flags = creation == FileCreation::truncate ? H5F_ACC_TRUNC : H5F_ACC_EXCL;
  return Handle(H5Fcreate(path.c_str(), flags, H5P_DEFAULT, access_list), call_on_path("H5Fcreate", path));
}

Handle open_file(const std::string& path, FileAccess access, hid_t access_list) {
  const unsigned flags = access == FileAccess::read_only ? H5F_ACC_RDONLY : H5F_ACC_RDWR;
  return Handle(H5Fopen(path.c_str(), flags, access_list), call_on_path("H5Fopen", path));
}

Handle open_existing_file(const std::string& path, FileAccess access) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw std::invalid_argument("path = '" + path + "' is invalid: file does not exist");
  if (std::filesystem::is_directory(path, ec))
    throw std::invalid_argument("path = '" + path + "' is a directory: expected an HDF5 file (a run file "
                                "written by `slipstrip run`)");
  if (H5Fis_hdf5(path.c_str()) <= 0)
    throw std::invalid_argument("path = '" + path + "' is invalid: not an HDF5 file");
  return open_file(path, access);
}

void close_file(Handle& file) {
  if (!file.valid()) return;
  const std::string path = file_name(file);
  const herr_t status = H5Fclose(file.release());
  if (status < 0) throw std::runtime_error(with_cause("H5Fclose(" + path + ")"));
}

Handle file_access_list(bool use_locking) {
  Handle list(H5Pcreate(H5P_FILE_ACCESS), "H5Pcreate(file access)");
  check(H5Pset_file_locking(list, use_locking, true), "H5Pset_file_locking");
  return list;
}

// --- Groups and links ---------------------------------------------------------

bool has_member(hid_t parent, const std::string& name) {
  const htri_t exists = H5Lexists(parent, name.c_str(), H5P_DEFAULT);
  check(exists, "H5Lexists", parent, name);
  return exists > 0;
}

Handle create_group(hid_t parent, const std::string& name) {
  return adopt(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "H5Gcreate2", parent, name);
}

Handle open_group(hid_t parent, const std::string& name) {
  if (!has_member(parent, name))
    throw std::invalid_argument("path = '" + file_name(parent) + "' is invalid: group " + path_in_file(parent, name) +
                                " is missing");
  return adopt(H5Gopen2(parent, name.c_str(), H5P_DEFAULT), "H5Gopen2", parent, name);
}

Handle open_dataset(hid_t parent, const std::string& name) {
  if (!has_member(parent, name))
    throw std::invalid_argument("path = '" + file_name(parent) + "' is invalid: dataset " +
                                path_in_file(parent, name) + " is missing");
  return adopt(H5Dopen2(parent, name.c_str(), H5P_DEFAULT), "H5Dopen2", parent, name);
}

void remove_member_if_present(hid_t parent, const std::string& name) {
  if (has_member(parent, name)) check(H5Ldelete(parent, name.c_str(), H5P_DEFAULT), "H5Ldelete", parent, name);
}

std::vector<std::string> member_names(hid_t group) {
  std::vector<std::string> names;
  check(H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, nullptr, append_name<H5L_info_t>, &names), "H5Literate", group);
  return names;
}

long open_object_count() { return static_cast<long>(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL)); }

}  // namespace slipstrip::io
