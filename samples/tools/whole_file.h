// The sample tools write a file whole or not at all (temp + rename), so an
// interrupted mbx_make_samples never leaves a half sample behind.
#pragma once
#include <string>

namespace mbx_samples {

// Throws std::runtime_error naming `path` when it cannot be written.
void write_whole_file(const std::string& path, const std::string& text);
// Creates `path` unless it exists as a directory; throws when it cannot.
void make_directory(const std::string& path);

}  // namespace mbx_samples
