// SPDX-License-Identifier: MIT
#include "pipeline/full_disk.hpp"

#include "h5/file.hpp"
#include "store/frames.hpp"
#include "store/schema.hpp"

#include <filesystem>
#include <sys/statvfs.h>

namespace pd::pipeline {

namespace {

/// Bytes free to an unprivileged writer beside `file`; negative when unknown.
double free_beside(const std::string& file) {
    std::string dir = std::filesystem::path(file).parent_path().string();
    struct statvfs fs {};
    if (::statvfs(dir.empty() ? "." : dir.c_str(), &fs) != 0)
        return -1;
    return static_cast<double>(fs.f_bavail) * static_cast<double>(fs.f_frsize);
}

/// Cuts `f` back to its latest checkpoint and closes it; the message of the InputError to throw.
std::string cut_back(h5::File& f, const std::exception& e) {
    const std::string name = f.name(), root = store::path::checkpoints;
    std::string kept = "no checkpoint yet: its frames and observables were dropped";
    try {
        std::int64_t step = -1;
        if (f.exists(root) && f.has_attr(root, "latest")) {
            const std::string latest = f.attr_string(root, "latest");
            for (const auto& g : f.list(root))
                if (g != latest) // one being written when the disk filled
                    f.remove(root + "/" + g);
            step = std::stoll(latest.substr(latest.find('_') + 1));
            kept = fmt::format("its frames and observables up to its latest checkpoint (step "
                               "{})",
                               step);
        }
        store::truncate_after(f, step);
        f.close();
    } catch (const std::exception& again) {
        return fmt::format("{}: the disk is full: the run stopped ({}); cutting the file back to "
                           "its latest checkpoint failed too ({}): check it with pd-post --check",
                           name, e.what(), again.what());
    }
    return fmt::format("{}: the disk is full: the run stopped ({}). The file is valid and keeps "
                       "{}; free some space and continue with pd-solve --restart",
                       name, e.what(), kept);
}

} // namespace

bool disk_full(const std::exception& e, const std::string& file) {
    if (std::string(e.what()).find("No space left on device") != std::string::npos)
        return true;
    const double free = free_beside(file);
    return free >= 0 && free < 1024.0 * 1024;
}

void ensure_room(const std::string& file, std::uint64_t bytes, const std::string& what,
                 MPI_Comm comm, int rank) {
    const double need = 1.1 * static_cast<double>(bytes) + 1024.0 * 1024;
    double free = rank == 0 ? free_beside(file) : 0;
    MPI_Bcast(&free, 1, MPI_DOUBLE, 0, comm);
    if (free < 0 || free >= need)
        return;
    throw DiskFullError(fmt::format("{:.3g} MB free beside the file, {} needs up to {:.3g} MB "
                                    "with HDF5's metadata: not written, on any rank",
                                    free / 1e6, what, need / 1e6));
}

void end_on_full_disk(h5::File& f, const std::exception& e) {
    throw InputError(cut_back(f, e));
}

void end_on_full_disk(std::unique_ptr<h5::File>& f, const std::string& file,
                      const std::exception& e, MPI_Comm comm, int rank) {
    MPI_Barrier(comm); // rank 0's reserve is freed: room for the metadata the close writes
    std::string closing;
    try {
        if (f)
            f->close();
    } catch (const std::exception& x) {
        closing = x.what();
    }
    f.reset();
    std::string msg;
    if (rank == 0) {
        try {
            h5::File g(file, h5::Mode::read_write);
            msg = cut_back(g, e);
        } catch (const std::exception& x) {
            msg = fmt::format("{}: the disk is full: the run stopped ({}); the file could not be "
                              "reopened to cut it back ({}{}{}): check it with pd-post --check",
                              file, e.what(), x.what(),
                              closing.empty() ? "" : "; closing: ", closing);
        }
    }
    int n = static_cast<int>(msg.size());
    MPI_Bcast(&n, 1, MPI_INT, 0, comm);
    msg.resize(static_cast<std::size_t>(n));
    MPI_Bcast(msg.data(), n, MPI_CHAR, 0, comm);
    throw InputError(msg);
}

} // namespace pd::pipeline
