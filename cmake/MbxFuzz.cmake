# libFuzzer builds (fuzz/, docs/fuzzing.md): the readers of outside input get
# coverage instrumentation (mbx_fuzz_coverage in their CMakeLists) on top of
# the sanitizer build's ASan and UBSan, so their code is what the fuzzer
# explores and any memory or UB error in it stops the run. The same build
# serves the sanitizer test suite (.ci/test --sanitize): nothing is compiled
# twice for the fuzzers, and code no fuzzer reaches (the simulator, the
# exporters, the tests) is not slowed by counters. Only the fuzz executables
# link the libFuzzer driver (-fsanitize=fuzzer).
if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  message(FATAL_ERROR "MBX_FUZZ needs clang (libFuzzer), e.g. -DCMAKE_CXX_COMPILER=clang++-15 -DCMAKE_C_COMPILER=clang-15")
endif()
if(NOT MBX_SANITIZE)
  include(cmake/MbxSanitize.cmake)
endif()
