# SPDX-License-Identifier: Apache-2.0
# Install rules: libraries, headers, CMake package (find_package(codrive)) and pkg-config file.
include(CMakePackageConfigHelpers)
get_property(exported GLOBAL PROPERTY CODRIVE_EXPORTED_TARGETS)
# codrive::sim (simulated drives, docs/codrive-sim.md) is built with the tools; it is exported
# next to the stack but is not part of the codrive::codrive umbrella.
set(exported_sim "")
if(TARGET codrive_sim)
    set(exported_sim codrive_sim)
endif()
install(TARGETS ${exported} ${exported_sim} codrive_umbrella EXPORT codriveTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT codriveTargets NAMESPACE codrive:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/codrive)
configure_package_config_file(cmake/codriveConfig.cmake.in
    ${CMAKE_CURRENT_BINARY_DIR}/codriveConfig.cmake
    INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/codrive)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/codriveConfigVersion.cmake
    COMPATIBILITY SameMajorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/codriveConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/codriveConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/codrive)

# pkg-config: static libraries listed top layer first so the linker resolves downwards. The
# prefix is computed from the .pc file's own place (${pcfiledir}), so the files stay right after
# `cmake --install build --prefix X`, in a DESTDIR staging tree and in the .deb.
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}")
    set(CODRIVE_PC_PREFIX "${CMAKE_INSTALL_PREFIX}")
else()
    file(RELATIVE_PATH pc_up "/p/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/p")
    string(REGEX REPLACE "/$" "" pc_up "${pc_up}")
    set(CODRIVE_PC_PREFIX "\${pcfiledir}/${pc_up}")
endif()
set(CODRIVE_PC_LIBS "")
list(REVERSE exported)
foreach(t IN LISTS exported)
    string(APPEND CODRIVE_PC_LIBS " -l${t}")
endforeach()
configure_file(cmake/codrive.pc.in ${CMAKE_CURRENT_BINARY_DIR}/codrive.pc @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/codrive.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
if(exported_sim)
    configure_file(cmake/codrive-sim.pc.in ${CMAKE_CURRENT_BINARY_DIR}/codrive-sim.pc @ONLY)
    install(FILES ${CMAKE_CURRENT_BINARY_DIR}/codrive-sim.pc
            DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endif()

# A Debian package of the libraries, headers, tools and CMake package: `cpack -G DEB`.
set(CPACK_GENERATOR "DEB")
set(CPACK_PACKAGE_NAME "codrive")
set(CPACK_PACKAGE_VENDOR "codrive")
set(CPACK_PACKAGE_CONTACT "codrive developers <codrive@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "CANopen and EtherCAT master stack for CiA 402 drives")
# One string: two quoted arguments would make a CMake list, and the ';' would reach dpkg.
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libsocketcan-dev, libfmt-dev, libexpected-dev, \
libyaml-cpp-dev, libeigen3-dev, libpugixml-dev")
if(CODRIVE_BUILD_PYTHON)
    # The `codrive` module in /usr/lib/python3/dist-packages is built for this Python version.
    string(APPEND CPACK_DEBIAN_PACKAGE_DEPENDS
           ", python3 (>= ${Python_VERSION_MAJOR}.${Python_VERSION_MINOR}),"
           " python3 (<< ${Python_VERSION_MAJOR}.${Python_VERSION_MINOR}.99)")
endif()
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_PACKAGING_INSTALL_PREFIX "/usr")
include(CPack)
