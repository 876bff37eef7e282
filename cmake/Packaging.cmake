# Debian packages with CPack (included by cmake/Install.cmake):
#
#   cmake -S . -B build/pkg -DCMAKE_INSTALL_PREFIX=/usr
#   cmake --build build/pkg -j2 && (cd build/pkg && cpack -G DEB)
#
# gives libsh2000, libsh2000-motion, libsh2000-sim, their -dev packages,
# sh2000-tools and sh2000-dkms (and sh2000-linuxcnc, python3-sh2000 where
# their build dependencies are installed), version PROJECT_VERSION-SH2000_DEB_RELEASE
# (docs/install.md has the table). Debian packages live in /usr: cpack
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
set(CPACK_COMPONENTS_ALL runtime motion sim dev motion_dev sim_dev dkms)
if(SH2000_TOOLS_INSTALLED)
  list(APPEND CPACK_COMPONENTS_ALL tools)
endif()
# hal_sh2000, when linuxcnc-uspace-dev was there to build it (hal/)
if(SH2000_LINUXCNC_INSTALLED)
  list(APPEND CPACK_COMPONENTS_ALL linuxcnc)
endif()
# python3-sh2000, when python3-dev was there to build the binding (python/)
if(SH2000_PYTHON_INSTALLED)
  list(APPEND CPACK_COMPONENTS_ALL python)
endif()

set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_RELEASE ${SH2000_DEB_RELEASE})
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${SH2000_DEB_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)

# ---- Depends between our own packages: shlibs --------------------------
# dpkg-shlibdeps fills in every package's Depends from the libraries its
# binaries load: libc6, libjson-c5, and ours. For ours it needs what
# Debian's dh_makeshlibs gives it: a shlibs line per library (written here
# once, shipped as each library package's DEBIAN/shlibs so that programs
# built against the installed packages depend right, and handed to this
# build's own dpkg-shlibdeps runs as debian/shlibs.local by
# cmake/debian/prebuild.cmake) and the libraries themselves (the build
# tree's, -l below). CPack's own shlibs generation knows one policy for all
# packages; ours differ:
#   libsh2000, libsh2000-motion: ">=" this version (the ABI rule in
#     docs/install.md: additions keep the SONAME);
#   libsh2000-sim: "=" this version (no ABI promise to applications).
# libsh2000-sim talks to libsh2000 through a private contract (the `sim`
# provider), so its own dependency on libsh2000 is "=" too: the sim
# component's shlibs.local says so.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS ${CMAKE_LIBRARY_OUTPUT_DIRECTORY})
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS OFF)
set(_sh2000_shlibs_dir ${PROJECT_BINARY_DIR}/debian/shlibs)
# _sh2000_shlibs(<out var> <library target> <package> <op>)
function(_sh2000_shlibs out target pkg op)
  get_target_property(name ${target} OUTPUT_NAME)
  get_target_property(sover ${target} SOVERSION)
  set(line "lib${name} ${sover} ${pkg} (${op} ${_debver})")
  file(CONFIGURE OUTPUT ${_sh2000_shlibs_dir}/${pkg}/shlibs CONTENT "${line}\n")
  set(${out} "${line}" PARENT_SCOPE)
endfunction()
_sh2000_shlibs(_l_device sh2000 libsh2000 ">=")
_sh2000_shlibs(_l_motion sh2000_motion libsh2000-motion ">=")
_sh2000_shlibs(_l_sim sh2000_sim libsh2000-sim "=")
string(REPLACE "(>=" "(=" _l_device_exact "${_l_device}")
file(CONFIGURE OUTPUT ${_sh2000_shlibs_dir}/shlibs.local
  CONTENT "${_l_device}\n${_l_motion}\n${_l_sim}\n")
file(CONFIGURE OUTPUT ${_sh2000_shlibs_dir}/sim/shlibs.local
  CONTENT "${_l_device_exact}\n${_l_motion}\n${_l_sim}\n")
