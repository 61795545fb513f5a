// ISO 10303-21 ("Part 21", the STEP exchange file): the clear-text encoding
// every STEP file uses, read into a flat table of entity instances whose
// parameters are typed values. Nothing here knows an application protocol:
// AP203, AP214 and AP242 files read alike, and the geometry layer asks for
// the entities it needs by name and steps over the rest (PMI, presentation).
//
// One pass over the text; instances, records and values live in three flat
// arrays (no allocation per instance), and type names are interned, so a
// reader of geometry compares integers, not strings.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace mbx_step {

// A file that cannot be read: which file, line and entity instance (0 when
// none), and why. Message text: "file:line: #id: why".
class ReadError : public std::runtime_error {
public:
    ReadError(std::string file, int line, uint64_t entity, std::string message);
    const std::string& file() const { return file_; }
    int line() const { return line_; }
    uint64_t entity() const { return entity_; }
    const std::string& message() const { return message_; }

private:
    std::string file_;
    int line_;
    uint64_t entity_;
    std::string message_;
};

enum class Kind : uint8_t {
    Missing,      // $: an optional attribute left out
    Derived,      // *: a value the supertype derives
    Integer,
    Real,
    String,       // decoded to UTF-8
    Enumeration,  // .NAME. (the name without dots)
    Binary,       // "..." (hex digits, as written)
    Reference,    // #n
    List,         // ( ... ): aggregates of every kind
    Typed,        // TYPE(value): a select's typed parameter, LENGTH_MEASURE(1.)
};

constexpr uint32_t kUnresolved = 0xFFFFFFFFu;  // a reference to no instance

struct Value {
    Kind kind = Kind::Missing;
    // List: index of the first element in File::values; Typed: index of the
    // wrapped value; String, Enumeration, Binary: offset into File::text_pool;
    // Reference: the instance's index in File::instances (kUnresolved when
    // the file has no such instance).
    uint32_t a = 0;
    union {
        int64_t integer;
        double real;
        uint64_t id;      // Reference: the #n written
        uint64_t count;   // List: element count; String, Enumeration, Binary: length
        uint64_t type;    // Typed: interned type name
    };
    Value() : integer(0) {}
};

// One entity's attributes; a complex instance #n=(A(...)B(...)) has a record
// per partial type, in the order written (the standard sorts them by name).
struct Record {
    uint32_t type = 0;  // interned upper-case name
    uint32_t first = 0; // first attribute in File::values
    uint32_t count = 0;
};

struct Instance {
    uint64_t id = 0;
    uint32_t line = 0;
    uint32_t first_record = 0;
    uint32_t record_count = 0;
};

struct Header {
    std::vector<std::string> description;  // FILE_DESCRIPTION's descriptions
    std::string name;                      // FILE_NAME's name
    std::string originating_system;        // FILE_NAME's originating system
    std::vector<std::string> schemas;      // FILE_SCHEMA, e.g. "AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }"
};

// A defect the reader found but could read past: a dangling reference, a
// cycle of references. The geometry layer decides whether it matters.
struct Problem {
    int line = 0;
    uint64_t entity = 0;
    std::string message;
};

struct ReadLimits {
    uint32_t max_depth = 64;             // nested lists and typed values
    uint64_t max_instances = 50'000'000; // far above any real part or assembly
};

class File {
public:
    std::string path;
    Header header;
    std::vector<Instance> instances;  // in the order written
    std::vector<Record> records;
    std::vector<Value> values;
    std::string text_pool;            // strings, enumerations and binaries, back to back
    std::vector<Problem> problems;

    // The interned id of an upper-case type name, or kNoType when no
    // instance of the file uses it (so a lookup by name can fail fast).
    static constexpr uint32_t kNoType = 0xFFFFFFFFu;
    uint32_t type_id(std::string_view upper_name) const;
    const std::string& type_name(uint32_t type) const { return type_names_[type]; }
    size_t type_count() const { return type_names_.size(); }

    // The instance written as #id, or null.
    const Instance* find(uint64_t id) const;
    uint32_t index_of(uint64_t id) const;  // kUnresolved when absent

    // The instance's record of `type` (a complex instance has several), or
    // null when it has none.
    const Record* record(const Instance& instance, uint32_t type) const;
    const Record* record(uint32_t instance, uint32_t type) const { return record(instances[instance], type); }
    // The first (for a simple instance the only) record.
    const Record& first_record(const Instance& instance) const { return records[instance.first_record]; }

    const Value& attribute(const Record& r, uint32_t k) const { return values[r.first + k]; }
    const Value& element(const Value& list, uint32_t k) const { return values[list.a + k]; }
    std::string_view text(const Value& v) const { return std::string_view(text_pool).substr(v.a, size_t(v.count)); }

    // Interns a name (used by the reader; readers of the table need not).
    uint32_t intern(std::string_view upper_name);
    // Sorts the id index and resolves every reference to an instance index,
    // recording dangling references and reference cycles as problems.
    void resolve();

private:
    std::vector<std::string> type_names_;
    std::unordered_map<std::string, uint32_t> type_ids_;
    std::vector<std::pair<uint64_t, uint32_t>> by_id_;  // sorted (id, index)
};

// The instance a reference value points to, kUnresolved for any other value.
inline uint32_t ref(const Value& v) { return v.kind == Kind::Reference ? v.a : kUnresolved; }

// Reads the text of a Part 21 file; `path` names it in errors. Throws
// ReadError on text that is not Part 21 (with the line and instance).
File read_part21(std::string_view text, const std::string& path, const ReadLimits& limits = {});

// Reads a file from disk (refusing what is not a regular file, or larger
// than `max_bytes`).
File read_part21_file(const std::string& path, uint64_t max_bytes = 2'000'000'000ull, const ReadLimits& limits = {});

}  // namespace mbx_step
