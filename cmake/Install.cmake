# Installation of everything user space and the driver sources, the
# pkg-config file, the CMake package config and the Debian packages (CPack).
# docs/install.md is the user's side. Included by the root CMakeLists.txt
# after all targets exist; every version below is PROJECT_VERSION.
#
# Components, one Debian package each:
#   runtime    -> libsh2000            libsh2000.so.0 (+ the real file)
#   motion     -> libsh2000-motion     libsh2000-motion.so.0
#   sim        -> libsh2000-sim        libsh2000-sim.so.0
#   dev        -> libsh2000-dev        device, protocol and ioctl headers,
#                                      libsh2000.a, libsh2000.so, sh2000.pc,
#                                      lib/cmake/sh2000/ (config, version,
#                                      sh2000Targets*.cmake)
#   motion_dev -> libsh2000-motion-dev path.h, program.h, run.h, the .a, the
#                                      .so link, sh2000-motion.pc,
#                                      sh2000MotionTargets*.cmake
#   sim_dev    -> libsh2000-sim-dev    sim.h, sh2000_cardsim.h, the .a, the
#                                      .so link, sh2000-sim.pc,
#                                      sh2000SimTargets*.cmake
#   tools      -> sh2000-tools         sh2000ctl, sh2000-sim, sh2000-upload,
#                                      sh2000-tune, sh2000-comp, man pages
#   dkms       -> sh2000-dkms          driver sources in src/sh2000-<ver>/
#                                      with dkms.conf, the udev rule, the
#                                      modprobe example
#   linuxcnc   -> sh2000-linuxcnc      hal_sh2000 (hal/CMakeLists.txt)
#   python     -> python3-sh2000       the module sh2000
#                                      (python/CMakeLists.txt)

