// HDF5 checkpoint writer and reader: two loops over the forEachField tables of checkpoint.hpp. Every HDF5
// call is checked; handles are closed by RAII; HDF5's own error printing is silenced and every failure
// becomes a RuntimeFailure (writing) or an InputError (reading) that names the file and what is wrong.
#include "io/checkpoint.hpp"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

#include <hdf5.h>

#include "solver/errors.hpp"

namespace vitrum {

namespace {

namespace fs = std::filesystem;

// --- The tables cover every member -------------------------------------------------------------------------
// Every member of the stores is a std::vector (all the same size whatever the element type), so a member
// added to Particles or Bonds without a line in forEachField changes sizeof and stops the build here.

template <class Store> constexpr std::size_t fieldCount() {
    Store store{};
    std::size_t n = 0;
    forEachField(store, [&n](const char*, auto&, int) { ++n; });
    return n;
}

static_assert(sizeof(Particles) == fieldCount<Particles>() * sizeof(std::vector<double>),
              "a member was added to Particles: add it to forEachField(Particles&) in solver/model/particles.hpp");
static_assert(sizeof(Bonds) == fieldCount<Bonds>() * sizeof(std::vector<double>),
              "a member was added to Bonds: add it to forEachField(Bonds&) in solver/model/bonds.hpp");

static_assert(sizeof(ContactHistory) == fieldCount<ContactHistory>() * sizeof(std::vector<double>),
              "a member was added to ContactHistory: add it to forEachField(ContactHistory&) in io/checkpoint.hpp");

/// Per-bond state of an optional effect (densification): sized only when the effect is on, so it may be
/// empty; it is then stored with 0 rows and read back empty.
bool effectField(std::string_view name) {
    return name == "slip" || name == "reference_strain" || name == "stress" || name == "released" ||
           name == "release_step" || name == "broken_bonds";
}

// --- HDF5 plumbing -----------------------------------------------------------------------------------------

/// Owns one hid_t and closes it with the matching H5?close.
class Handle {
public:
    using Closer = herr_t (*)(hid_t);

    Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
    Handle(Handle&& other) noexcept
        : id_(std::exchange(other.id_, H5I_INVALID_HID)), closer_(other.closer_) {}
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    Handle& operator=(Handle&&) = delete;
    ~Handle() { close(); }

    bool valid() const { return id_ >= 0; }
    hid_t get() const { return id_; }

    /// Closes now; returns false if HDF5 reports a failure (for the file: the final flush failed).
    bool close() {
        herr_t status = 0;
        if (id_ >= 0) {
            status = closer_(id_);
            id_ = H5I_INVALID_HID;
        }
        return status >= 0;
    }

private:
    hid_t id_;
    Closer closer_;
};

/// HDF5 would print its error stack to stderr on every failed call; the failures become exceptions instead.
void silenceHdf5Errors() {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

/// Each element type's HDF5 type in memory (and in the file: the writer stores native types) and its name.
template <class T> hid_t nativeType() {
    if constexpr (std::is_same_v<T, double>) {
        return H5T_NATIVE_DOUBLE;
    } else if constexpr (std::is_same_v<T, std::int32_t>) {
        return H5T_NATIVE_INT32;
    } else if constexpr (std::is_same_v<T, std::int64_t>) {
        return H5T_NATIVE_INT64;
    } else if constexpr (std::is_same_v<T, std::uint32_t>) {
        return H5T_NATIVE_UINT32;
    } else {
        static_assert(std::is_same_v<T, std::uint8_t>, "add the element type here");
        return H5T_NATIVE_UINT8;
    }
}

template <class T> constexpr std::string_view typeName() {
    if constexpr (std::is_same_v<T, double>) {
        return "float64";
    } else if constexpr (std::is_same_v<T, std::int32_t>) {
        return "int32";
    } else if constexpr (std::is_same_v<T, std::int64_t>) {
        return "int64";
    } else if constexpr (std::is_same_v<T, std::uint32_t>) {
        return "uint32";
    } else {
        static_assert(std::is_same_v<T, std::uint8_t>, "add the element type here");
        return "uint8";
    }
}

/// Whether a stored type holds T exactly (class, size, signedness); byte order is converted by HDF5.
template <class T> bool storedTypeMatches(hid_t stored) {
    const H5T_class_t cls = H5Tget_class(stored);
    if (H5Tget_size(stored) != sizeof(T)) {
        return false;
    }
    if constexpr (std::is_floating_point_v<T>) {
        return cls == H5T_FLOAT;
    } else {
        const H5T_sign_t sign = H5Tget_sign(stored);
        return cls == H5T_INTEGER && sign == (std::is_signed_v<T> ? H5T_SGN_2 : H5T_SGN_NONE);
    }
}

/// File access with a strong close degree: closing the file closes everything in it, so the close that
/// precedes the rename really is the last write.
Handle fileAccess() {
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    if (fapl.valid() && H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG) < 0) {
        fapl.close(); // leaves it invalid: the caller reports the failure
    }
    return fapl;
}

// --- Writing -----------------------------------------------------------------------------------------------

class Writer {
public:
    explicit Writer(std::string path) : path_(std::move(path)) {}

