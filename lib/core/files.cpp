// SPDX-License-Identifier: MIT
#include "core/files.hpp"

#include "core/errors.hpp"

#include <cerrno>
#include <fcntl.h>
#include <mutex>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace pd {

namespace {

struct Input {
    dev_t dev;
    ino_t ino;
    std::string what, path;
};

std::mutex inputs_mutex;
std::vector<Input>& inputs() {
    static std::vector<Input> v;
    return v;
}

} // namespace

std::string file_kind(mode_t m) {
    if (S_ISREG(m))
        return "a regular file";
    if (S_ISDIR(m))
        return "a directory";
    if (S_ISFIFO(m))
        return "a FIFO (named pipe)";
    if (S_ISSOCK(m))
        return "a socket";
    if (S_ISCHR(m))
        return "a character device";
    if (S_ISBLK(m))
        return "a block device";
    if (S_ISLNK(m))
        return "a symbolic link";
    return "something else";
}

void note_input(const std::string& what, const std::string& path) {
    struct stat st {};
    if (path.empty() || ::stat(path.c_str(), &st) != 0)
        return;
    if (!S_ISREG(st.st_mode))
        throw InputError(fmt::format("{} {}: is {}, not a regular file; give the file itself", what,
                                     path, file_kind(st.st_mode)));
    const std::lock_guard<std::mutex> g(inputs_mutex);
    for (const auto& in : inputs())
        if (in.dev == st.st_dev && in.ino == st.st_ino)
            return;
    inputs().push_back({st.st_dev, st.st_ino, what, path});
}

std::pair<std::string, std::string> read_input_same_as(const std::string& path) {
    struct stat st {};
    if (path.empty() || ::stat(path.c_str(), &st) != 0)
        return {};
    const std::lock_guard<std::mutex> g(inputs_mutex);
    for (const auto& in : inputs())
        if (in.dev == st.st_dev && in.ino == st.st_ino)
            return {in.what, in.path};
    return {};
}

void check_output_target(const std::string& option, const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0)
        return; // a new file (or a dangling link: the writer replaces the link, not a target)
    if (S_ISDIR(st.st_mode))
        throw InputError(
            fmt::format("{} {}: is a directory; give the name of a file to write", option, path));
    if (!S_ISREG(st.st_mode))
        throw InputError(fmt::format("{} {}: is {}, not a regular file; it would be replaced or "
                                     "block the run; give the name of a file to write",
                                     option, path, file_kind(st.st_mode)));
    const auto [what, in] = read_input_same_as(path);
    if (!what.empty())
        throw InputError(fmt::format("{} {}: is the same file as the {} {} this run reads; it "
                                     "would be overwritten; give another name",
                                     option, path, what, in));
}

int create_side_file(const std::string& path) {
    for (int attempt = 0; attempt < 3; ++attempt) {
        const int fd =
            ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
        if (fd >= 0 || errno != EEXIST)
            return fd;
        struct stat st {};
        if (::lstat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
            errno = EISDIR;
            return -1;
        }
        // A leftover (a killed run's side file) or a planted link: the name goes, never the
        // file it may point to or share an inode with.
        if (::unlink(path.c_str()) != 0 && errno != ENOENT)
            return -1;
    }
    errno = EEXIST;
    return -1;
}

} // namespace pd
