#include "core/report/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <filesystem>
#include <set>
#include <system_error>
#include <tuple>

#include "core/finding.h"

namespace mbx {
namespace {

namespace fs = std::filesystem;

std::string describe(int err) { return std::error_code(err, std::generic_category()).message(); }

[[noreturn]] void fail(const std::string& path, const std::string& what, int err) {
    throw Error(MBX_ERROR_IO, Subject{MBX_SUBJECT_FILE, path, ""}, what + ": " + describe(err) + ".");
}

// Distinguishes temporaries of concurrent writers in one process; the pid
// distinguishes processes. Names are also claimed with O_EXCL / link(), so a
// stale file from a dead process with a recycled pid only costs a retry.
std::string unique_sibling(const std::string& path) {
    static std::atomic<unsigned long> counter{0};
    return path + ".tmp." + std::to_string(static_cast<long>(::getpid())) + "." +
           std::to_string(counter.fetch_add(1, std::memory_order_relaxed));
}

constexpr int kNameAttempts = 100;

// The pid of `name` if it is one of unique_sibling's ("<file>.tmp.<pid>.<n>"), else 0.
long temporary_owner(const std::string& name) {
    const size_t counter_dot = name.rfind('.');
    if (counter_dot == std::string::npos || counter_dot + 1 == name.size()) return 0;
    const size_t pid_dot = name.rfind('.', counter_dot - 1);
    if (pid_dot == std::string::npos || pid_dot < 4 || name.compare(pid_dot - 4, 4, ".tmp") != 0) return 0;
    auto digits = [&](size_t from, size_t to) {
        if (from >= to || to - from > 18) return false;
        for (size_t i = from; i < to; ++i)
            if (name[i] < '0' || name[i] > '9') return false;
        return true;
    };
    if (!digits(pid_dot + 1, counter_dot) || !digits(counter_dot + 1, name.size())) return 0;
    return std::stol(name.substr(pid_dot + 1, counter_dot - pid_dot - 1));
}

// Removes from `dir` the temporaries (and backups) of writers that died
// before renaming them: a run killed mid-export leaves its `*.tmp.<pid>.<n>`
// files, and the next run into the folder takes them away. Only those whose
// process is gone: a live writer's, this process's included, are its own.
void remove_stale_temporaries(const std::string& dir) {
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        const long pid = temporary_owner(name);
        if (pid <= 0 || pid == long(::getpid())) continue;
        if (::kill(pid_t(pid), 0) == 0 || errno != ESRCH) continue;  // alive (or not ours to judge)
        std::error_code type_ec;
        if (it->is_regular_file(type_ec)) ::unlink(it->path().c_str());
    }
}

std::string parent_directory(const std::string& path) {
    const fs::path parent = fs::path(path).parent_path();
    return parent.empty() ? std::string(".") : parent.string();
}

void create_parent_directories(const std::string& path) {
    const fs::path parent = fs::path(path).parent_path();
    if (parent.empty()) return;
    std::error_code ec;
    fs::create_directories(parent, ec);
    if (ec || !fs::is_directory(parent)) {
        // A file where a directory should be surfaces as EEXIST, whose text
        // ("File exists") would mislead; say what is actually wrong.
        const int err = !ec || ec.value() == EEXIST ? ENOTDIR : ec.value();
        fail(path, "Cannot create the directory '" + parent.string() + "' for '" + path + "'", err);
    }
}

bool write_all(int fd, const std::string& contents) {
    const char* p = contents.data();
    std::size_t left = contents.size();
    while (left > 0) {
        // Large single writes are split: some kernels cap a write near 2 GiB.
        const std::size_t chunk = left < (std::size_t{1} << 30) ? left : (std::size_t{1} << 30);
        const ssize_t n = ::write(fd, p, chunk);
        if (n < 0) {
            if (errno == EINTR) continue;
            return false;
        }
        p += n;
        left -= static_cast<std::size_t>(n);
    }
    return true;
}

// Creates a new temporary next to `path`: its name and open descriptor.
std::pair<std::string, int> open_temporary(const std::string& path) {
    create_parent_directories(path);
    std::string tmp;
    int fd = -1;
    for (int attempt = 0; attempt < kNameAttempts && fd < 0; ++attempt) {
        tmp = unique_sibling(path);
        fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0 && errno != EEXIST && errno != EINTR) break;
    }
    if (fd < 0) fail(path, "Cannot create a temporary file next to '" + path + "'", errno);
    return {tmp, fd};
}

// Syncs when asked and closes; 0 or the error.
int close_temporary(int fd, bool sync) {
    // fsync before rename: otherwise a crash may leave the new name pointing
    // at an empty file on file systems that reorder metadata and data.
    int err = 0;
    if (sync && ::fsync(fd) != 0) err = errno;
    if (::close(fd) != 0 && !err && errno != EINTR) err = errno;
    return err;
}

// Writes a new temporary next to `path` and returns its name; fsyncs it when
// `sync` (a batch syncs its file systems once instead, see write_all).
std::string write_temporary(const std::string& path, const std::string& contents, bool sync) {
    const auto [tmp, fd] = open_temporary(path);
    int err = write_all(fd, contents) ? 0 : errno;
    const int closed = close_temporary(fd, sync && !err);
    if (!err) err = closed;
    if (err) {
        ::unlink(tmp.c_str());
        fail(path, "Cannot write '" + path + "' (via the temporary '" + tmp + "')", err);
    }
    return tmp;
}

// Makes the renames themselves durable. Best effort: the data is already safe
// and the rename done, so a failure here is no reason to report an error.
void sync_directory(const std::string& dir) {
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    ::fsync(fd);
    ::close(fd);
}

