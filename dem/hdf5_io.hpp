#pragma once
// Small helpers over the HDF5 C API for the layouts mfdem writes: 1-D and [n, 3] datasets of
// doubles and 32-bit integers, scalar and text attributes, extendable series. Each throws
// std::runtime_error naming the dataset when HDF5 fails.
#include <hdf5.h>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "dem/types.hpp"

namespace mfdem::dem::h5 {

void check(herr_t status, const std::string& what);
// rows x cols doubles (cols = 0: a 1-D dataset of rows).
void write_doubles(hid_t loc, const std::string& name, const double* data, hsize_t rows, hsize_t cols);
void write_doubles(hid_t loc, const std::string& name, const std::vector<double>& v);
void write_vec3s(hid_t loc, const std::string& name, const std::vector<Vec3>& v);
void write_ints(hid_t loc, const std::string& name, const std::vector<Index>& v);
void write_attribute(hid_t loc, const std::string& name, double value);
void write_attribute(hid_t loc, const std::string& name, const std::string& value);
// Joined with commas.
void write_attribute(hid_t loc, const std::string& name, const std::vector<std::string>& values);
// Appends one row to an extendable dataset of shape [n, width] (width 0: 1-D).
void append_row(hid_t file, const std::string& name, const double* row, hsize_t width);
// Creates the group and any missing parents; close it with H5Gclose.
hid_t make_group(hid_t file, const std::string& name);

// Writes a new HDF5 file as PATH.partial, filled by `fill`, and renames it to PATH when complete:
// a reader sees the old file or the whole new one, never half of it. On an exception the partial
// file is removed and the exception passed on.
void write_file(const std::filesystem::path& path, const std::function<void(hid_t file)>& fill);

std::vector<double> read_doubles(hid_t file, const std::string& name);
std::vector<Vec3> read_vec3s(hid_t file, const std::string& name);
std::vector<Index> read_ints(hid_t file, const std::string& name);
double read_attribute(hid_t loc, const std::string& name);
// A text attribute written by write_attribute; "" when absent.
std::string read_text_attribute(hid_t loc, const std::string& name);

}  // namespace mfdem::dem::h5
