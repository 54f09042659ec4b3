# Helpers that give every target of ours the same warnings and sanitizer
# settings. Third-party headers are included as SYSTEM so -Werror applies to
# our code only.

function(ephor_target_defaults target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow
    -Wnon-virtual-dtor -Wold-style-cast -Wcast-align -Wunused -Woverloaded-virtual
    -Wnull-dereference -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough
    # GCC 12 reports false positives from libstdc++ internals at -O3 (GCC bugs 105329, 105651).
    -Wno-restrict -Wno-stringop-overflow -Wno-array-bounds)
  if(EPHOR_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(EPHOR_SANITIZE)
    # -Wno-maybe-uninitialized: GCC 12 false positives inside <regex> with sanitizers.
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-omit-frame-pointer
      -Wno-maybe-uninitialized)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  endif()
endfunction()

# ephor_library(NAME SOURCES a.cc b.cc DEPS dep1 dep2)
# A static library of pure code; its include root is the repository root, so
# headers are included as "procs/shepherd/vision/blobifier.h" or "common/lcm/bus.h".
function(ephor_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_library(${name} STATIC ${ARG_SOURCES})
  target_include_directories(${name} PUBLIC ${CMAKE_SOURCE_DIR})
  target_link_libraries(${name} PUBLIC ${ARG_DEPS})
  ephor_target_defaults(${name})
endfunction()

# ephor_executable(NAME SOURCES main.cc DEPS lib)
function(ephor_executable name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_include_directories(${name} PRIVATE ${CMAKE_SOURCE_DIR})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS})
  ephor_target_defaults(${name})
  # A process's main.cc is wiring (flags, subscriptions, the task table); its
  # work is in libraries built at the build type's level. At -O3 the
  # header-only CLI11 parser alone cost about 7 s of code generation per main
  # (42 mains: a third of a clean build on 2 cores); at -O2 a main builds in
  # about two thirds of the time. (GCC 12 at -O2 reports a false "potential
  # null pointer dereference" inside libstdc++'s std::string in the launcher's
  # main; the libraries, where the logic is, keep that warning.)
  foreach(src ${ARG_SOURCES})
    get_filename_component(base ${src} NAME)
    if(base STREQUAL "main.cc" AND CMAKE_BUILD_TYPE STREQUAL "Release")
      set_source_files_properties(${src} TARGET_DIRECTORY ${name} PROPERTIES COMPILE_OPTIONS "-O2;-Wno-null-dereference")
    endif()
  endforeach()
  # Every program a person can start, for the bad-input walk (tests/badinput);
  # Google Benchmark binaries take the library's flags and are listed apart.
  if("benchmark::benchmark" IN_LIST ARG_DEPS)
    set_property(GLOBAL APPEND PROPERTY EPHOR_GBENCH_EXECUTABLES ${name})
  endif()
  set_property(GLOBAL APPEND PROPERTY EPHOR_EXECUTABLES ${name})
endfunction()

# ephor_test(NAME SOURCES x_test.cc DEPS lib [NETNS [ALONE]] [LABELS l] [TIMEOUT s])
# A GoogleTest binary registered with CTest. NETNS runs it inside a private
# network namespace (tools/netns-run) so multicast stays on this test. ALONE
# runs it with no other test beside it: for tests that bound a time the
# machine's load stretches (a restart within 1 s, a hole in a recorded log).
function(ephor_test name)
  cmake_parse_arguments(ARG "NETNS;ALONE" "TIMEOUT" "SOURCES;DEPS;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_include_directories(${name} PRIVATE ${CMAKE_SOURCE_DIR})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gtest_main GTest::gmock)
  ephor_target_defaults(${name})
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
  if(ARG_NETNS)
    add_test(NAME ${name} COMMAND ${CMAKE_SOURCE_DIR}/tools/netns-run $<TARGET_FILE:${name}>)
    set(labels integration ${ARG_LABELS})
  else()
    add_test(NAME ${name} COMMAND ${name})
    set(labels unit ${ARG_LABELS})
  endif()
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 300)
  endif()
  if(EPHOR_SANITIZE)
    # AddressSanitizer and UBSan run code 2-3 times slower (rambo_test and
    # catch_vision_test passed their 60 s under them only on a quiet machine).
    math(EXPR ARG_TIMEOUT "${ARG_TIMEOUT} * 4")
  endif()
  set_tests_properties(${name} PROPERTIES LABELS "${labels}" TIMEOUT ${ARG_TIMEOUT}
    ENVIRONMENT "EPHOR_BIN_DIR=${CMAKE_BINARY_DIR}/bin;EPHOR_SOURCE_DIR=${CMAKE_SOURCE_DIR}")
  # Multi-process tests may run two at a time (ctest -j2): each system's
  # whole pipeline averages 0.05-0.4 of a core in its test (CPU time in a
  # cgroup over wall time, 2026-11-26), so two together leave a core free.
  if(ARG_ALONE)
    set_tests_properties(${name} PROPERTIES RUN_SERIAL TRUE)
  endif()
endfunction()

# ephor_proto_library(NAME PROTOS common/config/x.proto ...)
# Generates C++ with protoc, rooted at the repository root so that
# "common/config/x.proto" becomes "common/config/x.pb.h" in the build tree.
function(ephor_proto_library name)
  cmake_parse_arguments(ARG "" "" "PROTOS" ${ARGN})
  set(srcs "")
  foreach(proto ${ARG_PROTOS})
    string(REGEX REPLACE "\\.proto$" "" stem ${proto})
    set(out_cc ${CMAKE_BINARY_DIR}/${stem}.pb.cc)
    set(out_h ${CMAKE_BINARY_DIR}/${stem}.pb.h)
    add_custom_command(
      OUTPUT ${out_cc} ${out_h}
      COMMAND protobuf::protoc --cpp_out=${CMAKE_BINARY_DIR} -I${CMAKE_SOURCE_DIR} ${CMAKE_SOURCE_DIR}/${proto}
      DEPENDS ${CMAKE_SOURCE_DIR}/${proto}
      COMMENT "protoc ${proto}"
      VERBATIM)
    list(APPEND srcs ${out_cc})
  endforeach()
  add_library(${name} STATIC ${srcs})
  target_include_directories(${name} SYSTEM PUBLIC ${CMAKE_BINARY_DIR})
  target_link_libraries(${name} PUBLIC protobuf::libprotobuf)
endfunction()

# ephor_add_subfolders()
# Adds every subfolder of the current folder that has a CMakeLists.txt, in
# name order. EPHOR_ONLY_DIRS (a developer option: a list of folder names)
# limits the build to some of them.
macro(ephor_add_subfolders)
  file(GLOB _ephor_children LIST_DIRECTORIES true RELATIVE ${CMAKE_CURRENT_SOURCE_DIR}
       ${CMAKE_CURRENT_SOURCE_DIR}/*)
  list(SORT _ephor_children)
  foreach(_ephor_child ${_ephor_children})
    if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/${_ephor_child}/CMakeLists.txt
       AND (NOT EPHOR_ONLY_DIRS OR _ephor_child IN_LIST EPHOR_ONLY_DIRS))
      add_subdirectory(${_ephor_child})
    endif()
  endforeach()
endmacro()
