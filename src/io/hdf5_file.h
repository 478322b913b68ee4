// Minimal HDF5 writer and reader (the C API stays behind this header; internal to src/).
// Hdf5Writer writes under a temporary name and renames onto the target in Commit(); destroying an
// uncommitted writer removes the temporary file. Hdf5Reader reads what the writer writes; every
// error is a std::runtime_error naming the file and the dataset or attribute.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace fricrom {

class Hdf5Writer {
 public:
  explicit Hdf5Writer(std::filesystem::path target);  // throws std::runtime_error
  ~Hdf5Writer();
  Hdf5Writer(const Hdf5Writer&) = delete;
  Hdf5Writer& operator=(const Hdf5Writer&) = delete;

  // `path` is slash-separated ("frf/freq_hz"); missing groups are created.
  void Vector(const std::string& path, const std::vector<double>& values);
  void Vector(const std::string& path, const Eigen::VectorXd& values);
  void IntVector(const std::string& path, const std::vector<int>& values);
  void Int64Vector(const std::string& path, const std::vector<int64_t>& values);
  void Matrix(const std::string& path, const Eigen::MatrixXd& values);  // rows x cols
  void Strings(const std::string& path, const std::vector<std::string>& values);
  void String(const std::string& path, const std::string& value);  // scalar string dataset
  // Attribute on a group or dataset ("" = root).
  void Attribute(const std::string& object, const std::string& name, const std::string& value);
  void Attribute(const std::string& object, const std::string& name, double value);
  void Commit();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class Hdf5Reader {
 public:
  // Opens read-only; throws when the file is missing or not HDF5 (e.g. truncated).
  explicit Hdf5Reader(const std::string& path);
  ~Hdf5Reader();
  Hdf5Reader(const Hdf5Reader&) = delete;
  Hdf5Reader& operator=(const Hdf5Reader&) = delete;

  const std::string& path() const;
  // True when the group or dataset `object` exists (every group on the way checked).
  bool Has(const std::string& object) const;
  // Names of the members of a group, sorted; empty when the group does not exist.
  std::vector<std::string> Children(const std::string& group) const;
  // Dimensions of a dataset. The typed reads below throw on a missing dataset, a wrong rank or a
  // wrong type class (floating point for Matrix/Vector, integer for Int64Vector).
  std::vector<uint64_t> Dims(const std::string& dataset) const;
  Eigen::MatrixXd Matrix(const std::string& dataset) const;  // rank 2, row-major in the file
  Eigen::VectorXd Vector(const std::string& dataset) const;  // rank 1
  std::vector<int64_t> Int64Vector(const std::string& dataset) const;
  std::string String(const std::string& dataset) const;  // scalar string dataset
  // Attributes of a group or dataset ("" = root).
  bool HasAttribute(const std::string& object, const std::string& name) const;
  std::string StringAttribute(const std::string& object, const std::string& name) const;
  double DoubleAttribute(const std::string& object, const std::string& name) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace fricrom