set(CPACK_SH2000_SHLIBS_DIR ${_sh2000_shlibs_dir})
# Debian symbols files of the libraries that promise a stable ABI: every
# exported symbol with the version that added it, shipped as DEBIAN/symbols
# (dpkg-shlibdeps of programs built against the installed packages prefers
# them to shlibs) and checked by dpkg-gensymbols -c4 when the packages are
# built (cmake/debian/prebuild.cmake). libsh2000-sim has none: it promises
# no ABI, its shlibs pins the exact version.
foreach(_pkg libsh2000 libsh2000-motion)
  configure_file(${CMAKE_CURRENT_LIST_DIR}/debian/${_pkg}.symbols
    ${_sh2000_shlibs_dir}/${_pkg}/symbols COPYONLY)
endforeach()

# ---- the runtime libraries -----------------------------------------------
# ABI rule (docs/install.md): compatible changes keep the SONAME and need
# ">= the version that added them"; an incompatible change bumps the
# SONAME (and Debian's rule would then rename the package). ldconfig by
# trigger, as Debian's library packages do (CPack's own postinst/postrm
# call it too).
set(_sh2000_ldconfig ${CMAKE_CURRENT_LIST_DIR}/debian/libsh2000/triggers)

set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME libsh2000)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SECTION libs)
set(CPACK_DEBIAN_RUNTIME_DESCRIPTION
"SH-2000TH motion card library (runtime)
libsh2000 drives the SH-2000TH ISA motion controller through the sh2000
kernel driver (/dev/sh2000-N), direct port I/O or a simulated card
(sim, sim:NAME). This package holds the shared library.")
# `sim` loads libsh2000-sim.so.0 (dlopen) for any program that links
# libsh2000: apt installs it by default, a production machine may leave
# it out (then `sim` says to install it). Not Depends: libsh2000-sim
# depends on libsh2000, and real cards need no card model.
set(CPACK_DEBIAN_RUNTIME_PACKAGE_RECOMMENDS "libsh2000-sim")
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SUGGESTS "sh2000-dkms, sh2000-tools")
set(CPACK_DEBIAN_RUNTIME_PACKAGE_CONTROL_EXTRA
  ${_sh2000_shlibs_dir}/libsh2000/shlibs ${_sh2000_shlibs_dir}/libsh2000/symbols
  ${_sh2000_ldconfig})

