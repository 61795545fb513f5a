// The multi-domain object library (thesis section 2.8.1): folders per
// engineering domain, classes with a Modelica implementation and typed
// parameter declarations (units live here), objects with a 32-hex-digit ID
// and a value for every class parameter. Read from XML and validated as a
// whole, so a user sees every problem of a library file at once.
#pragma once
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace mbx {

enum class ParameterType { Real, Integer, Boolean, String };

struct ParameterDecl {
    std::string name;
    ParameterType type = ParameterType::Real;
    std::string unit;       // as written ("kg.m2", "rpm"); "" for dimensionless or non-numeric
    double si_factor = 1;   // value * si_factor = SI value (rpm -> rad/s)
    bool editable = false;  // may a drive assignment override it?
    std::string comment;
    std::optional<double> lower, upper;  // in the declared unit
    int line = 0;
};

struct ParameterValue {
    std::string text;  // as written
    double number = 0; // parsed, declared unit (Real, Integer, Boolean as 0/1)
    int line = 0;
};

struct LibraryObject {
    std::string name, id;  // id: 32 upper-case hex digits
    std::map<std::string, ParameterValue> values;
    std::string file;
    int line = 0;
};

struct LibraryClass {
    std::string name;
    std::string kind;      // what mbx knows how to use: "dc_motor", "gearbox", "ball_screw" or "" (other)
    std::string modelica;  // Modelica implementation path
    std::vector<ParameterDecl> parameters;
    std::vector<LibraryObject> objects;
    int line = 0;

    const ParameterDecl* parameter(const std::string& name) const;
};

struct LibraryFolder {
    std::string name;  // engineering domain
    std::vector<LibraryClass> classes;
};

// One problem found while reading a library file.
struct LibraryError {
    std::string file;
    int line = 0;
    std::string object;  // "<class>/<object>" or "<class>" it is about, "" for the file
    std::string message;

    std::string text() const;  // "file:line: object: message"
};

class ObjectLibrary {
public:
    // Reads `path` and appends its folders (folders of the same name merge).
    // Problems go to errors(); an object with a problem is not added.
    // A file already loaded (the same file by its real path, however it is
    // named) is skipped: a drive file and the command line may both name the
    // bundled library. Returns false when the file cannot be read.
    bool load_file(const std::string& path);
    // The same from text in memory (`file` names it in errors).
    void load_text(const std::string& text, const std::string& file);

    const std::vector<LibraryFolder>& folders() const { return folders_; }
    const std::vector<LibraryError>& errors() const { return errors_; }
    bool ok() const { return errors_.empty(); }

    struct Found {
        const LibraryClass* cls = nullptr;
        const LibraryObject* object = nullptr;
    };
    // By ID (case-insensitive); {nullptr, nullptr} when absent.
    Found find(const std::string& id) const;
    // SI value of `parameter` of `object`, or nullopt when it has none.
    // (Not si_value: <signal.h> defines that name as a macro.)
    std::optional<double> value_in_si(const Found& f, const std::string& parameter) const;

private:
    std::vector<LibraryFolder> folders_;
    std::vector<LibraryError> errors_;
    std::vector<std::string> loaded_files_;  // real paths
    std::map<std::string, std::pair<size_t, size_t>> class_index_;  // "folder\nclass" -> indices
    std::map<std::string, std::string> id_owner_;                  // ID -> "file:line"
};

// Unit table: SI factor of a unit string, nullopt when mbx does not know it.
std::optional<double> unit_si_factor(const std::string& unit);

}  // namespace mbx
