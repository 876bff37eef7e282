# cpack pre-build script (CPACK_PRE_BUILD_SCRIPTS): gzip the man pages in
# the staging tree, as Debian packages ship them (gzip -9n: no name, no
# time stamp, so the packages are reproducible).
file(GLOB_RECURSE _files LIST_DIRECTORIES false "${CPACK_TEMPORARY_DIRECTORY}/*")
foreach(p IN LISTS _files)
  if(p MATCHES "/share/man/man[^/]*/[^/]+\\.[0-9][a-z]*$")
    execute_process(COMMAND gzip -9nf "${p}" RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "gzip ${p} failed")
    endif()
  endif()
endforeach()
