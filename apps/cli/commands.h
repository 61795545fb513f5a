// Subcommands of the mbx CLI. Each returns the process exit code:
// 0 success, 1 failure (message on stderr), 2 usage error, 3 --strict and the
// report holds errors.
#pragma once
#include <string>
#include <vector>

namespace mbx_cli {

int run_translate(const std::vector<std::string>& args);
int run_list(const std::vector<std::string>& args);
int run_formats(const std::vector<std::string>& args);
int run_library(const std::vector<std::string>& args);
int run_simulate(const std::vector<std::string>& args);
int run_calibrate(const std::vector<std::string>& args);
int run_excite(const std::vector<std::string>& args);
int run_view(const std::vector<std::string>& args);
int run_geometry(const std::vector<std::string>& args);

// An option's whole text as a finite number (no trailing characters).
bool parse_number(const std::string& text, double& out);

}  // namespace mbx_cli
