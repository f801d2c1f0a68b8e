# SPDX-License-Identifier: MIT
# pd_add_module(name SOURCES ... PUBLIC_DEPS ... PRIVATE_DEPS ...): one library pd::<name> per
# lib/<name>/ folder. Includes are written from the lib/ root ("core/errors.hpp").
function(pd_add_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(pd_${name} STATIC ${ARG_SOURCES})
  add_library(pd::${name} ALIAS pd_${name})
  # Static, position-independent: the tools stay single files needing no RPATH, and the same
  # archives link into shared objects (the Python module, a consumer's plugin). Installed as
  # pdgrain::<name> (EXPORT_NAME), headers under include/pdgrain/<name>/.
  set_target_properties(pd_${name} PROPERTIES POSITION_INDEPENDENT_CODE ON EXPORT_NAME ${name})
  target_compile_options(pd_${name} PRIVATE $<$<CXX_COMPILER_ID:GNU>:-fno-semantic-interposition>)
  target_include_directories(pd_${name} PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/lib>
                                               $<INSTALL_INTERFACE:include/pdgrain>)
  set_property(GLOBAL APPEND PROPERTY PD_MODULES ${name})
  target_compile_features(pd_${name} PUBLIC cxx_std_20)
  target_link_libraries(pd_${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE pd_warnings ${ARG_PRIVATE_DEPS})
endfunction()

# pd_add_tool(name SOURCES ... DEPS ...): an executable in build/bin.
function(pd_add_tool name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE pd_warnings ${ARG_DEPS})
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bin)
endfunction()

# pd_add_gtest(name SOURCES ... DEPS ...): one GoogleTest executable, tests discovered, label unit.
function(pd_add_gtest name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE pd_warnings ${ARG_DEPS} GTest::gtest_main)
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/tests)
  gtest_discover_tests(${name} PROPERTIES LABELS unit DISCOVERY_TIMEOUT 60)
endfunction()
