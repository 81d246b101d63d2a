#include "io/attributes.hpp"

#include <stdexcept>

#include "io/strings.hpp"

namespace slipstrip::io {

NumberTypes number_types(bool floating, bool is_signed, std::size_t size) {
  if (floating) {
    if (size == 8) return {H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE};
    if (size == 4) return {H5T_NATIVE_FLOAT, H5T_IEEE_F32LE};
    throw std::invalid_argument("a floating-point type of " + std::to_string(size) +
                                " bytes has no HDF5 counterpart here (float and double do)");
  }
  switch (size) {
    case 1: return is_signed ? NumberTypes{H5T_NATIVE_INT8, H5T_STD_I8LE} : NumberTypes{H5T_NATIVE_UINT8, H5T_STD_U8LE};
    case 2: return is_signed ? NumberTypes{H5T_NATIVE_INT16, H5T_STD_I16LE} : NumberTypes{H5T_NATIVE_UINT16, H5T_STD_U16LE};
    case 4: return is_signed ? NumberTypes{H5T_NATIVE_INT32, H5T_STD_I32LE} : NumberTypes{H5T_NATIVE_UINT32, H5T_STD_U32LE};
    case 8: return is_signed ? NumberTypes{H5T_NATIVE_INT64, H5T_STD_I64LE} : NumberTypes{H5T_NATIVE_UINT64, H5T_STD_U64LE};
    default:
      throw std::invalid_argument("an integer type of " + std::to_string(size) + " bytes has no HDF5 counterpart");
  }
}

bool has_attribute(hid_t object, const std::string& name) {
  const htri_t exists = H5Aexists(object, name.c_str());
  if (exists < 0) throw_failure("H5Aexists", object, "@" + name);
  return exists > 0;
}

void remove_attribute_if_present(hid_t object, const std::string& name) {
  if (has_attribute(object, name)) check(H5Adelete(object, name.c_str()), "H5Adelete", object, "@" + name);
}

std::vector<std::string> attribute_names(hid_t object) {
  std::vector<std::string> names;
  check(H5Aiterate2(object, H5_INDEX_NAME, H5_ITER_INC, nullptr, append_name<H5A_info_t>, &names), "H5Aiterate2",
        object);
  return names;
}

namespace {

// Creates `name` on `object` (replacing an existing one) with the given type and shape.
Handle create_attribute(hid_t object, const std::string& name, hid_t file_type, hid_t space) {
  remove_attribute_if_present(object, name);
  return adopt(H5Acreate2(object, name.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT), "H5Acreate2", object,
               "@" + name);
}

Handle open_attribute(hid_t object, const std::string& name) {
  if (!has_attribute(object, name))
    throw std::invalid_argument(object_path(object) + " attribute '" + name + "' is missing");
  return adopt(H5Aopen(object, name.c_str(), H5P_DEFAULT), "H5Aopen", object, "@" + name);
}

// "<file>:<object> attribute '<name>' is invalid: " for shape and type errors.
std::string invalid(hid_t object, const std::string& name) {
  return object_path(object) + " attribute '" + name + "' is invalid: ";
}

std::string shape_text(hid_t space) {
  const H5S_class_t shape = H5Sget_simple_extent_type(space);
  if (shape == H5S_SCALAR) return "a scalar";
  if (shape == H5S_SIMPLE) return "an array of " + std::to_string(H5Sget_simple_extent_npoints(space)) + " values";
  return "empty";
}

std::string type_text(H5T_class_t kind) {
  switch (kind) {
    case H5T_ENUM: return "boolean/enum";
    case H5T_STRING: return "a string";
    case H5T_INTEGER: return "an integer";
    case H5T_FLOAT: return "a float";
    default: return "not a number or string";
  }
}

}  // namespace

void write_attribute(hid_t object, const std::string& name, std::string_view text) {
  const Handle type = utf8_string_type();
  Handle space(H5Screate(H5S_SCALAR), "H5Screate");
  const Handle attribute = create_attribute(object, name, type, space);
  const std::string terminated(text);  // HDF5 reads variable-length strings up to the NUL
  const char* pointer = terminated.c_str();
  check(H5Awrite(attribute, type, &pointer), "H5Awrite", object, "@" + name);
}

void write_number_attribute(hid_t object, const std::string& name, NumberTypes types, const void* value) {
  Handle space(H5Screate(H5S_SCALAR), "H5Screate");
  const Handle attribute = create_attribute(object, name, types.file, space);
  check(H5Awrite(attribute, types.memory, value), "H5Awrite", object, "@" + name);
}

void write_attribute(hid_t object, const std::string& name, std::span<const std::string> texts) {
  const Handle type = utf8_string_type();
  const hsize_t dims[1] = {texts.size()};
  Handle space(H5Screate_simple(1, dims, nullptr), "H5Screate_simple");
  const Handle attribute = create_attribute(object, name, type, space);
  if (texts.empty()) return;
  const std::vector<const char*> pointers = c_strings(texts);
  check(H5Awrite(attribute, type, pointers.data()), "H5Awrite", object, "@" + name);
}

std::string read_string_attribute(hid_t object, const std::string& name) {
  const Handle attribute = open_attribute(object, name);
  const Handle space = adopt(H5Aget_space(attribute), "H5Aget_space", object, "@" + name);
  const Handle type = adopt(H5Aget_type(attribute), "H5Aget_type", object, "@" + name);
  if (H5Sget_simple_extent_type(space) != H5S_SCALAR || H5Tget_class(type) != H5T_STRING)
    throw std::invalid_argument(invalid(object, name) + "it is " + shape_text(space) + " of type " +
                                type_text(H5Tget_class(type)) + ", expected a scalar string");
  std::vector<std::string> texts = read_string_values(type, 1, [&](hid_t memory_type, void* buffer) {
    return H5Aread(attribute, memory_type, buffer);
  });
  if (texts.size() != 1) throw_failure("H5Aread", object, "@" + name);
  return std::move(texts.front());
}

std::vector<std::string> read_string_array_attribute(hid_t object, const std::string& name) {
  const Handle attribute = open_attribute(object, name);
  const Handle space = adopt(H5Aget_space(attribute), "H5Aget_space", object, "@" + name);
  const Handle type = adopt(H5Aget_type(attribute), "H5Aget_type", object, "@" + name);
  if (H5Sget_simple_extent_type(space) != H5S_SIMPLE || H5Sget_simple_extent_ndims(space) != 1 ||
      H5Tget_class(type) != H5T_STRING)
    throw std::invalid_argument(invalid(object, name) + "it is " + shape_text(space) + " of type " +
                                type_text(H5Tget_class(type)) + ", expected a 1-D array of strings");
  const auto count = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space));
  std::vector<std::string> texts = read_string_values(type, count, [&](hid_t memory_type, void* buffer) {
    return H5Aread(attribute, memory_type, buffer);
  });
  if (texts.size() != count) throw_failure("H5Aread", object, "@" + name);
  return texts;
}

// A damaged or hand-made file may hold an array, a string or a bool (an HDF5
// enum) where a number belongs: reading it into one value would overrun the
// buffer (measured: a segfault), so shape and type are checked first.
void read_number_attribute(hid_t object, const std::string& name, hid_t memory_type, void* value) {
  const Handle attribute = open_attribute(object, name);
  const Handle space = adopt(H5Aget_space(attribute), "H5Aget_space", object, "@" + name);
  if (H5Sget_simple_extent_type(space) != H5S_SCALAR)
    throw std::invalid_argument(invalid(object, name) + "it is " + shape_text(space) + ", expected a scalar number");
  const Handle type = adopt(H5Aget_type(attribute), "H5Aget_type", object, "@" + name);
  const H5T_class_t kind = H5Tget_class(type);
  if (kind != H5T_FLOAT && kind != H5T_INTEGER)
    throw std::invalid_argument(invalid(object, name) + "its type is " + type_text(kind) + ", expected a scalar number");
  check(H5Aread(attribute, memory_type, value), "H5Aread", object, "@" + name);
}

}  // namespace slipstrip::io
