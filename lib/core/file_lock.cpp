// SPDX-License-Identifier: MIT
#include "core/file_lock.hpp"

#include "core/errors.hpp"
#include "core/files.hpp"

#include <cerrno>
#include <csignal>
#include <cstring>
#include <ctime>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <sys/stat.h>
#include <unistd.h>

namespace pd {

namespace {

/// The record lock's bytes: far beyond any data, so they never meet the byte-range locks an
/// MPI-IO layer may take on the data it writes.
constexpr off_t writer_byte = off_t{1} << 62; ///< exclusive: the run holding the file
constexpr off_t rank_byte = writer_byte + 1;  ///< shared: every rank of that run

std::string host_name() {
    char h[256] = {};
    if (::gethostname(h, sizeof h - 1) != 0)
        return "unknown";
    return h;
}

std::string program_name() {
    std::ifstream in("/proc/self/comm");
    std::string s;
    std::getline(in, s);
    return s.empty() ? "a process" : s;
}

/// Field 22 of /proc/PID/stat (start time in clock ticks since boot), 0 if unknown.
long long start_time(long pid) {
    std::ifstream in(fmt::format("/proc/{}/stat", pid));
    std::string s;
    std::getline(in, s);
    const auto close = s.rfind(')');
    if (close == std::string::npos)
        return 0;
    std::istringstream rest(s.substr(close + 1));
    std::string field;
    for (int k = 3; k <= 22 && rest >> field; ++k)
        if (k == 22)
            return std::atoll(field.c_str());
    return 0;
}

struct Holder {
    long pid = 0;
    std::string host, tool;
    long since = 0;
    long long started = 0; ///< the holder's start time (0: an older lock file without it)
    bool readable = false;
};

Holder read_holder(const std::string& lock) {
    Holder h;
    const int fd = ::open(lock.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0)
        return h;
    struct stat st {};
    char buf[512] = {};
    ssize_t n = -1;
    if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode))
        n = ::read(fd, buf, sizeof buf - 1);
    ::close(fd);
    if (n <= 0)
        return h;
    std::istringstream in(std::string(buf, static_cast<std::size_t>(n)));
    if (in >> h.pid >> h.host >> h.tool >> h.since) {
        h.readable = true;
        if (!(in >> h.started))
            h.started = 0;
    }
    return h;
}

/// The holder's process still runs: its pid is live and, when recorded, started when it did
/// (not a reused pid).
bool alive(const Holder& h) {
    if (h.pid <= 0 || !(::kill(static_cast<pid_t>(h.pid), 0) == 0 || errno == EPERM))
        return false;
    return h.started == 0 || start_time(h.pid) == h.started;
}

std::string since(const Holder& h) {
    char when[64] = "?";
    const std::time_t t = h.since;
    std::tm tm{};
    if (::gmtime_r(&t, &tm))
        std::strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S UTC", &tm);
    return when;
}

std::string in_use(const std::string& file, const std::string& lock, const Holder& h,
                   bool record_locked) {
    if (!h.readable)
        return fmt::format("{}: in use by another pdgrain tool (it holds the lock of this file, "
                           "maybe under another name: a link or another path; lock file {}): "
                           "wait for it to finish",
                           file, lock);
    if (record_locked)
        return fmt::format("{}: in use by {} (pid {} on {}, since {}; lock {}): wait for it to "
                           "finish",
                           file, h.tool, h.pid, h.host, since(h), lock);
    return fmt::format("{}: in use by {} (pid {} on {}, since {}): wait for it to finish; if it "
                       "is not running any more, remove the lock: rm '{}'",
                       file, h.tool, h.pid, h.host, since(h), lock);
}

int set_lock(int fd, int cmd, short type, off_t start, off_t len) {
    struct flock fl {};
    fl.l_type = type;
    fl.l_whence = SEEK_SET;
    fl.l_start = start;
    fl.l_len = len;
    fl.l_pid = 0;
    return ::fcntl(fd, cmd, &fl);
}

/// True if another open file description holds a record lock on the lock bytes of `fd`'s file.
bool locked_elsewhere(int fd) {
    struct flock fl {};
    fl.l_type = F_WRLCK;
    fl.l_whence = SEEK_SET;
    fl.l_start = writer_byte;
    fl.l_len = 2;
    fl.l_pid = 0;
    return ::fcntl(fd, F_OFD_GETLK, &fl) == 0 && fl.l_type != F_UNLCK;
}

