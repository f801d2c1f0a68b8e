// SPDX-License-Identifier: MIT
// RAII gmsh session for the mesh module's .cpp files (the only place gmsh is included). gmsh
// keeps global state: one session at a time, not thread-safe. gmsh 4.8 reports errors by throwing
// std::string; with_gmsh() turns them into pd::InputError naming the operation.
#pragma once

#include "core/errors.hpp"

#include <gmsh.h>

#include <string>
#include <utility>

namespace pd::mesh {

/// gmsh::initialize (no config files) / gmsh::finalize, terminal output off.
class GmshSession {
  public:
    GmshSession() {
        gmsh::initialize(0, nullptr, false);
        gmsh::option::setNumber("General.Terminal", 0);
        gmsh::option::setNumber("General.Verbosity", 1);
    }
    ~GmshSession() { gmsh::finalize(); }
    GmshSession(const GmshSession&) = delete;
    GmshSession& operator=(const GmshSession&) = delete;
};

/// Runs f(); a gmsh error (std::string thrown by gmsh 4.8) becomes InputError("<what>: gmsh:
/// <message>").
template <class F>
decltype(auto) with_gmsh(const std::string& what, F&& f) {
    try {
        return std::forward<F>(f)();
    } catch (const std::string& msg) {
        throw InputError(fmt::format("{}: gmsh: {}", what, msg));
    }
}

} // namespace pd::mesh
