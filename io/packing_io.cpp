#include "io/packing_io.hpp"

#include <hdf5.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <system_error>
#include <type_traits>
#include <utility>
#include <vector>

#include "solver/errors.hpp"

namespace vitrum {

namespace {

constexpr const char* kFormat = "vitrum-packing";
constexpr std::int64_t kFormatVersion = 1;

using CloseFn = herr_t (*)(hid_t);

/// Owns one HDF5 identifier and closes it with its H5?close.
class H5Handle {
public:
    H5Handle() = default;
    H5Handle(hid_t id, CloseFn close) : id_(id), close_(close) {}
    H5Handle(H5Handle&& other) noexcept
        : id_(std::exchange(other.id_, H5I_INVALID_HID)), close_(other.close_) {}
    H5Handle& operator=(H5Handle&& other) noexcept {
        if (this != &other) {
            close();
            id_ = std::exchange(other.id_, H5I_INVALID_HID);
            close_ = other.close_;
        }
        return *this;
    }
    H5Handle(const H5Handle&) = delete;
    H5Handle& operator=(const H5Handle&) = delete;
    ~H5Handle() { close(); }

    hid_t get() const { return id_; }
    bool valid() const { return id_ >= 0; }
    /// Closes now; returns the close status (negative on failure).
    herr_t close() {
        herr_t status = 0;
        if (id_ >= 0 && close_ != nullptr) {
            status = close_(id_);
        }
        id_ = H5I_INVALID_HID;
        return status;
    }

private:
    hid_t id_ = H5I_INVALID_HID;
    CloseFn close_ = nullptr;
};

/// Turns off HDF5's automatic printing of its error stack for the scope (we report errors ourselves) and
/// restores the previous handler on exit.
class QuietHdf5 {
public:
    QuietHdf5() {
        H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
        H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    }
    ~QuietHdf5() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }
    QuietHdf5(const QuietHdf5&) = delete;
    QuietHdf5& operator=(const QuietHdf5&) = delete;

private:
    H5E_auto2_t func_ = nullptr;
    void* data_ = nullptr;
};

/// The innermost message of HDF5's current error stack, as " (HDF5: ...)", or "" when the stack is empty.
std::string hdf5Detail() {
    std::string innermost;
    H5Ewalk2(
        H5E_DEFAULT, H5E_WALK_UPWARD,
        [](unsigned n, const H5E_error2_t* err, void* data) -> herr_t {
            auto* out = static_cast<std::string*>(data);
            if (n == 0 && err != nullptr && err->desc != nullptr) {
                *out = err->desc;
            }
            return 0;
        },
        &innermost);
    H5Eclear2(H5E_DEFAULT);
    return innermost.empty() ? std::string() : " (HDF5: " + innermost + ")";
}

// ---- writing ----------------------------------------------------------------------------------------------

class Writer {
public:
    explicit Writer(std::string path) : path_(std::move(path)) {}

    [[noreturn]] void fail(const std::string& what) const {
        throw RuntimeFailure("cannot write packing '" + path_ + "': " + what + hdf5Detail());
    }

    H5Handle check(hid_t id, CloseFn close, const std::string& what) const {
        if (id < 0) {
            fail(what);
        }
        return H5Handle(id, close);
    }

    void status(herr_t s, const std::string& what) const {
        if (s < 0) {
            fail(what);
        }
    }

