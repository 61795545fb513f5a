// Where an Inline's url points on disk. Only local files are read: CAD
// exports reference the part files next to (or below) the assembly file.
#pragma once
#include <string>
#include <unordered_map>

namespace mbx_files::vrml {

struct InlineUrl {
    enum class Status { found, remote, missing } status = Status::missing;
    std::string path;  // found: the file (lexically normalised); otherwise the path that was tried
};

// Resolves urls relative to the directory of the including file. "file:"
// URLs and %XX escapes are accepted, "#fragment" dropped, backslashes read
// as separators (Windows exporters write them). When the exact path does
// not exist, each component is matched case-insensitively, because exports
// made on Windows disagree with the disk about case. Directory listings and
// answers are cached, so a file naming many missing parts costs one listing
// per directory, not one per url.
class InlineResolver {
public:
    InlineUrl resolve(const std::string& url, const std::string& including_file);

private:
    std::string find_ignoring_case(const std::string& base, const std::string& relative);
    const std::unordered_map<std::string, std::string>& listing(const std::string& dir);

    std::unordered_map<std::string, InlineUrl> answers_;  // by including directory + '\n' + url
    std::unordered_map<std::string, std::unordered_map<std::string, std::string>> listings_;  // lower-case -> name
};

}  // namespace mbx_files::vrml
