# SPDX-License-Identifier: MIT
# FindGmsh: the gmsh C++ API (Debian: libgmsh-dev ships no CMake config). Defines gmsh::gmsh.
find_path(GMSH_INCLUDE_DIR gmsh.h)
find_library(GMSH_LIBRARY gmsh)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(Gmsh
  REQUIRED_VARS GMSH_LIBRARY GMSH_INCLUDE_DIR
  REASON_FAILURE_MESSAGE "install the Debian package libgmsh-dev (make deps)")
if(Gmsh_FOUND AND NOT TARGET gmsh::gmsh)
  add_library(gmsh::gmsh UNKNOWN IMPORTED)
  set_target_properties(gmsh::gmsh PROPERTIES
    IMPORTED_LOCATION "${GMSH_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${GMSH_INCLUDE_DIR}")
endif()
mark_as_advanced(GMSH_INCLUDE_DIR GMSH_LIBRARY)
