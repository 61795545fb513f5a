// An input file that cannot be turned into an assembly: which file, which
// line, and why. Every reader of the file adapter throws this (never a bare
// exception from a library), so a caller can print "file:line: message".
#pragma once
#include <stdexcept>
#include <string>

namespace mbx_files {

class FileError : public std::runtime_error {
public:
    FileError(std::string file, int line, std::string message)
        : std::runtime_error(file + ":" + std::to_string(line) + ": " + message),
          file_(std::move(file)),
          line_(line),
          message_(std::move(message)) {}
    const std::string& file() const { return file_; }
    int line() const { return line_; }  // 1-based, 0 when the file as a whole is at fault
    const std::string& message() const { return message_; }

private:
    std::string file_;
    int line_;
    std::string message_;
};

}  // namespace mbx_files
