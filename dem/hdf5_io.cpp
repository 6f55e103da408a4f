#include "dem/hdf5_io.hpp"

#include <stdexcept>

namespace mfdem::dem::h5 {
namespace {

// Link creation that makes missing parent groups ("curve/u" creates "curve").
struct IntermediateGroups {
  hid_t id = H5Pcreate(H5P_LINK_CREATE);
  IntermediateGroups() { H5Pset_create_intermediate_group(id, 1); }
  ~IntermediateGroups() { H5Pclose(id); }
};

}  // namespace

void check(herr_t status, const std::string& what) {
  if (status < 0) throw std::runtime_error("HDF5 error while " + what);
}

void write_doubles(hid_t loc, const std::string& name, const double* data, hsize_t rows,
                   hsize_t cols) {
  hsize_t dims[2] = {rows, cols};
  const hid_t space = H5Screate_simple(cols ? 2 : 1, dims, nullptr);
  const IntermediateGroups lcpl;
  const hid_t set = H5Dcreate2(loc, name.c_str(), H5T_IEEE_F64LE, space, lcpl.id, H5P_DEFAULT, H5P_DEFAULT);
  if (set < 0) throw std::runtime_error("HDF5: cannot create dataset " + name);
  if (rows) check(H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "writing " + name);
  H5Dclose(set);
  H5Sclose(space);
}

void write_doubles(hid_t loc, const std::string& name, const std::vector<double>& v) {
  write_doubles(loc, name, v.data(), v.size(), 0);
}

void write_vec3s(hid_t loc, const std::string& name, const std::vector<Vec3>& v) {
  std::vector<double> flat(v.size() * 3);
  for (std::size_t i = 0; i < v.size(); ++i)
    for (int a = 0; a < 3; ++a) flat[3 * i + a] = v[i][a];
  write_doubles(loc, name, flat.data(), v.size(), 3);
}

void write_ints(hid_t loc, const std::string& name, const std::vector<Index>& v) {
  hsize_t dims[1] = {v.size()};
  const hid_t space = H5Screate_simple(1, dims, nullptr);
  const IntermediateGroups lcpl;
  const hid_t set = H5Dcreate2(loc, name.c_str(), H5T_STD_I32LE, space, lcpl.id, H5P_DEFAULT, H5P_DEFAULT);
  if (!v.empty()) check(H5Dwrite(set, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), "writing " + name);
  H5Dclose(set);
  H5Sclose(space);
}

void write_attribute(hid_t loc, const std::string& name, double value) {
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attr = H5Acreate2(loc, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(attr, H5T_NATIVE_DOUBLE, &value);
  H5Aclose(attr);
  H5Sclose(space);
}

void write_attribute(hid_t loc, const std::string& name, const std::string& value) {
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.size() + 1);
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attr = H5Acreate2(loc, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(attr, type, value.c_str());
  H5Aclose(attr);
  H5Sclose(space);
  H5Tclose(type);
}

void write_attribute(hid_t loc, const std::string& name, const std::vector<std::string>& values) {
  std::string joined;
  for (std::size_t i = 0; i < values.size(); ++i) joined += (i ? "," : "") + values[i];
  write_attribute(loc, name, joined);
}

// Appends one row to an extendable dataset of shape [n, width] (width 0: 1-D).
void append_row(hid_t file, const std::string& name, const double* row, hsize_t width) {
  const int rank = width ? 2 : 1;
  hid_t set;
  hsize_t old_rows = 0;
  if (H5Lexists(file, name.c_str(), H5P_DEFAULT) > 0) {
    set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
    const hid_t space = H5Dget_space(set);
    hsize_t dims[2];
    H5Sget_simple_extent_dims(space, dims, nullptr);
    old_rows = dims[0];
    H5Sclose(space);
    hsize_t grown[2] = {old_rows + 1, width};
    check(H5Dset_extent(set, grown), "growing " + name);
  } else {
    hsize_t dims[2] = {1, width};
    hsize_t max[2] = {H5S_UNLIMITED, width};
    hsize_t chunk[2] = {64, width ? width : 1};
    const hid_t space = H5Screate_simple(rank, dims, max);
    const hid_t plist = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(plist, rank, chunk);
    const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
    H5Pset_create_intermediate_group(lcpl, 1);
    set = H5Dcreate2(file, name.c_str(), H5T_IEEE_F64LE, space, lcpl, plist, H5P_DEFAULT);
    H5Pclose(lcpl);
    H5Pclose(plist);
    H5Sclose(space);
  }
  const hid_t filespace = H5Dget_space(set);
  hsize_t start[2] = {old_rows, 0};
  hsize_t count[2] = {1, width};
  H5Sselect_hyperslab(filespace, H5S_SELECT_SET, start, nullptr, count, nullptr);
  const hid_t memspace = H5Screate_simple(rank, count, nullptr);
  check(H5Dwrite(set, H5T_NATIVE_DOUBLE, memspace, filespace, H5P_DEFAULT, row), "appending " + name);
  H5Sclose(memspace);
  H5Sclose(filespace);
  H5Dclose(set);
}

hid_t make_group(hid_t file, const std::string& name) {
  const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  const hid_t g = H5Gcreate2(file, name.c_str(), lcpl, H5P_DEFAULT, H5P_DEFAULT);
  H5Pclose(lcpl);
  if (g < 0) throw std::runtime_error("HDF5: cannot create group " + name);
  return g;
}

void write_file(const std::filesystem::path& path, const std::function<void(hid_t file)>& fill) {
  const std::filesystem::path partial = path.string() + ".partial";
  const hid_t file = H5Fcreate(partial.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file < 0) throw std::runtime_error("HDF5: cannot create " + partial.string());
  try {
    fill(file);
  } catch (...) {
    H5Fclose(file);
    std::filesystem::remove(partial);
    throw;
  }
  check(H5Fclose(file), "closing " + partial.string());
  std::filesystem::rename(partial, path);
}

std::vector<double> read_doubles(hid_t file, const std::string& name) {
  const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  if (set < 0) throw std::runtime_error("HDF5: missing dataset " + name);
  const hid_t space = H5Dget_space(set);
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  std::vector<double> out(static_cast<std::size_t>(n));
  if (n > 0) check(H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), "reading " + name);
  H5Sclose(space);
  H5Dclose(set);
  return out;
}

std::vector<Vec3> read_vec3s(hid_t file, const std::string& name) {
  const auto flat = read_doubles(file, name);
  std::vector<Vec3> out(flat.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = Vec3(flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]);
  return out;
}

std::vector<Index> read_ints(hid_t file, const std::string& name) {
  const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  if (set < 0) throw std::runtime_error("HDF5: missing dataset " + name);
  const hid_t space = H5Dget_space(set);
  std::vector<Index> out(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  if (!out.empty()) check(H5Dread(set, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), "reading " + name);
  H5Sclose(space);
  H5Dclose(set);
  return out;
}

double read_attribute(hid_t loc, const std::string& name) {
  double value = 0.0;
  const hid_t attr = H5Aopen(loc, name.c_str(), H5P_DEFAULT);
  if (attr < 0) throw std::runtime_error("HDF5: missing attribute " + name);
  H5Aread(attr, H5T_NATIVE_DOUBLE, &value);
  H5Aclose(attr);
  return value;
}

std::string read_text_attribute(hid_t loc, const std::string& name) {
  if (H5Aexists(loc, name.c_str()) <= 0) return "";
  const hid_t attr = H5Aopen(loc, name.c_str(), H5P_DEFAULT);
  const hid_t type = H5Aget_type(attr);
  std::string value(H5Tget_size(type), '\0');
  check(H5Aread(attr, type, value.data()), "reading attribute " + name);
  H5Tclose(type);
  H5Aclose(attr);
  value.resize(value.find('\0') == std::string::npos ? value.size() : value.find('\0'));
  return value;
}

}  // namespace mfdem::dem::h5
