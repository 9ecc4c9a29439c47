# Install rules (the libraries, their headers, the `tricell` command) and package configuration,
# so that find_package(tricell CONFIG), add_subdirectory() and FetchContent all work. The
# build-tree export is always generated.
# tricell is BSD-3-Clause: the install puts LICENSE into the documentation directory
# (share/doc/tricell), and the package and pkg-config files name the licence.
include(CMakePackageConfigHelpers)
include(GNUInstallDirs)

set(TRICELL_CONFIG_DIR "${CMAKE_INSTALL_LIBDIR}/cmake/tricell")
set(TRICELL_EXPORTED_TARGETS tricell_core)
if(TARGET tricell_io)
    list(APPEND TRICELL_EXPORTED_TARGETS tricell_io)
endif()
if(TARGET tricell_mpi)
    list(APPEND TRICELL_EXPORTED_TARGETS tricell_mpi)
endif()
if(TARGET tricell_c)
    list(APPEND TRICELL_EXPORTED_TARGETS tricell_c)
endif()
if(TARGET tricell_fortran)
    list(APPEND TRICELL_EXPORTED_TARGETS tricell_fortran)
endif()

configure_package_config_file(
    "${CMAKE_CURRENT_LIST_DIR}/tricell-config.cmake.in"
    "${PROJECT_BINARY_DIR}/tricell-config.cmake"
    INSTALL_DESTINATION "${TRICELL_CONFIG_DIR}")
write_basic_package_version_file(
    "${PROJECT_BINARY_DIR}/tricell-config-version.cmake"
    COMPATIBILITY SameMinorVersion)

export(TARGETS ${TRICELL_EXPORTED_TARGETS} NAMESPACE tricell::
    FILE "${PROJECT_BINARY_DIR}/tricell-targets.cmake")

if(TRICELL_INSTALL)
    install(TARGETS ${TRICELL_EXPORTED_TARGETS} EXPORT tricell-targets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
    install(DIRECTORY "${PROJECT_SOURCE_DIR}/include/tricell"
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
    install(FILES "${PROJECT_BINARY_DIR}/include/tricell/export.hpp"
        DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/tricell")
    if(TARGET tricell_c)
        install(FILES "${PROJECT_SOURCE_DIR}/include/tricell.h"
            DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
    endif()
    if(TARGET tricell)
        install(TARGETS tricell RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
    endif()
    if(TARGET tricell_fortran)
        install(DIRECTORY "${PROJECT_BINARY_DIR}/fortran/modules/"
            DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/tricell/fortran")
    endif()
    # pkg-config files for C and Fortran programs built without CMake. They find the prefix
    # from their own place (pcfiledir), so an install with --prefix or DESTDIR stays usable.
    set(pkgconfig_dir "${CMAKE_INSTALL_LIBDIR}/pkgconfig")
    if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}" OR IS_ABSOLUTE "${CMAKE_INSTALL_INCLUDEDIR}")
        message(STATUS "tricell: no pkg-config files, they need a relative CMAKE_INSTALL_LIBDIR "
                       "and CMAKE_INSTALL_INCLUDEDIR (got ${CMAKE_INSTALL_LIBDIR}, "
                       "${CMAKE_INSTALL_INCLUDEDIR})")
    else()
        file(RELATIVE_PATH tricell_pc_to_prefix "/prefix/${pkgconfig_dir}" "/prefix")
        foreach(target_and_file "tricell_c;tricell" "tricell_fortran;tricell-fortran")
            list(GET target_and_file 0 target)
            list(GET target_and_file 1 pc_name)
            if(TARGET ${target})
                configure_file("${CMAKE_CURRENT_LIST_DIR}/${pc_name}.pc.in"
                    "${PROJECT_BINARY_DIR}/${pc_name}.pc" @ONLY)
                install(FILES "${PROJECT_BINARY_DIR}/${pc_name}.pc" DESTINATION "${pkgconfig_dir}")
            endif()
        endforeach()
    endif()
    install(FILES "${PROJECT_SOURCE_DIR}/LICENSE" DESTINATION "${CMAKE_INSTALL_DOCDIR}")
    install(EXPORT tricell-targets NAMESPACE tricell::
        DESTINATION "${TRICELL_CONFIG_DIR}")
    install(FILES
        "${PROJECT_BINARY_DIR}/tricell-config.cmake"
        "${PROJECT_BINARY_DIR}/tricell-config-version.cmake"
        DESTINATION "${TRICELL_CONFIG_DIR}")
endif()
