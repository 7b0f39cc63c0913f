#include "hdf5_forger.hpp"

#include <hdf5.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <utility>

namespace vitrum::fuzz {

namespace {

// ---- values -----------------------------------------------------------------------------------------------

bool isNumber(Kind k) { return k != Kind::FixedString && k != Kind::VarString && k != Kind::Opaque; }

std::size_t numberSize(Kind k) {
    switch (k) {
    case Kind::I8: case Kind::U8: case Kind::Enum8: return 1;
    case Kind::I16: case Kind::U16: return 2;
    case Kind::I32: case Kind::U32: case Kind::F32: return 4;
    default: return 8;
    }
}

/// Element `i` of a numeric value as a long double (exact for every 64-bit integer on x86-64).
long double decode(const Value& v, std::size_t i) {
    const unsigned char* p = v.bytes.data() + i * v.elementSize();
    auto get = [p](auto sample) {
        decltype(sample) x;
        std::memcpy(&x, p, sizeof x);
        return static_cast<long double>(x);
    };
    switch (v.kind) {
    case Kind::I8: case Kind::Enum8: return get(std::int8_t{});
    case Kind::U8: return get(std::uint8_t{});
    case Kind::I16: return get(std::int16_t{});
    case Kind::U16: return get(std::uint16_t{});
    case Kind::I32: return get(std::int32_t{});
    case Kind::U32: return get(std::uint32_t{});
    case Kind::I64: return get(std::int64_t{});
    case Kind::U64: return get(std::uint64_t{});
    case Kind::F32: return get(float{});
    case Kind::F64: return get(double{});
    default: return 0.0L;
    }
}

template <class T> void putSaturated(unsigned char* p, long double x) {
    T out;
    if constexpr (std::is_floating_point_v<T>) {
        const long double top = std::numeric_limits<T>::max();
        out = std::isnan(x) ? std::numeric_limits<T>::quiet_NaN()
              : x > top     ? std::numeric_limits<T>::infinity()
              : x < -top    ? -std::numeric_limits<T>::infinity()
                            : static_cast<T>(x);
    } else {
        const long double lo = static_cast<long double>(std::numeric_limits<T>::min());
        const long double hi = static_cast<long double>(std::numeric_limits<T>::max());
        out = std::isnan(x) ? T{0} : x <= lo ? std::numeric_limits<T>::min() : x >= hi ? std::numeric_limits<T>::max()
                                                                                     : static_cast<T>(x);
    }
    std::memcpy(p, &out, sizeof out);
}

void encode(Value& v, std::size_t i, long double x) {
    unsigned char* p = v.bytes.data() + i * v.elementSize();
    switch (v.kind) {
    case Kind::I8: case Kind::Enum8: putSaturated<std::int8_t>(p, x); break;
    case Kind::U8: putSaturated<std::uint8_t>(p, x); break;
    case Kind::I16: putSaturated<std::int16_t>(p, x); break;
    case Kind::U16: putSaturated<std::uint16_t>(p, x); break;
    case Kind::I32: putSaturated<std::int32_t>(p, x); break;
    case Kind::U32: putSaturated<std::uint32_t>(p, x); break;
    case Kind::I64: putSaturated<std::int64_t>(p, x); break;
    case Kind::U64: putSaturated<std::uint64_t>(p, x); break;
    case Kind::F32: putSaturated<float>(p, x); break;
    case Kind::F64: putSaturated<double>(p, x); break;
    default: break;
    }
}

/// Resizes the element storage to count() (zeros or empty strings appended), or drops it when too large.
void fitStorage(Value& v) {
    const std::uint64_t n = v.count();
    v.written = n <= kMaxWrittenElements;
    const std::size_t held = v.written ? static_cast<std::size_t>(n) : 0;
    if (v.isString()) {
        v.strings.resize(held);
        v.bytes.clear();
    } else {
        v.bytes.resize(held * v.elementSize(), 0);
        v.strings.clear();
    }
}

// ---- pools --------------------------------------------------------------------------------------------------

long double interesting(std::uint8_t k) {
    constexpr long double kTable[] = {
        0.0L, -0.0L, 1.0L, -1.0L, 2.0L, 3.0L, 0.5L, 1e-300L,
        static_cast<long double>(std::numeric_limits<double>::denorm_min()),
        static_cast<long double>(std::numeric_limits<double>::max()),
        -static_cast<long double>(std::numeric_limits<double>::max()),
        std::numeric_limits<long double>::infinity(), -std::numeric_limits<long double>::infinity(),
        std::numeric_limits<long double>::quiet_NaN(), -std::numeric_limits<long double>::quiet_NaN(),
        1e30L, -1e30L, 127.0L, -128.0L, 255.0L, 65535.0L, 2147483647.0L, -2147483648.0L, 2147483648.0L,
        4294967295.0L, 4294967296.0L, 9007199254740993.0L, 9223372036854775807.0L, -9223372036854775808.0L,
        18446744073709551615.0L, 1e-5L, 0.9999999999999999L, 72.5L, 0.17L, 2200.0L, 1e6L, -1e-12L, 6.0L,
    };
    return kTable[k % (sizeof kTable / sizeof kTable[0])];
}

std::uint64_t sizeFromPool(std::uint8_t k, std::uint64_t current) {
    const std::uint64_t table[] = {0, 1, 2, 3, 4, 5, 6, 7, 8, current, current ? current - 1 : 0, current + 1,
                                   2 * current + 1, 255, 256, 65536, 2147483647ULL, 2147483648ULL,
                                   4294967297ULL, 1ULL << 40, 1ULL << 53, 1ULL << 61};
    return table[k % (sizeof table / sizeof table[0])];
}

const char* const kHostileNames[] = {"", ".", "..", "/", "a", "x/y", "count", "unit", "format", "data",
                                     "\xff\xfe", "name with spaces",
                                     "a-name-that-is-rather-long-for-any-reader-to-expect-in-this-file-"
                                     "a-name-that-is-rather-long-for-any-reader-to-expect-in-this-file"};

const char* const kHostileTexts[] = {"", " ", "0", "-1", "1e999", "nan", "\xff\xfe\xfd", "\xc3\x28", "box\n",
                                     "BOX", "interior ", "whole", "sphere", "hemisphere", "cylinder", "torus"};

void collectNames(const Node& n, std::vector<std::string>& out) {
    out.push_back(n.name);
    for (const Attribute& a : n.attributes) out.push_back(a.name);
    for (const Node& c : n.children) collectNames(c, out);
}

void collectTexts(const Node& n, std::vector<std::string>& out) {
    auto take = [&out](const Value& v) {
        for (const std::string& s : v.strings) out.push_back(s);
    };
    take(n.value);
    for (const Attribute& a : n.attributes) take(a.value);
    for (const Node& c : n.children) collectTexts(c, out);
}

// ---- picking --------------------------------------------------------------------------------------------------

struct Slot {
    Node* parent = nullptr; ///< the group holding `node` (objects) or nullptr (attributes)
    Node* node = nullptr;   ///< the object, or the owner of the attribute
    std::size_t attribute = SIZE_MAX;
    std::string path;

