// Running the `mbx` CLI from a test: exit code, stdout and stderr.
#pragma once
#include <sys/wait.h>

#include <cstdlib>
#include <string>

#include "adapter_test_support.h"

namespace atest {

struct CliRun {
    int code = -1;
    std::string out, err;
};

// `mbx arguments` through the shell, after `prefix` (shell commands that end
// in `&& exec`, or nothing).
inline CliRun run_cli_after(const TempDir& dir, const std::string& prefix, const std::string& arguments) {
    const std::string command = prefix + "'" + MBX_CLI_PATH + "' " + arguments + " >'" + dir.file("stdout") + "' 2>'" +
                                dir.file("stderr") + "'";
    const int status = std::system(command.c_str());
    CliRun r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = read_file(dir.file("stdout"));
    r.err = read_file(dir.file("stderr"));
    return r;
}

inline CliRun run_cli(const TempDir& dir, const std::string& arguments) { return run_cli_after(dir, "", arguments); }

// The same under an address-space limit of `kib` KiB (ulimit -v, RLIMIT_AS),
// killed after `seconds` when positive (exit 124, as timeout(1) says).
inline CliRun run_cli_under(const TempDir& dir, long kib, const std::string& arguments, int seconds = 0) {
    const std::string timeout = seconds > 0 ? "timeout " + std::to_string(seconds) + " " : "";
    return run_cli_after(dir, "ulimit -v " + std::to_string(kib) + " && exec " + timeout, arguments);
}

// The least address-space limit (KiB, in steps of 4 MiB) the CLI starts
// under at all (its libraries' mappings); 0 if none up to 1 GiB.
inline long least_cli_address_space(const TempDir& dir) {
    for (long kib = 32 * 1024; kib <= 1024 * 1024; kib += 4 * 1024)
        if (run_cli_under(dir, kib, "--version").code == 0) return kib;
    return 0;
}

}  // namespace atest
