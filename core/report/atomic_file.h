// Writing files so that a reader (or a crash) never sees half of one: data
// goes to a temporary file in the target's directory, is fsynced, and is then
// renamed over the target, which POSIX makes atomic within one file system.
#pragma once
#include <string>
#include <string_view>
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

// A file too large to hold in memory (a long run's trajectory), written to
// its temporary as it is made; write_files_atomically(files, streamed) then
// renames it with the others as one unit. Destroyed before that (an error,
// a cancel), it removes its temporary: the target never sees a part of it.
class StreamedFile {
public:
    // Creates the temporary next to `path` (and missing parent folders).
    explicit StreamedFile(std::string path);
    ~StreamedFile();
    StreamedFile(const StreamedFile&) = delete;
    StreamedFile& operator=(const StreamedFile&) = delete;

    // Buffered; throws mbx::Error(MBX_ERROR_IO) naming the file when the
    // disk refuses it (full, gone).
    void append(std::string_view text);
    const std::string& path() const { return path_; }

    // Writes what is buffered, syncs when asked and closes; the name of the
    // temporary (for write_files_atomically).
    const std::string& finish(bool sync);
    // After the rename: nothing left to remove.
    void committed() { temporary_.clear(); }

private:
    void flush();

    std::string path_, temporary_, buffer_;
    int fd_ = -1;
};

void write_files_atomically(const std::vector<std::pair<std::string, std::string>>& files,
                            const std::vector<StreamedFile*>& streamed);

}  // namespace mbx
