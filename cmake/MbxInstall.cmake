# Installing the SDK and packaging it (docs/install.md): the C header, libmbx
# (soname libmbx.so.0), libmbx_files (the PMXML + VRML file host's C face),
# the `mbx` CLI, an exported CMake package (find_package(mbx 0.1), target
# mbx::mbx), an mbx.pc for pkg-config, the Python package, and a CPack
# Debian package.
#
# libmbx links its internal static libraries (mbx_core, mbx_sim,
# mbx_calibration, ...) PRIVATE and exports only mbx_* symbols, so none of
# them, nor their third-party headers, appear in what a consumer links.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(MBX_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/mbx CACHE STRING
  "Where mbxConfig.cmake goes, relative to the prefix")
# Debian's python3 looks in /usr/lib/python3/dist-packages, the path the .deb
# installs to; other prefixes need PYTHONPATH (docs/python.md).
set(MBX_INSTALL_PYTHONDIR lib/python3/dist-packages CACHE STRING
  "Where the Python package mbx goes, relative to the prefix")

# The installed CLI finds libmbx beside it, wherever the prefix is.
file(RELATIVE_PATH _mbx_bin_to_lib /${CMAKE_INSTALL_BINDIR} /${CMAKE_INSTALL_LIBDIR})
set_target_properties(mbx_cli PROPERTIES INSTALL_RPATH "$ORIGIN/${_mbx_bin_to_lib}")
set_target_properties(mbx_files PROPERTIES EXPORT_NAME files)

install(TARGETS mbx mbx_files EXPORT mbxTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(FILES ${PROJECT_SOURCE_DIR}/sdk/include/mbx/mbx.h
              ${PROJECT_SOURCE_DIR}/host_adapters/files_capi/include/mbx/mbx_files.h
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/mbx)
install(TARGETS mbx_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

install(EXPORT mbxTargets NAMESPACE mbx:: FILE mbxTargets.cmake DESTINATION ${MBX_INSTALL_CMAKEDIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/mbxConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/mbxConfig.cmake INSTALL_DESTINATION ${MBX_INSTALL_CMAKEDIR})
# 0.x: a minor release may break the API (find_package(mbx 0.1) accepts 0.1.*
# only); from 1.0 on, SameMajorVersion.
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/mbxConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/mbxConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/mbxConfigVersion.cmake
  DESTINATION ${MBX_INSTALL_CMAKEDIR})

# pkg-config: paths relative to the .pc file, so a prefix chosen at install
# time (cmake --install --prefix, DESTDIR, the .deb) still resolves.
file(RELATIVE_PATH _mbx_pc_to_prefix /${CMAKE_INSTALL_LIBDIR}/pkgconfig /)
string(REGEX REPLACE "/$" "" _mbx_pc_to_prefix "${_mbx_pc_to_prefix}")
set(MBX_PC_PREFIX "\${pcfiledir}/${_mbx_pc_to_prefix}")
configure_file(${CMAKE_CURRENT_LIST_DIR}/mbx.pc.in ${CMAKE_CURRENT_BINARY_DIR}/mbx.pc @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/mbx.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# Python package: pure Python over ctypes; _paths.py tells it where libmbx
# lies relative to itself once installed.
file(RELATIVE_PATH _mbx_py_to_lib /${MBX_INSTALL_PYTHONDIR}/mbx /${CMAKE_INSTALL_LIBDIR})
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/python_paths.py
  "# Written by cmake/MbxInstall.cmake at configure time.\n"
  "LIBRARY_DIR_FROM_PACKAGE = \"${_mbx_py_to_lib}\"\n")
install(DIRECTORY ${PROJECT_SOURCE_DIR}/python/mbx DESTINATION ${MBX_INSTALL_PYTHONDIR}
  FILES_MATCHING PATTERN "*.py" PATTERN "__pycache__" EXCLUDE)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/python_paths.py DESTINATION ${MBX_INSTALL_PYTHONDIR}/mbx
  RENAME _paths.py)

# Debian package: `cpack -G DEB` in the build folder (docs/install.md).
set(CPACK_PACKAGE_NAME mbx)
set(CPACK_PACKAGE_VENDOR "mbx")
set(CPACK_PACKAGE_CONTACT "mbx maintainers <mbx@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "CAD assembly to multibody mechanism SDK (C API, CLI, Python)")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
# Debug info stays in the build tree; the package ships what runs.
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
# Depends: what dpkg-shlibdeps finds for libmbx, libmbx_files and the CLI
# (libassimp, libsundials-cvode, libceres, libpugixml, libstdc++, ...), not a
# hand-kept list that drifts from what the binaries link.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON)
# The Python package is optional for C hosts.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "python3, python3-numpy")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "python3-matplotlib")
include(CPack)
