# Unity builds: CMake compiles a target's files a few at a time as one
# translation unit, so the standard library, Eigen, pugixml, doctest and mbx's
# headers are parsed, and their templates instantiated, once per batch rather
# than once per file (docs/build.md has the figures). Used for the libraries of
# many small files and for the test executables; the simulator and calibration,
# whose units are few and heavy, compile file by file so both cores share them.
# MBX_UNITY=OFF compiles every file on its own.
option(MBX_UNITY "Compile libraries of many small files, and the tests, in unity batches" ON)

# A library or program: its anonymous-namespace helpers must have names of
# their own across the target (a clash is a compile error in the batch).
function(mbx_unity target)
  if(MBX_UNITY)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
  endif()
endfunction()

# A test executable: each test file keeps its names in a namespace of its own,
# `namespace MBX_UNITY_ID {` after its includes, which CMake makes unique per
# file here (outside a unity build it is one more namespace). The file that
# defines the test runner (main.cpp) stays out.
function(mbx_unity_tests target)
  if(NOT MBX_UNITY)
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
