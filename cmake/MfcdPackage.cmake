# The CMake package config that `cmake --install` writes next to the libraries, so that
# another CMake project finds them with find_package(mfcd) (doc/package.md):
#   <prefix>/<libdir>/cmake/mfcd/mfcdConfig.cmake          finds HDF5, LAPACK and OpenMP again
#   <prefix>/<libdir>/cmake/mfcd/mfcdConfigVersion.cmake   0.1.x satisfies find_package(mfcd 0.1)
#   <prefix>/<libdir>/cmake/mfcd/mfcdTargets*.cmake        mfcd::mfcd_solid, ..., mfcd::mfcd
#   <prefix>/<libdir>/cmake/mfcd/MfcdFindGmsh.cmake        finds libgmsh (a build with gmsh)
# Every path in them is relative to the file's own place: the prefix can be moved.
include(CMakePackageConfigHelpers)

install(EXPORT mfcdTargets NAMESPACE mfcd:: DESTINATION ${MFCD_INSTALL_CMAKEDIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/mfcdConfig.cmake.in
  ${PROJECT_BINARY_DIR}/mfcdConfig.cmake
  INSTALL_DESTINATION ${MFCD_INSTALL_CMAKEDIR}
  PATH_VARS MFCD_INSTALL_MODULEDIR CMAKE_INSTALL_BINDIR)
# Before 1.0 a minor version may change the modules' interfaces: 0.1.x answers only 0.1.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/mfcdConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
# MfcdFindGmsh.cmake: with gmsh built in, the config finds libgmsh again through it
install(FILES ${PROJECT_BINARY_DIR}/mfcdConfig.cmake ${PROJECT_BINARY_DIR}/mfcdConfigVersion.cmake
  ${PROJECT_SOURCE_DIR}/cmake/MfcdFindGmsh.cmake
  DESTINATION ${MFCD_INSTALL_CMAKEDIR})