/// Opens `file` for its record lock (read-write if `write`, falling back to read-only), -1 if it
/// does not exist or cannot be opened; refuses a file that is not a regular file.
int open_for_lock(const std::string& file, bool write, bool& writable) {
    writable = false;
    int fd = -1;
    if (write) {
        fd = ::open(file.c_str(), O_RDWR | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
        writable = fd >= 0;
    }
    if (fd < 0)
        fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (fd < 0)
        return -1;
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        const mode_t m = st.st_mode;
        ::close(fd);
        throw InputError(
            fmt::format("{}: is {}, not a regular file (a pd-file)", file, file_kind(m)));
    }
    return fd;
}

/// This process's holds, by the file's device + inode ("path:<lock>" for a file that does not
/// exist yet): re-entrant, released by the last holder.
struct Entry {
    int fd = -1;      ///< the record lock's open file description (-1: none)
    std::string info; ///< the lock file this process created ("" : none)
    int refs = 0;
};
std::mutex held_mutex;
std::map<std::string, Entry>& holds() {
    static std::map<std::string, Entry> m;
    return m;
}

std::string key_of(const std::string& file) {
    struct stat st {};
    if (::stat(file.c_str(), &st) == 0)
        return fmt::format("{}:{}", static_cast<unsigned long long>(st.st_dev),
                           static_cast<unsigned long long>(st.st_ino));
    return "path:" + FileLock::lock_path(file);
}

/// Creates the holder's lock file; "" if it could not be (read-only directory). Throws the
/// refusal if a live holder's lock file is there (`have_record`: this process holds the record
/// lock, so no process on this host uses the file and any lock file from this host is stale).
std::string write_info(const std::string& file, const std::string& lock, bool have_record) {
    const std::string here = host_name();
    for (int attempt = 0; attempt < 3; ++attempt) {
        const int fd =
            ::open(lock.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
        if (fd >= 0) {
            const long pid = static_cast<long>(::getpid());
            const std::string line =
                fmt::format("{} {} {} {} {}\n", pid, here, program_name(),
                            static_cast<long>(std::time(nullptr)), start_time(pid));
            const bool ok =
                ::write(fd, line.data(), line.size()) == static_cast<ssize_t>(line.size());
            ::close(fd);
            if (!ok) {
                ::unlink(lock.c_str());
                throw InputError(
                    fmt::format("{}: cannot write the lock file {} (disk full?)", file, lock));
            }
            return lock;
        }
        if (errno == EACCES || errno == EROFS || errno == EPERM)
            return ""; // no lock file possible here (read-only directory)
        if (errno != EEXIST)
            throw InputError(fmt::format("{}: cannot create the lock file {}: {}", file, lock,
                                         std::strerror(errno)));
        Holder h = read_holder(lock);
        if (!h.readable) { // being written this instant by its creator, or torn: look again once
            ::usleep(100000);
            h = read_holder(lock);
        }
        if (h.readable && h.host != here)
            throw InputError(in_use(file, lock, h, false));
        if (h.readable && !have_record && alive(h))
            throw InputError(in_use(file, lock, h, false));
        if (!h.readable && !have_record && ::access(lock.c_str(), F_OK) == 0)
            throw InputError(fmt::format("{}: locked by {} (unreadable lock file); if no "
                                         "pdgrain tool is running on it, remove it: rm '{}'",
                                         file, lock, lock));
        ::unlink(lock.c_str()); // stale: its process is gone (killed), or its pid reused
    }
    throw InputError(
        fmt::format("{}: cannot take the lock {} (another tool keeps taking it)", file, lock));
}

/// A new reference to this process's entry `key`, if it has one.
bool add_ref(const std::string& key) {
    const std::lock_guard<std::mutex> g(held_mutex);
    auto it = holds().find(key);
    if (it == holds().end())
        return false;
    ++it->second.refs;
    return true;
}

void release(const std::string& key) noexcept {
    const std::lock_guard<std::mutex> g(held_mutex);
    auto it = holds().find(key);
    if (it == holds().end() || --it->second.refs > 0)
        return;
    if (!it->second.info.empty())
        ::unlink(it->second.info.c_str());
    if (it->second.fd >= 0)
        ::close(it->second.fd); // drops the record lock
    holds().erase(it);
}

} // namespace

std::string FileLock::lock_path(const std::string& file) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const auto abs = fs::absolute(file, ec);
    const auto real = ec ? fs::path(file) : fs::weakly_canonical(abs, ec);
    return (ec || real.empty() ? fs::path(file) : real).string() + ".lock";
}

