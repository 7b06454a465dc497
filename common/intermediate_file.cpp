#include "common/intermediate_file.h"

#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>

#include "common/error.h"
#include "common/file_bytes.h"
#include "common/sha256.h"
#include "common/text_encoding.h"

namespace syn {
namespace {

// HDF5 prints its own error stack to stderr by default; we report errors
// ourselves, with the file name, so silence it once.
void SilenceHdf5ErrorStack() {
  static const bool silenced = [] {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)silenced;
}

// Closes an HDF5 identifier when it goes out of scope.
class Id {
 public:
  Id() = default;
  Id(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  Id(Id&& other) noexcept : id_(other.id_), close_(other.close_) { other.id_ = -1; }
  Id& operator=(Id&& other) noexcept {
    reset();
    id_ = other.id_;
    close_ = other.close_;
    other.id_ = -1;
    return *this;
  }
  ~Id() { reset(); }
  void reset() {
    if (id_ >= 0 && close_) close_(id_);
    id_ = -1;
  }
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }

 private:
  hid_t id_ = -1;
  herr_t (*close_)(hid_t) = nullptr;
};

Id Checked(hid_t id, herr_t (*close)(hid_t), const std::string& file, const std::string& what) {
  if (id < 0) throw DataError(Location::InFile(file), "HDF5: " + what);
  return Id(id, close);
}

void CheckStatus(herr_t status, const std::string& file, const std::string& what) {
  if (status < 0) throw DataError(Location::InFile(file), "HDF5: " + what);
}

// Variable-length UTF-8 string type, used for every string we store.
Id StringType(const std::string& file) {
  Id type = Checked(H5Tcopy(H5T_C_S1), H5Tclose, file, "cannot copy string type");
  H5Tset_size(type.get(), H5T_VARIABLE);
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  return type;
}

// Object-creation properties without modification/creation times, so files
// are byte-identical across runs.
Id NoTimesGroupProperties(const std::string& file) {
  Id properties = Checked(H5Pcreate(H5P_GROUP_CREATE), H5Pclose, file, "cannot create group properties");
  H5Pset_obj_track_times(properties.get(), false);
  return properties;
}

Id NoTimesDatasetProperties(const std::string& file) {
  Id properties = Checked(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, file, "cannot create dataset properties");
  H5Pset_obj_track_times(properties.get(), false);
  return properties;
}

std::string ParentGroup(const std::string& name) {
  const size_t slash = name.rfind('/');
  return slash == std::string::npos ? std::string() : name.substr(0, slash);
}

}  // namespace

nlohmann::json DescribeInput(const std::string& path) {
  return nlohmann::json{{"path", path}, {"sha256", Sha256OfFile(path)}};
}

std::string CanonicalJson(const nlohmann::json& value) {
  // nlohmann::json keeps object keys in a std::map (sorted) and prints
  // doubles as the shortest text that reads back to the same value.
  // Text from files may be Latin-1 or garbage: stored as UTF-8 by the one rule of common/text_encoding.h,
  // so a dump never fails on a byte.
  nlohmann::json utf8 = value;
  MakeJsonUtf8(utf8);
  return utf8.dump(-1, ' ', false, nlohmann::json::error_handler_t::strict);
}

// ---- writer ------------------------------------------------------------------

struct IntermediateWriter::Handles {
  Id file;
};

IntermediateWriter::IntermediateWriter(std::string path, const Provenance& provenance)
    : path_(std::move(path)), handles_(std::make_unique<Handles>()) {
  SilenceHdf5ErrorStack();
  temporary_path_ = path_ + ".tmp-" + std::to_string(::getpid());
  const std::filesystem::path parent = std::filesystem::path(path_).parent_path();
  std::error_code unreadable;
  if (!parent.empty() && !std::filesystem::is_directory(parent, unreadable)) {
    throw DataError(Location::InFile(path_), "output directory does not exist: " + parent.string());
  }
  Id file_properties = Checked(H5Pcreate(H5P_FILE_CREATE), H5Pclose, path_, "cannot create file properties");
  H5Pset_obj_track_times(file_properties.get(), false);  // the root group's times
  handles_->file = Checked(H5Fcreate(temporary_path_.c_str(), H5F_ACC_TRUNC, file_properties.get(), H5P_DEFAULT),
                           H5Fclose, path_, "cannot create " + temporary_path_);
  writeAttribute("", "schema", provenance.schema);
  writeAttribute("", "schema_version", provenance.schema_version);
  writeAttribute("", "producer", provenance.producer);
  writeAttribute("", "parameters", CanonicalJson(provenance.parameters));
  writeAttribute("", "inputs", CanonicalJson(provenance.inputs));
}

IntermediateWriter::~IntermediateWriter() {
  if (!committed_) {
    handles_->file.reset();
    std::remove(temporary_path_.c_str());
  }
}

namespace {

// Creates every missing group along `group_path` ("a/b/c").
void EnsureGroups(hid_t file, const std::string& group_path, const std::string& file_name) {
  if (group_path.empty()) return;
  size_t start = 0;
  while (start <= group_path.size()) {
    size_t slash = group_path.find('/', start);
    if (slash == std::string::npos) slash = group_path.size();
    const std::string prefix = group_path.substr(0, slash);
    if (H5Lexists(file, prefix.c_str(), H5P_DEFAULT) <= 0) {
      Id properties = NoTimesGroupProperties(file_name);
      Checked(H5Gcreate2(file, prefix.c_str(), H5P_DEFAULT, properties.get(), H5P_DEFAULT), H5Gclose, file_name,
              "cannot create group " + prefix);
    }
    start = slash + 1;
  }
}

void WriteNumeric(hid_t file, const std::string& file_name, const std::string& name,
                  const std::vector<int64_t>& dims, hid_t memory_type, hid_t file_type, const void* data) {
  EnsureGroups(file, ParentGroup(name), file_name);
  std::vector<hsize_t> shape(dims.begin(), dims.end());
  Id space = Checked(H5Screate_simple(static_cast<int>(shape.size()), shape.data(), nullptr), H5Sclose, file_name,
                     "cannot create dataspace for " + name);
  Id properties = NoTimesDatasetProperties(file_name);
  Id dataset = Checked(H5Dcreate2(file, name.c_str(), file_type, space.get(), H5P_DEFAULT, properties.get(),
                                  H5P_DEFAULT),
                       H5Dclose, file_name, "cannot create dataset " + name);
  hsize_t count = 1;
  for (hsize_t d : shape) count *= d;
  if (count > 0) {
    CheckStatus(H5Dwrite(dataset.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), file_name,
                "cannot write dataset " + name);
  }
}

Id OpenObject(hid_t file, const std::string& object, const std::string& file_name) {
  const char* name = object.empty() ? "/" : object.c_str();
  return Checked(H5Oopen(file, name, H5P_DEFAULT), H5Oclose, file_name, "no object " + object);
}

void WriteAttributeRaw(hid_t file, const std::string& file_name, const std::string& object, const std::string& name,
                       hid_t type, const void* value) {
  Id target = OpenObject(file, object, file_name);
  Id space = Checked(H5Screate(H5S_SCALAR), H5Sclose, file_name, "cannot create scalar dataspace");
  if (H5Aexists(target.get(), name.c_str()) > 0) H5Adelete(target.get(), name.c_str());
  Id attribute = Checked(H5Acreate2(target.get(), name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT),
                         H5Aclose, file_name, "cannot create attribute " + name);
  CheckStatus(H5Awrite(attribute.get(), type, value), file_name, "cannot write attribute " + name);
}

}  // namespace

void IntermediateWriter::writeDoubles(const std::string& name, const std::vector<int64_t>& dims, const double* data) {
  WriteNumeric(handles_->file.get(), path_, name, dims, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, data);
}

void IntermediateWriter::writeDoubles(const std::string& name, const std::vector<double>& values) {
  writeDoubles(name, {static_cast<int64_t>(values.size())}, values.data());
}

void IntermediateWriter::writeInts(const std::string& name, const std::vector<int64_t>& dims, const int64_t* data) {
  WriteNumeric(handles_->file.get(), path_, name, dims, H5T_NATIVE_INT64, H5T_STD_I64LE, data);
}

void IntermediateWriter::writeInts(const std::string& name, const std::vector<int64_t>& values) {
  writeInts(name, {static_cast<int64_t>(values.size())}, values.data());
}

void IntermediateWriter::writeStrings(const std::string& name, const std::vector<std::string>& values) {
  std::vector<const char*> pointers;
  pointers.reserve(values.size());
  // HDF5 strings are declared UTF-8: text from files is converted by the rule of common/text_encoding.h.
  std::vector<std::string> utf8;
  utf8.reserve(values.size());
  for (const std::string& value : values) utf8.push_back(ToUtf8(value));
  for (const std::string& value : utf8) pointers.push_back(value.c_str());
  Id type = StringType(path_);
  WriteNumeric(handles_->file.get(), path_, name, {static_cast<int64_t>(values.size())}, type.get(), type.get(),
               pointers.data());
}

void IntermediateWriter::writeAttribute(const std::string& object, const std::string& name, const std::string& value) {
  Id type = StringType(path_);
  const std::string utf8 = ToUtf8(value);
  const char* pointer = utf8.c_str();
  WriteAttributeRaw(handles_->file.get(), path_, object, name, type.get(), &pointer);
}

void IntermediateWriter::writeAttribute(const std::string& object, const std::string& name, double value) {
  WriteAttributeRaw(handles_->file.get(), path_, object, name, H5T_NATIVE_DOUBLE, &value);
}

void IntermediateWriter::writeAttribute(const std::string& object, const std::string& name, int64_t value) {
  WriteAttributeRaw(handles_->file.get(), path_, object, name, H5T_NATIVE_INT64, &value);
}

void IntermediateWriter::commit() {
  CheckStatus(H5Fflush(handles_->file.get(), H5F_SCOPE_GLOBAL), path_, "cannot flush");
  handles_->file.reset();
  PauseBeforeRenameIfRequested(path_, temporary_path_);
  std::error_code error;
  std::filesystem::rename(temporary_path_, path_, error);
  if (error) {
    std::remove(temporary_path_.c_str());
    throw DataError(Location::InFile(path_), "cannot rename " + temporary_path_ + ": " + error.message());
  }
  committed_ = true;
}

// ---- reader ------------------------------------------------------------------

struct IntermediateReader::Handles {
  Id file;
};

namespace {

std::string ReadStringAttributeOf(hid_t target, const std::string& name, const std::string& file_name) {
  Id attribute = Checked(H5Aopen(target, name.c_str(), H5P_DEFAULT), H5Aclose, file_name,
                         "missing attribute '" + name + "'");
  Id type = Checked(H5Aget_type(attribute.get()), H5Tclose, file_name, "bad attribute type");
  if (H5Tget_class(type.get()) != H5T_STRING) {
    throw DataError(Location::InFile(file_name), "attribute '" + name + "' is not a string");
  }
  if (H5Tis_variable_str(type.get()) > 0) {
    Id memory_type = StringType(file_name);
    char* text = nullptr;
    CheckStatus(H5Aread(attribute.get(), memory_type.get(), &text), file_name, "cannot read attribute " + name);
    std::string value = text ? text : "";
    H5free_memory(text);
    return value;
  }
  const size_t size = H5Tget_size(type.get());
  std::string value(size, '\0');
  CheckStatus(H5Aread(attribute.get(), type.get(), value.data()), file_name, "cannot read attribute " + name);
  value.resize(std::strlen(value.c_str()));
  return value;
}

template <typename T>
T ReadScalarAttributeOf(hid_t target, const std::string& name, hid_t memory_type, const std::string& file_name) {
  Id attribute = Checked(H5Aopen(target, name.c_str(), H5P_DEFAULT), H5Aclose, file_name,
                         "missing attribute '" + name + "'");
  T value{};
  CheckStatus(H5Aread(attribute.get(), memory_type, &value), file_name, "cannot read attribute " + name);
  return value;
}

}  // namespace

IntermediateReader::IntermediateReader(std::string path, const std::string& expected_schema,
                                       int64_t expected_version)
    : path_(std::move(path)), handles_(std::make_unique<Handles>()) {
  SilenceHdf5ErrorStack();
  std::error_code unreadable;
  if (!std::filesystem::exists(path_, unreadable)) throw DataError(Location::InFile(path_), "no such file");
  if (H5Fis_hdf5(path_.c_str()) <= 0) {
    throw DataError(Location::InFile(path_), "not an HDF5 file; expected a " + expected_schema + " intermediate");
  }
  handles_->file = Checked(H5Fopen(path_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, path_, "cannot open");
  Id root = OpenObject(handles_->file.get(), "", path_);
  if (H5Aexists(root.get(), "schema") <= 0 || H5Aexists(root.get(), "schema_version") <= 0) {
    throw DataError(Location::InFile(path_),
                    "no schema attributes: not a synsculpt intermediate file (expected " + expected_schema + ")");
  }
  provenance_.schema = ReadStringAttributeOf(root.get(), "schema", path_);
  provenance_.schema_version = ReadScalarAttributeOf<int64_t>(root.get(), "schema_version", H5T_NATIVE_INT64, path_);
  if (provenance_.schema != expected_schema || provenance_.schema_version != expected_version) {
    throw DataError(Location::InFile(path_),
                    "schema mismatch: file is " + provenance_.schema + " version " +
                        std::to_string(provenance_.schema_version) + ", this tool reads " + expected_schema +
                        " version " + std::to_string(expected_version) + "; re-run the stage that produced it");
  }
  provenance_.producer = ReadStringAttributeOf(root.get(), "producer", path_);
  provenance_.parameters = nlohmann::json::parse(ReadStringAttributeOf(root.get(), "parameters", path_));
  provenance_.inputs = nlohmann::json::parse(ReadStringAttributeOf(root.get(), "inputs", path_));
}

IntermediateReader::~IntermediateReader() = default;

bool IntermediateReader::has(const std::string& name) const {
  // H5Lexists must be asked one path component at a time.
  size_t start = 0;
  while (true) {
    const size_t slash = name.find('/', start);
    const std::string prefix = name.substr(0, slash);
    if (H5Lexists(handles_->file.get(), prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    if (slash == std::string::npos) return true;
    start = slash + 1;
  }
}

namespace {

Id OpenDataset(hid_t file, const std::string& name, const std::string& file_name) {
  return Checked(H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose, file_name, "missing dataset '" + name + "'");
}

std::vector<int64_t> DatasetDims(hid_t dataset, const std::string& file_name) {
  Id space = Checked(H5Dget_space(dataset), H5Sclose, file_name, "cannot get dataspace");
  const int rank = H5Sget_simple_extent_ndims(space.get());
  std::vector<hsize_t> shape(static_cast<size_t>(std::max(rank, 0)));
  H5Sget_simple_extent_dims(space.get(), shape.data(), nullptr);
  return {shape.begin(), shape.end()};
}

int64_t Product(const std::vector<int64_t>& dims) {
  int64_t count = 1;
  for (int64_t d : dims) count *= d;
  return count;
}

}  // namespace

DoubleArray IntermediateReader::readDoubles(const std::string& name) const {
  Id dataset = OpenDataset(handles_->file.get(), name, path_);
  DoubleArray array;
  array.dims = DatasetDims(dataset.get(), path_);
  array.values.resize(static_cast<size_t>(Product(array.dims)));
  if (!array.values.empty()) {
    CheckStatus(H5Dread(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, array.values.data()),
                path_, "cannot read dataset " + name);
  }
  return array;
}

std::vector<int64_t> IntermediateReader::readInts(const std::string& name) const {
  Id dataset = OpenDataset(handles_->file.get(), name, path_);
  std::vector<int64_t> values(static_cast<size_t>(Product(DatasetDims(dataset.get(), path_))));
  if (!values.empty()) {
    CheckStatus(H5Dread(dataset.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), path_,
                "cannot read dataset " + name);
  }
  return values;
}

std::vector<std::string> IntermediateReader::readStrings(const std::string& name) const {
  Id dataset = OpenDataset(handles_->file.get(), name, path_);
  const size_t count = static_cast<size_t>(Product(DatasetDims(dataset.get(), path_)));
  std::vector<char*> pointers(count, nullptr);
  Id type = StringType(path_);
  if (count > 0) {
    CheckStatus(H5Dread(dataset.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, pointers.data()), path_,
                "cannot read strings " + name);
  }
  std::vector<std::string> values;
  values.reserve(count);
  for (char* pointer : pointers) {
    values.emplace_back(pointer ? pointer : "");
    H5free_memory(pointer);
  }
  return values;
}

std::string IntermediateReader::readStringAttribute(const std::string& object, const std::string& name) const {
  Id target = OpenObject(handles_->file.get(), object, path_);
  return ReadStringAttributeOf(target.get(), name, path_);
}

double IntermediateReader::readDoubleAttribute(const std::string& object, const std::string& name) const {
  Id target = OpenObject(handles_->file.get(), object, path_);
  return ReadScalarAttributeOf<double>(target.get(), name, H5T_NATIVE_DOUBLE, path_);
}

int64_t IntermediateReader::readIntAttribute(const std::string& object, const std::string& name) const {
  Id target = OpenObject(handles_->file.get(), object, path_);
  return ReadScalarAttributeOf<int64_t>(target.get(), name, H5T_NATIVE_INT64, path_);
}

bool IntermediateReader::hasAttribute(const std::string& object, const std::string& name) const {
  Id target = OpenObject(handles_->file.get(), object, path_);
  return H5Aexists(target.get(), name.c_str()) > 0;
}

std::vector<std::string> IntermediateReader::listGroup(const std::string& group) const {
  Id target = OpenObject(handles_->file.get(), group, path_);
  std::vector<std::string> names;
  H5Literate(
      target.get(), H5_INDEX_NAME, H5_ITER_INC, nullptr,
      [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
        static_cast<std::vector<std::string>*>(data)->emplace_back(name);
        return 0;
      },
      &names);
  return names;
}

// ---- description ---------------------------------------------------------------

namespace {

nlohmann::json AttributeValue(hid_t attribute, const std::string& file_name) {
  Id type = Checked(H5Aget_type(attribute), H5Tclose, file_name, "bad attribute type");
  Id space = Checked(H5Aget_space(attribute), H5Sclose, file_name, "bad attribute space");
  const hssize_t count = H5Sget_simple_extent_npoints(space.get());
  switch (H5Tget_class(type.get())) {
    case H5T_STRING: {
      if (count != 1) return "<string array>";
      if (H5Tis_variable_str(type.get()) > 0) {
        Id memory_type = StringType(file_name);
        char* text = nullptr;
        H5Aread(attribute, memory_type.get(), &text);
        std::string value = text ? text : "";
        H5free_memory(text);
        // JSON-valued attributes (parameters, inputs) are shown as JSON.
        if (!value.empty() && (value.front() == '{' || value.front() == '[')) {
          nlohmann::json parsed = nlohmann::json::parse(value, nullptr, false);
          if (!parsed.is_discarded()) return parsed;
        }
        return value;
      }
      std::string value(H5Tget_size(type.get()), '\0');
      H5Aread(attribute, type.get(), value.data());
      value.resize(std::strlen(value.c_str()));
      return value;
    }
    case H5T_INTEGER: {
      std::vector<int64_t> values(static_cast<size_t>(count));
      H5Aread(attribute, H5T_NATIVE_INT64, values.data());
      return count == 1 ? nlohmann::json(values[0]) : nlohmann::json(values);
    }
    case H5T_FLOAT: {
      std::vector<double> values(static_cast<size_t>(count));
      H5Aread(attribute, H5T_NATIVE_DOUBLE, values.data());
      return count == 1 ? nlohmann::json(values[0]) : nlohmann::json(values);
    }
    default:
      return "<unsupported attribute type>";
  }
}

nlohmann::json Attributes(hid_t object, const std::string& file_name) {
  nlohmann::json attributes = nlohmann::json::object();
  H5O_info_t info;
  H5Oget_info2(object, &info, H5O_INFO_NUM_ATTRS);
  for (hsize_t i = 0; i < info.num_attrs; ++i) {
    Id attribute = Checked(H5Aopen_by_idx(object, ".", H5_INDEX_NAME, H5_ITER_INC, i, H5P_DEFAULT, H5P_DEFAULT),
                           H5Aclose, file_name, "cannot open attribute");
    const ssize_t length = H5Aget_name(attribute.get(), 0, nullptr);
    std::string name(static_cast<size_t>(length), '\0');
    H5Aget_name(attribute.get(), name.size() + 1, name.data());
    attributes[name] = AttributeValue(attribute.get(), file_name);
  }
  return attributes;
}

struct DescribeContext {
  std::string file_name;
  nlohmann::json datasets = nlohmann::json::object();
  nlohmann::json groups = nlohmann::json::object();
};

}  // namespace

nlohmann::json DescribeIntermediateFile(const std::string& path) {
  SilenceHdf5ErrorStack();
  std::error_code unreadable;
  if (!std::filesystem::exists(path, unreadable)) throw DataError(Location::InFile(path), "no such file");
  if (H5Fis_hdf5(path.c_str()) <= 0) throw DataError(Location::InFile(path), "not an HDF5 file");
  Id file = Checked(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, path, "cannot open");
  DescribeContext context{path, nlohmann::json::object(), nlohmann::json::object()};
  H5Ovisit2(
      file.get(), H5_INDEX_NAME, H5_ITER_INC,
      [](hid_t root, const char* name, const H5O_info_t* info, void* data) -> herr_t {
        auto* context = static_cast<DescribeContext*>(data);
        if (std::string(name) == ".") return 0;
        Id object = Checked(H5Oopen(root, name, H5P_DEFAULT), H5Oclose, context->file_name, "cannot open object");
        nlohmann::json entry;
        if (info->type == H5O_TYPE_DATASET) {
          Id dataset = Checked(H5Dopen2(root, name, H5P_DEFAULT), H5Dclose, context->file_name, "cannot open");
          entry["shape"] = DatasetDims(dataset.get(), context->file_name);
          Id type = Checked(H5Dget_type(dataset.get()), H5Tclose, context->file_name, "bad type");
          const H5T_class_t type_class = H5Tget_class(type.get());
          entry["type"] = type_class == H5T_FLOAT     ? "float64"
                          : type_class == H5T_INTEGER ? "int64"
                          : type_class == H5T_STRING  ? "string"
                                                      : "other";
          nlohmann::json attributes = Attributes(object.get(), context->file_name);
          if (!attributes.empty()) entry["attributes"] = attributes;
          context->datasets[name] = entry;
        } else if (info->type == H5O_TYPE_GROUP) {
          nlohmann::json attributes = Attributes(object.get(), context->file_name);
          if (!attributes.empty()) context->groups[name] = attributes;
        }
        return 0;
      },
      &context, H5O_INFO_BASIC);
  Id root = OpenObject(file.get(), "", path);
  nlohmann::json description;
  description["file"] = path;
  description["attributes"] = Attributes(root.get(), path);
  description["datasets"] = context.datasets;
  if (!context.groups.empty()) description["groups"] = context.groups;
  return description;
}

}  // namespace syn
