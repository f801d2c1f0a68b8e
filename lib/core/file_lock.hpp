// SPDX-License-Identifier: MIT
// pdgrain's own advisory lock on a pd file: `<file>.lock` beside it, created exclusively by the
// process that writes the file (under MPI: rank 0). HDF5's lock protects serial writers only; an
// MPI-IO writer takes none, so without this a second tool could open a file an MPI run holds and
// both would corrupt it (issue 13). A lock left by a killed process on this host (its pid is gone)
// is stale and taken over; one from another host is refused with the command that removes it.
#pragma once

#include <cstdint>
#include <string>

namespace pd {

class FileLock {
  public:
    FileLock() = default;
    /// Takes the lock of `file` for writing. Throws InputError naming the holder (tool, pid, host,
    /// since when) if another live process holds it. Re-entrant within one process (a process
    /// holding it may open the file again). If the directory is not writable (a file given
    /// read-write in a read-only directory) no lock file can exist: no lock is taken.
    static FileLock acquire(const std::string& file);
    /// Throws InputError if another live process holds the lock of `file` (it is being written).
    static void check_free(const std::string& file);
    FileLock(FileLock&& o) noexcept
        : path_(std::move(o.path_)) {
        o.path_.clear();
    }
    FileLock& operator=(FileLock&& o) noexcept;
    FileLock(const FileLock&) = delete;
    FileLock& operator=(const FileLock&) = delete;
    ~FileLock(); ///< removes the lock file if this object created it
    bool held() const { return !path_.empty(); }
    static std::string lock_path(const std::string& file) { return file + ".lock"; }

  private:
    std::string path_; ///< the lock file this object created (empty: none)
};

/// Disk space set aside beside a file being written (`<file>.reserve`, allocated with
/// posix_fallocate): when a write fails because the disk is full, release() frees it so that HDF5
/// can still flush its metadata and close the file consistently (a full disk otherwise leaves a
/// file HDF5 cannot read, and a crash at exit). Released (removed) on destruction too.
class SpaceReserve {
  public:
    SpaceReserve() = default;
    /// Throws InputError (exit 2) naming the free space needed if `bytes` cannot be set aside.
    static SpaceReserve create(const std::string& file, std::uint64_t bytes);
    SpaceReserve(SpaceReserve&& o) noexcept
        : path_(std::move(o.path_)) {
        o.path_.clear();
    }
    SpaceReserve& operator=(SpaceReserve&& o) noexcept {
        release();
        path_ = std::move(o.path_);
        o.path_.clear();
        return *this;
    }
    SpaceReserve(const SpaceReserve&) = delete;
    SpaceReserve& operator=(const SpaceReserve&) = delete;
    ~SpaceReserve() { release(); }
    void release() noexcept;

  private:
    std::string path_;
};

} // namespace pd
