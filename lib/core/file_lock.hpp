// SPDX-License-Identifier: MIT
// pdgrain's own advisory lock on a pd file: `<file>.lock` beside it, created exclusively by the
// process that writes the file (under MPI: rank 0). HDF5's lock protects serial writers only; an
// MPI-IO writer takes none, so without this a second tool could open a file an MPI run holds and
// both would corrupt it (issue 13). A lock left by a killed process on this host (its pid is gone)
// is stale and taken over; one from another host is refused with the command that removes it.
#pragma once

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

} // namespace pd
