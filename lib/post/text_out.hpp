// SPDX-License-Identifier: MIT
// Small helpers shared by the text products of pd-post (CSV, PVD, XDMF): an owned output
// file that names its path when it cannot be opened, and XML escaping. The output is written
// under a temporary name and renamed into place only when its writer returns normally, so a
// killed or failing pd-post (full disk) never leaves a truncated product under the real name.
#pragma once

#include "core/errors.hpp"
#include "core/files.hpp"

#include <cstdio>
#include <exception>
#include <memory>
#include <stdio.h> // fdopen
#include <string>

namespace pd::post {

/// `path`.tmp while written; renamed to `path` when it goes out of scope with no exception in
/// flight and no stream error (writers check fflush before returning); else removed.
class OutFile {
  public:
    explicit OutFile(const std::string& path)
        : path_(path)
        , tmp_(path + ".tmp")
        , file_(open_tmp(tmp_))
        , exceptions_(std::uncaught_exceptions()) {}
    OutFile(OutFile&& o) noexcept
        : path_(std::move(o.path_))
        , tmp_(std::move(o.tmp_))
        , file_(o.file_)
        , exceptions_(o.exceptions_) {
        o.file_ = nullptr;
    }
    OutFile& operator=(OutFile&&) = delete;
    OutFile(const OutFile&) = delete;
    OutFile& operator=(const OutFile&) = delete;
    ~OutFile() {
        if (!file_)
            return;
        const bool ok = std::uncaught_exceptions() == exceptions_ && std::ferror(file_) == 0;
        const bool closed = std::fclose(file_) == 0;
        if (!(ok && closed && std::rename(tmp_.c_str(), path_.c_str()) == 0))
            std::remove(tmp_.c_str());
    }
    std::FILE* get() const { return file_; }
    explicit operator bool() const { return file_ != nullptr; }

  private:
    /// The temporary file, created exclusively: a link planted under its name is removed, never
    /// followed (its target is not truncated).
    static std::FILE* open_tmp(const std::string& tmp) {
        const int fd = create_side_file(tmp);
        return fd < 0 ? nullptr : ::fdopen(fd, "w");
    }

    std::string path_, tmp_;
    std::FILE* file_;
    int exceptions_;
};

/// Opens `path` (as `path`.tmp, see OutFile) for writing; throws InputError naming it on failure.
inline OutFile open_output(const std::string& path) {
    OutFile out(path);
    if (!out)
        throw InputError(fmt::format("{}: cannot open for writing", path));
    return out;
}

/// `s` with &, <, > and " escaped for an XML attribute or text.
inline std::string xml_escape(const std::string& s) {
    std::string out;
    for (char c : s) {
        switch (c) {
        case '&':
            out += "&amp;";
            break;
        case '<':
            out += "&lt;";
            break;
        case '>':
            out += "&gt;";
            break;
        case '"':
            out += "&quot;";
            break;
        default:
            out += c;
        }
    }
    return out;
}

} // namespace pd::post
