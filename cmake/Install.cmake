# Installation of everything user space and the driver sources, the
# pkg-config file, the CMake package config and the Debian packages (CPack).
# docs/install.md is the user's side. Included by the root CMakeLists.txt
# after all targets exist; every version below is PROJECT_VERSION.
#
# Components, one Debian package each:
#   runtime -> libsh2000       libsh2000.so.0 (+ the real file)
#   dev     -> libsh2000-dev   headers, libsh2000.a, libsh2000.so, sh2000.pc,
#                              lib/cmake/sh2000/
#   tools   -> sh2000-tools    sh2000ctl, sh2000-sim, sh2000-upload, man pages
#   dkms    -> sh2000-dkms     driver sources in src/sh2000-<ver>/ with
#                              dkms.conf, the udev rule, the modprobe example

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
# The library's VERSION is set in libsh2000/src and the driver's in
# driver/sh2000_core.h; they must say the same as project().
if(TARGET sh2000)
  get_target_property(_sh2000_libver sh2000 VERSION)
  if(NOT _sh2000_libver STREQUAL PROJECT_VERSION)
    message(WARNING "libsh2000 VERSION ${_sh2000_libver} != project version ${PROJECT_VERSION}")
  endif()
endif()
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
foreach(t sh2000 sh2000_motion sh2000_sim)
  add_dependencies(sh2000_installables ${t} ${t}_static)
endforeach()
set_target_properties(sh2000 PROPERTIES EXPORT_NAME sh2000)
set_target_properties(sh2000_static PROPERTIES EXPORT_NAME sh2000_static)
set_target_properties(sh2000_motion PROPERTIES EXPORT_NAME motion)
set_target_properties(sh2000_motion_static PROPERTIES EXPORT_NAME motion_static)
set_target_properties(sh2000_sim PROPERTIES EXPORT_NAME sim)
set_target_properties(sh2000_sim_static PROPERTIES EXPORT_NAME sim_static)
install(TARGETS sh2000 sh2000_motion sh2000_sim EXPORT sh2000Targets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    COMPONENT runtime
    NAMELINK_COMPONENT dev)
install(TARGETS sh2000_static sh2000_motion_static sh2000_sim_static
  EXPORT sh2000Targets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev)
foreach(t sh2000_static sh2000_motion_static sh2000_sim_static)
  # `cmake --install --strip` and the packages (CPACK_STRIP_FILES) strip the
  # shared libraries and the tools; strip the archives' debug sections too,
  # as Debian's dh_strip does (they hold the build machine's paths).
  install(CODE "
    if(CMAKE_INSTALL_DO_STRIP)
      execute_process(COMMAND \"${CMAKE_STRIP}\" --strip-debug --enable-deterministic-archives
        \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR}/$<TARGET_FILE_NAME:${t}>\")
    endif()" COMPONENT dev)
endforeach()

# Public headers, all in include/sh2000/, one folder per layer in the
# source tree. They include each other as "sh2000/...". The driver's ioctl
# ABI is there too for programs that talk to /dev/sh2000-N themselves
# (#include <sh2000/uapi/sh2000.h>).
foreach(layer protocol device motion sim)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/libsh2000/${layer}/include/sh2000
    DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT dev
    FILES_MATCHING PATTERN "*.h")
endforeach()
install(FILES ${PROJECT_SOURCE_DIR}/driver/uapi/sh2000.h
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sh2000/uapi COMPONENT dev)

# pkg-config: the shared library; `pkg-config --static` adds what
# libsh2000.a needs.
configure_file(${CMAKE_CURRENT_LIST_DIR}/sh2000.pc.in
  ${PROJECT_BINARY_DIR}/sh2000.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/sh2000.pc
  DESTINATION ${SH2000_PKGCONFIGDIR} COMPONENT dev)

# CMake: find_package(sh2000) gives sh2000::sh2000 (shared) and
# sh2000::sh2000_static.
if(TARGET sh2000)
  install(EXPORT sh2000Targets NAMESPACE sh2000::
    DESTINATION ${SH2000_CMAKEDIR} COMPONENT dev)
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
endif()

install(FILES ${PROJECT_SOURCE_DIR}/docs/library.md ${PROJECT_SOURCE_DIR}/docs/protocol.md
  DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/doc/libsh2000-dev COMPONENT dev)

# ---- the tools ------------------------------------------------------------
# Whatever tools exist when configuring (they arrive one by one).
set(SH2000_TOOLS sh2000ctl sh2000-sim sh2000-upload)
set(SH2000_TOOLS_INSTALLED)
foreach(t IN LISTS SH2000_TOOLS)
  if(TARGET ${t})
    install(TARGETS ${t} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT tools)
    add_dependencies(sh2000_installables ${t})
    list(APPEND SH2000_TOOLS_INSTALLED ${t})
  endif()
endforeach()

# Do the tools load libsh2000.so (then sh2000-tools depends on libsh2000)
# or carry libsh2000.a? Follows the link libraries of the tools' targets.
function(_sh2000_links_shared out)
  set(todo ${ARGN})
  set(seen)
  set(found OFF)
  while(todo)
    list(POP_FRONT todo t)
    if(t IN_LIST seen OR NOT TARGET ${t})
      continue()
    endif()
    list(APPEND seen ${t})
    if(t STREQUAL "sh2000")
      set(found ON)
      break()
    endif()
    get_target_property(_type ${t} TYPE)
    set(_libs)
    if(NOT _type STREQUAL "INTERFACE_LIBRARY")
      get_target_property(_libs ${t} LINK_LIBRARIES)
    endif()
    get_target_property(_ilibs ${t} INTERFACE_LINK_LIBRARIES)
    foreach(l IN LISTS _libs _ilibs)
      if(l AND NOT l MATCHES "NOTFOUND$")
        list(APPEND todo ${l})
      endif()
    endforeach()
  endwhile()
  set(${out} ${found} PARENT_SCOPE)
endfunction()
_sh2000_links_shared(SH2000_TOOLS_NEED_LIB ${SH2000_TOOLS_INSTALLED})

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