    bool isAttribute() const { return attribute != SIZE_MAX; }
    /// The value of a dataset or attribute, else nullptr.
    Value* value() const {
        if (isAttribute()) return &node->attributes[attribute].value;
        return node->type == Node::Type::Dataset ? &node->value : nullptr;
    }
};

void collectSlots(Node& n, const std::string& path, std::vector<Slot>& slots, std::vector<Node*>& groups) {
    if (n.type == Node::Type::Group) groups.push_back(&n);
    for (std::size_t a = 0; a < n.attributes.size(); ++a) {
        slots.push_back({nullptr, &n, a, path});
    }
    for (Node& c : n.children) {
        const std::string child = (path == "/" ? "/" : path + "/") + c.name;
        slots.push_back({&n, &c, SIZE_MAX, child});
        collectSlots(c, child, slots, groups);
    }
}

/// Whether `inner` is `outer` or lies inside it (a group may not move into itself).
bool contains(const Node& outer, const Node* inner) {
    if (&outer == inner) return true;
    for (const Node& c : outer.children) {
        if (contains(c, inner)) return true;
    }
    return false;
}

Value scalarDouble(long double x) {
    Value v;
    v.kind = Kind::F64;
    v.space = Space::Scalar;
    fitStorage(v);
    encode(v, 0, x);
    return v;
}

void retype(Value& v, Kind to) {
    if (to == v.kind) return;
    const std::size_t n = v.written ? static_cast<std::size_t>(v.count()) : 0;
    std::vector<long double> numbers(n, 0.0L);
    std::vector<std::string> texts(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (isNumber(v.kind)) {
            numbers[i] = decode(v, i);
            char buffer[64];
            std::snprintf(buffer, sizeof buffer, "%.17Lg", numbers[i]);
            texts[i] = buffer;
        } else if (v.isString()) {
            texts[i] = v.strings[i];
            numbers[i] = std::strtold(texts[i].c_str(), nullptr);
        }
    }
    const std::vector<unsigned char> raw = v.bytes;
    v.kind = to;
    fitStorage(v);
    for (std::size_t i = 0; i < n && v.written; ++i) {
        if (isNumber(to)) {
            encode(v, i, numbers[i]);
        } else if (v.isString()) {
            v.strings[i] = texts[i];
            v.string_size = std::max(v.string_size, texts[i].size());
        }
    }
    if (to == Kind::Opaque) {
        std::copy_n(raw.begin(), std::min(raw.size(), v.bytes.size()), v.bytes.begin());
    }
}

Value newValue(FuzzBytes& bytes, bool attribute) {
    Value v;
    v.kind = static_cast<Kind>(bytes.u8() % static_cast<int>(Kind::Count));
    const int rank = bytes.u8() % 6;
    v.space = rank == 0 ? Space::Scalar : rank == 5 ? Space::Null : Space::Simple;
    for (int d = 0; v.space == Space::Simple && d < rank; ++d) {
        v.dims.push_back(sizeFromPool(bytes.u8(), 3));
    }
    fitStorage(v);
    const long double x = interesting(bytes.u8());
    for (std::size_t i = 0; v.written && i < v.count() && isNumber(v.kind); ++i) encode(v, i, x);
    if (attribute && v.count() > kMaxAttributeElements) {
        v.space = Space::Scalar;
        v.dims.clear();
        fitStorage(v);
    }
    return v;
}

class Mutator {
public:
    Mutator(const Node& base, Forgery& f) : f_(f) {
        collectNames(base, names_);
        for (const char* n : kHostileNames) names_.emplace_back(n);
        collectTexts(base, texts_);
        for (const char* t : kHostileTexts) texts_.emplace_back(t);
        for (const std::string& n : names_) texts_.push_back(n);
        texts_.push_back(std::string(3000, 'x'));
        texts_.push_back(std::string("vitrum\0packing", 14));
    }

