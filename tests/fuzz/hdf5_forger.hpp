// The HDF5 forger of the structured fuzz targets (tests/fuzz/README.md). Raw bytes are a poor way to fuzz an
// HDF5 reader: almost every mutation of a file breaks the library's own checksums and structure, so the
// reader's code behind H5Fopen is never reached. Instead the fuzz bytes are a recipe: a list of edits applied to
// the tree of a valid file (snapshot() of what vitrum's own writer wrote), which forge() then writes as a new
// HDF5 file through the C API. The edits choose the names, presence, kinds (integers of every width and
// signedness, float32/64, fixed and variable strings, opaque, enum), byte order, ranks, dimensions (0 to 2^61),
// values (NaN, ±inf, extremes, off-by-one), groups turned into datasets and back, soft/external/hard links, and
// a final truncation. The empty recipe writes the valid file again.
//
// Recipe format (each read past the end of the bytes gives 0, so every byte string is a recipe): a sequence of
// operations, at most kMaxOps, each an opcode byte (Op below, modulo its count) followed by its arguments.
// "pick" is a u16 index (modulo) into every dataset, group, link and attribute in depth-first order (the root
// excluded); "group" a u16 index into the groups (the root first); "name" a u8 index into the name pool (every
// name of the base file, then a few hostile ones); "size" a u8 index into the size pool; "value" a u8 index
// into the value pool. tests/fuzz/make_seeds.py writes recipes with the same numbers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "fuzz_support.hpp"

namespace vitrum::fuzz {

enum class Kind : std::uint8_t { I8, U8, I16, U16, I32, U32, I64, U64, F32, F64, FixedString, VarString, Opaque, Enum8, Count };

enum class Space : std::uint8_t { Simple, Scalar, Null };

/// The contents of a dataset or an attribute: its type, shape and values.
struct Value {
    Kind kind = Kind::F64;
    bool big_endian = false;
    Space space = Space::Scalar;
    std::vector<std::uint64_t> dims; ///< Simple only
    bool chunked = false;            ///< datasets only
    bool written = true;             ///< false: too many elements to hold; the dataset keeps its fill value
    std::vector<unsigned char> bytes; ///< numbers, opaque, enum: count() elements of elementSize(), native order
    std::vector<std::string> strings; ///< strings: count() of them
    std::size_t string_size = 1;      ///< FixedString: bytes per string
    bool null_terminated = false;     ///< FixedString padding: NULLTERM, else NULLPAD
    bool utf8 = false;
    std::size_t opaque_size = 8;

    /// Elements of the shape, saturated at SIZE_MAX.
    std::uint64_t count() const;
    std::size_t elementSize() const;
    bool isString() const { return kind == Kind::FixedString || kind == Kind::VarString; }
};

struct Attribute {
    std::string name;
    Value value;
};

struct Node {
    enum class Type : std::uint8_t { Group, Dataset, SoftLink, ExternalLink, HardLink };
    Type type = Type::Group;
    std::string name;
    Value value;                       ///< Dataset
    std::string target;                ///< links: the path they point to (external: in a file that does not exist)
    std::vector<Attribute> attributes; ///< Group, Dataset
    std::vector<Node> children;        ///< Group
};

enum class Op : std::uint8_t {
    Remove = 0,     ///< pick
    Retype = 1,     ///< pick, kind (u8, modulo Kind::Count): values converted (saturated; text parsed)
    Reshape = 2,    ///< pick, rank (u8 % 6: 0 scalar, 5 null, else simple), size × rank
    Rows = 3,       ///< pick, size: the first dimension (rank 1 made if scalar)
    Set = 4,        ///< pick, index (u32), value
    SetRaw = 5,     ///< pick, index (u32), 8 raw bytes (the element's bytes)
    Fill = 6,       ///< pick, value: every element
    Nudge = 7,      ///< pick, index (u32), how (u8 % 6: +1, -1, negate, x2, swap with the next, copy the previous)
    Rename = 8,     ///< pick, name
    Move = 9,       ///< pick, group: an object to another group (an attribute to another object)
    Copy = 10,      ///< pick, group, name
    Add = 11,       ///< group, name, dataset-or-attribute (u8 & 1), kind, rank, size × rank, value
    Link = 12,      ///< group, name, type (u8 % 3: soft, external, hard), target pick
    Swap = 13,      ///< pick: a group becomes a scalar dataset, a dataset an empty group
    Text = 14,      ///< pick, text (u8 into the text pool), index (u32)
    StringType = 15, ///< pick, how (u8 % 5: fixed/variable, size from the size pool, padding, charset, all
                     ///< strings to one)
    Order = 16,     ///< pick: byte order flipped
    Chunk = 17,     ///< pick: chunked layout toggled
    Truncate = 18,  ///< fraction (u16 / 65536) of the written file kept
    Count
};

inline constexpr int kMaxOps = 64;
/// Datasets with more elements are created without data (their fill value); attributes with more are left
/// out (HDF5 keeps attribute data in memory).
inline constexpr std::uint64_t kMaxWrittenElements = 1u << 18;
inline constexpr std::uint64_t kMaxAttributeElements = 1u << 12;

/// The tree of the HDF5 file at `path` (every group, dataset and attribute with its values). Throws
/// std::runtime_error on what the forger does not model (it is used on vitrum's own files).
Node snapshot(const std::string& path);

struct Forgery {
    Node root;
    double keep_fraction = 1.0; ///< Truncate
};

/// Applies the recipe in `bytes` to a copy of `base` (up to kMaxOps operations).
Forgery mutate(const Node& base, FuzzBytes& bytes);

/// Writes `forgery` as the HDF5 file `path` (replacing it). Objects HDF5 refuses (a clash of names, an
/// impossible size) are left out: the file is whatever HDF5 accepts of the tree. Returns false if the file
/// itself cannot be created.
bool forge(const Forgery& forgery, const std::string& path);

/// HDF5 identifiers open in this process (files, groups, datasets, types, spaces, attributes): a reader that
/// returns or throws with any left open is a finding.
long openHdf5Objects();

/// Silences HDF5's error printing (the forger and the readers fail on purpose).
void silenceHdf5();

} // namespace vitrum::fuzz
