# SPDX-License-Identifier: MIT
# `cmake --install build --prefix P` (`make install PREFIX=P`):
#   P/bin/pd-{pack,partition,solve,post}
#   P/lib/libpd_<module>.a                    static, position-independent (see PdHelpers)
#   P/include/pdgrain/<module>/*.hpp           included as "<module>/<name>.hpp"
#   P/lib/cmake/pdgrain/                       pdgrainConfig.cmake: find_package(pdgrain) and
#                                              link pdgrain::pipeline (pack, solve, Simulation),
#                                              pdgrain::solver, pdgrain::store, ...
#   P/share/pdgrain/{data-schema,workflows}/   the file's schema and checker, the workflows
#   P/lib/python3/dist-packages/pdgrain/       `import pdgrain` (PYTHONPATH=that dist-packages)
# Static archives: one self-contained tool per file with no RPATH to manage, and no ABI promise
# between pdgrain versions; a consumer links the third-party libraries the archives need, which
# pdgrainConfig.cmake finds again (find_dependency) as the build did.
include(CMakePackageConfigHelpers)
set(PD_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/pdgrain)

get_property(pd_modules GLOBAL PROPERTY PD_MODULES)
set(pd_module_targets)
foreach(m ${pd_modules})
  list(APPEND pd_module_targets pd_${m})
endforeach()
# pd_hdf5 and pd_warnings are link-only dependencies of the archives (the export needs them).
set_target_properties(pd_hdf5 PROPERTIES EXPORT_NAME hdf5)
set_target_properties(pd_warnings PROPERTIES EXPORT_NAME warnings)
install(TARGETS ${pd_module_targets} pd_hdf5 pd_warnings EXPORT pdgrainTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS pd-pack pd-partition pd-solve pd-post RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY lib/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/pdgrain
        FILES_MATCHING PATTERN "*.hpp" PATTERN "*.def"
        PATTERN "detail.hpp" EXCLUDE PATTERN "model_io_detail.hpp" EXCLUDE
        PATTERN "gmsh_session.hpp" EXCLUDE)
install(FILES ${PROJECT_BINARY_DIR}/generated/core/version.hpp
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/pdgrain/core)
install(EXPORT pdgrainTargets NAMESPACE pdgrain:: DESTINATION ${PD_CMAKE_DIR})
configure_package_config_file(cmake/pdgrainConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/pdgrainConfig.cmake
                              INSTALL_DESTINATION ${PD_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/pdgrainConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/pdgrainConfig.cmake
              ${PROJECT_BINARY_DIR}/pdgrainConfigVersion.cmake cmake/FindMETIS.cmake
              cmake/FindGmsh.cmake
        DESTINATION ${PD_CMAKE_DIR})
install(DIRECTORY data-schema/ DESTINATION ${CMAKE_INSTALL_DATADIR}/pdgrain/data-schema)
install(DIRECTORY workflows/ DESTINATION ${CMAKE_INSTALL_DATADIR}/pdgrain/workflows
        USE_SOURCE_PERMISSIONS PATTERN "__pycache__" EXCLUDE PATTERN "*.cpp" EXCLUDE
        PATTERN "CMakeLists.txt" EXCLUDE)
