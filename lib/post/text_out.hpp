// SPDX-License-Identifier: MIT
// Small helpers shared by the text products of pd-post (CSV, PVD, XDMF): an owned output
// file that names its path when it cannot be opened, and XML escaping.
#pragma once

#include "core/errors.hpp"

#include <cstdio>
#include <memory>
#include <string>

namespace pd::post {

using OutFile = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

/// Opens `path` for writing; throws InputError naming it on failure.
inline OutFile open_output(const std::string& path) {
    OutFile out(std::fopen(path.c_str(), "w"), &std::fclose);
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
