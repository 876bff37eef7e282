# cpack pre-build script (CPACK_PRE_BUILD_SCRIPTS), run on the staging tree
# before the Debian packages are made from it: what Debian's tools
# (dh_installdocs, dh_installchangelogs, dh_compress) would add.
#  - usr/share/doc/<package>/copyright and changelog.Debian.gz in each package
#  - man pages gzipped
# and what this build's dpkg-shlibdeps runs (CPackDeb, in each package's
# staging directory) read: debian/shlibs.local (cmake/Packaging.cmake).
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