    void apply(FuzzBytes& b) {
        std::vector<Slot> slots;
        std::vector<Node*> groups;
        collectSlots(f_.root, "/", slots, groups);
        const Op op = static_cast<Op>(b.u8() % static_cast<int>(Op::Count));
        auto pick = [&]() -> Slot* { return slots.empty() ? nullptr : &slots[b.u16() % slots.size()]; };
        auto group = [&]() -> Node* { return groups[b.u16() % groups.size()]; };
        auto name = [&]() -> const std::string& { return names_[b.u8() % names_.size()]; };
        switch (op) {
        case Op::Remove: {
            Slot* s = pick();
            if (!s) return;
            if (s->isAttribute()) {
                s->node->attributes.erase(s->node->attributes.begin() + static_cast<std::ptrdiff_t>(s->attribute));
            } else {
                auto& siblings = s->parent->children;
                siblings.erase(siblings.begin() + (s->node - siblings.data()));
            }
            return;
        }
        case Op::Retype: {
            Slot* s = pick();
            const Kind to = static_cast<Kind>(b.u8() % static_cast<int>(Kind::Count));
            if (Value* v = s ? s->value() : nullptr) retype(*v, to);
            return;
        }
        case Op::Reshape: {
            Slot* s = pick();
            Value* v = s ? s->value() : nullptr;
            const int rank = b.u8() % 6;
            std::vector<std::uint64_t> dims;
            for (int d = 0; rank > 0 && rank < 5 && d < rank; ++d) {
                const std::uint64_t current = v && d < static_cast<int>(v->dims.size()) ? v->dims[d] : 1;
                dims.push_back(sizeFromPool(b.u8(), current));
            }
            if (!v) return;
            v->space = rank == 0 ? Space::Scalar : rank == 5 ? Space::Null : Space::Simple;
            v->dims = dims;
            if (s->isAttribute() && v->count() > kMaxAttributeElements) return undo(*v);
            fitStorage(*v);
            return;
        }
        case Op::Rows: {
            Slot* s = pick();
            Value* v = s ? s->value() : nullptr;
            const std::uint8_t k = b.u8();
            if (!v) return;
            if (v->space != Space::Simple) {
                v->space = Space::Simple;
                v->dims = {1};
            }
            const Value before = *v;
            v->dims[0] = sizeFromPool(k, v->dims[0]);
            if (s->isAttribute() && v->count() > kMaxAttributeElements) {
                *v = before;
                return;
            }
            fitStorage(*v);
            return;
        }
        case Op::Set:
        case Op::SetRaw: {
            Slot* s = pick();
            const std::uint32_t index = b.u32();
            const std::uint8_t k = op == Op::Set ? b.u8() : 0;
            const std::uint64_t raw = op == Op::SetRaw ? b.u64() : 0;
            Value* v = s ? s->value() : nullptr;
            if (!v || !v->written || v->count() == 0 || v->isString()) return;
            const std::size_t i = index % v->count();
            if (op == Op::Set) {
                if (isNumber(v->kind)) encode(*v, i, interesting(k));
            } else {
                std::memcpy(v->bytes.data() + i * v->elementSize(), &raw, std::min<std::size_t>(8, v->elementSize()));
            }
            return;
        }
        case Op::Fill: {
            Slot* s = pick();
            const long double x = interesting(b.u8());
            Value* v = s ? s->value() : nullptr;
            if (!v || !v->written || !isNumber(v->kind)) return;
            for (std::size_t i = 0; i < v->count(); ++i) encode(*v, i, x);
            return;
        }
        case Op::Nudge: {
            Slot* s = pick();
            const std::uint32_t index = b.u32();
            const int how = b.u8() % 6;
            Value* v = s ? s->value() : nullptr;
            if (!v || !v->written || v->count() == 0 || !isNumber(v->kind)) return;
            const std::size_t n = static_cast<std::size_t>(v->count());
            const std::size_t i = index % n;
            const long double x = decode(*v, i);
            switch (how) {
            case 0: encode(*v, i, x + 1); break;
            case 1: encode(*v, i, x - 1); break;
            case 2: encode(*v, i, -x); break;
            case 3: encode(*v, i, 2 * x); break;
            case 4: {
                const long double y = decode(*v, (i + 1) % n);
                encode(*v, i, y);
                encode(*v, (i + 1) % n, x);
                break;
            }
            default: encode(*v, i, decode(*v, (i + n - 1) % n)); break;
            }
            return;
        }
        case Op::Rename: {
            Slot* s = pick();
            const std::string& to = name();
            if (!s) return;
            (s->isAttribute() ? s->node->attributes[s->attribute].name : s->node->name) = to;
            return;
        }
        case Op::Move:
        case Op::Copy: {
            Slot* s = pick();
            Node* to = group();
            const std::string& new_name = op == Op::Copy ? name() : std::string();
            if (!s) return;
            if (s->isAttribute()) {
                Attribute a = s->node->attributes[s->attribute];
                if (op == Op::Copy) a.name = new_name;
                else s->node->attributes.erase(s->node->attributes.begin() + static_cast<std::ptrdiff_t>(s->attribute));
                to->attributes.push_back(std::move(a));
                return;
            }
            if (op == Op::Move && contains(*s->node, to)) return;
            Node moved = *s->node;
            if (op == Op::Copy) {
                moved.name = new_name;
                to->children.push_back(std::move(moved));
                return;
            }
            // Erasing shifts the siblings in memory: find the destination again by its path.
            const std::string destination = pathOf(slots, to);
            auto& siblings = s->parent->children;
            siblings.erase(siblings.begin() + (s->node - siblings.data()));
            if (Node* again = findGroup(f_.root, destination)) again->children.push_back(std::move(moved));
            return;
        }
        case Op::Add: {
            Node* to = group();
            const std::string& n = name();
            const bool attribute = b.u8() & 1;
            Value v = newValue(b, attribute);
            if (attribute) {
                to->attributes.push_back({n, std::move(v)});
            } else {
                Node d;
                d.type = Node::Type::Dataset;
                d.name = n;
                d.value = std::move(v);
                to->children.push_back(std::move(d));
            }
            return;
        }
        case Op::Link: {
            Node* to = group();
            const std::string& n = name();
            const int type = b.u8() % 3;
            Slot* s = pick();
            Node link;
            link.name = n;
            link.type = type == 0 ? Node::Type::SoftLink : type == 1 ? Node::Type::ExternalLink : Node::Type::HardLink;
            link.target = s ? s->path : "/nowhere";
            to->children.push_back(std::move(link));
            return;
        }
        case Op::Swap: {
            Slot* s = pick();
            if (!s || s->isAttribute()) return;
            Node& n = *s->node;
            if (n.type == Node::Type::Group) {
                n.type = Node::Type::Dataset;
                n.children.clear();
                n.value = scalarDouble(1.0L);
            } else {
                n.type = Node::Type::Group;
                n.value = Value{};
            }
            return;
        }
        case Op::Text: {
            Slot* s = pick();
            const std::string& text = texts_[b.u8() % texts_.size()];
            const std::uint32_t index = b.u32();
            Value* v = s ? s->value() : nullptr;
            if (!v || !v->isString() || !v->written || v->count() == 0) return;
            v->strings[index % v->count()] = text;
            return;
        }
        case Op::StringType: {
            Slot* s = pick();
            const int how = b.u8() % 5;
            const std::uint8_t k = b.u8();
            Value* v = s ? s->value() : nullptr;
            if (!v || !v->isString()) return;
            switch (how) {
            case 0: v->kind = v->kind == Kind::FixedString ? Kind::VarString : Kind::FixedString; break;
            case 1: v->string_size = std::clamp<std::uint64_t>(sizeFromPool(k, v->string_size), 1, 65536); break;
            case 2: v->null_terminated = !v->null_terminated; break;
            case 3: v->utf8 = !v->utf8; break;
            default: std::fill(v->strings.begin(), v->strings.end(), texts_[k % texts_.size()]); break;
            }
            return;
        }
        case Op::Order: {
            Slot* s = pick();
            if (Value* v = s ? s->value() : nullptr) v->big_endian = !v->big_endian;
            return;
        }
        case Op::Chunk: {
            Slot* s = pick();
            if (s && !s->isAttribute() && s->node->type == Node::Type::Dataset) {
                s->node->value.chunked = !s->node->value.chunked;
            }
            return;
        }
        case Op::Truncate:
            f_.keep_fraction = b.u16() / 65536.0;
            return;
        case Op::Count:
            return;
        }
    }