FileLock& FileLock::operator=(FileLock&& o) noexcept {
    if (this != &o) {
        if (!key_.empty())
            release(key_);
        key_ = std::move(o.key_);
        o.key_.clear();
    }
    return *this;
}

FileLock::~FileLock() {
    if (!key_.empty())
        release(key_);
}

void FileLock::check_free(const std::string& file) {
    if (add_ref(key_of(file))) { // ours
        release(key_of(file));
        return;
    }
    bool writable = false;
    const int fd = open_for_lock(file, false, writable);
    if (fd < 0)
        return; // missing or unreadable: the reader says so
    const bool locked = locked_elsewhere(fd);
    ::close(fd);
    const std::string lock = lock_path(file);
    const Holder h = read_holder(lock);
    if (locked)
        throw InputError(in_use(file, lock, h, true));
    if (h.readable && h.host != host_name())
        throw InputError(in_use(file, lock, h, false)); // another host's run (a shared disk)
}

FileLock FileLock::acquire(const std::string& file) {
    const std::string key = key_of(file);
    FileLock l;
    if (add_ref(key)) {
        l.key_ = key;
        return l;
    }
    const std::string lock = lock_path(file);
    bool writable = false;
    const int fd = open_for_lock(file, true, writable);
    bool have_record = false;
    if (fd >= 0 && writable) {
        // Both bytes exclusive (refused while any rank of another run is still there), then the
        // rank byte shared with this run's other ranks.
        if (set_lock(fd, F_OFD_SETLK, F_WRLCK, writer_byte, 2) != 0) {
            ::close(fd);
            throw InputError(in_use(file, lock, read_holder(lock), true));
        }
        set_lock(fd, F_OFD_SETLK, F_RDLCK, rank_byte, 1);
        have_record = true;
    } else if (fd >= 0) {
        const bool locked = locked_elsewhere(fd);
        ::close(fd);
        if (locked)
            throw InputError(in_use(file, lock, read_holder(lock), true));
    }
    std::string info;
    try {
        info = write_info(file, lock, have_record);
    } catch (...) {
        if (have_record)
            ::close(fd);
        throw;
    }
    {
        const std::lock_guard<std::mutex> g(held_mutex);
        holds()[key] = Entry{have_record ? fd : -1, info, 1};
    }
    l.key_ = key;
    return l;
}

FileLock FileLock::share(const std::string& file) {
    const std::string key = key_of(file);
    FileLock l;
    if (add_ref(key)) {
        l.key_ = key;
        return l;
    }
    bool writable = false;
    const int fd = open_for_lock(file, false, writable);
    if (fd < 0)
        return l;
    if (set_lock(fd, F_OFD_SETLK, F_RDLCK, rank_byte, 1) != 0) {
        ::close(fd);
        return l; // not shared (another run's writer byte cannot block it): nothing to hold
    }
    const std::lock_guard<std::mutex> g(held_mutex);
    holds()[key] = Entry{fd, "", 1};
    l.key_ = key;
    return l;
}

SpaceReserve SpaceReserve::create(const std::string& file, std::uint64_t bytes) {
    SpaceReserve r;
    const std::string path = file + ".reserve";
    // Exclusive, never through a link: a planted `FILE.reserve -> notes.txt` (or a hard link to
    // it) is removed as a name, and notes.txt is not truncated or filled.
    const int fd = create_side_file(path);
    if (fd < 0) {
        if (errno == EACCES || errno == EROFS || errno == EPERM)
            return r; // a directory we cannot write to: no reserve (HDF5 reports what fails)
        throw InputError(fmt::format("{}: cannot set aside {} MB of disk space beside it ({}: "
                                     "{}): free some space first",
                                     file, bytes >> 20, path, std::strerror(errno)));
    }
    r.path_ = path;
    const int rc = ::posix_fallocate(fd, 0, static_cast<off_t>(bytes));
    ::close(fd);
    if (rc != 0)
        throw InputError(fmt::format("{}: cannot set aside {} MB of disk space beside it ({}): "
                                     "the run needs room for its frames; free some space first",
                                     file, bytes >> 20, std::strerror(rc)));
    return r;
}

void SpaceReserve::release() noexcept {
    if (!path_.empty())
        ::unlink(path_.c_str());
    path_.clear();
}

std::array<std::uint64_t, 2> file_identity(const std::string& file) {
    struct stat st {};
    if (::stat(file.c_str(), &st) != 0)
        return {0, 0};
    return {static_cast<std::uint64_t>(st.st_dev), static_cast<std::uint64_t>(st.st_ino)};
}

} // namespace pd