    [[noreturn]] void fail(const std::string& what) const {
        throw RuntimeFailure("cannot write checkpoint '" + path_ + "': " + what);
    }

    template <class T> void attribute(hid_t where, const char* name, const T& value) const {
        Handle space(H5Screate(H5S_SCALAR), H5Sclose);
        if (!space.valid()) {
            fail(std::string("cannot create the dataspace of attribute '") + name + "'");
        }
        Handle attr(H5Acreate2(where, name, nativeType<T>(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
                    H5Aclose);
        if (!attr.valid() || H5Awrite(attr.get(), nativeType<T>(), &value) < 0) {
            fail(std::string("cannot write attribute '") + name + "'");
        }
    }

    /// A fixed-length, null-padded UTF-8 string (HDF5 forbids size 0, so "" is stored as one NUL).
    void attribute(hid_t where, const char* name, const std::string& value) const {
        std::string padded = value;
        padded.resize(std::max<std::size_t>(value.size(), 1), '\0');
        Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
        Handle space(H5Screate(H5S_SCALAR), H5Sclose);
        if (!type.valid() || !space.valid() || H5Tset_size(type.get(), padded.size()) < 0 ||
            H5Tset_strpad(type.get(), H5T_STR_NULLPAD) < 0 || H5Tset_cset(type.get(), H5T_CSET_UTF8) < 0) {
            fail(std::string("cannot create the string type of attribute '") + name + "'");
        }
        Handle attr(H5Acreate2(where, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
        if (!attr.valid() || H5Awrite(attr.get(), type.get(), padded.data()) < 0) {
            fail(std::string("cannot write attribute '") + name + "'");
        }
    }

    void vector(hid_t where, const char* name, const std::vector<double>& values) const {
        const hsize_t dims[1] = {values.size()};
        Handle space(H5Screate_simple(1, dims, nullptr), H5Sclose);
        Handle dataset(space.valid() ? H5Dcreate2(where, name, H5T_NATIVE_DOUBLE, space.get(), H5P_DEFAULT,
                                                  H5P_DEFAULT, H5P_DEFAULT)
                                     : H5I_INVALID_HID,
                       H5Dclose);
        if (!dataset.valid() || (!values.empty() && H5Dwrite(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL,
                                                             H5P_DEFAULT, values.data()) < 0)) {
            fail(std::string("cannot write dataset '/") + name + "'");
        }
    }

    template <class Store> void store(hid_t file, const std::string& group_name, const Store& store) const {
        Handle group(H5Gcreate2(file, group_name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
        if (!group.valid()) {
            fail("cannot create group '/" + group_name + "'");
        }
        const std::size_t n = store.size();
        attribute(group.get(), "count", static_cast<std::int64_t>(n));
        forEachField(store, [&](const char* name, const auto& values, int components) {
            using T = typename std::decay_t<decltype(values)>::value_type;
            const std::string where = "/" + group_name + "/" + name;
            const bool absent = values.empty() && effectField(name); // stored with 0 rows
            if (values.size() != n * components && !absent) {
                fail("field '" + where + "' holds " + std::to_string(values.size()) + " values, expected " +
                     std::to_string(n) + " x " + std::to_string(components));
            }
            const hsize_t dims[2] = {absent ? 0 : n, static_cast<hsize_t>(components)};
            Handle space(H5Screate_simple(2, dims, nullptr), H5Sclose);
            if (!space.valid()) {
                fail("cannot create the dataspace of '" + where + "'");
            }
            Handle dataset(H5Dcreate2(group.get(), name, nativeType<T>(), space.get(), H5P_DEFAULT,
                                      H5P_DEFAULT, H5P_DEFAULT),
                           H5Dclose);
            if (!dataset.valid()) {
                fail("cannot create dataset '" + where + "'");
            }
            if (n > 0 &&
                H5Dwrite(dataset.get(), nativeType<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0) {
                fail("cannot write dataset '" + where + "'");
            }
        });
    }

private:
    std::string path_;
};

/// Pushes the file's bytes to the disk, so the rename never publishes a name for data still in flight.
bool syncToDisk(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY);
    if (fd < 0) {
        return false;
    }
    const bool synced = ::fsync(fd) == 0;
    return ::close(fd) == 0 && synced;
}

// --- Reading -----------------------------------------------------------------------------------------------

class Reader {
public:
    explicit Reader(std::string path) : path_(std::move(path)) {}

    [[noreturn]] void fail(const std::string& what) const {
        throw InputError("checkpoint '" + path_ + "': " + what);
    }

    /// Opens attribute `name` of `where` (described as `owner` in messages), which must be a single value.
    Handle openAttribute(hid_t where, const char* name, const std::string& owner) const {
        const htri_t exists = H5Aexists(where, name);
        if (exists < 0) {
            fail("cannot read the attributes of " + owner + " (corrupt file?)");
        }
        if (exists == 0) {
            fail("missing attribute '" + std::string(name) + "' of " + owner);
        }
        Handle attr(H5Aopen(where, name, H5P_DEFAULT), H5Aclose);
        if (!attr.valid()) {
            fail("cannot open attribute '" + std::string(name) + "' of " + owner);
        }
        Handle space(H5Aget_space(attr.get()), H5Sclose);
        if (!space.valid() || H5Sget_simple_extent_npoints(space.get()) != 1) {
            fail("attribute '" + std::string(name) + "' of " + owner + " is not a single value");
        }
        return attr;
    }

    template <class T> T attribute(hid_t where, const char* name, const std::string& owner) const {
        Handle attr = openAttribute(where, name, owner);
        Handle type(H5Aget_type(attr.get()), H5Tclose);
        if (!type.valid() || !storedTypeMatches<T>(type.get())) {
            fail("attribute '" + std::string(name) + "' of " + owner + " is not of type " +
                 std::string(typeName<T>()));
        }
        T value{};
        if (H5Aread(attr.get(), nativeType<T>(), &value) < 0) {
            fail("cannot read attribute '" + std::string(name) + "' of " + owner);
        }
        return value;
    }

    std::string stringAttribute(hid_t where, const char* name, const std::string& owner) const {
        Handle attr = openAttribute(where, name, owner);
        Handle stored(H5Aget_type(attr.get()), H5Tclose);
        if (!stored.valid() || H5Tget_class(stored.get()) != H5T_STRING ||
            H5Tis_variable_str(stored.get()) != 0) {
            fail("attribute '" + std::string(name) + "' of " + owner + " is not a fixed-length string");
        }
        const std::size_t size = H5Tget_size(stored.get());
        // The stored type with null padding: same size and character set, so HDF5 only has to adjust padding.
        Handle type(H5Tcopy(stored.get()), H5Tclose);
        if (size == 0 || !type.valid() || H5Tset_strpad(type.get(), H5T_STR_NULLPAD) < 0) {
            fail("cannot read attribute '" + std::string(name) + "' of " + owner);
        }
        std::string value(size, '\0');
        if (H5Aread(attr.get(), type.get(), value.data()) < 0) {
            fail("cannot read attribute '" + std::string(name) + "' of " + owner);
        }
        value.resize(value.find('\0') == std::string::npos ? size : value.find('\0'));
        return value;
    }

    /// A 1D double dataset `name` of `where`, at most max_count long.
    std::vector<double> vector(hid_t where, const char* name, std::uintmax_t max_count) const {
        const std::string path = std::string("/") + name;
        if (H5Lexists(where, name, H5P_DEFAULT) <= 0) {
            fail("missing dataset '" + path + "'");
        }
        Handle dataset(H5Dopen2(where, name, H5P_DEFAULT), H5Dclose);
        if (!dataset.valid()) {
            fail("cannot open dataset '" + path + "'");
        }
        Handle type(H5Dget_type(dataset.get()), H5Tclose);
        Handle space(H5Dget_space(dataset.get()), H5Sclose);
        hsize_t dims[1] = {0};
        if (!type.valid() || !storedTypeMatches<double>(type.get()) || !space.valid() ||
            H5Sget_simple_extent_ndims(space.get()) != 1 || H5Sget_simple_extent_dims(space.get(), dims, nullptr) != 1 ||
            dims[0] > max_count) {
            fail("dataset '" + path + "' is not a 1D array of doubles");
        }
        std::vector<double> values(dims[0]);
        if (!values.empty() &&
            H5Dread(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0) {
            fail("cannot read dataset '" + path + "' (truncated or corrupt file?)");
        }
        return values;
    }

    /// Reads every field of `store` from group `group_name`; `max_count` bounds the stored count (the file
    /// size, since every entry takes at least one byte) so a corrupt count cannot ask for absurd memory.
    template <class Store>
    void store(hid_t file, const std::string& group_name, Store& store, std::uintmax_t max_count) const {
        const std::string group_path = "/" + group_name;
        const htri_t exists = H5Lexists(file, group_name.c_str(), H5P_DEFAULT);
        if (exists <= 0) {
            fail("missing group '" + group_path + "'");
        }
        Handle group(H5Gopen2(file, group_name.c_str(), H5P_DEFAULT), H5Gclose);
        if (!group.valid()) {
            fail("'" + group_path + "' is not a group");
        }
        const std::int64_t count = attribute<std::int64_t>(group.get(), "count", "'" + group_path + "'");
        if (count < 0 || static_cast<std::uintmax_t>(count) > max_count) {
            fail("'" + group_path + "' has an impossible count " + std::to_string(count));
        }
        const auto n = static_cast<std::size_t>(count);
        forEachField(store, [&](const char* name, auto& values, int components) {
            using T = typename std::decay_t<decltype(values)>::value_type;
            const std::string where = group_path + "/" + name;
            const htri_t present = H5Lexists(group.get(), name, H5P_DEFAULT);
            if (present < 0) {
                fail("cannot look up dataset '" + where + "' (corrupt file?)");
            }
            if (present == 0) {
                fail("missing dataset '" + where + "'");
            }
            Handle dataset(H5Dopen2(group.get(), name, H5P_DEFAULT), H5Dclose);
            if (!dataset.valid()) {
                fail("cannot open dataset '" + where + "'");
            }
            Handle type(H5Dget_type(dataset.get()), H5Tclose);
            if (!type.valid() || !storedTypeMatches<T>(type.get())) {
                fail("dataset '" + where + "' is not of type " + std::string(typeName<T>()));
            }
            Handle space(H5Dget_space(dataset.get()), H5Sclose);
            hsize_t dims[2] = {0, 0};
            if (!space.valid() || H5Sget_simple_extent_ndims(space.get()) != 2 ||
                H5Sget_simple_extent_dims(space.get(), dims, nullptr) != 2 ||
                (dims[0] != n && !(dims[0] == 0 && effectField(name))) ||
                dims[1] != static_cast<hsize_t>(components)) {
                fail("dataset '" + where + "' does not have shape (" + std::to_string(n) + ", " +
                     std::to_string(components) + ")");
            }
            if (dims[0] == 0 && n > 0) { // an effect's state the run did not have
                values.clear();
                return;
            }
            values.assign(n * components, T{});
            if (n > 0 &&
                H5Dread(dataset.get(), nativeType<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0) {
                fail("cannot read dataset '" + where + "' (truncated or corrupt file?)");
            }
        });
    }

private:
    std::string path_;
};

} // namespace

void writeCheckpoint(const std::string& path, const Particles& particles, const Bonds& bonds,
                     const CheckpointMeta& meta) {
    silenceHdf5Errors();
    const Writer writer(path);
    const std::string tmp = path + ".tmp";

    Handle fapl = fileAccess();
    if (!fapl.valid()) {
        writer.fail("cannot set up HDF5 file access");
    }
    // H5F_ACC_TRUNC: a .tmp left by a crashed write is simply overwritten.
    Handle file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()), H5Fclose);
    if (!file.valid()) {
        writer.fail("cannot create '" + tmp + "'");
    }
    try {
        const hid_t root = file.get();
        writer.attribute(root, "format_version", static_cast<std::int32_t>(kCheckpointFormatVersion));
        writer.attribute(root, "vitrum_version", meta.vitrum_version);
        writer.attribute(root, "scene_name", meta.scene_name);
        writer.attribute(root, "scene_sha256", meta.scene_sha256);
        writer.attribute(root, "step", static_cast<std::int64_t>(meta.step));
        writer.attribute(root, "time", meta.time);
        writer.attribute(root, "dt", meta.dt);
        writer.store(root, "particles", particles);
        writer.store(root, "bonds", bonds);
        writer.store(root, "contacts", meta.contacts);
        writer.vector(root, "controller", meta.controller);
        if (!meta.cnem_state.empty()) {
            writer.vector(root, "cnem_state", meta.cnem_state);
        }
        if (H5Fflush(root, H5F_SCOPE_GLOBAL) < 0 || !file.close()) {
            writer.fail("cannot flush and close '" + tmp + "'");
        }
        if (!syncToDisk(tmp)) {
            writer.fail("cannot sync '" + tmp + "' to disk");
        }
    } catch (...) {
        file.close();
        std::error_code ignored;
        fs::remove(tmp, ignored);
        throw;
    }
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        writer.fail("cannot rename '" + tmp + "' onto it: " + ec.message());
    }
}

CheckpointMeta readCheckpoint(const std::string& path, Particles& particles, Bonds& bonds) {
    silenceHdf5Errors();
    const Reader reader(path);

    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (!fs::exists(status)) {
        reader.fail("no such file");
    }
    if (!fs::is_regular_file(status)) {
        reader.fail("not a regular file");
    }
    const std::uintmax_t file_size = fs::file_size(path, ec);
    if (ec) {
        reader.fail("cannot read its size: " + ec.message());
    }
    const htri_t is_hdf5 = H5Fis_hdf5(path.c_str());
    if (is_hdf5 < 0) {
        reader.fail("cannot be read");
    }
    if (is_hdf5 == 0) {
        reader.fail("not an HDF5 file");
    }
    Handle fapl = fileAccess();
    if (!fapl.valid()) {
        reader.fail("cannot set up HDF5 file access");
    }
    Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl.get()), H5Fclose);
    if (!file.valid()) {
        reader.fail("cannot be opened as HDF5 (truncated or corrupt file?)");
    }
    const hid_t root = file.get();
    const std::string owner = "the root group";

    const auto version = reader.attribute<std::int32_t>(root, "format_version", owner);
    if (version != kCheckpointFormatVersion) {
        reader.fail("format version " + std::to_string(version) + ", but this vitrum reads version " +
                    std::to_string(kCheckpointFormatVersion));
    }
    CheckpointMeta meta;
    meta.vitrum_version = reader.stringAttribute(root, "vitrum_version", owner);
    meta.scene_name = reader.stringAttribute(root, "scene_name", owner);
    meta.scene_sha256 = reader.stringAttribute(root, "scene_sha256", owner);
    meta.step = reader.attribute<std::int64_t>(root, "step", owner);
    meta.time = reader.attribute<double>(root, "time", owner);
    meta.dt = reader.attribute<double>(root, "dt", owner);

    // Read into fresh stores and hand them over only once everything is consistent.
    Particles p;
    Bonds b;
    reader.store(root, "particles", p, file_size);
    reader.store(root, "bonds", b, file_size);
    if (H5Lexists(root, "contacts", H5P_DEFAULT) > 0) { // effect contact (absent in older files: no history)
        reader.store(root, "contacts", meta.contacts, file_size);
        for (std::size_t k = 0; k < meta.contacts.size(); ++k) {
            if (meta.contacts.i[k] < 0 || meta.contacts.i[k] >= meta.contacts.j[k] ||
                meta.contacts.j[k] >= static_cast<std::int32_t>(p.size())) {
                reader.fail("contact " + std::to_string(k) + " joins particles " + std::to_string(meta.contacts.i[k]) +
                            " and " + std::to_string(meta.contacts.j[k]) + ", but there are " +
                            std::to_string(p.size()) + " particles");
            }
        }
    }
    meta.controller = reader.vector(root, "controller", file_size);
    if (H5Lexists(root, "cnem_state", H5P_DEFAULT) > 0) { // effect coupling
        meta.cnem_state = reader.vector(root, "cnem_state", file_size);
    }

    const auto n_particles = static_cast<std::int64_t>(p.size());
    for (std::size_t k = 0; k < b.size(); ++k) {
        const std::int64_t i = b.i[k];
        const std::int64_t j = b.j[k];
        if (i < 0 || j < 0 || i >= n_particles || j >= n_particles || i == j) {
            reader.fail("bond " + std::to_string(k) + " joins particles " + std::to_string(i) + " and " +
                        std::to_string(j) + ", but there are " + std::to_string(n_particles) + " particles");
        }
    }
    if (!file.close()) {
        reader.fail("cannot close the file");
    }
    particles = std::move(p);
    bonds = std::move(b);
    return meta;
}

} // namespace vitrum
