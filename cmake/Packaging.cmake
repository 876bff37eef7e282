# Debian packages with CPack (included by cmake/Install.cmake):
#
#   cmake -S . -B build/pkg -DCMAKE_INSTALL_PREFIX=/usr
#   cmake --build build/pkg -j2 && (cd build/pkg && cpack -G DEB)
#
# gives libsh2000, libsh2000-dev, sh2000-tools and sh2000-dkms, version
# PROJECT_VERSION-SH2000_DEB_RELEASE. Debian packages live in /usr: cpack
# refuses another prefix (see cmake/CPackOptions.cmake.in).

set(SH2000_DEB_RELEASE 1 CACHE STRING "Debian revision of the packages")
set(SH2000_DEB_MAINTAINER "SH-2000 developers <sh2000@localhost>" CACHE STRING
  "Maintainer field of the Debian packages")
set(_debver ${PROJECT_VERSION}-${SH2000_DEB_RELEASE})

set(CPACK_PACKAGE_NAME sh2000)
set(CPACK_PACKAGE_VENDOR "SH-2000 project")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "${SH2000_DEB_MAINTAINER}")
set(CPACK_PACKAGING_INSTALL_PREFIX ${CMAKE_INSTALL_PREFIX})
set(CPACK_GENERATOR DEB)
set(CPACK_SOURCE_GENERATOR TXZ)
set(CPACK_SOURCE_IGNORE_FILES "/\\\\.git/" "/build" "/\\\\.cache/")
set(CPACK_PACKAGE_DIRECTORY ${PROJECT_BINARY_DIR}/packages)
set(CPACK_PROJECT_CONFIG_FILE ${PROJECT_BINARY_DIR}/CPackOptions.cmake)
configure_file(${CMAKE_CURRENT_LIST_DIR}/CPackOptions.cmake.in
  ${PROJECT_BINARY_DIR}/CPackOptions.cmake @ONLY)

# Shipped binaries are stripped (no debug info, no build paths), man pages
# gzipped.
set(CPACK_STRIP_FILES ON)
# copyright, changelog.Debian.gz and gzipped man pages (cmake/debian/prebuild.cmake)
set(CPACK_PRE_BUILD_SCRIPTS ${CMAKE_CURRENT_LIST_DIR}/debian/prebuild.cmake)
set(CPACK_SH2000_DEBIAN_DIR ${CMAKE_CURRENT_LIST_DIR}/debian)
# The changelog's date: now, or SOURCE_DATE_EPOCH for a reproducible build.
string(TIMESTAMP CPACK_SH2000_DATE "%a, %d %b %Y %H:%M:%S +0000" UTC)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL runtime dev dkms)
if(SH2000_TOOLS_INSTALLED)
  list(APPEND CPACK_COMPONENTS_ALL tools)
endif()

set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_RELEASE ${SH2000_DEB_RELEASE})
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${SH2000_DEB_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
# dpkg-shlibdeps fills in libc6, libjson-c5, ...; libsh2000's own shlibs
# file (below) is what other packages' shlibdeps use for libsh2000.so.0.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)

# libsh2000: libsh2000.so.0. ABI rule (docs/install.md): compatible changes
# keep the SONAME and need ">= the version that added them"; an incompatible
# change bumps the SONAME (and Debian's rule would then rename the package).
set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME libsh2000)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SECTION libs)
set(CPACK_DEBIAN_RUNTIME_DESCRIPTION
"SH-2000TH motion card library (runtime)
libsh2000 drives the SH-2000TH ISA motion controller through the sh2000
kernel driver (/dev/sh2000-N), direct port I/O or the simulated card
(sim, sim:NAME). This package holds the shared library.")
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SUGGESTS "sh2000-dkms, sh2000-tools")
# (CPack writes a shlibs file for every package with a SONAME: only this one.)
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON)
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS_POLICY ">=")
# ldconfig by trigger, as Debian's library packages do (CPack's own
# postinst/postrm call it too).
set(CPACK_DEBIAN_RUNTIME_PACKAGE_CONTROL_EXTRA ${CMAKE_CURRENT_LIST_DIR}/debian/libsh2000/triggers)

