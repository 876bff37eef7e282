# cpack pre-build script (CPACK_PRE_BUILD_SCRIPTS), run on the staging tree
# before the Debian packages are made from it: what Debian's tools
# (dh_installdocs, dh_installchangelogs, dh_compress) would add.
#  - usr/share/doc/<package>/copyright and changelog.Debian.gz in each package
#  - man pages gzipped
# and what this build's dpkg-shlibdeps runs (CPackDeb, in each package's
# staging directory) read: debian/shlibs.local (cmake/Packaging.cmake).
# Last, as dh_makeshlibs does, dpkg-gensymbols checks each library that has
# a symbols file (cmake/debian/<package>.symbols, shipped as DEBIAN/symbols)
# against it, at the strictest level (-c4): a symbol gone, a symbol new, a
# library gone or new all stop the build, so the symbols file, the ABI
# baseline (abi/) and the SONAME are updated together (docs/install.md).
# gzip -9n: no name, no time stamp, so the packages are reproducible.

file(GLOB _components LIST_DIRECTORIES true "${CPACK_TEMPORARY_DIRECTORY}/*")
foreach(dir IN LISTS _components)
  if(NOT IS_DIRECTORY "${dir}")
    continue()
  endif()
  get_filename_component(comp "${dir}" NAME)
  string(TOUPPER "${comp}" COMP)
  set(pkg "${CPACK_DEBIAN_${COMP}_PACKAGE_NAME}")
  if(NOT pkg)
    continue()
  endif()
  set(doc "${dir}${CPACK_PACKAGING_INSTALL_PREFIX}/share/doc/${pkg}")
  file(MAKE_DIRECTORY "${doc}")
  file(COPY_FILE "${CPACK_SH2000_DEBIAN_DIR}/copyright" "${doc}/copyright")
  file(WRITE "${doc}/changelog.Debian"
"${pkg} (${CPACK_PACKAGE_VERSION}-${CPACK_DEBIAN_PACKAGE_RELEASE}) unstable; urgency=medium

  * Built with CPack from the SH-2000 sources, version ${CPACK_PACKAGE_VERSION}
    (git log is the upstream change history).

 -- ${CPACK_DEBIAN_PACKAGE_MAINTAINER}  ${CPACK_SH2000_DATE}
")
  execute_process(COMMAND gzip -9nf "${doc}/changelog.Debian" RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "gzip ${doc}/changelog.Debian failed")
  endif()
  # Only where CPackDeb runs dpkg-shlibdeps (ELF files), as it removes
  # debian/ afterwards: anywhere else it would be packaged.
  file(GLOB_RECURSE elfs LIST_DIRECTORIES false "${dir}/*")
  foreach(f IN LISTS elfs)
    if(NOT IS_SYMLINK "${f}")
      file(READ "${f}" magic LIMIT 4 HEX)
      if(magic STREQUAL "7f454c46")
        set(shlibs "${CPACK_SH2000_SHLIBS_DIR}/${comp}/shlibs.local")
        if(NOT EXISTS "${shlibs}")
          set(shlibs "${CPACK_SH2000_SHLIBS_DIR}/shlibs.local")
        endif()
        file(MAKE_DIRECTORY "${dir}/debian")
        file(COPY_FILE "${shlibs}" "${dir}/debian/shlibs.local")
        break()
      endif()
    endif()
  endforeach()
endforeach()

file(GLOB_RECURSE _files LIST_DIRECTORIES false "${CPACK_TEMPORARY_DIRECTORY}/*")
foreach(p IN LISTS _files)
  if(p MATCHES "/share/man/man[^/]*/[^/]+\\.[0-9][a-z]*$")
    execute_process(COMMAND gzip -9nf "${p}" RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "gzip ${p} failed")
    endif()
  endif()
endforeach()

# dpkg-gensymbols -c4 on the staged library of each package with a symbols
# file; its output (the symbols as built) goes beside the checked file.
foreach(dir IN LISTS _components)
  get_filename_component(comp "${dir}" NAME)
  string(TOUPPER "${comp}" COMP)
  set(pkg "${CPACK_DEBIAN_${COMP}_PACKAGE_NAME}")
  set(sym "${CPACK_SH2000_SHLIBS_DIR}/${pkg}/symbols")
  if(NOT pkg OR NOT EXISTS "${sym}")
    continue()
  endif()
  execute_process(
    COMMAND dpkg-gensymbols -c4 -p${pkg}
      -v${CPACK_PACKAGE_VERSION}-${CPACK_DEBIAN_PACKAGE_RELEASE}
      -P${dir} -I${sym} -O${sym}.built
    WORKING_DIRECTORY "${dir}"
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "dpkg-gensymbols -c4: ${pkg} does not match "
      "cmake/debian/${pkg}.symbols (a symbol added or removed: add new "
      "ones with the version that adds them; a removal breaks the ABI and "
      "needs a new SONAME, docs/install.md):\n${out}")
  endif()
  message(STATUS "dpkg-gensymbols -c4: ${pkg} matches its symbols file")
endforeach()
