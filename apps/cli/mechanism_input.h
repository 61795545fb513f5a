// What `translate` and `simulate` share: the input options (a file of any
// format in host_adapters/inputs/input_formats.h with its shapes and mesh folders, or a built-in assembly; libraries and a
// description file), opening the input, translating it through the C API and
// attaching the description's drives.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "host_adapters/inputs/input_formats.h"
#include "mbx/mbx.h"
#include "apps/stub_host/assemblies/stub_assembly.h"

namespace mbx_cli {

struct InputOptions {
    std::string input;
    mbx_files::FileInputOptions file_options;
    std::vector<std::string> libraries;
    std::string drives_path;
    bool collision_hulls = false;  // --collision hulls: the description's body="*" hull default
    bool mass_check = true;
    bool progress = false;
    double length_tolerance = 0;
};

// Parses one input option at args[i] (advancing i past its value). Returns
// 1 if it was one, 0 if not, 2 on a usage error (message printed, naming `command`).
int parse_input_option(const std::vector<std::string>& args, size_t& i, InputOptions& o, const char* command);

// Usage lines of the input options, for the commands' help texts.
extern const char* kInputOptionsHelp;

// The translated input with everything that must outlive it, in destruction order.
struct OpenedInput {
    std::unique_ptr<mbx_files::FileInput> adapter;
    std::unique_ptr<mbx_stub::Host> stub_host;
    mbx_context* ctx = nullptr;
    mbx_mechanism* mech = nullptr;
    mbx_mechatronics* mechatronics = nullptr;
    bool file_input = false;
    OpenedInput() = default;
    OpenedInput(const OpenedInput&) = delete;
    OpenedInput& operator=(const OpenedInput&) = delete;
    ~OpenedInput();
};

// Opens, translates and attaches drives. Returns 0, or the exit code after
// printing why (1: failure, 2: usage).
int open_input(const InputOptions& o, const char* command, OpenedInput& out);

// Attaches the description anew: the input's own, `o`'s libraries, then
// `drives_path` in place of o.drives_path (a calibrated description.xml).
// Returns 0, or 1 after printing why.
int attach_description(const InputOptions& o, const std::string& drives_path, OpenedInput& in);

// "mbx: <what> failed (<status>): <message>" and exit code 1.
int fail(const OpenedInput& in, mbx_status status, const char* what);

// File name without directory and extension ("a/b/Robot.xml" -> "Robot").
std::string stem_of(const std::string& path);

}  // namespace mbx_cli
