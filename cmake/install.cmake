# `cmake --install`: the public headers, libcorebox.so, a CMake package (coreboxConfig.cmake with the
# imported target corebox::corebox, and its version file) and a pkg-config file. A program then uses
# corebox with find_package(corebox) or `pkg-config --cflags --libs corebox`; nothing of the build tree
# (internal headers, static libraries, CUDA or toml++ headers) is needed, since the API hides them.
include(CMakePackageConfigHelpers)

install(TARGETS corebox_shared EXPORT coreboxTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/corebox DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.h")

set(COREBOX_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/corebox)
install(EXPORT coreboxTargets NAMESPACE corebox:: DESTINATION ${COREBOX_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/coreboxConfig.cmake.in ${PROJECT_BINARY_DIR}/coreboxConfig.cmake
                              INSTALL_DESTINATION ${COREBOX_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/coreboxConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/coreboxConfig.cmake ${PROJECT_BINARY_DIR}/coreboxConfigVersion.cmake DESTINATION ${COREBOX_CMAKE_DIR})

configure_file(${PROJECT_SOURCE_DIR}/cmake/corebox.pc.in ${PROJECT_BINARY_DIR}/corebox.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/corebox.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
