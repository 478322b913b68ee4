// Minimal HDF5 result writer (C API kept behind this header). The file is written under a
// temporary name and renamed onto the target by Commit(); destroying an uncommitted writer
// removes the temporary file.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace fricrom::app {

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

}  // namespace fricrom::app
