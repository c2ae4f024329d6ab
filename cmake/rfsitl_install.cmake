# Install rules: `cmake --install build/<flavour> [--prefix P]` or the Debian
# packages (cmake/rfsitl_package.cmake). Paths are GNUInstallDirs' and relative
# to the prefix, so an installed tree can be moved: the program finds its
# library through a $ORIGIN run path and its plugins and scenarios relative to
# itself (apps/rfsitl/installed_paths.cpp).
#
# Components (one Debian package each, named in rfsitl_package.cmake):
#   program  rfsitl, librfsitl.so.<major>, scenarios, examples, man pages,
#            bash completion, the (empty) plugin folder
#   dev      the headers, librfsitl.so and the CMake package a plugin author
#            uses (find_package(rfsitl), rfsitl_add_plugin())
#   soapy    the SoapySDR module (src/soapy/CMakeLists.txt)
include(CMakePackageConfigHelpers)

# <prefix>/bin -> <prefix>/<libdir>; a system prefix needs no run path, but the
# same binary works from any prefix with it.
file(RELATIVE_PATH RFSITL_BIN_TO_LIB ${CMAKE_INSTALL_FULL_BINDIR} ${CMAKE_INSTALL_FULL_LIBDIR})
set_target_properties(rfsitl PROPERTIES INSTALL_RPATH "$ORIGIN/${RFSITL_BIN_TO_LIB}")

install(TARGETS rfsitl RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT program)
install(TARGETS rfsitl_library EXPORT rfsitl-targets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT program
    NAMELINK_COMPONENT dev)
# The plugin folder an installed rfsitl loads from, empty until a plugin goes there.
install(DIRECTORY DESTINATION ${RFSITL_PLUGIN_SUBDIR} COMPONENT program)

# What `rfsitl run <name>` finds by name, and the GNU Radio examples. The
# scenarios' relative files (traces/, patterns/) keep their places.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenarios DESTINATION ${RFSITL_DATA_SUBDIR}
  COMPONENT program)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples DESTINATION ${RFSITL_DATA_SUBDIR}
  COMPONENT program PATTERN "*.py" PERMISSIONS OWNER_READ OWNER_WRITE GROUP_READ WORLD_READ)

# The development files: the public headers, the generated version.hpp, and
# the CMake package.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/rfsitl ${PROJECT_BINARY_DIR}/include/rfsitl
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT dev)
set(RFSITL_CMAKE_SUBDIR ${CMAKE_INSTALL_LIBDIR}/cmake/rfsitl)
install(EXPORT rfsitl-targets NAMESPACE rfsitl:: DESTINATION ${RFSITL_CMAKE_SUBDIR}
  COMPONENT dev)
# A plugin built for a sanitized rfsitl must be sanitized too (the ABI tag
# says so); an ordinary build adds nothing.
set(RFSITL_PLUGIN_ABI_OPTIONS "")
if(RFSITL_SANITIZE)
  set(RFSITL_PLUGIN_ABI_OPTIONS -fsanitize=address,undefined)
endif()
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/rfsitl-config.cmake.in
  ${PROJECT_BINARY_DIR}/install/rfsitl-config.cmake
  INSTALL_DESTINATION ${RFSITL_CMAKE_SUBDIR}
  PATH_VARS RFSITL_PLUGIN_SUBDIR)
# A plugin must be built against the very version that loads it (its ABI tag
# names the version), hence an exact match when a version is asked for.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/install/rfsitl-config-version.cmake
  COMPATIBILITY ExactVersion)
install(FILES ${PROJECT_BINARY_DIR}/install/rfsitl-config.cmake
  ${PROJECT_BINARY_DIR}/install/rfsitl-config-version.cmake
  ${PROJECT_SOURCE_DIR}/cmake/rfsitl-plugin.cmake
  DESTINATION ${RFSITL_CMAKE_SUBDIR} COMPONENT dev)
