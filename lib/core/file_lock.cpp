// SPDX-License-Identifier: MIT
#include "core/file_lock.hpp"

#include "core/errors.hpp"

#include <cerrno>
#include <csignal>
#include <cstring>
#include <ctime>
#include <fcntl.h>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace pd {

namespace {

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

struct Holder {
    long pid = 0;
    std::string host, tool;
    long since = 0;
    bool readable = false;
};

Holder read_holder(const std::string& lock) {
    Holder h;
    std::ifstream in(lock);
    if (in >> h.pid >> h.host >> h.tool >> h.since)
        h.readable = true;
    return h;
}

bool alive(long pid) {
    return pid > 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM);
}

/// "" if the lock is free, ours or stale (removed), else the refusal message.
std::string foreign_holder(const std::string& file, const std::string& lock, bool take_over) {
    const Holder h = read_holder(lock);
    if (!h.readable) {
        // Being written this instant by its creator, or a torn lock: look again once.
        ::usleep(100000);
        const Holder again = read_holder(lock);
        if (!again.readable) {
            if (::access(lock.c_str(), F_OK) != 0)
                return "";
            return fmt::format("{}: locked by {} (unreadable lock file); if no pdgrain tool is "
                               "running on it, remove it: rm '{}'",
                               file, lock, lock);
        }
        return foreign_holder(file, lock, take_over);
    }
    const std::string here = host_name();
    if (h.host == here && h.pid == static_cast<long>(::getpid()))
        return ""; // ours (re-entrant)
    if (h.host == here && !alive(h.pid)) {
        if (take_over)
            ::unlink(lock.c_str()); // stale: its process is gone (killed)
        return "";
    }
    char when[64] = "?";
    const std::time_t t = h.since;
    std::tm tm{};
    if (::gmtime_r(&t, &tm))
        std::strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S UTC", &tm);
    return fmt::format("{}: in use by {} (pid {} on {}, since {}): wait for it to finish; if it "
                       "is not running any more, remove the lock: rm '{}'",
                       file, h.tool, h.pid, h.host, when, lock);
}

} // namespace

FileLock& FileLock::operator=(FileLock&& o) noexcept {
    if (this != &o) {
        if (!path_.empty())
            ::unlink(path_.c_str());
        path_ = std::move(o.path_);
        o.path_.clear();
    }
    return *this;
}

FileLock::~FileLock() {
    if (!path_.empty())
        ::unlink(path_.c_str());
}

void FileLock::check_free(const std::string& file) {
    const std::string lock = lock_path(file);
    if (::access(lock.c_str(), F_OK) != 0)
        return;
    const std::string why = foreign_holder(file, lock, false);
    if (!why.empty())
        throw InputError(why);
}

FileLock FileLock::acquire(const std::string& file) {
    const std::string lock = lock_path(file);
    for (int attempt = 0; attempt < 3; ++attempt) {
        const int fd = ::open(lock.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
        if (fd >= 0) {
            const std::string line =
                fmt::format("{} {} {} {}\n", ::getpid(), host_name(), program_name(),
                            static_cast<long>(std::time(nullptr)));
            const bool ok =
                ::write(fd, line.data(), line.size()) == static_cast<ssize_t>(line.size());
            ::close(fd);
            if (!ok) {
                ::unlink(lock.c_str());
                throw InputError(
                    fmt::format("{}: cannot write the lock file {} (disk full?)", file, lock));
            }
            FileLock l;
            l.path_ = lock;
            return l;
        }
        if (errno == EACCES || errno == EROFS || errno == EPERM)
            return {}; // no lock file possible here (read-only directory)
        if (errno != EEXIST)
            throw InputError(fmt::format("{}: cannot create the lock file {}: {}", file, lock,
                                         std::strerror(errno)));
        const std::string why = foreign_holder(file, lock, true);
        if (!why.empty())
            throw InputError(why);
        if (::access(lock.c_str(), F_OK) == 0)
            return {}; // ours, taken earlier in this process: the first owner releases it
    }
    throw InputError(
        fmt::format("{}: cannot take the lock {} (another tool keeps taking it)", file, lock));
}

SpaceReserve SpaceReserve::create(const std::string& file, std::uint64_t bytes) {
    SpaceReserve r;
    const std::string path = file + ".reserve";
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) {
        if (errno == EACCES || errno == EROFS || errno == EPERM)
            return r; // a directory we cannot write to: no reserve (HDF5 reports what fails)
        throw InputError(fmt::format("{}: cannot set aside {} MB of disk space beside it ({}): "
                                     "free some space first",
                                     file, bytes >> 20, std::strerror(errno)));
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

} // namespace pd
