// Numbers as CAD exporters print them, read independently of the process
// locale: a German locale must not turn "1.5" into 1, and the Windows runtime
// prints three-digit exponents ("1.5e-006").
#pragma once
#include <cstddef>
#include <optional>
#include <string_view>

namespace mbx_files {

// A finite decimal number, optionally signed, with surrounding whitespace;
// nothing else. NaN and infinities are refused: no CAD quantity is one.
std::optional<double> parse_number(std::string_view text);

// Exactly `count` numbers separated by commas (whitespace around them is
// allowed). Returns false when the count or any number is wrong.
bool parse_number_list(std::string_view text, double* out, size_t count);

std::string_view trim(std::string_view text);

}  // namespace mbx_files