    void dataset(hid_t loc, const char* name, hid_t file_type, hid_t mem_type, std::vector<hsize_t> dims,
                 const void* data) const {
        const H5Handle space = check(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
                                     H5Sclose, std::string("dataspace of ") + name);
        const H5Handle set =
            check(H5Dcreate2(loc, name, file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                  H5Dclose, std::string("create dataset ") + name);
        hsize_t count = 1;
        for (hsize_t d : dims) {
            count *= d;
        }
        if (count > 0) {
            status(H5Dwrite(set.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data),
                   std::string("write dataset ") + name);
        }
    }

    void attribute(hid_t obj, const char* name, hid_t file_type, hid_t mem_type, hsize_t count,
                   const void* data, bool scalar) const {
        const H5Handle space =
            check(scalar ? H5Screate(H5S_SCALAR)
                         : (count == 0 ? H5Screate(H5S_NULL) : H5Screate_simple(1, &count, nullptr)),
                  H5Sclose, std::string("dataspace of attribute ") + name);
        const H5Handle attr = check(H5Acreate2(obj, name, file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT),
                                    H5Aclose, std::string("create attribute ") + name);
        if (scalar || count > 0) {
            status(H5Awrite(attr.get(), mem_type, data), std::string("write attribute ") + name);
        }
    }

    void put(hid_t obj, const char* name, double value) const {
        attribute(obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, &value, true);
    }
    void put(hid_t obj, const char* name, std::int64_t value) const {
        attribute(obj, name, H5T_STD_I64LE, H5T_NATIVE_INT64, 1, &value, true);
    }
    void put(hid_t obj, const char* name, std::uint64_t value) const {
        attribute(obj, name, H5T_STD_U64LE, H5T_NATIVE_UINT64, 1, &value, true);
    }
    void put(hid_t obj, const char* name, const std::vector<double>& values) const {
        attribute(obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, values.size(), values.data(), false);
    }
    void put(hid_t obj, const char* name, const std::vector<std::int64_t>& values) const {
        attribute(obj, name, H5T_STD_I64LE, H5T_NATIVE_INT64, values.size(), values.data(), false);
    }
    void put(hid_t obj, const char* name, const std::string& value) const {
        const H5Handle type = check(H5Tcopy(H5T_C_S1), H5Tclose, "string type");
        status(H5Tset_size(type.get(), std::max<std::size_t>(value.size(), 1)), "string size");
        status(H5Tset_strpad(type.get(), H5T_STR_NULLPAD), "string padding");
        std::string padded = value.empty() ? std::string(1, '\0') : value;
        attribute(obj, name, type.get(), type.get(), 1, padded.data(), true);
    }

private:
    std::string path_;
};

void writeFile(const std::string& file_path, const std::string& shown_path, const Packing& k) {
    const Writer w(shown_path);
    H5Handle file = w.check(H5Fcreate(file_path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose,
                            "cannot create '" + file_path + "'");
    const hid_t root = file.get();
    w.put(root, "format", std::string(kFormat));
    w.put(root, "format_version", kFormatVersion);
    w.put(root, "spacing", k.sample.spacing);
    w.put(root, "shape_volume", k.sample.shape_volume);

    const std::size_t n = k.sample.centres.size();
    std::vector<double> centres(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
        store3(centres.data(), i, k.sample.centres[i]);
    }
    w.dataset(root, "centres", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {n, 3}, centres.data());
    w.dataset(root, "radii", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {k.sample.radii.size()},
              k.sample.radii.data());
    std::vector<std::int32_t> pairs;
    pairs.reserve(2 * k.bond_pairs.size());
    for (const auto& [a, b] : k.bond_pairs) {
        pairs.push_back(a);
        pairs.push_back(b);
    }
    w.dataset(root, "bond_pairs", H5T_STD_I32LE, H5T_NATIVE_INT32, {k.bond_pairs.size(), 2}, pairs.data());

    {
        const PackingParams& p = k.params;
        const H5Handle g = w.check(H5Gcreate2(root, "params", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                                   H5Gclose, "create group params");
        w.put(g.get(), "shape", std::string(nameOf(p.shape)));
        w.put(g.get(), "size", std::vector<double>{p.size.x(), p.size.y(), p.size.z()});
        w.put(g.get(), "radius", p.radius);
        w.put(g.get(), "height", p.height);
        w.put(g.get(), "particles", static_cast<std::int64_t>(p.particles));
        w.put(g.get(), "radius_dispersion", p.radius_dispersion);
        w.put(g.get(), "target_packing_fraction", p.target_packing_fraction);
        w.put(g.get(), "packing_fraction_tolerance", p.packing_fraction_tolerance);
        w.put(g.get(), "target_coordination", p.target_coordination);
        w.put(g.get(), "min_bonds", static_cast<std::int64_t>(p.min_bonds));
        w.put(g.get(), "overlap_tolerance", p.overlap_tolerance);
        w.put(g.get(), "seed", static_cast<std::uint64_t>(p.seed));
        w.put(g.get(), "max_iterations", static_cast<std::int64_t>(p.max_iterations));
    }
    {
        const PackingReport& r = k.report;
        const H5Handle g = w.check(H5Gcreate2(root, "report", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                                   H5Gclose, "create group report");
        const hid_t id = g.get();
        w.put(id, "particles", static_cast<std::int64_t>(r.particles));
        w.put(id, "bonds", static_cast<std::int64_t>(r.bonds));
        w.put(id, "mean_radius", r.mean_radius);
        w.put(id, "min_radius", r.min_radius);
        w.put(id, "max_radius", r.max_radius);
        w.put(id, "shape_volume", r.shape_volume);
        w.put(id, "packing_fraction", r.packing_fraction);
        w.put(id, "packing_fraction_interior", r.packing_fraction_interior);
        w.put(id, "interior_margin", r.interior_margin);
        w.put(id, "interior_volume", r.interior_volume);
        w.put(id, "target_region", r.target_region);
        w.put(id, "coordination_mean", r.coordination_mean);
        w.put(id, "coordination_mean_interior", r.coordination_mean_interior);
        w.put(id, "coordination_min", static_cast<std::int64_t>(r.coordination_min));
        w.put(id, "coordination_max", static_cast<std::int64_t>(r.coordination_max));
        w.put(id, "coordination_histogram",
              std::vector<std::int64_t>(r.coordination_histogram.begin(), r.coordination_histogram.end()));
        w.put(id, "fabric", std::vector<double>(r.fabric.begin(), r.fabric.end()));
        w.put(id, "fabric_anisotropy", r.fabric_anisotropy);
        w.put(id, "fabric_anisotropy_interior", r.fabric_anisotropy_interior);
        w.put(id, "gap_min", r.gap_min);
        w.put(id, "gap_mean", r.gap_mean);
        w.put(id, "gap_max", r.gap_max);
        w.put(id, "max_overlap", r.max_overlap);
        w.put(id, "max_wall_overlap", r.max_wall_overlap);
        w.put(id, "surface_fraction", r.surface_fraction);
        w.put(id, "gap_tolerance", r.gap_tolerance);
        w.put(id, "bonds_added_for_min", static_cast<std::int64_t>(r.bonds_added_for_min));
        w.put(id, "iterations", static_cast<std::int64_t>(r.iterations));
        w.put(id, "neighbour_builds", static_cast<std::int64_t>(r.neighbour_builds));
        w.put(id, "radius_rescales", static_cast<std::int64_t>(r.radius_rescales));
        w.put(id, "seconds", r.seconds);
    }
    w.status(file.close(), "close (flush) '" + file_path + "'");
}

// ---- reading ----------------------------------------------------------------------------------------------

class Reader {
public:
    /// `file_size` bounds the number of values a dataset may claim: each takes at least one byte of the file
    /// (savePacking stores them uncompressed), so a corrupt shape cannot ask for absurd memory.
    Reader(std::string path, std::uintmax_t file_size) : path_(std::move(path)), file_size_(file_size) {}

    [[noreturn]] void fail(const std::string& what) const {
        throw InputError("packing file '" + path_ + "': " + what + hdf5Detail());
    }

    H5Handle check(hid_t id, CloseFn close, const std::string& what) const {
        if (id < 0) {
            fail(what);
        }
        return H5Handle(id, close);
    }

    /// Dataset `name` of rank dims.size() whose dimensions match `dims` where they are not 0 (0 = any);
    /// returns the dimensions found. `float_data`: expects a float class, else an integer class.
    template <class T>
    std::vector<T> dataset(hid_t loc, const char* name, std::vector<hsize_t>& dims, bool float_data) const {
        if (H5Lexists(loc, name, H5P_DEFAULT) <= 0) {
            fail(std::string("dataset '") + name + "' is missing (not a vitrum packing file?)");
        }
        const H5Handle set = check(H5Dopen2(loc, name, H5P_DEFAULT), H5Dclose,
                                   std::string("cannot open dataset '") + name + "' (corrupt file?)");
        const H5Handle type = check(H5Dget_type(set.get()), H5Tclose, std::string("type of '") + name + "'");
        const H5T_class_t cls = H5Tget_class(type.get());
        if (cls != (float_data ? H5T_FLOAT : H5T_INTEGER)) {
            fail(std::string("dataset '") + name + "' has the wrong type; expected " +
                 (float_data ? "floating point" : "integer"));
        }
        const H5Handle space =
            check(H5Dget_space(set.get()), H5Sclose, std::string("shape of '") + name + "'");
        const int rank = H5Sget_simple_extent_ndims(space.get());
        if (rank != static_cast<int>(dims.size())) {
            fail(std::string("dataset '") + name + "' has rank " + std::to_string(rank) + "; expected " +
                 std::to_string(dims.size()));
        }
        std::vector<hsize_t> found(dims.size());
        H5Sget_simple_extent_dims(space.get(), found.data(), nullptr);
        hsize_t count = 1;
        for (std::size_t d = 0; d < dims.size(); ++d) {
            if (dims[d] != 0 && found[d] != dims[d]) {
                fail(std::string("dataset '") + name + "' has dimension " + std::to_string(d) + " = " +
                     std::to_string(found[d]) + "; expected " + std::to_string(dims[d]));
            }
            // Checked per factor, so the product cannot wrap around.
            if (found[d] != 0 && count > file_size_ / found[d]) {
                fail(std::string("dataset '") + name + "' claims more values than the file's " +
                     std::to_string(file_size_) + " bytes can hold (truncated or corrupt file?)");
            }
            count *= found[d];
        }
        dims = found;
        std::vector<T> out(static_cast<std::size_t>(count));
        if (count > 0) {
            hid_t mem = std::is_same_v<T, double> ? H5T_NATIVE_DOUBLE : H5T_NATIVE_INT32;
            if (H5Dread(set.get(), mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0) {
                fail(std::string("cannot read dataset '") + name + "' (truncated or corrupt file?)");
            }
        }
        return out;
    }

    /// Opens attribute `name` of `obj` and checks its type class; `where` names it in messages.
    H5Handle openAttribute(hid_t obj, const std::string& where, const char* name, H5T_class_t cls,
                           hssize_t& points) const {
        const std::string full = where + name;
        if (H5Aexists(obj, name) <= 0) {
            fail("attribute '" + full + "' is missing");
        }
        H5Handle attr =
            check(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose, "cannot open attribute '" + full + "'");
        const H5Handle type = check(H5Aget_type(attr.get()), H5Tclose, "type of attribute '" + full + "'");
        if (H5Tget_class(type.get()) != cls) {
            fail("attribute '" + full + "' has the wrong type");
        }
        const H5Handle space = check(H5Aget_space(attr.get()), H5Sclose, "shape of attribute '" + full + "'");
        points = H5Sget_simple_extent_npoints(space.get());
        if (points < 0) {
            fail("attribute '" + full + "' has an unreadable shape");
        }
        return attr;
    }

    template <class T> std::vector<T> numbers(hid_t obj, const std::string& where, const char* name) const {
        const bool is_float = std::is_floating_point_v<T>;
        hssize_t points = 0;
        const H5Handle attr = openAttribute(obj, where, name, is_float ? H5T_FLOAT : H5T_INTEGER, points);
        std::vector<T> out(static_cast<std::size_t>(points));
        hid_t mem = H5T_NATIVE_DOUBLE;
        if constexpr (std::is_same_v<T, std::int64_t>) {
            mem = H5T_NATIVE_INT64;
        } else if constexpr (std::is_same_v<T, std::uint64_t>) {
            mem = H5T_NATIVE_UINT64;
        }
        if (points > 0 && H5Aread(attr.get(), mem, out.data()) < 0) {
            fail("cannot read attribute '" + where + name + "'");
        }
        return out;
    }

    template <class T> T scalar(hid_t obj, const std::string& where, const char* name) const {
        const std::vector<T> v = numbers<T>(obj, where, name);
        if (v.size() != 1) {
            fail("attribute '" + where + name + "' has " + std::to_string(v.size()) + " values; expected 1");
        }
        return v[0];
    }

    std::string text(hid_t obj, const std::string& where, const char* name) const {
        hssize_t points = 0;
        const H5Handle attr = openAttribute(obj, where, name, H5T_STRING, points);
        if (points != 1) {
            fail("attribute '" + where + name + "' is not a single string");
        }
        const H5Handle type = check(H5Aget_type(attr.get()), H5Tclose, "type of '" + where + name + "'");
        if (H5Tis_variable_str(type.get()) > 0) {
            char* value = nullptr;
            if (H5Aread(attr.get(), type.get(), &value) < 0 || value == nullptr) {
                fail("cannot read attribute '" + where + name + "'");
            }
            std::string out(value);
            H5free_memory(value);
            return out;
        }
        const std::size_t size = H5Tget_size(type.get());
        std::string buffer(size + 1, '\0');
        if (size == 0 || H5Aread(attr.get(), type.get(), buffer.data()) < 0) {
            fail("cannot read attribute '" + where + name + "'");
        }
        return std::string(buffer.c_str());
    }

private:
    std::string path_;
    std::uintmax_t file_size_;
};

Packing readFile(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
        throw InputError("packing file '" + path + "': no such file");
    }
    if (!std::filesystem::is_regular_file(path, ec)) {
        throw InputError("packing file '" + path + "': not a regular file");
    }
    const std::uintmax_t file_size = std::filesystem::file_size(path, ec);
    if (ec) {
        throw InputError("packing file '" + path + "': cannot read its size: " + ec.message());
    }
    const Reader r(path, file_size);
    const htri_t is_hdf5 = H5Fis_hdf5(path.c_str());
    if (is_hdf5 == 0) {
        r.fail("not an HDF5 file");
    }
    if (is_hdf5 < 0) {
        r.fail("cannot be read as HDF5");
    }
    const H5Handle file = r.check(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose,
                                  "cannot open: truncated or corrupt HDF5 file");
    const hid_t root = file.get();
    if (H5Aexists(root, "format") <= 0) {
        r.fail("no 'format' attribute: not a vitrum packing file");
    }
    const std::string format = r.text(root, "", "format");
    if (format != kFormat) {
        r.fail("format is '" + format + "'; expected '" + kFormat + "'");
    }
    const auto version = r.scalar<std::int64_t>(root, "", "format_version");
    if (version < 1 || version > kFormatVersion) {
        r.fail("format_version " + std::to_string(version) + " is not supported; expected 1 to " +
               std::to_string(kFormatVersion));
    }

    Packing k;
    k.sample.spacing = r.scalar<double>(root, "", "spacing");
    k.sample.shape_volume = r.scalar<double>(root, "", "shape_volume");
    std::vector<hsize_t> cdims = {0, 3};
    const std::vector<double> centres = r.dataset<double>(root, "centres", cdims, true);
    const std::size_t n = static_cast<std::size_t>(cdims[0]);
    std::vector<hsize_t> rdims = {n};
    k.sample.radii = r.dataset<double>(root, "radii", rdims, true);
    std::vector<hsize_t> pdims = {0, 2};
    const std::vector<std::int32_t> pairs = r.dataset<std::int32_t>(root, "bond_pairs", pdims, false);
    if (n == 0) {
        r.fail("the packing has no particles");
    }
    k.sample.centres.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        k.sample.centres[i] = load3(centres.data(), i);
        if (!k.sample.centres[i].allFinite()) {
            r.fail("centre " + std::to_string(i) + " is not finite");
        }
        if (!(k.sample.radii[i] > 0.0) || !std::isfinite(k.sample.radii[i])) {
            r.fail("radius " + std::to_string(i) + " is not a positive finite number");
        }
    }
    k.bond_pairs.resize(static_cast<std::size_t>(pdims[0]));
    for (std::size_t b = 0; b < k.bond_pairs.size(); ++b) {
        const std::int32_t i = pairs[2 * b];
        const std::int32_t j = pairs[2 * b + 1];
        if (i < 0 || j <= i || static_cast<std::size_t>(j) >= n) {
            r.fail("bond " + std::to_string(b) + " = (" + std::to_string(i) + ", " + std::to_string(j) +
                   ") is not a pair i < j of the " + std::to_string(n) + " particles");
        }
        k.bond_pairs[b] = {i, j};
    }

    {
        const H5Handle g =
            r.check(H5Gopen2(root, "params", H5P_DEFAULT), H5Gclose, "group 'params' is missing");
        const hid_t id = g.get();
        const std::string w = "params/";
        PackingParams& p = k.params;
        const std::string shape = r.text(id, w, "shape");
        const std::optional<SampleShape> known = enumFromName<SampleShape>(shape);
        if (!known) {
            r.fail("attribute 'params/shape' is \"" + shape +
                   "\"; expected box, cylinder, sphere or hemisphere");
        }
        p.shape = *known;
        const std::vector<double> size = r.numbers<double>(id, w, "size");
        if (size.size() != 3) {
            r.fail("attribute 'params/size' has " + std::to_string(size.size()) + " values; expected 3");
        }
        p.size = Vec3(size[0], size[1], size[2]);
        p.radius = r.scalar<double>(id, w, "radius");
        p.height = r.scalar<double>(id, w, "height");
        p.particles = static_cast<long>(r.scalar<std::int64_t>(id, w, "particles"));
        p.radius_dispersion = r.scalar<double>(id, w, "radius_dispersion");
        p.target_packing_fraction = r.scalar<double>(id, w, "target_packing_fraction");
        p.packing_fraction_tolerance = r.scalar<double>(id, w, "packing_fraction_tolerance");
        p.target_coordination = r.scalar<double>(id, w, "target_coordination");
        p.min_bonds = static_cast<int>(r.scalar<std::int64_t>(id, w, "min_bonds"));
        p.overlap_tolerance = r.scalar<double>(id, w, "overlap_tolerance");
        p.seed = r.scalar<std::uint64_t>(id, w, "seed");
        p.max_iterations = static_cast<long>(r.scalar<std::int64_t>(id, w, "max_iterations"));
    }
    {
        const H5Handle g =
            r.check(H5Gopen2(root, "report", H5P_DEFAULT), H5Gclose, "group 'report' is missing");
        const hid_t id = g.get();
        const std::string w = "report/";
        PackingReport& rep = k.report;
        auto i64 = [&](const char* name) { return static_cast<long>(r.scalar<std::int64_t>(id, w, name)); };
        auto f64 = [&](const char* name) { return r.scalar<double>(id, w, name); };
        rep.particles = i64("particles");
        rep.bonds = i64("bonds");
        rep.mean_radius = f64("mean_radius");
        rep.min_radius = f64("min_radius");
        rep.max_radius = f64("max_radius");
        rep.shape_volume = f64("shape_volume");
        rep.packing_fraction = f64("packing_fraction");
        rep.packing_fraction_interior = f64("packing_fraction_interior");
        rep.interior_margin = f64("interior_margin");
        rep.interior_volume = f64("interior_volume");
        rep.target_region = r.text(id, w, "target_region");
        rep.coordination_mean = f64("coordination_mean");
        rep.coordination_mean_interior = f64("coordination_mean_interior");
        rep.coordination_min = static_cast<int>(i64("coordination_min"));
        rep.coordination_max = static_cast<int>(i64("coordination_max"));
        const std::vector<std::int64_t> hist = r.numbers<std::int64_t>(id, w, "coordination_histogram");
        rep.coordination_histogram.assign(hist.begin(), hist.end());
        const std::vector<double> fabric = r.numbers<double>(id, w, "fabric");
        if (fabric.size() != 6) {
            r.fail("attribute 'report/fabric' has " + std::to_string(fabric.size()) + " values; expected 6");
        }
        std::copy(fabric.begin(), fabric.end(), rep.fabric.begin());
        rep.fabric_anisotropy = f64("fabric_anisotropy");
        rep.fabric_anisotropy_interior = f64("fabric_anisotropy_interior");
        rep.gap_min = f64("gap_min");
        rep.gap_mean = f64("gap_mean");
        rep.gap_max = f64("gap_max");
        rep.max_overlap = f64("max_overlap");
        rep.max_wall_overlap = f64("max_wall_overlap");
        rep.surface_fraction = f64("surface_fraction");
        rep.gap_tolerance = f64("gap_tolerance");
        rep.bonds_added_for_min = i64("bonds_added_for_min");
        rep.iterations = i64("iterations");
        rep.neighbour_builds = i64("neighbour_builds");
        rep.radius_rescales = i64("radius_rescales");
        rep.seconds = f64("seconds");
    }
    if (k.report.particles != static_cast<long>(n) ||
        k.report.bonds != static_cast<long>(k.bond_pairs.size())) {
        r.fail("report counts (" + std::to_string(k.report.particles) + " particles, " +
               std::to_string(k.report.bonds) + " bonds) disagree with the datasets (" + std::to_string(n) +
               ", " + std::to_string(k.bond_pairs.size()) + ")");
    }
    return k;
}

} // namespace

void savePacking(const std::string& path, const Packing& packing) {
    const QuietHdf5 quiet;
    if (packing.sample.radii.size() != packing.sample.centres.size()) {
        throw RuntimeFailure("cannot write packing '" + path +
                             "': " + std::to_string(packing.sample.centres.size()) + " centres but " +
                             std::to_string(packing.sample.radii.size()) + " radii");
    }
    const std::string tmp = path + ".tmp";
    try {
        writeFile(tmp, path, packing);
        // Make the bytes durable before the rename publishes them.
        const int fd = ::open(tmp.c_str(), O_RDONLY);
        if (fd < 0 || ::fsync(fd) != 0) {
            if (fd >= 0) {
                ::close(fd);
            }
            throw RuntimeFailure("cannot write packing '" + path + "': fsync of '" + tmp + "' failed");
        }
        ::close(fd);
        std::error_code ec;
        std::filesystem::rename(tmp, path, ec);
        if (ec) {
            throw RuntimeFailure("cannot write packing '" + path + "': rename from '" + tmp +
                                 "' failed: " + ec.message());
        }
    } catch (...) {
        std::error_code ignored;
        std::filesystem::remove(tmp, ignored);
        throw;
    }
}

Packing loadPacking(const std::string& path) {
    const QuietHdf5 quiet;
    return readFile(path);
}

nlohmann::ordered_json packingParamsJson(const PackingParams& p) {
    nlohmann::ordered_json j;
    j["shape"] = std::string(nameOf(p.shape));
    j["size_um"] = {p.size.x(), p.size.y(), p.size.z()};
    j["radius_um"] = p.radius;
    j["height_um"] = p.height;
    j["particles"] = p.particles;
    j["radius_dispersion"] = p.radius_dispersion;
    j["target_packing_fraction"] = p.target_packing_fraction;
    j["packing_fraction_tolerance"] = p.packing_fraction_tolerance;
    j["target_coordination"] = p.target_coordination;
    j["min_bonds"] = p.min_bonds;
    j["overlap_tolerance"] = p.overlap_tolerance;
    j["seed"] = p.seed;
    j["max_iterations"] = p.max_iterations;
    return j;
}

nlohmann::ordered_json packingReportJson(const PackingReport& r) {
    nlohmann::ordered_json j;
    j["particles"] = r.particles;
    j["bonds"] = r.bonds;
    j["radius_um"] = {{"mean", r.mean_radius}, {"min", r.min_radius}, {"max", r.max_radius}};
    j["shape_volume_um3"] = r.shape_volume;
    j["packing_fraction"] = {{"whole", r.packing_fraction},
                             {"interior", r.packing_fraction_interior},
                             {"interior_margin_um", r.interior_margin},
                             {"interior_volume_um3", r.interior_volume},
                             {"target_region", r.target_region}};
    j["coordination"] = {{"mean", r.coordination_mean},
                         {"mean_interior", r.coordination_mean_interior},
                         {"min", r.coordination_min},
                         {"max", r.coordination_max},
                         {"histogram", r.coordination_histogram}};
    j["fabric"] = {{"tensor_xx_yy_zz_xy_xz_yz", r.fabric},
                   {"anisotropy", r.fabric_anisotropy},
                   {"anisotropy_interior", r.fabric_anisotropy_interior},
                   {"anisotropy_definition", "sqrt(3/2) |<n n> - I/3| (0 isotropic, 1 all bonds parallel)"}};
    j["bonded_gap"] = {{"definition", "d/(Ri+Rj) - 1"},
                       {"min", r.gap_min},
                       {"mean", r.gap_mean},
                       {"max", r.gap_max},
                       {"selection_tolerance", r.gap_tolerance},
                       {"bonds_added_for_min_bonds", r.bonds_added_for_min}};
    j["max_overlap"] = {{"pairs", r.max_overlap}, {"walls", r.max_wall_overlap}};
    j["surface_fraction"] = r.surface_fraction;
    j["minimiser"] = {{"sweeps", r.iterations},
                      {"neighbour_builds", r.neighbour_builds},
                      {"radius_rescales", r.radius_rescales},
                      {"seconds", r.seconds}};
    return j;
}

} // namespace vitrum
