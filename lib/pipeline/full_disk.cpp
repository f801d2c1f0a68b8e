// SPDX-License-Identifier: MIT
#include "pipeline/full_disk.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"
#include "store/frames.hpp"
#include "store/schema.hpp"

#include <filesystem>
#include <sys/statvfs.h>

namespace pd::pipeline {

bool disk_full(const std::exception& e, const std::string& file) {
    if (std::string(e.what()).find("No space left on device") != std::string::npos)
        return true;
    std::string dir = std::filesystem::path(file).parent_path().string();
    struct statvfs fs {};
    if (::statvfs(dir.empty() ? "." : dir.c_str(), &fs) != 0)
        return false;
    return static_cast<double>(fs.f_bavail) * static_cast<double>(fs.f_frsize) < 1024.0 * 1024;
}

void end_on_full_disk(h5::File& f, const std::exception& e) {
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
        throw InputError(fmt::format("{}: the disk is full: the run stopped ({}); cutting the "
                                     "file back to its latest checkpoint failed too ({}): check "
                                     "it with pd-post --check",
                                     name, e.what(), again.what()));
    }
    throw InputError(fmt::format("{}: the disk is full: the run stopped ({}). The file is valid "
                                 "and keeps {}; free some space and continue with pd-solve "
                                 "--restart",
                                 name, e.what(), kept));
}

} // namespace pd::pipeline
