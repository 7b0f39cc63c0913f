// HDF5 checkpoint writer and reader: two loops over the forEachField tables of checkpoint.hpp. Every HDF5
// call is checked; handles are closed by RAII; HDF5's own error printing is silenced and every failure
// becomes a RuntimeFailure (writing) or an InputError (reading) that names the file and what is wrong.
#include "io/checkpoint.hpp"

#include <algorithm>
#include <optional>
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
    forEachField(store, [&n](const Field&, auto&) { ++n; });
    return n;
}

static_assert(sizeof(Particles) == fieldCount<Particles>() * sizeof(std::vector<double>),
              "a member was added to Particles: add it to forEachField(Particles&) in solver/model/particles.hpp");
static_assert(sizeof(Bonds) == fieldCount<Bonds>() * sizeof(std::vector<double>),
              "a member was added to Bonds: add it to forEachField(Bonds&) in solver/model/bonds.hpp");

static_assert(sizeof(ContactHistory) == fieldCount<ContactHistory>() * sizeof(std::vector<double>),
              "a member was added to ContactHistory: add it to forEachField(ContactHistory&) in "
              "solver/effects/contact.hpp");

/// Per-bond or per-particle state of an optional effect (densification, fracture, plasticity): sized only when the effect is on, so it may be
/// empty; it is then stored with 0 rows and read back empty.
/// The bonds' reference data are stored in double or in float ([precision] bond_reference): one of the two
/// sets is empty. The restart compares every field's length with the store the scene builds.
bool referenceField(std::string_view name) {
    return name == "rest_length" || name == "axis_i" || name == "axis_j" || name == "twist_ref" ||
           name.ends_with("_f32");
}

