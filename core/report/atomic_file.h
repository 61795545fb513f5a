// Writing files so that a reader (or a crash) never sees half of one: data
// goes to a temporary file in the target's directory, is fsynced, and is then
// renamed over the target, which POSIX makes atomic within one file system.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace mbx {

// Creates missing parent directories and replaces `path` with `contents`.
// Throws mbx::Error(MBX_ERROR_IO, file subject = path) on failure, after
// removing its temporary file; the previous target, if any, is left intact.
void write_file_atomically(const std::string& path, const std::string& contents);

// Writes several files as one unit: every temporary is written and fsynced
// before the first rename, and if a rename still fails the targets already
// replaced are put back from hard-link backups. So a failure leaves the old
// set of files (e.g. report.json + report.txt) as it was. Only a crash in the
// short window between renames can leave a mix. Each file is (path, contents).
void write_files_atomically(const std::vector<std::pair<std::string, std::string>>& files);

}  // namespace mbx
