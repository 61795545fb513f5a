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

inline CliRun run_cli(const TempDir& dir, const std::string& arguments) {
    const std::string command = std::string("'") + MBX_CLI_PATH + "' " + arguments + " >'" + dir.file("stdout") +
                                "' 2>'" + dir.file("stderr") + "'";
    const int status = std::system(command.c_str());
    CliRun r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = read_file(dir.file("stdout"));
    r.err = read_file(dir.file("stderr"));
    return r;
}

}  // namespace atest
