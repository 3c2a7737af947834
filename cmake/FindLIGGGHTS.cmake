# LIGGGHTS from Debian's libliggghts-dev ships no CMake config or pkg-config file:
# find its header and library and wrap them in an imported target.
find_path(LIGGGHTS_INCLUDE_DIR NAMES library.h PATHS /usr/include/liggghts NO_DEFAULT_PATH)
find_library(LIGGGHTS_LIBRARY NAMES liggghts)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(LIGGGHTS REQUIRED_VARS LIGGGHTS_LIBRARY LIGGGHTS_INCLUDE_DIR)
if(LIGGGHTS_FOUND AND NOT TARGET LIGGGHTS::liggghts)
  add_library(LIGGGHTS::liggghts UNKNOWN IMPORTED)
  set_target_properties(LIGGGHTS::liggghts PROPERTIES
    IMPORTED_LOCATION "${LIGGGHTS_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${LIGGGHTS_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "MPI::MPI_CXX")
endif()
