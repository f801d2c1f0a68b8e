// SPDX-License-Identifier: MIT
// pdgrain's own lock on a pd file (issue 13, issue 27). HDF5's lock protects serial writers only;
// an MPI-IO writer takes none, so without this a second tool could open a file an MPI run holds
// and both would corrupt it.
// - The lock itself is an open-file-description (OFD) record lock on the pd-file, far beyond its
//   data (byte 2^62: the writer, exclusive; byte 2^62 + 1: every rank of the writing run, shared).
//   It names the file by device + inode, so a symlink, a hard link or another path to it is the
//   same lock; the kernel drops it when its holder exits, however it ends (kill -9 included), so
//   a reused pid can never hold it; under MPI the last rank of the run to leave releases it.
// - `<file>.lock` beside the file (its resolved path) names the holder for the messages: tool,
//   pid, host, since when, and the process start time (/proc/PID/stat) which tells a reused pid
//   apart where the file does not exist yet (pd-pack's new output). Created with O_EXCL, never
//   through a link; one left by a killed process is stale and taken over; one from another host
//   is refused with the command that removes it.
#pragma once

#include <array>
#include <cstdint>
#include <string>

namespace pd {

class FileLock {
  public:
    FileLock() = default;
    /// Takes the lock of `file` for writing. Throws InputError naming the holder (tool, pid, host,
    /// since when) if another live process holds it. Re-entrant within one process (a process
    /// holding it may open the file again). If the directory is not writable no lock file can exist
    /// (the record lock on the file still holds); a file this process cannot write is not locked
    /// (HDF5 refuses to open it for writing).
    static FileLock acquire(const std::string& file);
    /// Under MPI, each other rank of the run rank 0 took the lock for: a shared hold that keeps
    /// the file locked until the last rank has left. Never refused by the run's own lock.
    static FileLock share(const std::string& file);
    /// Throws InputError if another live process holds the lock of `file` (it is being written),
    /// or if `file` exists and is not a regular file (a FIFO would block its reader).
    static void check_free(const std::string& file);
    FileLock(FileLock&& o) noexcept
        : key_(std::move(o.key_)) {
        o.key_.clear();
    }
    FileLock& operator=(FileLock&& o) noexcept;
    FileLock(const FileLock&) = delete;
    FileLock& operator=(const FileLock&) = delete;
    ~FileLock(); ///< the last holder in this process removes the lock file and drops the lock
    bool held() const { return !key_.empty(); }
    /// `<file>.lock`, beside the file's resolved path.
    static std::string lock_path(const std::string& file);

  private:
    std::string key_; ///< this process's entry for the file (device + inode); empty: none
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

/// Device and inode of `file` ({0, 0} when it cannot be reached): the file a name leads to.
std::array<std::uint64_t, 2> file_identity(const std::string& file);

} // namespace pd
