# ASan + UBSan for every target; UB is made fatal so ctest sees it. -O1 as the
# sanitizers' own documentation advises: at -O0 Eigen's expression templates
# run ~1000x slower than optimised and the simulator's 10 s runs would not fit
# CI's time; -O1 keeps the checks (and Debug's asserts) at a fraction of that.
add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -O1)
add_link_options(-fsanitize=address,undefined)
set(MBX_SANITIZER_PRELOAD "")
if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  # clang links its sanitizer runtime statically into executables only, which
  # leaves a shared libmbx with undefined runtime symbols and a C program that
  # loads it without UBSan's C++ handlers. The shared runtime (which holds
  # ASan, UBSan and those handlers) serves executables and libraries alike.
  execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-resource-dir
    OUTPUT_VARIABLE _mbx_clang_resources OUTPUT_STRIP_TRAILING_WHITESPACE)
  set(MBX_SANITIZER_RUNTIME_DIR "${_mbx_clang_resources}/lib/linux")
  set(MBX_SANITIZER_PRELOAD "${MBX_SANITIZER_RUNTIME_DIR}/libclang_rt.asan-${CMAKE_SYSTEM_PROCESSOR}.so")
  if(NOT EXISTS "${MBX_SANITIZER_PRELOAD}")
    message(FATAL_ERROR "no shared sanitizer runtime at ${MBX_SANITIZER_PRELOAD}")
  endif()
  add_link_options(-shared-libsan "-Wl,-rpath,${MBX_SANITIZER_RUNTIME_DIR}")
  set(MBX_SANITIZER_CONSUMER_FLAGS
    "-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -shared-libsan -Wl,-rpath,${MBX_SANITIZER_RUNTIME_DIR}")
else()
  # gcc's runtimes are shared libraries already: an uninstrumented program
  # (python3) loads them first by LD_PRELOAD.
  execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=libasan.so
    OUTPUT_VARIABLE _mbx_libasan OUTPUT_STRIP_TRAILING_WHITESPACE)
  execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=libubsan.so
    OUTPUT_VARIABLE _mbx_libubsan OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(IS_ABSOLUTE "${_mbx_libasan}" AND EXISTS "${_mbx_libasan}" AND EXISTS "${_mbx_libubsan}")
    set(MBX_SANITIZER_PRELOAD "${_mbx_libasan}:${_mbx_libubsan}")
  endif()
  set(MBX_SANITIZER_CONSUMER_FLAGS "-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer")
endif()