set(CPACK_DEBIAN_DEV_PACKAGE_NAME libsh2000-dev)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_DEV_DESCRIPTION
"SH-2000TH motion card library (development files)
Headers (<sh2000/sh2000.h>, <sh2000/path.h>, <sh2000/sim.h>, the protocol
and the driver's ioctl ABI), the static library, libsh2000.so, sh2000.pc
for pkg-config and the CMake package (find_package(sh2000) gives
sh2000::sh2000 and sh2000::sh2000_static).")
# The static library needs libm and pthreads (in libc6-dev); the ioctl
# header includes <linux/ioctl.h>.
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS "libsh2000 (= ${_debver}), libc6-dev | libc-dev, linux-libc-dev")

set(CPACK_DEBIAN_TOOLS_PACKAGE_NAME sh2000-tools)
set(CPACK_DEBIAN_TOOLS_PACKAGE_SECTION utils)
set(CPACK_DEBIAN_TOOLS_DESCRIPTION
"SH-2000TH motion card tools
sh2000ctl (status, commands, parameters), sh2000-sim (serves a simulated
card for sim:NAME) and sh2000-upload (G-code, canonical, CSV and NURBS
programs to the card), with their man pages.")
# The tools link libsh2000.a today; should they load libsh2000.so, they
# need exactly this build of it (its internals may change in a release).
if(SH2000_TOOLS_NEED_LIB)
  set(CPACK_DEBIAN_TOOLS_PACKAGE_DEPENDS "libsh2000 (= ${_debver})")
endif()
set(CPACK_DEBIAN_TOOLS_PACKAGE_RECOMMENDS "sh2000-dkms")

# sh2000-dkms: sources in /usr/src/sh2000-<ver>/, built by DKMS for each
# kernel; the udev rule; the postinst adds the sh2000 group.
set(CPACK_DEBIAN_DKMS_PACKAGE_NAME sh2000-dkms)
set(CPACK_DEBIAN_DKMS_PACKAGE_SECTION kernel)
set(CPACK_DEBIAN_DKMS_PACKAGE_ARCHITECTURE all)
set(CPACK_DEBIAN_DKMS_PACKAGE_SHLIBDEPS OFF)
set(CPACK_DEBIAN_DKMS_DESCRIPTION
"SH-2000TH motion card kernel driver (DKMS sources)
The sh2000 module (/dev/sh2000-N for each card listed in io=) and
sh2000_sim (simulated cards), rebuilt by DKMS for every installed kernel
that has its headers. The udev rule gives the nodes to group sh2000,
which the package creates.")
set(CPACK_DEBIAN_DKMS_PACKAGE_DEPENDS "dkms (>= 2.1.0.0), passwd")
set(CPACK_DEBIAN_DKMS_PACKAGE_RECOMMENDS "linux-headers-amd64 | linux-headers")
foreach(s postinst prerm)
  configure_file(${CMAKE_CURRENT_LIST_DIR}/debian/dkms-${s}.in
    ${PROJECT_BINARY_DIR}/debian/sh2000-dkms/${s} @ONLY)
endforeach()
set(CPACK_DEBIAN_DKMS_PACKAGE_CONTROL_EXTRA
  ${PROJECT_BINARY_DIR}/debian/sh2000-dkms/postinst
  ${PROJECT_BINARY_DIR}/debian/sh2000-dkms/prerm)

include(CPack)

cpack_add_component(runtime DISPLAY_NAME "libsh2000")
cpack_add_component(dev DISPLAY_NAME "libsh2000-dev" DEPENDS runtime)
cpack_add_component(tools DISPLAY_NAME "sh2000-tools" DEPENDS runtime)
cpack_add_component(dkms DISPLAY_NAME "sh2000-dkms")
