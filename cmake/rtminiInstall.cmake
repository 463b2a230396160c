# Install rules and the package config for find_package(rtmini). Included last from the
# top-level CMakeLists.txt, so every target it names is already defined.
#
#   cmake --install build --prefix P   installs
#     P/lib/librtmini_{common,host}.a, P/include/rtmini/...     the library (rtmini::common, rtmini::host)
#     P/bin/{bake,sketchtrace,rtmini-ao,rtmini-gen-inputs,...}  the programs
#     P/share/rtmini/inputs/...                                  bundled scenes and meshes
#     P/lib/cmake/rtmini/rtmini{Config,ConfigVersion,Targets}.cmake
# The export names no absolute path: include dirs are relative to the prefix, and dependencies
# (Kokkos, MPI, HDF5, CLI11, ...) are imported targets that rtminiConfig.cmake finds again, so
# the prefix can be moved or packaged.
include(CMakePackageConfigHelpers)
set(RTMINI_INSTALL_INPUTSDIR ${CMAKE_INSTALL_DATADIR}/rtmini/inputs)
set(RTMINI_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/rtmini
    CACHE STRING "Where rtminiConfig.cmake is installed, relative to the prefix")

install(TARGETS rtmini_host rtmini_common EXPORT rtminiTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/common/include/rtmini DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})

# Programs: those this configuration builds (the optional ones exist only when enabled).
set(_rtmini_programs bake sketchtrace sketchtrace-post rtmini-ao rtmini-gen-inputs rtmini-bvh-bench
                     rtmini-bake-lookup-bench)
foreach(program ${_rtmini_programs})
  if(TARGET ${program})
    install(TARGETS ${program} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  endif()
endforeach()
# Scenes name their meshes relative to themselves (../meshes/spot.obj), so the tree works from
# any prefix. The generators' sources and build files stay behind.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/inputs/ DESTINATION ${RTMINI_INSTALL_INPUTSDIR}
        PATTERN "CMakeLists.txt" EXCLUDE PATTERN "*.cpp" EXCLUDE)

install(EXPORT rtminiTargets NAMESPACE rtmini:: DESTINATION ${RTMINI_INSTALL_CMAKEDIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/rtminiConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/rtminiConfig.cmake
                              INSTALL_DESTINATION ${RTMINI_INSTALL_CMAKEDIR}
                              PATH_VARS RTMINI_INSTALL_INPUTSDIR)
# 0.x: a minor release may change the interface, so 0.1 accepts 0.1.* only.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/rtminiConfigVersion.cmake
                                  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/rtminiConfig.cmake ${PROJECT_BINARY_DIR}/rtminiConfigVersion.cmake
        DESTINATION ${RTMINI_INSTALL_CMAKEDIR})
