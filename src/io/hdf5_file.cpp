#include "io/hdf5_file.h"

#include <hdf5.h>

#include <algorithm>
#include <stdexcept>

#include "io/atomic_file.h"

namespace fricrom {

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
    const hid_t set =
        H5Dcreate2(parent, leaf.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
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
  const hsize_t dims[2] = {static_cast<hsize_t>(values.rows()),
                           static_cast<hsize_t>(values.cols())};
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
  const hid_t set =
      H5Dcreate2(parent, leaf.c_str(), t, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
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
    const hid_t a =
        H5Acreate2(obj, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT);
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

// ---- Reader ----------------------------------------------------------------------------------

namespace {

// Closes an HDF5 id on scope exit (exceptions included).
class Id {
 public:
  Id(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Id() {
    if (id_ >= 0) close_(id_);
  }
  Id(const Id&) = delete;
  Id& operator=(const Id&) = delete;
  hid_t get() const { return id_; }
  bool ok() const { return id_ >= 0; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

// A scalar string of a dataset or attribute, variable or fixed length.
template <typename ReadFn>
bool ReadStringValue(hid_t file_type, hid_t space, ReadFn read, std::string* out) {
  if (H5Tget_class(file_type) != H5T_STRING || H5Sget_simple_extent_npoints(space) != 1) {
    return false;
  }
  if (H5Tis_variable_str(file_type) > 0) {
    const Id mem(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(mem.get(), H5T_VARIABLE);
    H5Tset_cset(mem.get(), H5Tget_cset(file_type));  // HDF5 converts no character sets
    char* p = nullptr;
    if (read(mem.get(), &p) < 0) return false;
    *out = p ? p : "";
    H5Dvlen_reclaim(mem.get(), space, H5P_DEFAULT, &p);
    return true;
  }
  const size_t size = H5Tget_size(file_type);
  const Id mem(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(mem.get(), size + 1);  // room for the terminator of a full-length value
  H5Tset_cset(mem.get(), H5Tget_cset(file_type));
  std::string buf(size + 1, '\0');
  if (read(mem.get(), buf.data()) < 0) return false;
  *out = buf.c_str();
  return true;
}

}  // namespace

struct Hdf5Reader::Impl {
  std::string path;
  hid_t file = -1;

  [[noreturn]] void Fail(const std::string& what) const {
    throw std::runtime_error(path + ": " + what);
  }
  hid_t OpenDataset(const std::string& name, Hdf5Reader const& r) const {
    if (!r.Has(name)) Fail("missing dataset '" + name + "'");
    const hid_t d = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
    if (d < 0) Fail("'" + name + "' is not a dataset");
    return d;
  }
  // Reads a whole numeric dataset of the given rank and type class into `data` (sized here).
  template <typename T>
  std::vector<uint64_t> ReadNumeric(const std::string& name, int rank, H5T_class_t cls,
                                    hid_t mem_type, std::vector<T>* data,
                                    const Hdf5Reader& r) const {
    const Id d(OpenDataset(name, r), H5Dclose);
    const Id space(H5Dget_space(d.get()), H5Sclose);
    const Id type(H5Dget_type(d.get()), H5Tclose);
    const int got_rank = H5Sget_simple_extent_ndims(space.get());
    if (got_rank != rank) {
      Fail("dataset '" + name + "' has rank " + std::to_string(got_rank) + ", expected " +
           std::to_string(rank));
    }
    if (H5Tget_class(type.get()) != cls) {
      Fail("dataset '" + name + "' holds " +
           (cls == H5T_FLOAT ? "no floating-point values" : "no integers"));
    }
    std::vector<hsize_t> dims(static_cast<size_t>(rank));
    H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
    size_t count = 1;
    for (const hsize_t n : dims) count *= n;
    data->assign(count, T{});
    if (count > 0 && H5Dread(d.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data->data()) < 0) {
      Fail("cannot read dataset '" + name + "' (damaged or truncated file)");
    }
    return {dims.begin(), dims.end()};
  }
  hid_t OpenAttribute(const std::string& object, const std::string& name) const {
    const std::string obj = object.empty() ? "/" : object;
    const hid_t a = H5Aopen_by_name(file, obj.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT);
    if (a < 0) Fail("missing attribute '" + name + "' of '" + obj + "'");
    return a;
  }
};

Hdf5Reader::Hdf5Reader(const std::string& path) : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are reported by exceptions instead
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) impl_->Fail("no such file");
  if (H5Fis_hdf5(path.c_str()) <= 0) impl_->Fail("not an HDF5 file");
  impl_->file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (impl_->file < 0) impl_->Fail("cannot open the HDF5 file (truncated or damaged)");
}

Hdf5Reader::~Hdf5Reader() {
  if (impl_->file >= 0) H5Fclose(impl_->file);
}

const std::string& Hdf5Reader::path() const { return impl_->path; }

bool Hdf5Reader::Has(const std::string& object) const {
  if (object.empty() || object == "/") return true;
  size_t pos = 0;
  for (;;) {
    const size_t slash = object.find('/', pos);
    const std::string prefix = object.substr(0, slash);
    if (H5Lexists(impl_->file, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    if (slash == std::string::npos) return true;
    pos = slash + 1;
  }
}

std::vector<std::string> Hdf5Reader::Children(const std::string& group) const {
  std::vector<std::string> names;
  if (!Has(group)) return names;
  const Id g(H5Gopen2(impl_->file, group.empty() ? "/" : group.c_str(), H5P_DEFAULT), H5Gclose);
  if (!g.ok()) impl_->Fail("'" + group + "' is not a group");
  H5G_info_t info;
  if (H5Gget_info(g.get(), &info) < 0) impl_->Fail("cannot list group '" + group + "'");
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t len =
        H5Lget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (len < 0) impl_->Fail("cannot list group '" + group + "'");
    std::string name(static_cast<size_t>(len) + 1, '\0');
    H5Lget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size(),
                       H5P_DEFAULT);
    name.resize(static_cast<size_t>(len));
    names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<uint64_t> Hdf5Reader::Dims(const std::string& dataset) const {
  const Id d(impl_->OpenDataset(dataset, *this), H5Dclose);
  const Id space(H5Dget_space(d.get()), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  std::vector<hsize_t> dims(static_cast<size_t>(std::max(rank, 0)));
  H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  return {dims.begin(), dims.end()};
}

Eigen::MatrixXd Hdf5Reader::Matrix(const std::string& dataset) const {
  std::vector<double> v;
  const std::vector<uint64_t> dims =
      impl_->ReadNumeric(dataset, 2, H5T_FLOAT, H5T_NATIVE_DOUBLE, &v, *this);
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  return Eigen::Map<const RowMajor>(v.data(), static_cast<Eigen::Index>(dims[0]),
                                    static_cast<Eigen::Index>(dims[1]));
}

Eigen::VectorXd Hdf5Reader::Vector(const std::string& dataset) const {
  std::vector<double> v;
  impl_->ReadNumeric(dataset, 1, H5T_FLOAT, H5T_NATIVE_DOUBLE, &v, *this);
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

std::vector<int64_t> Hdf5Reader::Int64Vector(const std::string& dataset) const {
  std::vector<int64_t> v;
  impl_->ReadNumeric(dataset, 1, H5T_INTEGER, H5T_NATIVE_INT64, &v, *this);
  return v;
}

std::string Hdf5Reader::String(const std::string& dataset) const {
  const Id d(impl_->OpenDataset(dataset, *this), H5Dclose);
  const Id space(H5Dget_space(d.get()), H5Sclose);
  const Id type(H5Dget_type(d.get()), H5Tclose);
  std::string out;
  const auto read = [&](hid_t mem, void* buf) {
    return H5Dread(d.get(), mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf);
  };
  if (!ReadStringValue(type.get(), space.get(), read, &out)) {
    impl_->Fail("dataset '" + dataset + "' is not a readable scalar string");
  }
  return out;
}

bool Hdf5Reader::HasAttribute(const std::string& object, const std::string& name) const {
  if (!Has(object)) return false;
  const std::string obj = object.empty() ? "/" : object;
  return H5Aexists_by_name(impl_->file, obj.c_str(), name.c_str(), H5P_DEFAULT) > 0;
}

std::string Hdf5Reader::StringAttribute(const std::string& object, const std::string& name) const {
  const Id a(impl_->OpenAttribute(object, name), H5Aclose);
  const Id space(H5Aget_space(a.get()), H5Sclose);
  const Id type(H5Aget_type(a.get()), H5Tclose);
  std::string out;
  const auto read = [&](hid_t mem, void* buf) { return H5Aread(a.get(), mem, buf); };
  if (!ReadStringValue(type.get(), space.get(), read, &out)) {
    impl_->Fail("attribute '" + name + "' of '" + (object.empty() ? "/" : object) +
                "' is not a readable scalar string");
  }
  return out;
}

double Hdf5Reader::DoubleAttribute(const std::string& object, const std::string& name) const {
  const Id a(impl_->OpenAttribute(object, name), H5Aclose);
  const Id space(H5Aget_space(a.get()), H5Sclose);
  const Id type(H5Aget_type(a.get()), H5Tclose);
  const H5T_class_t cls = H5Tget_class(type.get());
  double value = 0.0;
  if ((cls != H5T_FLOAT && cls != H5T_INTEGER) || H5Sget_simple_extent_npoints(space.get()) != 1 ||
      H5Aread(a.get(), H5T_NATIVE_DOUBLE, &value) < 0) {
    impl_->Fail("attribute '" + name + "' of '" + (object.empty() ? "/" : object) +
                "' is not a readable scalar number");
  }
  return value;
}

}  // namespace fricrom
