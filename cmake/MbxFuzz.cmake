# libFuzzer builds (fuzz/, docs/fuzzing.md): every target gets coverage
# instrumentation on top of the sanitizer build's ASan and UBSan, so the
# readers' own code is what the fuzzer explores and any memory or UB error in
# it stops the run. The same build serves the sanitizer test suite (.ci/test
# --sanitize): nothing is compiled twice for the fuzzers. Only the fuzz
# executables link the libFuzzer driver (-fsanitize=fuzzer).
if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  message(FATAL_ERROR "MBX_FUZZ needs clang (libFuzzer), e.g. -DCMAKE_CXX_COMPILER=clang++-15 -DCMAKE_C_COMPILER=clang-15")
endif()
if(NOT MBX_SANITIZE)
  include(cmake/MbxSanitize.cmake)
endif()
add_compile_options(-fsanitize=fuzzer-no-link)
