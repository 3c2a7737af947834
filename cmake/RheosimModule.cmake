# rheosim_add_module(<name> [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# One library per module: public headers in <name>/include/rheosim/<name>/, sources in
# <name>/src/. Target rheosim_<name>, alias rheosim::<name>. Only the listed dependencies
# are visible, so the one-way module order is enforced by the build. A module without
# sources yet is a header-only (INTERFACE) library.
function(rheosim_add_module name)
  cmake_parse_arguments(ARG "" "" "PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  file(GLOB_RECURSE sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/*.cpp)
  if(sources)
    add_library(rheosim_${name} ${sources})
    target_include_directories(rheosim_${name}
      PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include
      PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
    target_link_libraries(rheosim_${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS} rheosim_warnings)
  else()
    add_library(rheosim_${name} INTERFACE)
    target_include_directories(rheosim_${name} INTERFACE ${CMAKE_CURRENT_SOURCE_DIR}/include)
    target_link_libraries(rheosim_${name} INTERFACE ${ARG_PUBLIC_DEPS})
  endif()
  add_library(rheosim::${name} ALIAS rheosim_${name})
endfunction()
