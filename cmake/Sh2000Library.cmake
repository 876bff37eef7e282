# sh2000_add_library(<name>
#   OUTPUT <file name without lib/.so>   e.g. sh2000-motion
#   VERSION <x.y.z> SOVERSION <n>
#   SOURCES <c files...>
#   PUBLIC_INCLUDE <dirs...>     the layer's own public header folder(s)
#   PRIVATE_INCLUDE <dirs...>    the layer's private headers
#   ABI_HEADERS <headers...>     whose sh2000_*() functions the .so exports
#   EXTRA_SYMBOLS <names...>     further exported symbols (data)
#   LINK_PUBLIC <targets...>     lower layers (the shared one; the static
#                                library links their _static twins)
#   LINK_PRIVATE <libs...>       e.g. PkgConfig::JSONC, m
#   DEFINITIONS <defs...>)
#
# One layer of libsh2000 as lib<OUTPUT>.so.<SOVERSION> (target <name>) and
# lib<OUTPUT>.a (target <name>_static), made of the same objects. The shared
# library exports only the functions its public headers declare (a linker
# version script made from them) and must have no undefined symbols.
# Include directories are per layer: a target sees its own headers and the
# public headers of the layers it links, nothing else.
function(sh2000_add_library name)
  cmake_parse_arguments(L "" "OUTPUT;VERSION;SOVERSION"
    "SOURCES;PUBLIC_INCLUDE;PRIVATE_INCLUDE;ABI_HEADERS;EXTRA_SYMBOLS;LINK_PUBLIC;LINK_PRIVATE;DEFINITIONS"
    ${ARGN})
  add_library(${name}_obj OBJECT ${L_SOURCES})
  set_target_properties(${name}_obj PROPERTIES POSITION_INDEPENDENT_CODE ON)
  target_include_directories(${name}_obj
    PUBLIC ${L_PUBLIC_INCLUDE} PRIVATE ${L_PRIVATE_INCLUDE})
  target_compile_definitions(${name}_obj PRIVATE ${L_DEFINITIONS})
  # the objects see the lower layers' public headers (usage requirements)
  target_link_libraries(${name}_obj PUBLIC ${L_LINK_PUBLIC})

  add_library(${name} SHARED $<TARGET_OBJECTS:${name}_obj>)
  set_target_properties(${name} PROPERTIES OUTPUT_NAME ${L_OUTPUT}
    VERSION ${L_VERSION} SOVERSION ${L_SOVERSION})
  add_library(${name}_static STATIC $<TARGET_OBJECTS:${name}_obj>)
  set_target_properties(${name}_static PROPERTIES OUTPUT_NAME ${L_OUTPUT})
  foreach(t ${name} ${name}_static)
    foreach(d IN LISTS L_PUBLIC_INCLUDE)
      target_include_directories(${t} PUBLIC $<BUILD_INTERFACE:${d}>)
    endforeach()
    target_include_directories(${t} PUBLIC
      $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
    target_link_libraries(${t} PRIVATE ${L_LINK_PRIVATE})
  endforeach()
  target_link_libraries(${name} PUBLIC ${L_LINK_PUBLIC})
  foreach(dep IN LISTS L_LINK_PUBLIC)
    if(TARGET ${dep}_static)
      target_link_libraries(${name}_static PUBLIC ${dep}_static)
    else()
      target_link_libraries(${name}_static PUBLIC ${dep})
    endif()
  endforeach()
  # A static library's private dependencies are its consumer's to link.
  target_link_libraries(${name}_static INTERFACE ${L_LINK_PRIVATE})
  # (not in the fuzz tree: clang leaves the sanitizers' and the fuzzer's
  # runtime symbols to the executable)
  if(NOT SH2000_FUZZ)
    target_link_options(${name} PRIVATE -Wl,--no-undefined)
  endif()

  set(map ${PROJECT_BINARY_DIR}/lib${L_OUTPUT}.map)
  add_custom_command(OUTPUT ${map}
    COMMAND ${CMAKE_COMMAND} -DOUT=${map} "-DHEADERS=${L_ABI_HEADERS}"
      "-DEXTRA=${L_EXTRA_SYMBOLS}" -P ${PROJECT_SOURCE_DIR}/cmake/AbiMap.cmake
    DEPENDS ${L_ABI_HEADERS} ${PROJECT_SOURCE_DIR}/cmake/AbiMap.cmake
    COMMENT "lib${L_OUTPUT}.map: the public headers' functions"
    VERBATIM)
  add_custom_target(${name}_abi_map DEPENDS ${map})
  add_dependencies(${name} ${name}_abi_map)
  target_link_options(${name} PRIVATE "LINKER:--version-script=${map}")
  set_property(TARGET ${name} APPEND PROPERTY LINK_DEPENDS ${map})
endfunction()
