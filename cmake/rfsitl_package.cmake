# Debian packages by CPack: `cpack -G DEB` in a build tree configured with
# -DCMAKE_INSTALL_PREFIX=/usr (scripts/package.sh), one package per install
# component, as SoapySDR's and GNU Radio's users find them in Debian:
#   rfsitl                        the program, librfsitl, scenarios, examples,
#                                 man pages, bash completion
#   librfsitl-dev                 headers and the CMake package, for plugins
#   soapysdr<ABI>-module-rfsitl   the SoapySDR module (Debian's own modules are
#                                 named so, and provide soapysdr<ABI>-module)
#   gr-rfsitl                     the GNU Radio blocks (with -DRFSITL_BUILD_GR=ON)
# Depends come from the binaries' shared libraries (dpkg-shlibdeps).
# The packages install under the configured prefix; Debian's SoapySDR looks
# for modules only in /usr/lib/<multiarch> (and /usr/local/lib...), which is
# where GNUInstallDirs puts <libdir> for the prefix /usr.
if(NOT CMAKE_INSTALL_PREFIX STREQUAL "/usr")
  message(STATUS "Packages install into ${CMAKE_INSTALL_PREFIX}: Debian packages are built "
                 "with -DCMAKE_INSTALL_PREFIX=/usr (scripts/package.sh)")
endif()
set(RFSITL_PACKAGE_CONTACT
  "rfsitl maintainers <maintainers@users.noreply.h-seed-b88b7151.example>"
  CACHE STRING "Maintainer field of the Debian packages")

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME rfsitl)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "${RFSITL_PACKAGE_CONTACT}")
set(CPACK_PACKAGING_INSTALL_PREFIX ${CMAKE_INSTALL_PREFIX})
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_SECTION hamradio)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
# Binaries are shipped stripped, as Debian's policy wants (no debug packages).
set(CPACK_STRIP_FILES ON)
# librfsitl's interfaces may change with any 0.x release: a program or plugin
# built against it wants this very version (shlibs "=").
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON)
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS_POLICY "=")
# A package with a public shared library lets dpkg run ldconfig once, by
# trigger (Debian policy 8.1.1; lintian: lacks-ldconfig-trigger). CPack's own
# postinst/postrm still call ldconfig too, which is redundant but harmless.
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(CPACK_DEBIAN_PROGRAM_PACKAGE_CONTROL_EXTRA ${PROJECT_SOURCE_DIR}/cmake/debian/triggers)
set(CPACK_DEBIAN_GR_PACKAGE_CONTROL_EXTRA ${PROJECT_SOURCE_DIR}/cmake/debian/triggers)

set(CPACK_DEBIAN_PROGRAM_PACKAGE_NAME rfsitl)
set(CPACK_COMPONENT_PROGRAM_DESCRIPTION "software-in-the-loop RF channel emulator
Emulates the radio links between robots (UAVs, ground stations) in real or
virtual time: PHYs, MACs and a channel of path loss, shadowing, fading and
multipath between the nodes' transceivers. Includes librfsitl, the engine that
out-of-tree plugins link, scenarios and examples (/usr/share/rfsitl).")

set(CPACK_DEBIAN_DEV_PACKAGE_NAME librfsitl-dev)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS
  "rfsitl (= ${PROJECT_VERSION}), nlohmann-json3-dev, libboost-dev")
