# `cmake --install build --prefix P`: octrace as a CMake package (docs/PACKAGE.md). Under P:
#   include/octrace/certify.h            the façade (octrace::api): #include <octrace/certify.h>
#   include/octrace/{core,cpu_ref,gpu,backends,validation}/...h
#                                        the libraries' headers, in their folders, so that their
#                                        own #include "core/scene/scene.h" resolve (include dir
#                                        include/octrace, octrace_core's INSTALL_INTERFACE)
#   lib/liboctrace_*.a                  the static libraries, exported as octrace::NAME
#   lib/cmake/octrace/octraceConfig.cmake (+ Version, Targets): find_package(octrace)
#   bin/octrace                          the command line
# Nothing of apps/, teach/, bench/ or tests/ is installed, so the package needs neither CLI11,
# GoogleTest nor the npm packages; only the libraries' own dependencies are found again by
# octraceConfig.cmake (cmake/octraceConfig.cmake.in).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# The exported targets, octrace_NAME as octrace::NAME (octrace::core, ..., octrace::api).
set(OCT_PACKAGE_TARGETS octrace_flags octrace_core octrace_cpu octrace_backends
                        octrace_validation_exact octrace_validation octrace_api)
if(TARGET octrace_gpu)
  list(APPEND OCT_PACKAGE_TARGETS octrace_gpu)
endif()
foreach(target IN LISTS OCT_PACKAGE_TARGETS)
  string(REGEX REPLACE "^octrace_" "" name ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
endforeach()

set(OCT_CMAKE_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/octrace)
install(TARGETS ${OCT_PACKAGE_TARGETS} EXPORT octraceTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
# The installed binary finds the libraries it was linked with outside the system's paths
# (CUDA's runtime under /usr/local/cuda) as the build tree's does.
set_target_properties(octrace PROPERTIES INSTALL_RPATH_USE_LINK_PATH ON)
install(TARGETS octrace RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

# Headers: "include" as the targets' INSTALL_INTERFACE spells it (the top CMakeLists.txt), not
# CMAKE_INSTALL_INCLUDEDIR, so that a changed include dir cannot part headers and interface.
# gpu/ holds .cu and .cpp beside its headers: only the .h go.
foreach(folder core cpu_ref gpu backends validation)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${folder} DESTINATION include/octrace
          FILES_MATCHING PATTERN "*.h")
endforeach()
install(FILES ${PROJECT_SOURCE_DIR}/api/octrace/certify.h DESTINATION include/octrace)

# The config: the dependencies of the exported link interfaces, then the targets. With CUDA
# it also names the toolkit octrace was compiled with, whose runtime its kernels need.
set(OCT_PACKAGE_CUDA ${OCT_HAVE_CUDA})
set(OCT_PACKAGE_CUDA_ROOT "")
if(OCT_HAVE_CUDA)
  get_filename_component(OCT_PACKAGE_CUDA_ROOT ${CUDAToolkit_BIN_DIR} DIRECTORY)
endif()
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/octraceConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/package/octraceConfig.cmake
                              INSTALL_DESTINATION ${OCT_CMAKE_INSTALL_DIR})
# 0.x: any 0.y >= the version asked for is accepted, as with 1.x; the façade (api/) is the part
# that keeps its signatures.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/package/octraceConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMajorVersion)
install(EXPORT octraceTargets NAMESPACE octrace:: DESTINATION ${OCT_CMAKE_INSTALL_DIR})
install(FILES ${PROJECT_BINARY_DIR}/package/octraceConfig.cmake
              ${PROJECT_BINARY_DIR}/package/octraceConfigVersion.cmake
        DESTINATION ${OCT_CMAKE_INSTALL_DIR})