// Hard-links an existing target to a fresh sibling name so it can be restored.
// Returns "" if the target does not exist or the file system cannot link.
std::string backup(const std::string& path) {
    for (int attempt = 0; attempt < kNameAttempts; ++attempt) {
        std::string name = unique_sibling(path);
        if (::link(path.c_str(), name.c_str()) == 0) return name;
        if (errno != EEXIST && errno != EINTR) break;
    }
    return {};
}

struct Pending {
    const std::string* path;
    std::string tmp;
    std::string backup;   // hard link to the previous target, "" if none
    bool existed = false; // whether a target existed before
};

void remove_temporaries(const std::vector<Pending>& pending, std::size_t from) {
    for (std::size_t i = from; i < pending.size(); ++i) {
        if (!pending[i].tmp.empty()) ::unlink(pending[i].tmp.c_str());
        if (!pending[i].backup.empty()) ::unlink(pending[i].backup.c_str());
    }
}

// Both public functions in one: files are referenced, never copied.
struct FileRef {
    const std::string* path;
    const std::string* contents;  // nullptr: `streamed` holds it
    StreamedFile* streamed = nullptr;
};

// Flushes every file system holding one of `dirs` with one syncfs() each:
// for an export of thousands of files, one fsync per file cost ~1 ms each and
// dominated the export. Returns 0 or the first error.
int sync_file_systems(const std::set<std::string>& dirs) {
    std::set<dev_t> synced;
    for (const std::string& dir : dirs) {
        const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
        if (fd < 0) return errno;
        struct stat st;
        int err = ::fstat(fd, &st) != 0 ? errno : 0;
        if (!err && synced.insert(st.st_dev).second && ::syncfs(fd) != 0) err = errno;
        ::close(fd);
        if (err) return err;
    }
    return 0;
}

void write_all(const std::vector<FileRef>& files) {
    std::vector<Pending> pending;
    pending.reserve(files.size());
    const bool batch = files.size() > 1;
    std::set<std::string> dirs;
    try {
        for (const FileRef& f : files) {
            pending.push_back({f.path, {}, {}, false});
            pending.back().tmp = f.streamed ? f.streamed->finish(!batch) : write_temporary(*f.path, *f.contents, !batch);
            dirs.insert(parent_directory(*f.path));
        }
        if (batch) {
            if (const int err = sync_file_systems(dirs))
                fail(*files.front().path, "Cannot flush the new files to disk", err);
        }
    } catch (...) {
        remove_temporaries(pending, 0);
        throw;
    }

    // A single file needs no backup: a failed rename leaves the target alone.
    if (pending.size() > 1) {
        for (Pending& p : pending) {
            struct stat st;
            p.existed = ::lstat(p.path->c_str(), &st) == 0;
            if (p.existed && !S_ISDIR(st.st_mode)) p.backup = backup(*p.path);
        }
    }

    for (std::size_t i = 0; i < pending.size(); ++i) {
        if (::rename(pending[i].tmp.c_str(), pending[i].path->c_str()) == 0) continue;
        const int err = errno;
        // Undo the renames already done, newest first, so the old set returns.
        for (std::size_t j = i; j-- > 0;) {
            const Pending& done = pending[j];
            if (!done.backup.empty())
                ::rename(done.backup.c_str(), done.path->c_str());
            else if (!done.existed)
                ::unlink(done.path->c_str());
        }
        remove_temporaries(pending, i);
        const std::string& path = *pending[i].path;
        fail(path, "Cannot replace '" + path + "' with its new contents", err);
    }

    for (const FileRef& f : files)
        if (f.streamed) f.streamed->committed();
    for (const Pending& p : pending)
        if (!p.backup.empty()) ::unlink(p.backup.c_str());
    for (const std::string& dir : dirs) {
        remove_stale_temporaries(dir);
        sync_directory(dir);
    }
}

}  // namespace

void write_file_atomically(const std::string& path, const std::string& contents) {
    write_all({{&path, &contents}});
}

void write_files_atomically(const std::vector<std::pair<std::string, std::string>>& files) {
    std::vector<FileRef> refs;
    refs.reserve(files.size());
    for (const auto& [path, contents] : files) refs.push_back({&path, &contents});
    write_all(refs);
}

void write_files_atomically(const std::vector<std::pair<std::string, std::string>>& files,
                            const std::vector<StreamedFile*>& streamed) {
    std::vector<FileRef> refs;
    refs.reserve(files.size() + streamed.size());
    for (StreamedFile* f : streamed) refs.push_back({&f->path(), nullptr, f});
    for (const auto& [path, contents] : files) refs.push_back({&path, &contents});
    write_all(refs);
}

StreamedFile::StreamedFile(std::string path) : path_(std::move(path)) {
    std::tie(temporary_, fd_) = open_temporary(path_);
}

StreamedFile::~StreamedFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!temporary_.empty()) ::unlink(temporary_.c_str());
}

void StreamedFile::append(std::string_view text) {
    buffer_.append(text);
    if (buffer_.size() >= (std::size_t{1} << 20)) flush();
}

void StreamedFile::flush() {
    if (fd_ < 0) fail(path_, "Cannot write '" + path_ + "' after it was finished", EBADF);
    if (!write_all(fd_, buffer_)) fail(path_, "Cannot write '" + path_ + "' (via the temporary '" + temporary_ + "')", errno);
    buffer_.clear();
}

const std::string& StreamedFile::finish(bool sync) {
    flush();
    const int err = close_temporary(fd_, sync);
    fd_ = -1;
    if (err) fail(path_, "Cannot write '" + path_ + "' (via the temporary '" + temporary_ + "')", err);
    return temporary_;
}

}  // namespace mbx
