#include "app/hdf5_writer.h"

#include <hdf5.h>

#include <stdexcept>

#include "app/atomic_file.h"

namespace fricrom::app {

struct Hdf5Writer::Impl {
  std::filesystem::path target, tmp;
  hid_t file = -1;
  bool committed = false;

  void Check(herr_t status, const std::string& what) const {
    if (status < 0) throw std::runtime_error(target.string() + ": HDF5 error while " + what);
  }
  hid_t CheckId(hid_t id, const std::string& what) const {
    if (id < 0) throw std::runtime_error(target.string() + ": HDF5 error while " + what);
    return id;
  }
  // Creates the parent groups of `path` and returns the parent's id (caller closes) and leaf.
  hid_t Parent(const std::string& path, std::string* leaf) {
    hid_t current = H5Gopen2(file, "/", H5P_DEFAULT);
    size_t start = 0;
    for (;;) {
      const size_t slash = path.find('/', start);
      if (slash == std::string::npos) {
        *leaf = path.substr(start);
        return current;
      }
      const std::string name = path.substr(start, slash - start);
      hid_t next;
      if (H5Lexists(current, name.c_str(), H5P_DEFAULT) > 0) {
        next = H5Gopen2(current, name.c_str(), H5P_DEFAULT);
      } else {
        next = H5Gcreate2(current, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      }
      H5Gclose(current);
      current = CheckId(next, "creating group " + name);
      start = slash + 1;
    }
  }
  void Write(const std::string& path, hid_t type, int rank, const hsize_t* dims, const void* data) {
    std::string leaf;
    const hid_t parent = Parent(path, &leaf);
    const hid_t space = H5Screate_simple(rank, dims, nullptr);
    const hid_t set = H5Dcreate2(parent, leaf.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT,
                                 H5P_DEFAULT);
    herr_t st = set >= 0 ? H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) : -1;
    if (set >= 0) H5Dclose(set);
    H5Sclose(space);
    H5Gclose(parent);
    Check(st, "writing " + path);
  }
  hid_t StringType() const {
    hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, H5T_VARIABLE);
    H5Tset_cset(t, H5T_CSET_UTF8);
    return t;
  }
};

Hdf5Writer::Hdf5Writer(std::filesystem::path target) : impl_(std::make_unique<Impl>()) {
  impl_->target = std::move(target);
  impl_->tmp = TemporarySibling(impl_->target);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are reported by exceptions instead
  impl_->file = H5Fcreate(impl_->tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (impl_->file < 0) throw std::runtime_error("cannot create HDF5 file " + impl_->tmp.string());
}

Hdf5Writer::~Hdf5Writer() {
  if (impl_->file >= 0) H5Fclose(impl_->file);
  if (!impl_->committed) {
    std::error_code ec;
    std::filesystem::remove(impl_->tmp, ec);
  }
}

void Hdf5Writer::Vector(const std::string& path, const std::vector<double>& values) {
  const hsize_t dims[1] = {values.size()};
  impl_->Write(path, H5T_NATIVE_DOUBLE, 1, dims, values.data());
}
void Hdf5Writer::Vector(const std::string& path, const Eigen::VectorXd& values) {
  Vector(path, std::vector<double>(values.data(), values.data() + values.size()));
}
void Hdf5Writer::IntVector(const std::string& path, const std::vector<int>& values) {
  const hsize_t dims[1] = {values.size()};
  impl_->Write(path, H5T_NATIVE_INT, 1, dims, values.data());
}
void Hdf5Writer::Int64Vector(const std::string& path, const std::vector<int64_t>& values) {
  const hsize_t dims[1] = {values.size()};
  impl_->Write(path, H5T_NATIVE_INT64, 1, dims, values.data());
}
void Hdf5Writer::Matrix(const std::string& path, const Eigen::MatrixXd& values) {
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rm = values;
  const hsize_t dims[2] = {static_cast<hsize_t>(values.rows()), static_cast<hsize_t>(values.cols())};
  impl_->Write(path, H5T_NATIVE_DOUBLE, 2, dims, rm.data());
}
void Hdf5Writer::Strings(const std::string& path, const std::vector<std::string>& values) {
  std::vector<const char*> ptrs;
  for (const std::string& s : values) ptrs.push_back(s.c_str());
  const hsize_t dims[1] = {values.size()};
  const hid_t t = impl_->StringType();
  impl_->Write(path, t, 1, dims, ptrs.data());
  H5Tclose(t);
}
void Hdf5Writer::String(const std::string& path, const std::string& value) {
  std::string leaf;
  const hid_t parent = impl_->Parent(path, &leaf);
  const hid_t t = impl_->StringType();
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t set = H5Dcreate2(parent, leaf.c_str(), t, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  const char* p = value.c_str();
  herr_t st = set >= 0 ? H5Dwrite(set, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, &p) : -1;
  if (set >= 0) H5Dclose(set);
  H5Sclose(space);
  H5Tclose(t);
  H5Gclose(parent);
  impl_->Check(st, "writing " + path);
}

namespace {
template <typename Fn>
void WithObject(hid_t file, const std::string& object, Fn fn) {
  const hid_t obj = H5Oopen(file, object.empty() ? "/" : object.c_str(), H5P_DEFAULT);
  if (obj < 0) throw std::runtime_error("HDF5: no object '" + object + "' for an attribute");
  fn(obj);
  H5Oclose(obj);
}
}  // namespace

void Hdf5Writer::Attribute(const std::string& object, const std::string& name,
                           const std::string& value) {
  WithObject(impl_->file, object, [&](hid_t obj) {
    const hid_t t = impl_->StringType();
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate2(obj, name.c_str(), t, space, H5P_DEFAULT, H5P_DEFAULT);
    const char* p = value.c_str();
    herr_t st = a >= 0 ? H5Awrite(a, t, &p) : -1;
    if (a >= 0) H5Aclose(a);
    H5Sclose(space);
    H5Tclose(t);
    impl_->Check(st, "writing attribute " + name);
  });
}
void Hdf5Writer::Attribute(const std::string& object, const std::string& name, double value) {
  WithObject(impl_->file, object, [&](hid_t obj) {
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate2(obj, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT);
    herr_t st = a >= 0 ? H5Awrite(a, H5T_NATIVE_DOUBLE, &value) : -1;
    if (a >= 0) H5Aclose(a);
    H5Sclose(space);
    impl_->Check(st, "writing attribute " + name);
  });
}

void Hdf5Writer::Commit() {
  impl_->Check(H5Fclose(impl_->file), "closing the file");
  impl_->file = -1;
  CommitFile(impl_->tmp, impl_->target);
  impl_->committed = true;
}

}  // namespace fricrom::app
