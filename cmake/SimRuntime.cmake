# The device string `sim` makes libsh2000 dlopen() libsh2000-sim.so.0 at run
# time, so no link line names it and CMake would not build it for a program
# built by target alone (`cmake --build B --target sh2000-upload`): the
# program would then fail at its first `-d sim`. Every executable and module
# of the project can open `sim`, so each one depends on the simulator's
# shared library being built beside libsh2000. Included by the root
# CMakeLists.txt after all targets exist.

function(_sh2000_sim_runtime_walk dir)
  get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  foreach(t IN LISTS targets)
    get_target_property(type ${t} TYPE)
    if(type STREQUAL "EXECUTABLE" OR type STREQUAL "MODULE_LIBRARY")
      add_dependencies(${t} sh2000_sim)
    endif()
  endforeach()
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  foreach(sub IN LISTS subdirs)
    _sh2000_sim_runtime_walk(${sub})
  endforeach()
endfunction()

if(SH2000_SIM_DLOPEN)
  _sh2000_sim_runtime_walk(${PROJECT_SOURCE_DIR})
endif()
