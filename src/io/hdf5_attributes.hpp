#pragma once
// Scalar attributes of an HDF5 object (file, group or dataset), shared by the solve, sweep,
// envelope and trace writers so that every file stores them alike: strings as variable-length
// UTF-8 (h5py returns str), numbers as little-endian IEEE doubles, integers and flags as
// little-endian 64-bit integers. Writing replaces an attribute that exists (the trace writer
// writes `complete` and `termination` twice); reading one that does not exist gives "" or 0.
// Failures throw OutputError naming the attribute (hdf5_handle.hpp). With them, the two small
// whole datasets the writers share: an array of doubles, and a text (the scene file as read).

#include <hdf5.h>

#include <algorithm>
#include <initializer_list>
#include <string>
#include <type_traits>
#include <vector>

#include "io/hdf5_handle.hpp"

namespace liftoff::io::hdf5 {

// A UTF-8 C string type: variable length, or `size` bytes (at least 1) when not.
inline Handle string_type(bool variable, std::size_t size = 1) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose, "string type");
  check(H5Tset_size(type, variable ? H5T_VARIABLE : std::max<std::size_t>(1, size)), "string type");
  check(H5Tset_cset(type, H5T_CSET_UTF8), "string type");
  return type;
}

inline void write_string_attribute(hid_t object, const std::string& name, const std::string& value) {
  if (H5Aexists(object, name.c_str()) > 0) check(H5Adelete(object, name.c_str()), name);
  Handle type = string_type(true);
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, "dataspace");
  Handle attribute(H5Acreate2(object, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose, name);
  const char* text = value.c_str();
  check(H5Awrite(attribute, type, &text), name);
}

// An integral T (bool and enums cast to int included) is stored as a 64-bit integer, any other
// as a double.
template <typename T>
void write_number_attribute(hid_t object, const std::string& name, T value) {
  constexpr bool integral = std::is_integral_v<T>;
  using Stored = std::conditional_t<integral, long long, double>;
  const Stored v = static_cast<Stored>(value);
  const hid_t memory_type = integral ? H5T_NATIVE_LLONG : H5T_NATIVE_DOUBLE;
  if (H5Aexists(object, name.c_str()) > 0) {
    Handle attribute(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose, name);
    check(H5Awrite(attribute, memory_type, &v), name);
    return;
  }
  const hid_t file_type = integral ? H5T_STD_I64LE : H5T_IEEE_F64LE;
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, "dataspace");
  Handle attribute(H5Acreate2(object, name.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose, name);
  check(H5Awrite(attribute, memory_type, &v), name);
}

inline std::string read_string_attribute(hid_t object, const std::string& name) {
  if (H5Aexists(object, name.c_str()) <= 0) return {};
  Handle attribute(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose, name);
  Handle type = string_type(true);
  char* text = nullptr;
  check(H5Aread(attribute, type, &text), name);
  std::string value = text != nullptr ? text : "";
  H5free_memory(text);
  return value;
}

inline double read_number_attribute(hid_t object, const std::string& name) {
  if (H5Aexists(object, name.c_str()) <= 0) return 0.0;
  Handle attribute(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose, name);
  double value = 0.0;
  check(H5Aread(attribute, H5T_NATIVE_DOUBLE, &value), name);
  return value;
}

// `values` row by row as a dataset of little-endian doubles: one-dimensional for one column,
// rows x columns otherwise.
inline void write_array(hid_t group, const char* name, const std::vector<double>& values, hsize_t columns = 1) {
  const hsize_t dims[2] = {values.size() / columns, columns};
  Handle space(H5Screate_simple(columns == 1 ? 1 : 2, dims, nullptr), H5Sclose, name);
  Handle dataset(H5Dcreate2(group, name, H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose, name);
  if (!values.empty()) check(H5Dwrite(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), name);
}

// A named column of doubles, for write_columns.
struct Column {
  const char* name;
  const std::vector<double>* values;
};

// What write_columns does with an empty column: the solve file leaves out a field the answer has
// not (u of a linear beam), the envelope file writes every column it has.
enum class EmptyColumns { skip, write };

// A group `group_name` in `parent` holding each column as a one-dimensional dataset.
inline void write_columns(hid_t parent, const char* group_name, std::initializer_list<Column> columns,
                          EmptyColumns empty) {
  Handle group(H5Gcreate2(parent, group_name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, group_name);
  for (const Column& c : columns)
    if (empty == EmptyColumns::write || !c.values->empty()) write_array(group, c.name, *c.values);
}

// `text` as a fixed-length UTF-8 string (h5py returns bytes; the trace writer reads it back).
inline void write_text(hid_t location, const char* name, const std::string& text) {
  Handle type = string_type(false, text.size());
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, name);
  Handle dataset(H5Dcreate2(location, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose, name);
  check(H5Dwrite(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, text.c_str()), name);
}

}  // namespace liftoff::io::hdf5