bool effectField(std::string_view name) {
    return name == "slip" || name == "reference_strain" || name == "stress" || name == "released" ||
           name == "release_step" || name == "broken_bonds" || name == "plastic_strain" || name == "compaction" ||
           name == "plastic_shear" || name == "plastic_work" || referenceField(name);
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
    } else if constexpr (std::is_same_v<T, float>) {
        return H5T_NATIVE_FLOAT;
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
    } else if constexpr (std::is_same_v<T, float>) {
        return "float32";
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

/// A field member as a run of elements of one type: a std::vector, an Eigen vector (Vec3) or a scalar. bool
/// is stored as uint8.
template <class M> struct Elements {
    using T = M;
    static T* data(M& m) { return &m; }
    static const T* data(const M& m) { return &m; }
    static std::size_t size(const M&) { return 1; }
    static void resize(M&, std::size_t) {}
};
template <class V> struct Elements<std::vector<V>> {
    using T = V;
    static T* data(std::vector<V>& m) { return m.data(); }
    static const T* data(const std::vector<V>& m) { return m.data(); }
    static std::size_t size(const std::vector<V>& m) { return m.size(); }
    static void resize(std::vector<V>& m, std::size_t n) { m.assign(n, V{}); }
};
template <> struct Elements<Vec3> {
    using T = double;
    static T* data(Vec3& m) { return m.data(); }
    static const T* data(const Vec3& m) { return m.data(); }
    static std::size_t size(const Vec3&) { return 3; }
    static void resize(Vec3&, std::size_t) {}
};
template <class M> constexpr bool kResizable = false;
template <class V> constexpr bool kResizable<std::vector<V>> = true;

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

    /// Group `group_name` with attribute count = `n` and one dataset (n, components) per field of `store`'s
    /// table, each with its unit. A field of an effect the run lacks may be empty: stored with 0 rows.
    template <class Store>
    void store(hid_t file, const std::string& group_name, std::size_t n, Store& store) const {
        Handle group(H5Gcreate2(file, group_name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
        if (!group.valid()) {
            fail("cannot create group '/" + group_name + "'");
        }
        attribute(group.get(), "count", static_cast<std::int64_t>(n));
        forEachField(store, [&](const Field& field, const auto& member) {
            using M = std::decay_t<decltype(member)>;
            using T = typename Elements<M>::T;
            const std::string where = "/" + group_name + "/" + field.name;
            const std::size_t size = Elements<M>::size(member);
            const bool absent = size == 0 && effectField(field.name); // stored with 0 rows
            if (size != n * static_cast<std::size_t>(field.components) && !absent) {
                fail("field '" + where + "' holds " + std::to_string(size) + " values, expected " +
                     std::to_string(n) + " x " + std::to_string(field.components));
            }
            const hsize_t dims[2] = {absent ? 0 : n, static_cast<hsize_t>(field.components)};
            Handle space(H5Screate_simple(2, dims, nullptr), H5Sclose);
            if (!space.valid()) {
                fail("cannot create the dataspace of '" + where + "'");
            }
            using Stored = std::conditional_t<std::is_same_v<T, bool>, std::uint8_t, T>;
            Handle dataset(H5Dcreate2(group.get(), field.name, nativeType<Stored>(), space.get(), H5P_DEFAULT,
                                      H5P_DEFAULT, H5P_DEFAULT),
                           H5Dclose);
            if (!dataset.valid()) {
                fail("cannot create dataset '" + where + "'");
            }
            std::vector<Stored> converted;
            const Stored* values = nullptr;
            if constexpr (std::is_same_v<T, bool>) {
                converted.assign(size, 0);
                for (std::size_t k = 0; k < size; ++k) converted[k] = Elements<M>::data(member)[k] ? 1 : 0;
                values = converted.data();
            } else {
                values = Elements<M>::data(member);
            }
            if (n > 0 && !absent &&
                H5Dwrite(dataset.get(), nativeType<Stored>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, values) < 0) {
                fail("cannot write dataset '" + where + "'");
            }
            attribute(dataset.get(), "unit", std::string(field.unit));
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

    /// Reads every field of `store` from group `group_name` and returns its count; `max_count` bounds the
    /// stored count (the file size, since every entry takes at least one byte) so a corrupt count cannot ask
    /// for absurd memory. A scalar or Vec3 field (one element) needs count 1.
    template <class Store>
    std::size_t store(hid_t file, const std::string& group_name, Store& store, std::uintmax_t max_count) const {
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
        forEachField(store, [&](const Field& field, auto& member) {
            using M = std::decay_t<decltype(member)>;
            using T = typename Elements<M>::T;
            using Stored = std::conditional_t<std::is_same_v<T, bool>, std::uint8_t, T>;
            const std::string where = group_path + "/" + field.name;
            const htri_t present = H5Lexists(group.get(), field.name, H5P_DEFAULT);
            if (present < 0) {
                fail("cannot look up dataset '" + where + "' (corrupt file?)");
            }
            if (present == 0) {
                fail("missing dataset '" + where + "'");
            }
            Handle dataset(H5Dopen2(group.get(), field.name, H5P_DEFAULT), H5Dclose);
            if (!dataset.valid()) {
                fail("cannot open dataset '" + where + "'");
            }
            Handle type(H5Dget_type(dataset.get()), H5Tclose);
            if (!type.valid() || !storedTypeMatches<Stored>(type.get())) {
                fail("dataset '" + where + "' is not of type " + std::string(typeName<Stored>()));
            }
            Handle space(H5Dget_space(dataset.get()), H5Sclose);
            hsize_t dims[2] = {0, 0};
            const std::size_t components = static_cast<std::size_t>(field.components);
            if (!space.valid() || H5Sget_simple_extent_ndims(space.get()) != 2 ||
                H5Sget_simple_extent_dims(space.get(), dims, nullptr) != 2 ||
                (dims[0] != n && !(dims[0] == 0 && effectField(field.name))) || dims[1] != components) {
                fail("dataset '" + where + "' does not have shape (" + std::to_string(n) + ", " +
                     std::to_string(components) + ")");
            }
            if (dims[0] == 0 && n > 0) { // an effect's state the run did not have
                if constexpr (kResizable<M>) {
                    member.clear();
                }
                return;
            }
            if constexpr (kResizable<M>) {
                Elements<M>::resize(member, n * components);
            } else if (n != 1 || Elements<M>::size(member) != components) {
                fail("dataset '" + where + "' holds " + std::to_string(n) + " elements, expected one");
            }
            std::vector<Stored> values(n * components);
            if (n > 0 && H5Dread(dataset.get(), nativeType<Stored>(), H5S_ALL, H5S_ALL, H5P_DEFAULT,
                                 values.data()) < 0) {
                fail("cannot read dataset '" + where + "' (truncated or corrupt file?)");
            }
            T* out = Elements<M>::data(member);
            for (std::size_t k = 0; k < values.size(); ++k) {
                out[k] = static_cast<T>(values[k]);
            }
        });
        return n;
    }

private:
    std::string path_;
};

} // namespace

void disableHdf5ExitCleanup() { H5dont_atexit(); }

void writeCheckpoint(const std::string& path, const CheckpointMeta& meta, const RunState& state) {
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
        if (!meta.observations.empty()) {
            writer.attribute(root, "observations", meta.observations);
        }
        writer.store(root, "particles", state.particles.size(), state.particles);
        writer.store(root, "bonds", state.bonds.size(), state.bonds);
        if (state.contacts) {
            ContactHistory history = state.contacts->history();
            writer.store(root, "contacts", history.size(), history);
        }
        if (state.indenter) {
            writer.store(root, "indenter", 1, *state.indenter);
        }
        if (state.cnem) {
            CnemState cnem = *state.cnem;
            writer.store(root, "cnem", cnem.size(), cnem);
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

CheckpointMeta readCheckpoint(const std::string& path, RunState& state) {
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
                    std::to_string(kCheckpointFormatVersion) +
                    (version < kCheckpointFormatVersion ? " (written by an older vitrum: rerun the scene)" : ""));
    }
    CheckpointMeta meta;
    meta.vitrum_version = reader.stringAttribute(root, "vitrum_version", owner);
    meta.scene_name = reader.stringAttribute(root, "scene_name", owner);
    meta.scene_sha256 = reader.stringAttribute(root, "scene_sha256", owner);
    meta.step = reader.attribute<std::int64_t>(root, "step", owner);
    meta.time = reader.attribute<double>(root, "time", owner);
    meta.dt = reader.attribute<double>(root, "dt", owner);
    if (H5Aexists(root, "observations") > 0) {
        meta.observations = reader.stringAttribute(root, "observations", owner);
    }

    // Read into fresh copies and hand them over only once everything is consistent.
    Particles p;
    Bonds b;
    reader.store(root, "particles", p, file_size);
    reader.store(root, "bonds", b, file_size);
    const auto n_particles = static_cast<std::int64_t>(p.size());
    for (std::size_t k = 0; k < b.size(); ++k) {
        const std::int64_t i = b.i[k];
        const std::int64_t j = b.j[k];
        if (i < 0 || j < 0 || i >= n_particles || j >= n_particles || i == j) {
            reader.fail("bond " + std::to_string(k) + " joins particles " + std::to_string(i) + " and " +
                        std::to_string(j) + ", but there are " + std::to_string(n_particles) + " particles");
        }
    }
    ContactHistory history;
    if (state.contacts && H5Lexists(root, "contacts", H5P_DEFAULT) > 0) {
        reader.store(root, "contacts", history, file_size);
        for (std::size_t k = 0; k < history.size(); ++k) {
            if (history.i[k] < 0 || history.i[k] >= history.j[k] || history.j[k] >= n_particles) {
                reader.fail("contact " + std::to_string(k) + " joins particles " + std::to_string(history.i[k]) +
                            " and " + std::to_string(history.j[k]) + ", but there are " +
                            std::to_string(n_particles) + " particles");
            }
            // The list carries the springs over by a merge of two lists sorted by (i, j) (ContactList::build).
            if (k > 0 && std::make_pair(history.i[k - 1], history.j[k - 1]) >= std::make_pair(history.i[k], history.j[k])) {
                reader.fail("contacts " + std::to_string(k - 1) + " and " + std::to_string(k) +
                            " are not in strictly increasing (i, j) order");
            }
        }
    }
    std::optional<Indenter> indenter;
    if (state.indenter) {
        if (H5Lexists(root, "indenter", H5P_DEFAULT) <= 0) {
            reader.fail("no group '/indenter': a checkpoint without the indenter's controller state");
        }
        indenter = *state.indenter;
        reader.store(root, "indenter", *indenter, file_size);
        if (indenter->stage < 0 || indenter->stage > static_cast<int>(indenter->stages.size())) {
            reader.fail("'/indenter/stage' is " + std::to_string(indenter->stage) + ", but the scene has " +
                        std::to_string(indenter->stages.size()) + " stages");
        }
    }
    std::vector<double> cnem_displacement, cnem_velocity, cnem_force;
    if (state.cnem) {
        if (H5Lexists(root, "cnem", H5P_DEFAULT) <= 0) {
            reader.fail("no group '/cnem': a checkpoint without the continuum's state of effect coupling");
        }
        CnemState cnem{cnem_displacement, cnem_velocity, cnem_force};
        const std::size_t nodes = reader.store(root, "cnem", cnem, file_size);
        if (nodes != state.cnem->size()) {
            reader.fail("'/cnem' holds " + std::to_string(nodes) + " nodes, but the scene's continuum has " +
                        std::to_string(state.cnem->size()));
        }
    }
    if (!file.close()) {
        reader.fail("cannot close the file");
    }
    state.particles = std::move(p);
    state.bonds = std::move(b);
    if (state.contacts) {
        state.contacts->restore(history);
    }
    if (state.indenter) {
        *state.indenter = std::move(*indenter);
    }
    if (state.cnem) {
        state.cnem->displacement = std::move(cnem_displacement);
        state.cnem->velocity = std::move(cnem_velocity);
        state.cnem->force = std::move(cnem_force);
    }
    return meta;
}

} // namespace vitrum