include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(SH2000_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/sh2000)
set(SH2000_PKGCONFIGDIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
set(SH2000_DKMS_SRCDIR src/sh2000-${PROJECT_VERSION})
set(SH2000_PKG_VERSION ${PROJECT_VERSION})

# Everything install() below needs built: `cmake --build B --target
# sh2000_installables` is enough for `cmake --install` and cpack when the
# tree was configured with -DCMAKE_SKIP_INSTALL_ALL_DEPENDENCY=ON (the
# packaging test does that to skip building the tests).
add_custom_target(sh2000_installables)

# ---- versions: one project version ----------------------------------------
# The libraries' VERSION is set in libsh2000/*/CMakeLists.txt, the driver's in
# driver/sh2000_core.h; they must say the same as project().
foreach(t sh2000 sh2000_motion sh2000_sim)
  get_target_property(_sh2000_libver ${t} VERSION)
  if(NOT _sh2000_libver STREQUAL PROJECT_VERSION)
    message(WARNING "${t} VERSION ${_sh2000_libver} != project version ${PROJECT_VERSION}")
  endif()
endforeach()
file(STRINGS ${PROJECT_SOURCE_DIR}/driver/sh2000_core.h _sh2000_drv
  REGEX "^#define[ \t]+SH2000_DRIVER_VERSION[ \t]")
string(REGEX REPLACE ".*\"(.*)\".*" "\\1" _sh2000_drv "${_sh2000_drv}")
if(NOT _sh2000_drv STREQUAL PROJECT_VERSION)
  message(WARNING "driver SH2000_DRIVER_VERSION \"${_sh2000_drv}\" != project version ${PROJECT_VERSION}")
endif()

# ---- the libraries ---------------------------------------------------------
# Each layer (cmake/Sh2000Library.cmake) is a shared and a static library;
# their targets carry build-tree include paths only as BUILD_INTERFACE.
# Installed consumers get <prefix>/include (headers as <sh2000/...>).
#
# _sh2000_install_layer(<target> <export name> <runtime comp> <dev comp>
#                       <export set> <header folders...>)
# The shared library goes to <runtime comp> (its namelink to <dev comp>),
# the static one, the layer's public headers, its CMake targets file
# (sh2000::<export name> and sh2000::<export name>_static) and its
# pkg-config file to <dev comp>: one Debian package each.
function(_sh2000_install_layer target export runtime dev set)
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${export})
  set_target_properties(${target}_static PROPERTIES EXPORT_NAME ${export}_static)
  add_dependencies(sh2000_installables ${target} ${target}_static)
  install(TARGETS ${target} EXPORT ${set}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
      COMPONENT ${runtime}
      NAMELINK_COMPONENT ${dev})
  install(TARGETS ${target}_static EXPORT ${set}
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT ${dev})
  # `cmake --install --strip` and the packages (CPACK_STRIP_FILES) strip the
  # shared libraries and the tools; strip the archive's debug sections too,
  # as Debian's dh_strip does (they hold the build machine's paths).
  install(CODE "
    if(CMAKE_INSTALL_DO_STRIP)
      execute_process(COMMAND \"${CMAKE_STRIP}\" --strip-debug --enable-deterministic-archives
        \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR}/$<TARGET_FILE_NAME:${target}_static>\")
    endif()" COMPONENT ${dev})
  install(EXPORT ${set} NAMESPACE sh2000::
    DESTINATION ${SH2000_CMAKEDIR} COMPONENT ${dev})
  # Every layer's public headers land in include/sh2000/ (they include
  # each other as "sh2000/..."); each -dev package holds its own.
  foreach(dir IN LISTS ARGN)
    install(DIRECTORY ${dir}/sh2000 DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
      COMPONENT ${dev} FILES_MATCHING PATTERN "*.h")
  endforeach()
  # The build tree's .pc has the configured prefix; the installed one gets
  # the prefix installed to (`cmake --install B --prefix P`, cpack's), put
  # in at install time, so pkg-config works for any prefix without
  # --define-variable. An absolute path rather than ${pcfiledir}/..: the
  # packages' flags stay -I/usr/include, which pkg-config knows as the
  # system's and leaves out.
  get_target_property(pc ${target} OUTPUT_NAME)
  configure_file(${CMAKE_CURRENT_FUNCTION_LIST_DIR}/${pc}.pc.in
    ${PROJECT_BINARY_DIR}/${pc}.pc @ONLY)
  install(CODE "
    file(READ \"${PROJECT_BINARY_DIR}/${pc}.pc\" _sh2000_pc)
    get_filename_component(_sh2000_prefix \"\${CMAKE_INSTALL_PREFIX}\" ABSOLUTE)
    string(REGEX REPLACE \"^prefix=[^\\n]*\" \"prefix=\${_sh2000_prefix}\"
      _sh2000_pc \"\${_sh2000_pc}\")
    file(WRITE \"${PROJECT_BINARY_DIR}/pkgconfig-install/${pc}.pc\" \"\${_sh2000_pc}\")
    file(INSTALL DESTINATION \"\${CMAKE_INSTALL_PREFIX}/${SH2000_PKGCONFIGDIR}\"
      TYPE FILE FILES \"${PROJECT_BINARY_DIR}/pkgconfig-install/${pc}.pc\")"
    COMPONENT ${dev})
endfunction()

# Installed, libsh2000-motion.a's json-c is json-c's own CMake target
# (Debian's libjson-c-dev ships it); PkgConfig::JSONC is this build's.
get_target_property(_sh2000_mlibs sh2000_motion_static INTERFACE_LINK_LIBRARIES)
list(TRANSFORM _sh2000_mlibs REPLACE "PkgConfig::JSONC"
  "$<BUILD_INTERFACE:PkgConfig::JSONC>$<INSTALL_INTERFACE:json-c::json-c>")
set_target_properties(sh2000_motion_static PROPERTIES
  INTERFACE_LINK_LIBRARIES "${_sh2000_mlibs}")

set(_sh2000_src ${PROJECT_SOURCE_DIR}/libsh2000)
# libsh2000: the device, the protocol's headers and the driver's ioctl ABI
# for programs that talk to /dev/sh2000-N themselves
# (#include <sh2000/uapi/sh2000.h>).
_sh2000_install_layer(sh2000 sh2000 runtime dev sh2000Targets
  ${_sh2000_src}/device/include ${_sh2000_src}/protocol/include)
install(FILES ${PROJECT_SOURCE_DIR}/driver/uapi/sh2000.h
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sh2000/uapi COMPONENT dev)
_sh2000_install_layer(sh2000_motion motion motion motion_dev sh2000MotionTargets
  ${_sh2000_src}/motion/include)
_sh2000_install_layer(sh2000_sim sim sim sim_dev sh2000SimTargets
  ${_sh2000_src}/sim/include)

# CMake: find_package(sh2000 [COMPONENTS motion sim]) gives sh2000::sh2000
# and sh2000::sh2000_static, and per component sh2000::<comp> and
# sh2000::<comp>_static (cmake/sh2000Config.cmake.in). The config and
# version files are libsh2000-dev's; each component's targets file is its
# -dev package's.
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/sh2000Config.cmake.in
  ${PROJECT_BINARY_DIR}/sh2000Config.cmake
  INSTALL_DESTINATION ${SH2000_CMAKEDIR})
# Same major: compatible (SONAME rule in docs/install.md). While the
# major is 0, a minor is a new ABI too.
if(PROJECT_VERSION_MAJOR EQUAL 0)
  set(_sh2000_compat SameMinorVersion)
else()
  set(_sh2000_compat SameMajorVersion)
endif()
write_basic_package_version_file(${PROJECT_BINARY_DIR}/sh2000ConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY ${_sh2000_compat})
install(FILES
  ${PROJECT_BINARY_DIR}/sh2000Config.cmake
  ${PROJECT_BINARY_DIR}/sh2000ConfigVersion.cmake
  DESTINATION ${SH2000_CMAKEDIR} COMPONENT dev)

install(FILES ${PROJECT_SOURCE_DIR}/docs/library.md ${PROJECT_SOURCE_DIR}/docs/protocol.md
  DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/doc/libsh2000-dev COMPONENT dev)
install(FILES ${PROJECT_SOURCE_DIR}/docs/planner.md ${PROJECT_SOURCE_DIR}/docs/programs.md
  DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/doc/libsh2000-motion-dev COMPONENT motion_dev)
install(FILES ${PROJECT_SOURCE_DIR}/docs/cardmodel.md
  DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/doc/libsh2000-sim-dev COMPONENT sim_dev)

# ---- the tools ------------------------------------------------------------
# Whatever tools exist when configuring (they arrive one by one).
set(SH2000_TOOLS sh2000ctl sh2000-sim sh2000-upload sh2000-tune sh2000-comp)
set(SH2000_TOOLS_INSTALLED)
foreach(t IN LISTS SH2000_TOOLS)
  if(TARGET ${t})
    install(TARGETS ${t} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT tools)
    add_dependencies(sh2000_installables ${t})
    list(APPEND SH2000_TOOLS_INSTALLED ${t})
  endif()
endforeach()

# hal_sh2000 (hal/, built when linuxcnc-uspace-dev is installed; its
# install rules are there)
if(TARGET hal_sh2000)
  add_dependencies(sh2000_installables hal_sh2000)
endif()
# the Python binding (python/, built when python3-dev is installed; its
# install rules are there)
if(TARGET sh2000_python)
  add_dependencies(sh2000_installables sh2000_python)
endif()

# Man pages. The packages ship them gzipped, as Debian does: cpack
# compresses them in its staging tree (cmake/debian/prebuild.cmake), so a
# source install and the tools' own rules agree on share/man/man1/NAME.1.
file(GLOB _sh2000_man1 CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/tools/*/*.1)
if(_sh2000_man1)
  install(FILES ${_sh2000_man1} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT tools)
endif()

# ---- the driver: DKMS sources, udev rule, modprobe example ----------------
# The sources DKMS builds: the root Kbuild, driver/ (sources only, never
# what a Kbuild run left there) and dkms.conf with the project version.
file(READ ${PROJECT_SOURCE_DIR}/dkms.conf _sh2000_dkms)
string(REGEX REPLACE "PACKAGE_VERSION=\"[^\"]*\"" "PACKAGE_VERSION=\"${PROJECT_VERSION}\""
  _sh2000_dkms "${_sh2000_dkms}")
file(CONFIGURE OUTPUT ${PROJECT_BINARY_DIR}/dkms/dkms.conf CONTENT "${_sh2000_dkms}" @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/dkms/dkms.conf ${PROJECT_SOURCE_DIR}/Kbuild
  DESTINATION ${SH2000_DKMS_SRCDIR} COMPONENT dkms)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/driver/
  DESTINATION ${SH2000_DKMS_SRCDIR}/driver COMPONENT dkms
  FILES_MATCHING
    PATTERN "*.c" PATTERN "*.h" PATTERN "Kbuild"
    PATTERN "*.mod.c" EXCLUDE
    PATTERN ".*" EXCLUDE)

# udev rules.d under the prefix: /usr/lib/udev/rules.d for the packages
# (the same directory as /lib/udev/rules.d on Debian 12's merged /usr),
# /usr/local/lib/udev/rules.d for a default source install (udev reads both).
install(FILES ${PROJECT_SOURCE_DIR}/udev/60-sh2000.rules
  DESTINATION lib/udev/rules.d COMPONENT dkms)
install(FILES ${PROJECT_SOURCE_DIR}/driver/sh2000.modprobe.conf
  DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/doc/sh2000-dkms/examples
  RENAME sh2000.conf COMPONENT dkms)
install(FILES ${PROJECT_SOURCE_DIR}/docs/driver.md
  DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/doc/sh2000-dkms COMPONENT dkms)

include(${CMAKE_CURRENT_LIST_DIR}/Packaging.cmake)