set(CPACK_DEBIAN_MOTION_PACKAGE_NAME libsh2000-motion)
set(CPACK_DEBIAN_MOTION_PACKAGE_SECTION libs)
set(CPACK_DEBIAN_MOTION_DESCRIPTION
"SH-2000TH motion card library: motion (runtime)
libsh2000-motion plans and runs motion on an SH-2000TH card opened with
libsh2000: geometry, the look-ahead planner, the streaming runner, homing,
soft limits and the program readers (G-code, rs274 canonical output, CSV,
NURBS JSON). This package holds the shared library.")
set(CPACK_DEBIAN_MOTION_PACKAGE_CONTROL_EXTRA
  ${_sh2000_shlibs_dir}/libsh2000-motion/shlibs ${_sh2000_shlibs_dir}/libsh2000-motion/symbols
  ${_sh2000_ldconfig})

set(CPACK_DEBIAN_SIM_PACKAGE_NAME libsh2000-sim)
set(CPACK_DEBIAN_SIM_PACKAGE_SECTION libs)
set(CPACK_DEBIAN_SIM_DESCRIPTION
"SH-2000TH motion card library: simulated card (runtime)
libsh2000-sim is a model of the SH-2000TH card (FPGA, dual-port RAM, DSP
firmware, servo loops, linear-motor plant) with fault injection and a
shared-memory server. libsh2000 loads it for the device string sim; the
sh2000-sim tool serves it for sim:NAME. This package holds the shared
library.")
set(CPACK_DEBIAN_SIM_PACKAGE_CONTROL_EXTRA
  ${_sh2000_shlibs_dir}/libsh2000-sim/shlibs ${_sh2000_ldconfig})

# ---- development packages -------------------------------------------------
# Each -dev package depends on its library of exactly this build and on
# the -dev packages of what its static library and headers need.
set(CPACK_DEBIAN_DEV_PACKAGE_NAME libsh2000-dev)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_DEV_DESCRIPTION
"SH-2000TH motion card library (development files)
Headers of the device API and the protocol (<sh2000/sh2000.h>,
<sh2000/card.h>, <sh2000/comp.h>, <sh2000/sh2000_protocol.h>, <sh2000/bspline.h>) and the
driver's ioctl ABI (<sh2000/uapi/sh2000.h>), libsh2000.a, libsh2000.so,
sh2000.pc for pkg-config and the CMake package: find_package(sh2000) gives
sh2000::sh2000 and sh2000::sh2000_static; its components motion and sim
come with libsh2000-motion-dev and libsh2000-sim-dev.")
# The static library needs libm, libdl and pthreads (in libc6-dev); the
# ioctl header includes <linux/ioctl.h>.
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS "libsh2000 (= ${_debver}), libc6-dev | libc-dev, linux-libc-dev")

set(CPACK_DEBIAN_MOTION_DEV_PACKAGE_NAME libsh2000-motion-dev)
set(CPACK_DEBIAN_MOTION_DEV_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_MOTION_DEV_DESCRIPTION
"SH-2000TH motion card library: motion (development files)
Headers (<sh2000/path.h>, <sh2000/program.h>, <sh2000/run.h>),
libsh2000-motion.a, libsh2000-motion.so, sh2000-motion.pc and the CMake
component: find_package(sh2000 COMPONENTS motion) gives sh2000::motion
and sh2000::motion_static.")
# json-c: libsh2000-motion.a links it (sh2000-motion.pc's Requires.private,
# json-c::json-c in the CMake targets).
set(CPACK_DEBIAN_MOTION_DEV_PACKAGE_DEPENDS
  "libsh2000-motion (= ${_debver}), libsh2000-dev (= ${_debver}), libjson-c-dev")

set(CPACK_DEBIAN_SIM_DEV_PACKAGE_NAME libsh2000-sim-dev)
set(CPACK_DEBIAN_SIM_DEV_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_SIM_DEV_DESCRIPTION
"SH-2000TH motion card library: simulated card (development files)
Headers (<sh2000/sim.h>, <sh2000/sh2000_cardsim.h>), libsh2000-sim.a,
libsh2000-sim.so, sh2000-sim.pc and the CMake component:
find_package(sh2000 COMPONENTS sim) gives sh2000::sim and
sh2000::sim_static.")
set(CPACK_DEBIAN_SIM_DEV_PACKAGE_DEPENDS
  "libsh2000-sim (= ${_debver}), libsh2000-dev (= ${_debver})")

# ---- tools and driver ------------------------------------------------------
set(CPACK_DEBIAN_TOOLS_PACKAGE_NAME sh2000-tools)
set(CPACK_DEBIAN_TOOLS_PACKAGE_SECTION utils)
set(CPACK_DEBIAN_TOOLS_DESCRIPTION
"SH-2000TH motion card tools
sh2000ctl (status, commands, parameters, moves, data gathering),
sh2000-sim (serves a simulated card for sim:NAME), sh2000-upload (G-code,
canonical, CSV and NURBS programs to the card) and sh2000-tune (step test
of a servo loop), with their man pages.")
# Depends from dpkg-shlibdeps: libsh2000 and libsh2000-motion (>=),
# libsh2000-sim (=, sh2000-sim links it, and it makes `-d sim` work).
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

# sh2000-linuxcnc: hal_sh2000 (libsh2000 linked in statically), its man
# page, the sample machine and docs/linuxcnc.md. dpkg-shlibdeps finds libc;
# the module's rtapi_* and hal_* symbols are rtapi_app's: that Depends by
# hand.
set(CPACK_DEBIAN_LINUXCNC_PACKAGE_NAME sh2000-linuxcnc)
set(CPACK_DEBIAN_LINUXCNC_PACKAGE_SECTION misc)
set(CPACK_DEBIAN_LINUXCNC_PACKAGE_DEPENDS "linuxcnc-uspace (>= 2.9.0~pre1)")
set(CPACK_DEBIAN_LINUXCNC_PACKAGE_RECOMMENDS "sh2000-tools")
set(CPACK_DEBIAN_LINUXCNC_PACKAGE_SUGGESTS "sh2000-dkms")
set(CPACK_DEBIAN_LINUXCNC_DESCRIPTION
"SH-2000TH motion cards as LinuxCNC joints (HAL driver)
hal_sh2000 drives SH-2000TH cards from LinuxCNC 2.9 uspace: loadrt
hal_sh2000 device=/dev/sh2000-0 (or sim:NAME for a simulated card), then
sh2000.N.read and sh2000.N.write in the servo thread. The man page
hal_sh2000(9) lists the pins; a sample 3-axis mill on a simulated card is
in /usr/share/doc/sh2000-linuxcnc/examples/sh2000-sim.")

# python3-sh2000: the module sh2000 (python/), in Debian's
# /usr/lib/python3/dist-packages. dpkg-shlibdeps gives libc6, libsh2000
# and libsh2000-motion (>=). The extension is built for one python3 minor:
# the python3 Depends dh_python3 would give (${python3:Depends}) by hand.
# numpy is recommended, not required: only the gather calls need it (their
# records are numpy arrays; push() takes any rows). postinst and
# prerm byte-compile and clean up as dh_python3's snippets do.
if(SH2000_PYTHON_INSTALLED)
  string(REPLACE "." ";" _pyver "${SH2000_PYTHON_VERSION}")
  list(GET _pyver 0 _pymaj)
  list(GET _pyver 1 _pymin)
  math(EXPR _pynext "${_pymin} + 1")
  set(CPACK_DEBIAN_PYTHON_PACKAGE_NAME python3-sh2000)
  set(CPACK_DEBIAN_PYTHON_PACKAGE_SECTION python)
  set(CPACK_DEBIAN_PYTHON_PACKAGE_DEPENDS
    "python3 (>= ${SH2000_PYTHON_VERSION}~), python3 (<< ${_pymaj}.${_pynext})")
  set(CPACK_DEBIAN_PYTHON_PACKAGE_RECOMMENDS "libsh2000-sim, python3-numpy")
  set(CPACK_DEBIAN_PYTHON_PACKAGE_CONTROL_EXTRA
    ${CMAKE_CURRENT_LIST_DIR}/debian/python3-sh2000/postinst
    ${CMAKE_CURRENT_LIST_DIR}/debian/python3-sh2000/prerm)
  set(CPACK_DEBIAN_PYTHON_DESCRIPTION
"SH-2000TH motion card library: Python 3 binding
The module sh2000 drives SH-2000TH cards from Python through libsh2000
and libsh2000-motion: sh2000.open(\"sim\"), status as dataclasses,
parameters by name, commands, coarse points, NC programs checked and run
with progress callbacks, data gathered on the card as numpy arrays; errors
are sh2000.Error with the library's code and message.
/usr/share/doc/python3-sh2000/python.md is the guide.")
endif()

include(CPack)

cpack_add_component(runtime DISPLAY_NAME "libsh2000")
cpack_add_component(motion DISPLAY_NAME "libsh2000-motion" DEPENDS runtime)
cpack_add_component(sim DISPLAY_NAME "libsh2000-sim" DEPENDS runtime)
cpack_add_component(dev DISPLAY_NAME "libsh2000-dev" DEPENDS runtime)
cpack_add_component(motion_dev DISPLAY_NAME "libsh2000-motion-dev" DEPENDS motion dev)
cpack_add_component(sim_dev DISPLAY_NAME "libsh2000-sim-dev" DEPENDS sim dev)
cpack_add_component(tools DISPLAY_NAME "sh2000-tools" DEPENDS runtime motion sim)
cpack_add_component(dkms DISPLAY_NAME "sh2000-dkms")
cpack_add_component(linuxcnc DISPLAY_NAME "sh2000-linuxcnc")
cpack_add_component(python DISPLAY_NAME "python3-sh2000" DEPENDS runtime motion)
