# Run at build time (core/CMakeLists.txt): writes OUTPUT, a source file defining
# rheosim::core::git_revision from `git describe --always --dirty --tags` of SOURCE_DIR, and
# rewrites it only when the revision changed, so an unchanged tree recompiles nothing.
# (A configure-time stamp went stale: incremental builds reported the revision of the last
# cmake run in --version and summary.json.)
execute_process(COMMAND git describe --always --dirty --tags
  WORKING_DIRECTORY ${SOURCE_DIR} OUTPUT_VARIABLE revision
  OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT revision)
  set(revision "unknown")
endif()
set(text "// Generated at build time by cmake/git_revision.cmake.
#include \"rheosim/core/version.hpp\"

namespace rheosim::core {
const char* const git_revision = \"${revision}\";
}  // namespace rheosim::core
")
set(previous "")
if(EXISTS ${OUTPUT})
  file(READ ${OUTPUT} previous)
endif()
if(NOT previous STREQUAL text)
  file(WRITE ${OUTPUT} "${text}")
endif()