    /// Prints the picks, groups, names and texts of the base tree with their indices (stdout).
    void list() {
        std::vector<Slot> slots;
        std::vector<Node*> groups;
        collectSlots(f_.root, "/", slots, groups);
        for (std::size_t k = 0; k < slots.size(); ++k) {
            const Slot& s = slots[k];
            std::printf("pick %zu %s%s%s\n", k, s.path.c_str(), s.isAttribute() ? "@" : "",
                        s.isAttribute() ? s.node->attributes[s.attribute].name.c_str() : "");
        }
        for (std::size_t k = 0; k < groups.size(); ++k) std::printf("group %zu %s\n", k, pathOf(slots, groups[k]).c_str());
        for (std::size_t k = 0; k < names_.size(); ++k) std::printf("name %zu %s\n", k, names_[k].c_str());
        for (std::size_t k = 0; k < texts_.size(); ++k) std::printf("text %zu %.40s\n", k, texts_[k].c_str());
        std::fflush(stdout);
    }

private:
    static std::string pathOf(const std::vector<Slot>& slots, const Node* group) {
        for (const Slot& s : slots) {
            if (!s.isAttribute() && s.node == group) return s.path;
        }
        return "/";
    }
    static Node* findGroup(Node& root, const std::string& path) {
        Node* at = &root;
        std::size_t from = 1;
        while (from < path.size()) {
            const std::size_t end = std::min(path.find('/', from), path.size());
            const std::string part = path.substr(from, end - from);
            Node* next = nullptr;
            for (Node& c : at->children) {
                if (c.name == part && c.type == Node::Type::Group) {
                    next = &c;
                    break;
                }
            }
            if (!next) return nullptr;
            at = next;
            from = end + 1;
        }
        return at;
    }
    static void undo(Value& v) {
        v.space = Space::Scalar;
        v.dims.clear();
        fitStorage(v);
    }