set(CPACK_COMPONENT_DEV_DESCRIPTION "rfsitl plugin development files
Headers and the CMake package (find_package(rfsitl), rfsitl_add_plugin()) to
build PHYs, MACs, channel stages, position sources and mobility models out of
tree, loaded by rfsitl from its plugin folder or RFSITL_PLUGIN_PATH.")

set(RFSITL_PACKAGES rfsitl librfsitl-dev)
set(CPACK_COMPONENTS_ALL program dev)
if(TARGET rfsitl_soapy)
  get_property(RFSITL_SOAPY_ABI GLOBAL PROPERTY RFSITL_SOAPY_ABI_VERSION)
  set(RFSITL_SOAPY_PACKAGE soapysdr${RFSITL_SOAPY_ABI}-module-rfsitl)
  set(CPACK_DEBIAN_SOAPY_PACKAGE_NAME ${RFSITL_SOAPY_PACKAGE})
  set(CPACK_DEBIAN_SOAPY_PACKAGE_PROVIDES soapysdr${RFSITL_SOAPY_ABI}-module)
  set(CPACK_COMPONENT_SOAPY_DESCRIPTION "rfsitl emulator nodes for SoapySDR (module)
The SoapySDR module driver=rfsitl: any SoapySDR application (GQRX, SDR++,
GNU Radio's soapy blocks, python3-soapysdr) becomes a node of a running rfsitl
emulator, sending and receiving its samples through the emulated channel.")
  list(APPEND RFSITL_PACKAGES ${RFSITL_SOAPY_PACKAGE})
  list(APPEND CPACK_COMPONENTS_ALL soapy)
endif()

if(TARGET rfsitl_pymodule)
  set(CPACK_DEBIAN_PYTHON_PACKAGE_NAME python3-rfsitl)
  set(CPACK_DEBIAN_PYTHON_PACKAGE_SECTION python)
  # The interpreter and NumPy, which no shared library of theirs names;
  # pandas is optional (tables are dicts of arrays without it).
  # Its one library beyond the C++ runtime is librfsitl, in the rfsitl package,
  # which dpkg-shlibdeps cannot see from this one: the dependencies are named.
  set(CPACK_DEBIAN_PYTHON_PACKAGE_SHLIBDEPS OFF)
  set(CPACK_DEBIAN_PYTHON_PACKAGE_DEPENDS
    "rfsitl (= ${PROJECT_VERSION}), ${RFSITL_PYTHON_DEPENDS}, python3-numpy, python3-yaml, libc6, libstdc++6, libgcc-s1")
  set(CPACK_DEBIAN_PYTHON_PACKAGE_SUGGESTS "python3-pandas, python3-matplotlib, python3-scipy")
  set(CPACK_COMPONENT_PYTHON_DESCRIPTION "rfsitl from Python (module)
The Python module rfsitl: scenarios from files or dicts, runs in virtual time
advanced step by step (move nodes, send frames, read counters, links and I/Q
as NumPy arrays or pandas tables), and real-time runs with their ports.")
  list(APPEND RFSITL_PACKAGES python3-rfsitl)
  list(APPEND CPACK_COMPONENTS_ALL python)
endif()

if(RFSITL_BUILD_GR)
  set(CPACK_DEBIAN_GR_PACKAGE_NAME gr-rfsitl)
  # The Python bindings need the interpreter and GNU Radio's own Python
  # package, which no shared library of theirs names.
  set(CPACK_DEBIAN_GR_PACKAGE_DEPENDS "python3, gnuradio (>= 3.10)")
  set(CPACK_COMPONENT_GR_DESCRIPTION "rfsitl emulator nodes for GNU Radio (blocks)
GNU Radio 3.10 blocks that make a flowgraph a node of a running rfsitl
emulator: Emulator Source and Sink in place of the SDR's, and UB-ANC framing;
Python module gnuradio.rfsitl and GRC blocks (category rfsitl).")
  list(APPEND RFSITL_PACKAGES gr-rfsitl)
  list(APPEND CPACK_COMPONENTS_ALL gr)
endif()

# Every package carries its copyright file and changelog where Debian's policy
# wants them (/usr/share/doc/<package>/); a version without a Debian revision
# makes these native packages, whose changelog is changelog.gz.
string(TIMESTAMP RFSITL_CHANGELOG_DATE "%a, %d %b %Y %H:%M:%S +0000" UTC)
set(RFSITL_CHANGELOG_DIR ${PROJECT_BINARY_DIR}/package)
set(RFSITL_GR_PACKAGE "")
if(RFSITL_BUILD_GR)
  set(RFSITL_GR_PACKAGE gr-rfsitl)
endif()
set(RFSITL_PYTHON_PACKAGE "")
if(TARGET rfsitl_pymodule)
  set(RFSITL_PYTHON_PACKAGE python3-rfsitl)
endif()
foreach(component_package program:rfsitl dev:librfsitl-dev soapy:${RFSITL_SOAPY_PACKAGE}
        gr:${RFSITL_GR_PACKAGE} python:${RFSITL_PYTHON_PACKAGE})
  string(REPLACE ":" ";" pair "${component_package}")
  list(GET pair 0 component)
  list(LENGTH pair n)
  if(n LESS 2)
    continue()
  endif()
  list(GET pair 1 package)
  configure_file(${PROJECT_SOURCE_DIR}/cmake/debian/changelog.in
    ${RFSITL_CHANGELOG_DIR}/${package}/changelog @ONLY)
  if(RFSITL_GZIP)
    execute_process(COMMAND ${RFSITL_GZIP} -9nf ${RFSITL_CHANGELOG_DIR}/${package}/changelog)
    install(FILES ${RFSITL_CHANGELOG_DIR}/${package}/changelog.gz
      DESTINATION ${CMAKE_INSTALL_DOCDIR}/../${package} COMPONENT ${component})
  endif()
  install(FILES ${PROJECT_SOURCE_DIR}/cmake/debian/copyright
    DESTINATION ${CMAKE_INSTALL_DOCDIR}/../${package} COMPONENT ${component})
endforeach()
include(CPack)
