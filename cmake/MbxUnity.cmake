# Unity builds for the test executables: CMake compiles their files a few at a
# time as one translation unit, so doctest, Eigen and mbx's headers are parsed
# and their templates instantiated once per batch, not once per file (the test
# files' compile time falls by about 40 %; docs/build.md). Each test file keeps
# its names in a namespace of its own, `namespace MBX_UNITY_ID {` after its
# includes, which CMake makes unique per file here (outside a unity build it is
# one more namespace). A file that defines the test runner (main.cpp) stays out.
# MBX_UNITY_TESTS=OFF compiles every file on its own.
option(MBX_UNITY_TESTS "Compile the test files in unity batches" ON)
function(mbx_unity_tests target)
  if(NOT MBX_UNITY_TESTS)
    return()
  endif()
  set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 6 UNITY_BUILD_UNIQUE_ID MBX_UNITY_ID)
  get_target_property(sources ${target} SOURCES)
  foreach(source IN LISTS sources)
    if(source MATCHES "(^|/)(main|doctest_main)\\.cpp$")
      set_source_files_properties(${source} TARGET_DIRECTORY ${target} PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
    endif()
  endforeach()
endfunction()