    Forgery& f_;
    std::vector<std::string> names_;
    std::vector<std::string> texts_;
};

// ---- writing ------------------------------------------------------------------------------------------------

/// Owns one identifier.
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

hid_t fileType(const Value& v) {
    const bool be = v.big_endian;
    switch (v.kind) {
    case Kind::I8: return H5Tcopy(be ? H5T_STD_I8BE : H5T_STD_I8LE);
    case Kind::U8: return H5Tcopy(be ? H5T_STD_U8BE : H5T_STD_U8LE);
    case Kind::I16: return H5Tcopy(be ? H5T_STD_I16BE : H5T_STD_I16LE);
    case Kind::U16: return H5Tcopy(be ? H5T_STD_U16BE : H5T_STD_U16LE);
    case Kind::I32: return H5Tcopy(be ? H5T_STD_I32BE : H5T_STD_I32LE);
    case Kind::U32: return H5Tcopy(be ? H5T_STD_U32BE : H5T_STD_U32LE);
    case Kind::I64: return H5Tcopy(be ? H5T_STD_I64BE : H5T_STD_I64LE);
    case Kind::U64: return H5Tcopy(be ? H5T_STD_U64BE : H5T_STD_U64LE);
    case Kind::F32: return H5Tcopy(be ? H5T_IEEE_F32BE : H5T_IEEE_F32LE);
    case Kind::F64: return H5Tcopy(be ? H5T_IEEE_F64BE : H5T_IEEE_F64LE);
    case Kind::FixedString:
    case Kind::VarString: {
        const hid_t t = H5Tcopy(H5T_C_S1);
        H5Tset_size(t, v.kind == Kind::VarString ? H5T_VARIABLE : std::max<std::size_t>(v.string_size, 1));
        H5Tset_strpad(t, v.null_terminated ? H5T_STR_NULLTERM : H5T_STR_NULLPAD);
        H5Tset_cset(t, v.utf8 ? H5T_CSET_UTF8 : H5T_CSET_ASCII);
        return t;
    }
    case Kind::Opaque: return H5Tcreate(H5T_OPAQUE, std::max<std::size_t>(v.opaque_size, 1));
    case Kind::Enum8: {
        const hid_t t = H5Tenum_create(H5T_NATIVE_INT8);
        const std::int8_t no = 0, yes = 1;
        H5Tenum_insert(t, "FALSE", &no);
        H5Tenum_insert(t, "TRUE", &yes);
        return t;
    }
    case Kind::Count: break;
    }
    return H5I_INVALID_HID;
}

hid_t memoryType(const Value& v) {
    switch (v.kind) {
    case Kind::I8: return H5Tcopy(H5T_NATIVE_INT8);
    case Kind::U8: return H5Tcopy(H5T_NATIVE_UINT8);
    case Kind::I16: return H5Tcopy(H5T_NATIVE_INT16);
    case Kind::U16: return H5Tcopy(H5T_NATIVE_UINT16);
    case Kind::I32: return H5Tcopy(H5T_NATIVE_INT32);
    case Kind::U32: return H5Tcopy(H5T_NATIVE_UINT32);
    case Kind::I64: return H5Tcopy(H5T_NATIVE_INT64);
    case Kind::U64: return H5Tcopy(H5T_NATIVE_UINT64);
    case Kind::F32: return H5Tcopy(H5T_NATIVE_FLOAT);
    case Kind::F64: return H5Tcopy(H5T_NATIVE_DOUBLE);
    default: {
        Value native = v;
        native.big_endian = false;
        return fileType(native);
    }
    }
}

hid_t dataspace(const Value& v) {
    if (v.space == Space::Null) return H5Screate(H5S_NULL);
    if (v.space == Space::Scalar || v.dims.empty()) return H5Screate(H5S_SCALAR);
    const std::vector<hsize_t> dims(v.dims.begin(), v.dims.end());
    return H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
}

/// The buffer H5Dwrite/H5Awrite take for `v` (strings laid out per their type); empty when nothing to write.
struct Buffer {
    std::vector<unsigned char> fixed;
    std::vector<const char*> pointers;
    const void* data = nullptr;
};

Buffer buffer(const Value& v) {
    Buffer b;
    if (!v.written || v.count() == 0 || v.space == Space::Null) return b;
    if (v.kind == Kind::VarString) {
        for (const std::string& s : v.strings) b.pointers.push_back(s.c_str());
        b.data = b.pointers.data();
    } else if (v.kind == Kind::FixedString) {
        const std::size_t size = std::max<std::size_t>(v.string_size, 1);
        b.fixed.assign(v.strings.size() * size, 0);
        for (std::size_t i = 0; i < v.strings.size(); ++i) {
            std::memcpy(b.fixed.data() + i * size, v.strings[i].data(), std::min(size, v.strings[i].size()));
        }
        b.data = b.fixed.data();
    } else {
        b.data = v.bytes.data();
    }
    return b;
}

void writeAttributes(hid_t object, const std::vector<Attribute>& attributes) {
    for (const Attribute& a : attributes) {
        if (a.value.count() > kMaxAttributeElements) continue;
        const Id type(fileType(a.value), H5Tclose);
        const Id memory(memoryType(a.value), H5Tclose);
        const Id space(dataspace(a.value), H5Sclose);
        if (!type.ok() || !memory.ok() || !space.ok()) continue;
        const Id attr(H5Acreate2(object, a.name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
        const Buffer data = buffer(a.value);
        if (attr.ok() && data.data) H5Awrite(attr.get(), memory.get(), data.data);
    }
}

void writeDataset(hid_t group, const Node& n) {
    const Value& v = n.value;
    const Id type(fileType(v), H5Tclose);
    const Id memory(memoryType(v), H5Tclose);
    if (!type.ok() || !memory.ok()) return;
    hid_t space_id = H5I_INVALID_HID;
    const Id dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
    if (v.chunked && v.space == Space::Simple && !v.dims.empty()) {
        std::vector<hsize_t> dims(v.dims.begin(), v.dims.end()), chunk(dims.size()), max(dims.size(), H5S_UNLIMITED);
        for (std::size_t d = 0; d < dims.size(); ++d) chunk[d] = std::clamp<hsize_t>(dims[d], 1, 64);
        space_id = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), max.data());
        H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data());
    } else {
        space_id = dataspace(v);
    }
    const Id space(space_id, H5Sclose);
    if (!space.ok()) return;
    const Id set(H5Dcreate2(group, n.name.c_str(), type.get(), space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
                 H5Dclose);
    if (!set.ok()) return;
    const Buffer data = buffer(v);
    if (data.data) H5Dwrite(set.get(), memory.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data);
    writeAttributes(set.get(), n.attributes);
}

void writeGroup(hid_t group, const Node& g, const std::string& path, std::vector<std::pair<std::string, const Node*>>& links) {
    writeAttributes(group, g.attributes);
    for (const Node& c : g.children) {
        switch (c.type) {
        case Node::Type::Group: {
            const Id sub(H5Gcreate2(group, c.name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
            if (sub.ok()) writeGroup(sub.get(), c, (path == "/" ? "/" : path + "/") + c.name, links);
            break;
        }
        case Node::Type::Dataset: writeDataset(group, c); break;
        default: links.emplace_back(path, &c); break; // after every object exists
        }
    }
}

// ---- reading (snapshot) ---------------------------------------------------------------------------------------

Value readValue(hid_t type, hid_t space, const std::function<herr_t(hid_t, void*)>& read) {
    Value v;
    const H5T_class_t cls = H5Tget_class(type);
    const std::size_t size = H5Tget_size(type);
    v.big_endian = H5Tget_order(type) == H5T_ORDER_BE;
    if (cls == H5T_INTEGER) {
        const bool sign = H5Tget_sign(type) == H5T_SGN_2;
        const Kind by_size[] = {sign ? Kind::I8 : Kind::U8, sign ? Kind::I16 : Kind::U16, sign ? Kind::I32 : Kind::U32,
                                sign ? Kind::I64 : Kind::U64};
        v.kind = size == 1 ? by_size[0] : size == 2 ? by_size[1] : size == 4 ? by_size[2] : by_size[3];
    } else if (cls == H5T_FLOAT) {
        v.kind = size == 4 ? Kind::F32 : Kind::F64;
    } else if (cls == H5T_STRING) {
        v.kind = H5Tis_variable_str(type) > 0 ? Kind::VarString : Kind::FixedString;
        v.string_size = size;
        v.null_terminated = H5Tget_strpad(type) == H5T_STR_NULLTERM;
        v.utf8 = H5Tget_cset(type) == H5T_CSET_UTF8;
    } else {
        throw std::runtime_error("hdf5_forger: snapshot of an unmodelled type class");
    }
    const H5S_class_t sc = H5Sget_simple_extent_type(space);
    v.space = sc == H5S_NULL ? Space::Null : sc == H5S_SCALAR ? Space::Scalar : Space::Simple;
    if (v.space == Space::Simple) {
        std::vector<hsize_t> dims(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)));
        H5Sget_simple_extent_dims(space, dims.data(), nullptr);
        v.dims.assign(dims.begin(), dims.end());
    }
    fitStorage(v);
    if (v.count() == 0 || v.space == Space::Null) return v;
    const Id memory(memoryType(v), H5Tclose);
    if (v.kind == Kind::VarString) {
        std::vector<char*> pointers(v.strings.size(), nullptr);
        if (read(memory.get(), pointers.data()) < 0) throw std::runtime_error("hdf5_forger: cannot read strings");
        for (std::size_t i = 0; i < pointers.size(); ++i) {
            v.strings[i] = pointers[i] ? pointers[i] : "";
            H5free_memory(pointers[i]);
        }
    } else if (v.kind == Kind::FixedString) {
        std::vector<char> raw(v.strings.size() * size);
        if (read(memory.get(), raw.data()) < 0) throw std::runtime_error("hdf5_forger: cannot read strings");
        for (std::size_t i = 0; i < v.strings.size(); ++i) {
            const char* s = raw.data() + i * size;
            v.strings[i].assign(s, strnlen(s, size));
        }
    } else if (read(memory.get(), v.bytes.data()) < 0) {
        throw std::runtime_error("hdf5_forger: cannot read values");
    }
    return v;
}

herr_t snapshotAttribute(hid_t object, const char* name, const H5A_info_t*, void* data) {
    auto* node = static_cast<Node*>(data);
    const Id attr(H5Aopen(object, name, H5P_DEFAULT), H5Aclose);
    const Id type(H5Aget_type(attr.get()), H5Tclose);
    const Id space(H5Aget_space(attr.get()), H5Sclose);
    node->attributes.push_back(
        {name, readValue(type.get(), space.get(), [&](hid_t memory, void* out) { return H5Aread(attr.get(), memory, out); })});
    return 0;
}

herr_t snapshotLink(hid_t group, const char* name, const H5L_info_t*, void* data) {
    auto* parent = static_cast<Node*>(data);
    H5O_info_t info;
    if (H5Oget_info_by_name(group, name, &info, H5P_DEFAULT) < 0) throw std::runtime_error("hdf5_forger: no object info");
    Node n;
    n.name = name;
    if (info.type == H5O_TYPE_GROUP) {
        n.type = Node::Type::Group;
        const Id sub(H5Gopen2(group, name, H5P_DEFAULT), H5Gclose);
        H5Aiterate2(sub.get(), H5_INDEX_NAME, H5_ITER_NATIVE, nullptr, snapshotAttribute, &n);
        H5Literate(sub.get(), H5_INDEX_NAME, H5_ITER_NATIVE, nullptr, snapshotLink, &n);
    } else if (info.type == H5O_TYPE_DATASET) {
        n.type = Node::Type::Dataset;
        const Id set(H5Dopen2(group, name, H5P_DEFAULT), H5Dclose);
        const Id type(H5Dget_type(set.get()), H5Tclose);
        const Id space(H5Dget_space(set.get()), H5Sclose);
        n.value = readValue(type.get(), space.get(), [&](hid_t memory, void* out) {
            return H5Dread(set.get(), memory, H5S_ALL, H5S_ALL, H5P_DEFAULT, out);
        });
        H5Aiterate2(set.get(), H5_INDEX_NAME, H5_ITER_NATIVE, nullptr, snapshotAttribute, &n);
    } else {
        throw std::runtime_error("hdf5_forger: snapshot of an unmodelled object");
    }
    parent->children.push_back(std::move(n));
    return 0;
}

} // namespace

std::uint64_t Value::count() const {
    if (space == Space::Null) return 0;
    if (space == Space::Scalar) return 1;
    std::uint64_t n = 1;
    for (const std::uint64_t d : dims) {
        if (d != 0 && n > std::numeric_limits<std::uint64_t>::max() / d) return std::numeric_limits<std::uint64_t>::max();
        n *= d;
    }
    return n;
}

std::size_t Value::elementSize() const {
    if (kind == Kind::Opaque) return std::max<std::size_t>(opaque_size, 1);
    if (isString()) return 0;
    return numberSize(kind);
}

void silenceHdf5() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

Node snapshot(const std::string& path) {
    silenceHdf5();
    const Id file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (!file.ok()) throw std::runtime_error("hdf5_forger: cannot open " + path);
    Node root;
    root.name.push_back('/'); // not = "/": GCC 12 warns falsely (-Wrestrict, its bug 105329)
    H5Aiterate2(file.get(), H5_INDEX_NAME, H5_ITER_NATIVE, nullptr, snapshotAttribute, &root);
    H5Literate(file.get(), H5_INDEX_NAME, H5_ITER_NATIVE, nullptr, snapshotLink, &root);
    return root;
}

Forgery mutate(const Node& base, FuzzBytes& bytes) {
    Forgery f{base, 1.0};
    Mutator m(base, f);
    if (std::getenv("VITRUM_FUZZ_LIST") != nullptr) m.list(); // for tests/fuzz/make_seeds.py
    for (int k = 0; k < kMaxOps && !bytes.empty(); ++k) {
        m.apply(bytes);
    }
    return f;
}

bool forge(const Forgery& f, const std::string& path) {
    silenceHdf5();
    {
        const Id file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
        if (!file.ok()) return false;
        std::vector<std::pair<std::string, const Node*>> links;
        writeGroup(file.get(), f.root, "/", links);
        for (const auto& [where, link] : links) {
            const Id group(H5Gopen2(file.get(), where.c_str(), H5P_DEFAULT), H5Gclose);
            if (!group.ok()) continue;
            if (link->type == Node::Type::SoftLink) {
                H5Lcreate_soft(link->target.c_str(), group.get(), link->name.c_str(), H5P_DEFAULT, H5P_DEFAULT);
            } else if (link->type == Node::Type::ExternalLink) {
                H5Lcreate_external("no-such-file.h5", link->target.c_str(), group.get(), link->name.c_str(),
                                   H5P_DEFAULT, H5P_DEFAULT);
            } else {
                H5Lcreate_hard(file.get(), link->target.c_str(), group.get(), link->name.c_str(), H5P_DEFAULT,
                               H5P_DEFAULT);
            }
        }
    }
    if (f.keep_fraction < 1.0) {
        std::error_code ec;
        const auto size = std::filesystem::file_size(path, ec);
        if (!ec) std::filesystem::resize_file(path, static_cast<std::uintmax_t>(static_cast<double>(size) * f.keep_fraction), ec);
    }
    return true;
}

long openHdf5Objects() {
    long total = 0;
    for (const H5I_type_t type : {H5I_FILE, H5I_GROUP, H5I_DATASET, H5I_ATTR, H5I_DATASPACE, H5I_DATATYPE, H5I_GENPROP_LST}) {
        hsize_t n = 0;
        if (H5Inmembers(type, &n) >= 0) total += static_cast<long>(n);
    }
    return total;
}

} // namespace vitrum::fuzz
