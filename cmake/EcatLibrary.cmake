# ecat_library(<target> <dir> [deps...])
# One library per layer folder; every .cpp below <dir> (recursively) is part of it.
# Static by default, shared with -DBUILD_SHARED_LIBS=ON (add_library without a type).
# Include paths are relative to the repository root: #include "esc/sync_manager.hpp";
# installed, the same paths resolve below <prefix>/include/ecatslave (cmake/EcatInstall.cmake).
function(ecat_library target dir)
  file(GLOB_RECURSE sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/${dir}/*.cpp)
  set(includes $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/ecatslave>)
  if(sources)
    add_library(${target} ${sources})
    # Build type Quick (scripts/quickstart): the standard headers, fmt and
    # tl::expected parsed once per library (about 18 % of an -O0 compile,
    # docs/build-times.md). The other build types parse them per file.
    if(CMAKE_BUILD_TYPE STREQUAL "Quick")
      target_precompile_headers(${target} PRIVATE ${PROJECT_SOURCE_DIR}/cmake/quick_pch.hpp)
    endif()
    target_include_directories(${target} PUBLIC ${includes})
    target_compile_features(${target} PUBLIC cxx_std_20)
    target_link_libraries(${target} PUBLIC ${ARGN})
  else()
    add_library(${target} INTERFACE)
    target_include_directories(${target} INTERFACE ${includes})
    target_compile_features(${target} INTERFACE cxx_std_20)
    target_link_libraries(${target} INTERFACE ${ARGN})
  endif()
endfunction()

# ecat_test(<name> <dir> [deps...]): one GoogleTest program per test folder.
function(ecat_test name dir)
  file(GLOB_RECURSE sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${dir}/*.cpp)
  if(NOT sources)
    return()
  endif()
  add_executable(${name} ${sources})
  target_link_libraries(${name} PRIVATE ${ARGN} GTest::gtest GTest::gtest_main GTest::gmock)
  # Allocation-counting tests replace the global operator new/delete with
  # malloc/free, which the standard allows; GCC's optimiser still reports
  # the pair as mismatched.
  target_compile_options(${name} PRIVATE $<$<CXX_COMPILER_ID:GNU>:-Wno-mismatched-new-delete>)
  target_compile_definitions(${name} PRIVATE
    ECAT_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    ECAT_ESI_SCHEMAS="${ECAT_ESI_SCHEMAS_PATH}"
    ECAT_BINARY_DIR="${PROJECT_BINARY_DIR}")
  if(ECAT_PCH)
    target_precompile_headers(${name} PRIVATE ${PROJECT_SOURCE_DIR}/tests/support/test_pch.hpp)
    # GCC 12 with a precompiled libstdc++ reports std::string concatenation
    # in test bodies as -Warray-bounds (the -Wrestrict false positive of
    # CMakeLists.txt, GCC bugs 105329/105651, gone in 13): visible, not fatal.
    if(ECAT_WERROR AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
      target_compile_options(${name} PRIVATE -Wno-error=array-bounds)
    endif()
  endif()
  # The tests' own code at another optimisation level than the libraries
  # under test (scripts/test: -O1 in the Clang -O3 stage); empty: the build type's.
  if(ECAT_TEST_CXX_FLAGS)
    separate_arguments(test_flags UNIX_COMMAND "${ECAT_TEST_CXX_FLAGS}")
    target_compile_options(${name} PRIVATE ${test_flags})
  endif()
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS unit)
  # `unit_tests` builds every unit-test program and nothing else (the
  # ASan+UBSan stage of scripts/test: the programs and scripts are not run there).
  if(NOT TARGET unit_tests)
    add_custom_target(unit_tests)
  endif()
  add_dependencies(unit_tests ${name})
endfunction()
