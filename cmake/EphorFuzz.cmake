# Fuzz targets (issue 18). Each target is one file *_fuzz.cc defining
#   extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
# beside the code it exercises, with its seed corpus in fuzz_corpus/NAME/ in
# the same folder. Two builds of the same file:
#  - always: fuzz_corpus_NAME, the target with common/fuzz/corpus_runner.cc as
#    main, and the ctest test fuzz_corpus_NAME that runs it once over its
#    corpus (labels unit and fuzz; well under a second);
#  - with -DEPHOR_FUZZ=ON (clang only; tools/ephor fuzz configures build-fuzz
#    so): fuzz_NAME, the target with libFuzzer, ASan and UBSan, for long runs.
#    Everything of ours in that build is compiled with coverage counters and
#    the sanitizers, so libFuzzer sees the libraries' branches.
option(EPHOR_FUZZ "Build the fuzz targets with clang, libFuzzer, ASan and UBSan (build-fuzz/)" OFF)

if(EPHOR_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "EPHOR_FUZZ needs clang (configure with CXX=clang++): libFuzzer is clang's")
  endif()
  # -fno-sanitize-recover: a UBSan finding aborts, so libFuzzer keeps the input.
  string(APPEND CMAKE_CXX_FLAGS
    " -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g")
  string(APPEND CMAKE_EXE_LINKER_FLAGS " -fsanitize=address,undefined")
endif()

# ephor_fuzz_target(NAME SOURCE path/from/root/x_fuzz.cc DEPS lib...)
function(ephor_fuzz_target name)
  cmake_parse_arguments(ARG "" "SOURCE" "DEPS" ${ARGN})
  set(source ${CMAKE_SOURCE_DIR}/${ARG_SOURCE})
  get_filename_component(dir ${source} DIRECTORY)
  set(corpus ${dir}/fuzz_corpus/${name})
  if(NOT IS_DIRECTORY ${corpus})
    message(FATAL_ERROR "fuzz target ${name}: no seed corpus ${corpus}")
  endif()

  add_executable(fuzz_corpus_${name} ${source})
  target_include_directories(fuzz_corpus_${name} PRIVATE ${CMAKE_SOURCE_DIR})
  target_link_libraries(fuzz_corpus_${name} PRIVATE ${ARG_DEPS} ephor_fuzz_support
    ephor_fuzz_corpus_runner)
  ephor_target_defaults(fuzz_corpus_${name})
  set_target_properties(fuzz_corpus_${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
  add_test(NAME fuzz_corpus_${name} COMMAND fuzz_corpus_${name} ${corpus})
  set_tests_properties(fuzz_corpus_${name} PROPERTIES LABELS "unit;fuzz" TIMEOUT 60)

  if(EPHOR_FUZZ)
    add_executable(fuzz_${name} ${source})
    target_include_directories(fuzz_${name} PRIVATE ${CMAKE_SOURCE_DIR})
    target_link_libraries(fuzz_${name} PRIVATE ${ARG_DEPS} ephor_fuzz_support)
    ephor_target_defaults(fuzz_${name})
    target_link_options(fuzz_${name} PRIVATE -fsanitize=fuzzer)
    set_target_properties(fuzz_${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/fuzz)
  endif()
endfunction()
